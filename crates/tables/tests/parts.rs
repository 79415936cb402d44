//! Parquet parts from real analyses (bundled engines and diagrams, measured
//! fixtures), read back with the parquet crate's own Arrow reader: schema,
//! types, nulls for absent keys, metadata; parts of a 4- and a 12-cylinder
//! campaign concatenate; the merge check names a missing part and a part
//! whose schema differs; the cycles table keeps skipped cycles.

use arrow_array::{
    Array, BooleanArray, Float64Array, Int16Array, Int32Array, Int64Array, RecordBatch, StringArray,
};
use arrow_schema::DataType;
use enginedyn_engine::Engine;
use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Resampled};
use enginedyn_pipeline::schema::{self, SummaryRecord};
use enginedyn_pipeline::{Analysis, Options, Scope};
use enginedyn_tables::{
    Campaign, Meta, Table, TablesError, check_campaign, commit_part, cycles_parquet, list_blake3,
    stage_part, summary_parquet, write_manifest, write_part,
};

/// `m` as part `part` of a 3-part campaign over the files `a`, `b`, `c`,
/// `d` (sorted: a and d in part 0, b in part 1, c in part 2), holding
/// `files`.
fn in_campaign(m: &Meta, part: usize, files: &[&str]) -> Meta {
    let mut m = m.clone();
    m.campaign = Some(Campaign {
        list_blake3: list_blake3(&["a", "b", "c", "d"]),
        parts: 3,
        part,
        tables: vec![Table::Summary, Table::Cycles],
    });
    m.files = Some(files.iter().map(|f| f.to_string()).collect());
    m
}
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// One diagram analysed as `enginedyn run` does (the CLI's reader options
/// for the engine; the speed from the flag, the diagram or the engine).
struct Run {
    file: String,
    resampled: Resampled,
    analysis: Analysis,
    sha: String,
}

fn engine(name: &str) -> Engine {
    enginedyn_engine::file::read(&root().join("data").join(name)).unwrap()
}

fn options(e: &Engine) -> (ParseOptions, GridOptions) {
    let mut parse = ParseOptions::new(e.cycle().to_degrees());
    parse.cylinder = Some(*e.cylinder());
    parse.max_cylinder = e.cylinders();
    parse.firing_deg = e.firing_angles().iter().map(|t| t.to_degrees()).collect();
    let mut grid = GridOptions::new(0.5, Interp::Auto);
    grid.cylinder = Some(*e.cylinder());
    grid.share_volume_law(parse.cycle_deg);
    (parse, grid)
}

fn run(e: &Engine, path: &Path, rpm: Option<f64>) -> Run {
    let (mut parse, grid) = options(e);
    parse.rpm = rpm;
    let bytes = std::fs::read(path).unwrap();
    let resampled = enginedyn_ingest::load(&bytes[..], &parse, &grid).unwrap();
    let speed = rpm
        .or(resampled.rpm)
        .or(e.operating().rpm)
        .expect("a speed");
    let opts = Options {
        step_deg: 0.5,
        scope: Scope::Summary,
        ..Options::default()
    };
    let analysis = enginedyn_pipeline::analyse(e, &resampled, speed, &opts).unwrap();
    Run {
        file: path.display().to_string(),
        resampled,
        analysis,
        sha: enginedyn_report::blake3_hex(&bytes),
    }
}

fn meta(e: &str) -> Meta {
    Meta::new(
        enginedyn_report::blake3_file(&root().join("data").join(e)).unwrap(),
        enginedyn_report::blake3_hex(engine(e).meaning().as_bytes()),
        serde_json::json!({"step_deg": 0.5, "interp": "auto"}),
    )
}

fn records<'a>(e: &'a Engine, runs: &'a [Run]) -> Vec<SummaryRecord<'a>> {
    runs.iter()
        .map(|r| SummaryRecord {
            file: &r.file,
            error: None,
            engine: e.name(),
            diagram_blake3: Some(&r.sha),
            summary: Some(&r.analysis.summary),
        })
        .collect()
}

