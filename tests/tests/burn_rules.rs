//! Issues 41, 43 and 44: the burn points from the command line: a design
//! trace is read back with its own γ model and a window that holds its
//! burn, SOC and EOC are the burn's own ends, noise that hides the burn
//! gives null burn points with a warning, and the filter's cost is
//! bounded before any work.

use enginedyn_synth::{DEFAULT_A, Wiebe};
use enginedyn_tests::{data, data_rows, run};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The petrol template with `edit` applied to its text, in `dir`.
fn template(dir: &std::path::Path, name: &str, edit: &[(&str, &str)]) -> String {
    enginedyn_tests::edited_template(dir, &["--combustion", "petrol"], name, edit)
}

/// Writes `text` as `name` in `dir` and runs the bundled engine on it
/// with `--json` and `flags`: the summary, and the output (exit 0).
fn vaz_json(
    dir: &std::path::Path,
    name: &str,
    text: String,
    flags: &[&str],
) -> (serde_json::Value, std::process::Output) {
    let f = dir.join(name);
    std::fs::write(&f, text).unwrap();
    let engine = data("vaz2108.toml");
    let mut args = vec![
        "run",
        "--engine",
        &engine,
        "--diagram",
        f.to_str().unwrap(),
        "--json",
    ];
    args.extend(flags);
    let o = run(&args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    (serde_json::from_slice(&o.stdout).unwrap(), o)
}

fn json(args: &[&str]) -> serde_json::Value {
    let o = run(args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// A diagram-free run analyses the design trace with the engine file's γ
/// model: with `gamma = "brunt"` the burn points come back as the law's
/// (CA50 8.81° for a law of 8° when it was read with 1.32), and SOC and
/// EOC lie within a degree of the law's 0.5 % and 99.5 % points (−84.9°
/// and 117° before: the window's edges).
#[test]
fn a_design_trace_round_trips_with_its_own_gamma() {
    let t = tempfile::tempdir().unwrap();
    let law = Wiebe::from_ca50(8.0, 20.0, 2.0, DEFAULT_A).unwrap();
    for (name, edit) in [
        ("constant.toml", vec![]),
        ("brunt.toml", vec![("# gamma = 1.32", "gamma = \"brunt\"")]),
    ] {
        let engine = template(t.path(), name, &edit);
        let s = json(&["run", "--engine", &engine, "--json"]);
        let num = |k: &str| {
            s[k].as_f64()
                .unwrap_or_else(|| panic!("{name} {k}: {}", s[k]))
        };
        for (k, x) in [("ca10_deg", 0.1), ("ca50_deg", 0.5), ("ca90_deg", 0.9)] {
            let want = law.angle_of(x);
            assert!(
                (num(k) - want).abs() < 0.05,
                "{name} {k}: {} for {want}",
                num(k)
            );
        }
        let (soc, eoc) = (law.angle_of(0.005), law.angle_of(0.995));
        assert!(
            (num("soc_deg") - soc).abs() < 1.0,
            "{name}: SOC {} for {soc}",
            num("soc_deg")
        );
        assert!(
            (num("eoc_deg") - eoc).abs() < 1.0,
            "{name}: EOC {} for {eoc}",
            num("eoc_deg")
        );
        let brunt = s["models"]["gamma"].as_str().unwrap().starts_with("brunt");
        assert_eq!(brunt, name == "brunt.toml", "{}", s["models"]["gamma"]);
    }
}

/// The bundled trace with 5 bar of noise: no CA50 (it was −74° with only
/// a below-zero warning), a warning naming the noise level.
#[test]
fn heavy_noise_gives_null_burn_points_with_a_warning() {
    let t = tempfile::tempdir().unwrap();
    let mut s: u64 = 7;
    let mut u = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let mut text = String::from("crank_deg,pressure_bar\n");
    for (a, p) in data_rows("vaz2108.csv") {
        let e = 5.0 * (-2.0 * u().ln()).sqrt() * (2.0 * std::f64::consts::PI * u()).cos();
        text.push_str(&format!("{a},{}\n", p + e));
    }
    let (s, o) = vaz_json(t.path(), "noisy.csv", text, &["--no-compression-check"]);
    assert!(s["ca50_deg"].is_null(), "CA50 {}", s["ca50_deg"]);
    let err = stderr(&o);
    assert!(
        err.contains("warning: the noise of the mean trace") && err.contains("bar RMS"),
        "{err}"
    );
}

/// The filter's cost is bounded before any work: SG 20° at a 0.001° step
/// (20,001 weights a point, 39 s a cycle) is a usage error naming the
/// flags, and so is a window with too few grid points.
#[test]
fn the_filter_and_the_window_are_checked_against_the_step() {
    let start = std::time::Instant::now();
    let o = run(&["run", "--step", "0.001", "--smooth", "SG:20"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--smooth SG:20"), "{}", stderr(&o));
    assert!(start.elapsed().as_secs_f64() < 5.0);
    let o = run(&["run", "--burn-window", "0:10", "--step", "5"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("burn window"), "{}", stderr(&o));
}

/// `--burn-points 3,7,33`: the levels reach `summary.csv` and `sweep.csv`
/// as `caK_deg` columns, with numbers (they reached `--json` and the run
/// folders only, and the tables kept ca5–ca90, all empty).
#[test]
fn every_table_carries_the_levels_asked_for() {
    let t = tempfile::tempdir().unwrap();
    let read = |p: &std::path::Path| {
        let mut r = csv::Reader::from_path(p).unwrap();
        let head: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
        let row: Vec<String> = r
            .records()
            .next()
            .unwrap()
            .unwrap()
            .iter()
            .map(String::from)
            .collect();
        (head, row)
    };
    let check = |p: &std::path::Path| {
        let (head, row) = read(p);
        let at = |k: &str| {
            let i = head
                .iter()
                .position(|h| h == k)
                .unwrap_or_else(|| panic!("no {k} in {head:?}"));
            row[i]
                .parse::<f64>()
                .unwrap_or_else(|_| panic!("{k}: `{}`", row[i]))
        };
        let (a, b, c) = (at("ca3_deg"), at("ca7_deg"), at("ca33_deg"));
        assert!(a < b && b < c && c < at("ca50_deg"), "{a} {b} {c}");
    };
    let out = t.path().join("batch");
    let o = run(&[
        "batch",
        "--engine",
        &data("vaz2108.toml"),
        "--burn-points",
        "3,7,33,50",
        &data("vaz2108.csv"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    check(&out.join("summary.csv"));
    let out = t.path().join("sweep");
    let o = run(&[
        "sweep",
        "--engine",
        &data("vaz2108.toml"),
        "--burn-points",
        "3,7,33,50",
        "--rpm",
        "2000:4000:1000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    check(&out.join("sweep.csv"));
}

/// The lists of a Parquet part's list column, row by row.
fn lists(path: &std::path::Path, name: &str) -> Vec<Option<Vec<f64>>> {
    use arrow_array::{Array, Float64Array, ListArray};
    let b = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(
        std::fs::File::open(path).unwrap(),
    )
    .unwrap();
    let mut out = Vec::new();
    for batch in b.build().unwrap() {
        let batch = batch.unwrap();
        let c = batch
            .column_by_name(name)
            .unwrap_or_else(|| panic!("no {name}"));
        let c = c.as_any().downcast_ref::<ListArray>().unwrap();
        for k in 0..c.len() {
            out.push(c.is_valid(k).then(|| {
                let v = c.value(k);
                let v = v.as_any().downcast_ref::<Float64Array>().unwrap();
                v.values().to_vec()
            }));
        }
    }
    out
}

/// `batch --parquet --burn-points 3,7,33`: the summary and cycles parts
/// carry every level asked for and its angle as list columns
/// (`burn_levels_pct`, `burn_levels_deg`: `summary/3`, `cycles/3`); they
/// kept ca5–ca90 only, all empty.
#[test]
fn parquet_parts_carry_the_levels_asked_for() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("pq");
    let o = run(&[
        "batch",
        "--engine",
        &data("vaz2108.toml"),
        "--burn-points",
        "3,7,33",
        &data("vaz2108.csv"),
        "--parquet",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let j = json(&["run", "--burn-points", "3,7,33", "--json"]);
    for table in ["summary", "cycles"] {
        let p = out.join(table).join("part-00000-of-00001.parquet");
        let pct = lists(&p, "burn_levels_pct");
        let deg = lists(&p, "burn_levels_deg");
        assert_eq!(pct[0].as_deref(), Some(&[3.0, 7.0, 33.0][..]), "{table}");
        let deg = deg[0].clone().unwrap();
        assert_eq!(deg.len(), 3);
        if table == "summary" {
            // The mean trace's, as `run` gives them (to rounding: batch
            // averages its cycles in its own order).
            for (k, key) in ["ca3_deg", "ca7_deg", "ca33_deg"].iter().enumerate() {
                let want = j[key].as_f64().unwrap();
                assert!((deg[k] - want).abs() < 1e-9, "{key}: {} for {want}", deg[k]);
            }
        }
        assert!(deg[0] < deg[1] && deg[1] < deg[2], "{deg:?}");
    }
}

/// Peak pressure, always (INTERFACE "Combustion"): `summary.json` has the
/// mean trace's `p_max_bar` and `p_max_angle_deg` (they had to be
/// back-calculated from `gas_force_max_n`), and every row of `sweep.csv`.
/// Against the file's own largest sample: within 0.1 % and half a step.
#[test]
fn the_peak_pressure_is_reported() {
    let rows = data_rows("vaz2108.csv");
    let (a, p) = rows
        .iter()
        .map(|(a, p)| (a.parse::<f64>().unwrap(), *p))
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .unwrap();
    let s = json(&["run", "--json"]);
    let got = s["p_max_bar"].as_f64().unwrap();
    assert!((got / p - 1.0).abs() < 1e-3, "{got} for {p}");
    let at = s["p_max_angle_deg"].as_f64().unwrap();
    assert!((at - a).abs() <= 0.5, "{at} for {a}");
    let t = tempfile::tempdir().unwrap();
    let o = run(&[
        "sweep",
        "--engine",
        &data("vaz2108.toml"),
        "--rpm",
        "2000:4000:1000",
        "--out",
        t.path().to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mut r = csv::Reader::from_path(t.path().join("sweep.csv")).unwrap();
    let i = r
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == "p_max_bar")
        .unwrap();
    let n = r
        .records()
        .map(|rec| rec.unwrap()[i].parse::<f64>().unwrap())
        .inspect(|x| assert!((x - got).abs() < 1e-9))
        .count();
    assert_eq!(n, 3);
}

/// A synthesised diagram's TDC is never questioned (issue 41.8), read
/// back from `synth --out` or made in memory: a late design burn (CA50
/// 60°, the latest a design may have, 10–90 in 90°, EVO 200°) runs, its
/// window taken from its law, and gives back the law's CA90 (106.21°;
/// read as a file with the default window, which stops at 120° where 95 %
/// has burnt, a warning names `--burn-window`); a light load (0.5 bar IMEP) gets
/// no "add it to --tdc-deg".
#[test]
fn a_synthesised_diagram_keeps_its_tdc_and_its_whole_burn() {
    let t = tempfile::tempdir().unwrap();
    let late = template(
        t.path(),
        "late.toml",
        &[
            ("ca50_deg = 8.0", "ca50_deg = 60.0"),
            ("duration_10_90_deg = 20.0", "duration_10_90_deg = 90.0"),
            ("imep_bar = 10.0", "imep_bar = 6.0"),
            ("# evo_deg = 130.0", "evo_deg = 200.0"),
        ],
    );
    let s = json(&["run", "--engine", &late, "--json"]);
    let law = Wiebe::from_ca50(60.0, 90.0, 2.0, DEFAULT_A).unwrap();
    let ca90 = s["ca90_deg"].as_f64().unwrap();
    // Within 0.1° of a 90° burn (the window ends at 180°, past its 99.9 %).
    assert!((ca90 - law.angle_of(0.9)).abs() < 0.1, "CA90 {ca90}");
    // Written by synth and read back as a file: the same.
    let csv = t.path().join("late.csv");
    let o = run(&["synth", "--engine", &late, "--out", csv.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = run(&[
        "run",
        "--engine",
        &late,
        "--diagram",
        csv.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // Read as a file, with the default window: EOC on its edge is said,
    // naming the flag (it was silent, the heat 11 % low).
    assert!(
        stderr(&o).contains("runs past the burn window's end (120°)")
            && stderr(&o).contains("--burn-window"),
        "{}",
        stderr(&o)
    );
    // A light load: no TDC advice for a TDC exact by construction.
    let light = template(t.path(), "light.toml", &[]);
    let csv = t.path().join("light.csv");
    let o = run(&[
        "synth",
        "--engine",
        &light,
        "--imep",
        "0.5",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = run(&[
        "run",
        "--engine",
        &light,
        "--diagram",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("--tdc-deg"), "{}", stderr(&o));
}

/// `models.interpolation` says what every cycle took: where `auto` chose
/// the spline for some cycles and pchip for others, each with its count
/// (it named the first trace's choice alone).
#[test]
fn the_interpolation_counts_each_choice() {
    let t = tempfile::tempdir().unwrap();
    let rows = data_rows("vaz2108.csv");
    let mut text = String::from("cycle,crank_deg,pressure_bar\n");
    for cycle in 1..=6 {
        for (k, (a, p)) in rows.iter().enumerate() {
            // Cycles 5 and 6: a sharp step in the gas exchange, which the
            // spline overshoots (auto takes pchip there).
            let step = if cycle > 4 && (400..440).contains(&k) {
                8.0
            } else {
                0.0
            };
            text.push_str(&format!("{cycle},{a},{}\n", p + step));
        }
    }
    let (s, o) = vaz_json(t.path(), "mixed.csv", text, &["--no-compression-check"]);
    assert_eq!(
        s["models"]["interpolation"],
        "spline (4 traces), pchip (2)",
        "{}",
        stderr(&o)
    );
}

/// `ca50_imep.svg` draws each cycle as a marker (it drew a short dash,
/// its legend a line), with the mean and the ±σ box named in the legend.
#[test]
fn the_ca50_imep_scatter_has_a_marker_a_cycle() {
    let t = tempfile::tempdir().unwrap();
    let rows = data_rows("vaz2108.csv");
    let mut text = String::from("cycle,crank_deg,pressure_bar\n");
    for cycle in 1..=7 {
        let scale = 1.0 + 0.01 * cycle as f64;
        for (a, p) in &rows {
            text.push_str(&format!("{cycle},{a},{}\n", p * scale));
        }
    }
    let f = t.path().join("seven.csv");
    std::fs::write(&f, text).unwrap();
    let out = t.path().join("r");
    let o = run(&[
        "run",
        "--engine",
        &data("vaz2108.toml"),
        "--diagram",
        f.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let svg = std::fs::read_to_string(out.join("ca50_imep.svg")).unwrap();
    // Seven cycles and one legend key.
    assert_eq!(svg.matches("<circle").count(), 7 + 1, "{svg}");
    assert!(svg.contains("±σ box"));
}

/// `--knock` on the bundled trace with a damped 7 kHz, 3 bar oscillation
/// added after the peak (at 4900 rpm, 0.5° is 2.9 samples a period of the
/// band's 20 kHz edge): MAPO within 10 % of the oscillation's first crest,
/// the cycle counted as knocking, and `knock.svg` draws its band-passed
/// pressure beside the threshold. Without `--knock` nothing of it.
#[test]
fn knock_is_measured_and_drawn_on_request() {
    let t = tempfile::tempdir().unwrap();
    let rpm = 4900.0;
    let (amp, tau, f) = (3.0, 1.5e-3, 7e3);
    let crest = (0..20_000)
        .map(|j| {
            let t = j as f64 * 1e-8;
            amp * (-t / tau).exp() * (2.0 * std::f64::consts::PI * f * t).sin()
        })
        .fold(0.0f64, f64::max);
    let mut text = String::from("crank_deg,pressure_bar\n");
    for (a, p) in data_rows("vaz2108.csv") {
        let deg: f64 = a.parse().unwrap();
        let s = (deg - 20.0) / (6.0 * rpm);
        let osc = if (0.0..0.02).contains(&s) {
            amp * (-s / tau).exp() * (2.0 * std::f64::consts::PI * f * s).sin()
        } else {
            0.0
        };
        text.push_str(&format!("{a},{}\n", p + osc));
    }
    let file = t.path().join("knocking.csv");
    std::fs::write(&file, text).unwrap();
    let out = t.path().join("r");
    let o = run(&[
        "run",
        "--engine",
        &data("vaz2108.toml"),
        "--diagram",
        file.to_str().unwrap(),
        "--knock",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let mapo = s["mapo_max_bar"].as_f64().unwrap();
    assert!((mapo / crest - 1.0).abs() < 0.1, "MAPO {mapo} for {crest}");
    assert_eq!(s["knock_share"].as_f64(), Some(1.0));
    assert!(
        stderr(&o).contains("knock in 1 of 1 cycles"),
        "{}",
        stderr(&o)
    );
    let svg = std::fs::read_to_string(out.join("knock.svg")).unwrap();
    assert!(
        svg.contains("threshold 1 bar") && svg.contains("MAPO"),
        "{svg}"
    );
    // Off by default: no figures, no chart.
    let plain = t.path().join("plain");
    let o = run(&[
        "run",
        "--engine",
        &data("vaz2108.toml"),
        "--diagram",
        file.to_str().unwrap(),
        "--json",
        "--out",
        plain.to_str().unwrap(),
    ]);
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(s["mapo_max_bar"].is_null());
    assert!(!plain.join("knock.svg").exists());
}
