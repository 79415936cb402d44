//! Issue 30, items 7 and 12: `summary.json`'s `inputs` (what the figures
//! came from: the engine and diagram files, their BLAKE3 (as `b3sum` prints it), the version;
//! shown in report.html under "Data and method"; no date, so a rerun is
//! byte-identical), `batch` on a folder taking every kind the reader reads
//! with a note on what it passed over, and `batch`/`sweep --json`.

use enginedyn_tests::{binary, data, ok_json};
use std::path::Path;
use std::process::Output;

/// The BLAKE3 of a file, as `b3sum` prints it (the reference crate, not
/// enginedyn's reading pass).
fn b3sum(path: impl AsRef<Path>) -> String {
    blake3::hash(&std::fs::read(path).unwrap())
        .to_hex()
        .to_string()
}

fn run(args: &[&str]) -> Output {
    std::process::Command::new(binary())
        .args(args)
        .output()
        .expect("run enginedyn")
}

const KEYS: [&str; 5] = [
    "engine_file",
    "engine_blake3",
    "diagram_files",
    "diagram_blake3",
    "enginedyn_version",
];

/// `inputs` is there, right after `notes`, with these files and hashes.
fn check_inputs(summary: &serde_json::Value, engine: (&str, &str), diagrams: &[(&str, &str)]) {
    let o = summary.as_object().expect("an object");
    let keys: Vec<&String> = o.keys().collect();
    let notes = keys.iter().position(|k| *k == "notes").expect("notes");
    assert_eq!(keys[notes + 1], "inputs", "{keys:?}");
    let inputs = &summary["inputs"];
    let got: Vec<&String> = inputs.as_object().unwrap().keys().collect();
    assert_eq!(got, KEYS, "{inputs}");
    assert_eq!(inputs["engine_file"], engine.0);
    assert_eq!(inputs["engine_blake3"], engine.1);
    let files: Vec<&str> = diagrams.iter().map(|d| d.0).collect();
    let hashes: Vec<&str> = diagrams.iter().map(|d| d.1).collect();
    assert_eq!(inputs["diagram_files"], serde_json::json!(files));
    assert_eq!(inputs["diagram_blake3"], serde_json::json!(hashes));
    assert_eq!(inputs["enginedyn_version"], env!("CARGO_PKG_VERSION"));
}

/// The bundled example: "bundled", with the hashes of the bundled texts
/// (the files in data/ are what the binary carries).
#[test]
fn the_bundled_example_says_so() {
    let j = ok_json(&["run", "--json"]);
    check_inputs(
        &j,
        ("bundled", &b3sum(data("vaz2108.toml"))),
        &[("bundled", &b3sum(data("vaz2108.csv")))],
    );
}

/// `run --out`: summary.json and report.html say what they came from; a
/// rerun writes every file byte for byte the same.
#[test]
fn run_records_its_inputs_and_a_rerun_is_byte_identical() {
    let t = tempfile::tempdir().unwrap();
    let d = t.path().join("out");
    let (engine, diagram) = (data("single.toml"), data("single.csv"));
    let args = [
        "run",
        "--engine",
        &engine,
        "--diagram",
        &diagram,
        "--out",
        d.to_str().unwrap(),
    ];
    let first = run(&args);
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("summary.json")).unwrap()).unwrap();
    let (eh, dh) = (b3sum(&engine), b3sum(&diagram));
    check_inputs(&summary, (&engine, &eh), &[(&diagram, &dh)]);
    let html = std::fs::read_to_string(d.join("report.html")).unwrap();
    let section = html
        .split("<h2>Data and method</h2>")
        .nth(1)
        .expect("a Data and method heading");
    let section = section.split("<h2>").next().unwrap();
    for text in [
        engine.as_str(),
        &eh,
        diagram.as_str(),
        &dh,
        env!("CARGO_PKG_VERSION"),
        "kinematics",
        "integration",
    ] {
        assert!(section.contains(text), "{text} not in: {section}");
    }
    let contents = |dir: &Path| {
        let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| {
                let e = e.unwrap();
                (
                    e.file_name().to_string_lossy().into_owned(),
                    std::fs::read(e.path()).unwrap(),
                )
            })
            .collect();
        v.sort();
        v
    };
    let before = contents(&d);
    let again = run(&args);
    assert!(again.status.success());
    let after = contents(&d);
    assert_eq!(before.len(), after.len());
    for ((name, a), (_, b)) in before.iter().zip(&after) {
        assert!(a == b, "{name} differs on a rerun");
    }
    // --json prints the same object the folder holds.
    let j = ok_json(&["run", "--engine", &engine, "--diagram", &diagram, "--json"]);
    assert_eq!(j, summary);
}