/// Reads a part back: its batches, concatenated, and its key-value metadata.
fn read(bytes: Vec<u8>) -> (RecordBatch, HashMap<String, String>) {
    let b = ParquetRecordBatchReaderBuilder::try_new(bytes::Bytes::from(bytes)).unwrap();
    let meta = b
        .metadata()
        .file_metadata()
        .key_value_metadata()
        .unwrap()
        .iter()
        .map(|k| (k.key.clone(), k.value.clone().unwrap_or_default()))
        .collect();
    let schema = b.schema().clone();
    let batches: Vec<RecordBatch> = b.build().unwrap().map(Result::unwrap).collect();
    (arrow_select_concat(&schema, &batches), meta)
}

fn arrow_select_concat(schema: &arrow_schema::SchemaRef, batches: &[RecordBatch]) -> RecordBatch {
    arrow_select::concat::concat_batches(schema, batches).unwrap()
}

fn col<'a, T: 'static>(b: &'a RecordBatch, name: &str) -> &'a T {
    b.column_by_name(name)
        .unwrap_or_else(|| panic!("no column {name}"))
        .as_any()
        .downcast_ref::<T>()
        .unwrap_or_else(|| panic!("{name}: another type"))
}

/// The summary part of two bundled runs: INTERFACE.md's columns and types
/// in order, every figure as `summary.json` has it (bit for bit), absent
/// optional keys null, the metadata.
#[test]
fn summary_part_reads_back() {
    let e = engine("vaz2108.toml");
    let runs = [
        run(&e, &root().join("data/vaz2108.csv"), None),
        run(
            &e,
            &root().join("tests/fixtures/measured/dropout_20cycles.csv"),
            Some(2000.0),
        ),
    ];
    let mut rows = records(&e, &runs);
    rows.push(SummaryRecord {
        file: "missing.csv",
        error: Some("cannot open: no such file"),
        engine: e.name(),
        diagram_blake3: None,
        summary: None,
    });
    let (b, kv) = read(summary_parquet(&rows, &meta("vaz2108.toml")).unwrap());
    assert_eq!(b.num_rows(), 3);
    // Names, order and types.
    let fields: Vec<(String, DataType)> = b
        .schema()
        .fields()
        .iter()
        .map(|f| (f.name().clone(), f.data_type().clone()))
        .collect();
    assert_eq!(fields.len(), schema::SUMMARY.len());
    assert_eq!(fields[0], ("file".into(), DataType::Utf8));
    assert_eq!(fields[3], ("diagram_blake3".into(), DataType::Utf8));
    assert_eq!(fields[4], ("rpm".into(), DataType::Float64));
    let ty = |n: &str| fields.iter().find(|f| f.0 == n).unwrap().1.clone();
    assert_eq!(ty("journal_most_loaded"), DataType::Int32);
    assert_eq!(ty("cycles"), DataType::Int64);
    assert_eq!(ty("cycles_skipped"), DataType::Int64);
    assert_eq!(ty("pegging.method"), DataType::Utf8);
    assert_eq!(ty("models.grid_step_deg"), DataType::Float64);
    // summary/2: the combustion columns after `notes`; summary/3: the
    // level lists after them.
    // summary/4: the brake figures and `design.*` after them.
    let n = fields.len() - 8;
    assert_eq!(fields[n - 11].0, "imep_lnv");
    assert_eq!(fields[n - 10].0, "models.wall_heat");
    assert_eq!(fields[n - 5].0, "knock_share");
    assert_eq!(fields[n - 4].0, "p_max_bar");
    assert_eq!(fields[n - 3].0, "p_max_angle_deg");
    assert_eq!(fields[n - 2].0, "burn_levels_pct");
    assert_eq!(fields[n - 1].0, "burn_levels_deg");
    assert_eq!(fields[n].0, "fmep_bar");
    assert_eq!(fields[n + 7].0, "design.lambda");
    assert!(matches!(ty("burn_levels_deg"), DataType::List(_)));
    assert_eq!(ty("ca50_deg"), DataType::Float64);
    assert_eq!(ty("models.gamma"), DataType::Utf8);
    // Metadata.
    assert_eq!(kv["enginedyn.schema"], "summary/4");
    assert_eq!(kv["enginedyn.version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(kv["engine.blake3"].len(), 64);
    assert_eq!(kv["engine.parsed_blake3"].len(), 64);
    let options: serde_json::Value = serde_json::from_str(&kv["options"]).unwrap();
    assert_eq!(options["step_deg"], 0.5);
    // Every number is summary.json's number, bit for bit; absent is null.
    for (k, r) in runs.iter().enumerate() {
        let s = &r.analysis.summary;
        let fields = enginedyn_report::flatten(s);
        for c in schema::SUMMARY
            .iter()
            .filter(|c| c.ty == schema::ColumnType::Float64)
        {
            let a = col::<Float64Array>(&b, c.name);
            match enginedyn_pipeline::Summary::key(c.name).and_then(|key| key.number(s)) {
                Some(x) if x.is_finite() => {
                    assert_eq!(a.value(k).to_bits(), x.to_bits(), "{}", c.name)
                }
                _ if c.name.contains('.') => {}
                _ => assert!(a.is_null(k), "{} row {k}", c.name),
            }
            // The CSV has no column where Parquet holds null for an absent key.
            if c.group.optional() && !fields.iter().any(|f| f.0 == c.name) {
                assert!(a.is_null(k), "{} row {k}", c.name);
            }
        }
        assert_eq!(
            col::<Int32Array>(&b, "journal_most_loaded").value(k) as usize,
            s.journal_most_loaded
        );
        assert_eq!(
            col::<StringArray>(&b, "notes").value(k),
            s.notes.join(" | ")
        );
        assert_eq!(col::<StringArray>(&b, "engine").value(k), e.name());
        assert_eq!(
            col::<StringArray>(&b, "models.kinematics").value(k),
            "exact"
        );
    }
    // The bundled diagram is one cycle: no cycle statistics, no pegging.
    assert!(col::<Int64Array>(&b, "cycles").is_null(0));
    assert!(col::<Float64Array>(&b, "imep_std_bar").is_null(0));
    assert!(col::<StringArray>(&b, "pegging.method").is_null(0));
    // The dropout file: 18 cycles averaged, 2 skipped.
    assert_eq!(col::<Int64Array>(&b, "cycles").value(1), 18);
    assert_eq!(col::<Int64Array>(&b, "cycles_skipped").value(1), 2);
    // The failed row: its error, nothing else.
    assert_eq!(
        col::<StringArray>(&b, "error").value(2),
        "cannot open: no such file"
    );
    assert!(col::<StringArray>(&b, "error").is_null(0));
    assert!(col::<Float64Array>(&b, "rpm").is_null(2));
    assert!(col::<StringArray>(&b, "diagram_blake3").is_null(2));
    assert!(col::<StringArray>(&b, "notes").is_null(2));
}

/// The cycles table of the dropout fixture: 20 rows by cycle, the two
/// skipped ones `used = false` with the reason and no figures, the used
/// ones in bar, with the run's speed.
#[test]
fn cycles_part_keeps_skipped_cycles() {
    let e = engine("vaz2108.toml");
    let r = run(
        &e,
        &root().join("tests/fixtures/measured/dropout_20cycles.csv"),
        Some(2000.0),
    );
    let rows = schema::cycle_rows(&r.file, &r.resampled, r.analysis.summary.rpm);
    let (b, kv) = read(cycles_parquet(&rows, &meta("vaz2108.toml")).unwrap());
    assert_eq!(kv["enginedyn.schema"], "cycles/3");
    let schema = b.schema();
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    assert_eq!(
        names,
        [
            "file",
            "cylinder",
            "cycle",
            "used",
            "skip_reason",
            "imep_bar",
            "p_max_bar",
            "p_max_angle_deg",
            "peg_offset_bar",
            "rpm",
            "imep_gross_bar",
            "pmep_bar",
            "ca5_deg",
            "ca10_deg",
            "ca50_deg",
            "ca90_deg",
            "burn_10_90_deg",
            "soc_deg",
            "eoc_deg",
            "heat_released_j",
            "dp_dphi_max_bar_deg",
            "dp_dphi_max_angle_deg",
            "combustion",
            "mapo_bar",
            "impo_bar_deg",
            "burn_levels_pct",
            "burn_levels_deg"
        ]
    );
    // This helper grids without the combustion analysis: its columns are
    // there, and null (never false: nothing was analysed).
    let burns = col::<BooleanArray>(&b, "combustion");
    assert_eq!(burns.null_count(), 20);
    assert_eq!(col::<Float64Array>(&b, "imep_gross_bar").null_count(), 20);
    assert_eq!(b.num_rows(), 20);
    let cycle = col::<Int64Array>(&b, "cycle");
    assert_eq!(cycle.values().to_vec(), (1..=20).collect::<Vec<i64>>());
    assert!(
        col::<Int16Array>(&b, "cylinder")
            .values()
            .iter()
            .all(|&c| c == 0)
    );
    let used = col::<BooleanArray>(&b, "used");
    let reason = col::<StringArray>(&b, "skip_reason");
    let imep = col::<Float64Array>(&b, "imep_bar");
    let pmax = col::<Float64Array>(&b, "p_max_bar");
    assert_eq!(used.false_count(), 2);
    for k in 0..20 {
        if used.value(k) {
            assert!(reason.is_null(k));
            // A fired cycle: IMEP of a few bar, a peak of tens of bar.
            assert!(
                imep.value(k) > 1.0 && imep.value(k) < 30.0,
                "{}",
                imep.value(k)
            );
            assert!(pmax.value(k) > 10.0 && pmax.value(k) < 200.0);
        } else {
            assert!(
                reason.value(k).starts_with("a gap in the data"),
                "{}",
                reason.value(k)
            );
            assert!(imep.is_null(k) && pmax.is_null(k));
        }
    }
    // The mean of the used cycles' IMEP is summary.json's imep_bar.
    let used_imep: Vec<f64> = (0..20)
        .filter(|&k| used.value(k))
        .map(|k| imep.value(k))
        .collect();
    let mean = used_imep.iter().sum::<f64>() / used_imep.len() as f64;
    let want = r.analysis.summary.imep_bar.unwrap();
    assert!((mean - want).abs() < 1e-9 * want, "{mean} {want}");
    assert!(col::<Float64Array>(&b, "peg_offset_bar").null_count() == 20);
    // No time record: every cycle at the run's speed.
    let rpm = col::<Float64Array>(&b, "rpm");
    assert!(
        rpm.values()
            .iter()
            .all(|x| x.to_bits() == 2000.0_f64.to_bits())
    );
}

/// Parts of a 4-cylinder and a 12-cylinder campaign have one schema, so
/// they concatenate; written into one campaign folder, merge takes them.
#[test]
fn four_and_twelve_cylinders_concatenate() {
    let e4 = engine("vaz2108.toml");
    let e12 = engine("v12_60.toml");
    let r4 = [run(&e4, &root().join("data/vaz2108.csv"), None)];
    let r12 = [run(&e12, &root().join("data/v12_60.csv"), None)];
    let m = meta("vaz2108.toml");
    let (a, _) = read(summary_parquet(&records(&e4, &r4), &m).unwrap());
    let (b, _) = read(summary_parquet(&records(&e12, &r12), &m).unwrap());
    assert_eq!(a.schema(), b.schema());
    let both = arrow_select::concat::concat_batches(&a.schema(), [&a, &b]).unwrap();
    assert_eq!(both.num_rows(), 2);
    assert_eq!(col::<StringArray>(&both, "engine").value(1), e12.name());
    // The traces of each: one schema too.
    let t4 = schema::trace_points(&r4[0].file, &r4[0].resampled);
    let t12 = schema::trace_points(&r12[0].file, &r12[0].resampled);
    let (ta, _) = read(enginedyn_tables::traces_parquet(&t4, &m).unwrap());
    let (tb, _) = read(enginedyn_tables::traces_parquet(&t12, &m).unwrap());
    assert_eq!(ta.schema(), tb.schema());
    assert_eq!(ta.num_rows(), 1440);
    let p = col::<Float64Array>(&ta, "pressure_bar");
    let peak = p.values().iter().copied().fold(f64::MIN, f64::max);
    let want = r4[0]
        .resampled
        .pressure
        .iter()
        .copied()
        .fold(f64::MIN, f64::max)
        / 1e5;
    assert_eq!(peak.to_bits(), want.to_bits());
}

/// A campaign of 3 parts: merge's manifest counts files, failures and
/// cycles; a missing part and a part with another schema are named.
#[test]
fn merge_names_a_missing_or_different_part() {
    let e = engine("vaz2108.toml");
    let files = [
        root().join("data/vaz2108.csv"),
        root().join("tests/fixtures/measured/dropout_20cycles.csv"),
        root().join("data/vaz2108.csv"),
    ];
    let runs: Vec<Run> = files
        .iter()
        .map(|f| {
            run(
                &e,
                f,
                if f.ends_with("dropout_20cycles.csv") {
                    Some(2000.0)
                } else {
                    None
                },
            )
        })
        .collect();
    let m = meta("vaz2108.toml");
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let keys: [&[&str]; 3] = [&["a", "d"], &["b"], &["c"]];
    for (i, r) in runs.iter().enumerate() {
        let m = in_campaign(&m, i, keys[i]);
        let mut rows = records(&e, std::slice::from_ref(r));
        if i == 0 {
            rows.push(SummaryRecord {
                file: "bad.csv",
                error: Some("line 3: no number"),
                engine: e.name(),
                diagram_blake3: None,
                summary: None,
            });
        }
        write_part(
            d,
            Table::Summary,
            i,
            3,
            &summary_parquet(&rows, &m).unwrap(),
        )
        .unwrap();
        let cycles = schema::cycle_rows(&r.file, &r.resampled, r.analysis.summary.rpm);
        write_part(
            d,
            Table::Cycles,
            i,
            3,
            &cycles_parquet(&cycles, &m).unwrap(),
        )
        .unwrap();
    }
    let manifest = check_campaign(d, None).unwrap();
    assert_eq!(manifest.parts, 3);
    assert_eq!((manifest.files, manifest.failed), (4, 1));
    // One cycle each for the bundled diagram, 20 for the dropout file.
    assert_eq!((manifest.cycles, manifest.cycles_skipped), (22, 2));
    assert_eq!(manifest.tables, [Table::Summary, Table::Cycles]);
    assert_eq!(manifest.engine_blake3, m.engine_blake3);
    assert_eq!(manifest.list_blake3, list_blake3(&["a", "b", "c", "d"]));
    assert_eq!(manifest.options, m.options);
    assert_eq!(check_campaign(d, Some(3)).unwrap(), manifest);
    let written = write_manifest(d, &manifest).unwrap();
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(written).unwrap()).unwrap();
    assert_eq!(json["files"], 4);
    assert_eq!(json["failed"], 1);
    assert_eq!(json["tables"][1], "cycles/3");

    // --parts 4: part 3 is missing, and named.
    match check_campaign(d, Some(4)) {
        Err(TablesError::Counts {
            found: 3,
            expected: 4,
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
    // A traces part alone: the traces table's other parts are missing.
    let t = schema::trace_points(&runs[0].file, &runs[0].resampled);
    let mut w = stage_part(d, Table::Traces, 1, 3, &in_campaign(&m, 1, &["b"])).unwrap();
    w.write(&t).unwrap();
    commit_part(w).unwrap();
    let e1 = check_campaign(d, None).unwrap_err();
    assert!(
        e1.to_string().ends_with(
            "traces/part-00000-of-00003.parquet: missing (part 0 of 3 of the traces table)"
        ),
        "{e1}"
    );
    std::fs::remove_dir_all(d.join("traces")).unwrap();
    // A cycles part removed: named.
    let gone = d.join("cycles/part-00002-of-00003.parquet");
    let kept = std::fs::read(&gone).unwrap();
    std::fs::remove_file(&gone).unwrap();
    match check_campaign(d, None) {
        Err(TablesError::Missing {
            path,
            part: 2,
            parts: 3,
            table: Table::Cycles,
        }) => {
            assert_eq!(path, gone)
        }
        other => panic!("{other:?}"),
    }
    // In its place a summary part: another schema, named with what differs.
    let other = std::fs::read(d.join("summary/part-00002-of-00003.parquet")).unwrap();
    std::fs::write(&gone, other).unwrap();
    let err = check_campaign(d, None).unwrap_err().to_string();
    assert!(
        err.contains("cycles/part-00002-of-00003.parquet: the schema differs"),
        "{err}"
    );
    assert!(
        err.contains("`enginedyn.schema` is `summary/4` here"),
        "{err}"
    );
    std::fs::write(&gone, &kept).unwrap();
    // A part written for another engine.
    let mut other_engine = in_campaign(&m, 1, &["b"]);
    other_engine.engine_parsed_blake3 = "0".repeat(64);
    let rows = records(&e, std::slice::from_ref(&runs[1]));
    write_part(
        d,
        Table::Summary,
        1,
        3,
        &summary_parquet(&rows, &other_engine).unwrap(),
    )
    .unwrap();
    let err = check_campaign(d, None).unwrap_err().to_string();
    assert!(
        err.contains("summary/part-00001-of-00003.parquet: `engine.parsed_blake3` differs"),
        "{err}"
    );
    write_part(
        d,
        Table::Summary,
        1,
        3,
        &summary_parquet(&rows, &in_campaign(&m, 1, &["b"])).unwrap(),
    )
    .unwrap();
    // Parts of two counts side by side.
    write_part(
        d,
        Table::Summary,
        0,
        2,
        &summary_parquet(&rows, &m).unwrap(),
    )
    .unwrap();
    let err = check_campaign(d, None).unwrap_err().to_string();
    assert!(err.contains("part-00000-of-00002.parquet"), "{err}");
    assert!(err.contains("part-00000-of-00003.parquet"), "{err}");
    assert!(
        err.ends_with("parts of two campaigns in one folder"),
        "{err}"
    );
    std::fs::remove_file(d.join("summary/part-00000-of-00002.parquet")).unwrap();
    assert_eq!(check_campaign(d, None).unwrap(), manifest);
    // No cycles at all.
    std::fs::remove_dir_all(d.join("cycles")).unwrap();
    assert!(matches!(
        check_campaign(d, None),
        Err(TablesError::NoParts {
            table: Table::Cycles,
            ..
        })
    ));
}

/// A rerun writes the same bytes (no dates in a part).
#[test]
fn parts_are_byte_identical_on_a_rerun() {
    let e = engine("vaz2108.toml");
    let r = [run(&e, &root().join("data/vaz2108.csv"), None)];
    let m = meta("vaz2108.toml");
    let a = summary_parquet(&records(&e, &r), &m).unwrap();
    let b = summary_parquet(&records(&e, &r), &m).unwrap();
    assert_eq!(a, b);
}

/// The cost of the tables against the analysis (issue 28: writing
/// `summary` and `cycles` adds at most 5 % to a batch). Timing, so not run
/// by default: `cargo test --release -p enginedyn-tables --test parts --
/// --ignored --nocapture`.
#[test]
#[ignore]
fn parquet_time_against_the_analysis() {
    let e = engine("vaz2108.toml");
    let path = root().join("tests/fixtures/measured/dropout_20cycles.csv");
    let n = 1000;
    let t = std::time::Instant::now();
    let runs: Vec<Run> = (0..50).map(|_| run(&e, &path, Some(2000.0))).collect();
    let per_file = t.elapsed().as_secs_f64() / 50.0;
    let rows: Vec<SummaryRecord<'_>> = (0..n)
        .map(|k| {
            let r = &runs[k % runs.len()];
            SummaryRecord {
                file: &r.file,
                error: None,
                engine: e.name(),
                diagram_blake3: Some(&r.sha),
                summary: Some(&r.analysis.summary),
            }
        })
        .collect();
    let m = meta("vaz2108.toml");
    let t = std::time::Instant::now();
    let summary = summary_parquet(&rows, &m).unwrap();
    let cycles: Vec<_> = (0..n)
        .flat_map(|k| {
            let r = &runs[k % runs.len()];
            schema::cycle_rows(&r.file, &r.resampled, r.analysis.summary.rpm)
        })
        .collect();
    let cycles = cycles_parquet(&cycles, &m).unwrap();
    let write = t.elapsed().as_secs_f64();
    let batch = per_file * n as f64;
    println!(
        "{n} files (20 cycles each): analysis {:.1} ms a file, {:.2} s in all; summary + cycles parquet {:.1} ms ({} + {} bytes): {:.3} % of the analysis",
        per_file * 1e3,
        batch,
        write * 1e3,
        summary.len(),
        cycles.len(),
        100.0 * write / batch
    );
    assert!(write < 0.05 * batch, "{write} s against {batch} s");
}