/// `batch --detail`'s run folders and `batch --json`'s objects carry
/// `inputs`; a failed file is its object with `file` and `error`;
/// summary.csv gets no new columns.
#[test]
fn batch_records_each_files_inputs() {
    let t = tempfile::tempdir().unwrap();
    let d = t.path().join("out");
    let engine = data("single.toml");
    let good = data("single.csv");
    let missing = t.path().join("missing.csv");
    let missing = missing.to_str().unwrap();
    let out = run(&[
        "batch",
        "--engine",
        &engine,
        &good,
        missing,
        "--out",
        d.to_str().unwrap(),
        "--detail",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON alone");
    let rows = rows.as_array().expect("an array");
    assert_eq!(rows.len(), 2);
    let (eh, gh) = (b3sum(&engine), b3sum(&good));
    assert_eq!(rows[0]["file"], good.as_str());
    assert!(rows[0]["error"].is_null());
    let keys: Vec<&String> = rows[0].as_object().unwrap().keys().collect();
    assert_eq!(keys[..3], ["file", "error", "rpm"]);
    check_inputs(&rows[0], (&engine, &eh), &[(&good, &gh)]);
    assert_eq!(rows[1]["file"], missing);
    assert!(
        rows[1]["error"].as_str().unwrap().contains("cannot open"),
        "{}",
        rows[1]
    );
    let folder: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("0001_single/summary.json")).unwrap())
            .unwrap();
    check_inputs(&folder, (&engine, &eh), &[(&good, &gh)]);
    // The folder's summary.json is the --json object without file and error.
    let mut row = rows[0].as_object().unwrap().clone();
    row.remove("file");
    row.remove("error");
    assert_eq!(serde_json::Value::Object(row), folder);
    let csv = std::fs::read_to_string(d.join("summary.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        !header.contains("inputs") && !header.contains("blake3"),
        "{header}"
    );
}

/// A folder gives every file of a kind the reader reads, whatever the
/// case of its extension, and a note counts what it passed over; the JSON
/// alone is on standard output.
#[test]
fn batch_on_a_folder_takes_every_kind_and_says_what_it_passed_over() {
    let t = tempfile::tempdir().unwrap();
    let folder = t.path().join("campaign");
    std::fs::create_dir(&folder).unwrap();
    let diagram = std::fs::read(data("single.csv")).unwrap();
    for name in ["a.CSV", "b.txt", "c.Dat", "d.tsv"] {
        std::fs::write(folder.join(name), &diagram).unwrap();
    }
    std::fs::write(folder.join("engine.toml"), "x").unwrap();
    std::fs::write(folder.join("README.md"), "x").unwrap();
    std::fs::create_dir(folder.join("old")).unwrap();
    let out = run(&[
        "batch",
        "--engine",
        &data("single.toml"),
        folder.to_str().unwrap(),
        "--json",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON alone");
    let files: Vec<String> = rows
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            assert!(r["error"].is_null(), "{r}");
            let f = r["file"].as_str().unwrap();
            Path::new(f)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    assert_eq!(files, ["a.CSV", "b.txt", "c.Dat", "d.tsv"]);
    let imep: Vec<f64> = rows
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["imep_bar"].as_f64().unwrap())
        .collect();
    assert!(
        imep.iter().all(|x| (x - imep[0]).abs() <= 1e-12 * imep[0]),
        "{imep:?}"
    );
    let note = err
        .lines()
        .find(|l| l.contains("passed over"))
        .unwrap_or_else(|| panic!("no note: {err}"));
    assert!(
        note.starts_with("note: 2 files of other kinds passed over in ")
            && note.contains("README.md, engine.toml"),
        "{note}"
    );
    // Without --json, the readable table, as before.
    let table = run(&[
        "batch",
        "--engine",
        &data("single.toml"),
        folder.to_str().unwrap(),
    ]);
    assert!(table.status.success());
    assert!(serde_json::from_slice::<serde_json::Value>(&table.stdout).is_err());
}

/// `sweep --json`: the per-speed summary objects, each with its inputs.
#[test]
fn sweep_prints_its_summaries_as_json() {
    let engine = data("single.toml");
    let out = run(&[
        "sweep",
        "--engine",
        &engine,
        "--rpm",
        "1000:3000:1000",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON alone");
    let rows = rows.as_array().expect("an array");
    let rpm: Vec<f64> = rows.iter().map(|r| r["rpm"].as_f64().unwrap()).collect();
    assert_eq!(rpm.len(), 3);
    for (got, want) in rpm.iter().zip([1000.0, 2000.0, 3000.0]) {
        assert!((got - want).abs() < 1e-9, "{rpm:?}");
    }
    // The engine file's `diagram` key, resolved beside it.
    let diagram = Path::new(&engine).with_file_name("single.csv");
    let diagram = diagram.to_str().unwrap();
    let (eh, dh) = (b3sum(&engine), b3sum(diagram));
    for r in rows {
        check_inputs(r, (&engine, &eh), &[(diagram, &dh)]);
    }
}
