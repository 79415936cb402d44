//! Names that break tables, folders and spreadsheets (issue 29,
//! INTERFACE.md "Other outputs"): a CSV text cell never starts a formula
//! (numbers are never altered), control characters in a name print escaped
//! in text tables, and a run folder's name holds no control character and
//! nothing Windows refuses.

use enginedyn_tests::{binary, data};
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// Runs the binary in `cwd` (so that the files' names are the cells).
fn run_in(cwd: &Path, args: &[&str]) -> Output {
    let out = Command::new(binary())
        .current_dir(cwd)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run enginedyn");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    out
}

/// Copies of the bundled single-cylinder diagram under `names` in `dir`.
fn diagrams(dir: &Path, names: &[&str]) {
    let text = std::fs::read(data("single.csv")).unwrap();
    for n in names {
        std::fs::write(dir.join(n), &text).unwrap();
    }
}

/// The records of a CSV text (RFC 4180: quoted cells may hold commas,
/// doubled quotes and line breaks).
fn records(text: &str) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    let (mut row, mut cell) = (Vec::new(), String::new());
    let mut chars = text.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                cell.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => cell.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut cell)),
            (false, '\n') => {
                row.push(std::mem::take(&mut cell));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => cell.push(c),
        }
    }
    rows
}

fn as_str(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// Whether a cell would be evaluated by a spreadsheet.
fn formula(cell: &str) -> bool {
    cell.starts_with(['=', '+', '-', '@', '\t', '\r'])
}

const HOSTILE: [&str; 4] = [
    "=HYPERLINK(\"http:x\",\"y\").csv",
    "+cmd.csv",
    "@SUM(1).csv",
    "-2+3.csv",
];

/// summary.csv (written and printed with --csv) and sweep.csv: the file
/// cells get a leading `'`; the negative numbers stay numbers.
#[test]
fn csv_text_cells_never_start_a_formula() {
    let t = tempfile::tempdir().unwrap();
    diagrams(t.path(), &HOSTILE);
    let engine = data("single.toml");
    // `--` before the names: `-2+3.csv` is a file, not a flag.
    let batch = |how: &[&'static str]| -> Vec<String> {
        ["batch", "--engine", engine.as_str()]
            .iter()
            .chain(how)
            .chain(&["--"])
            .chain(&HOSTILE)
            .map(|s| s.to_string())
            .collect()
    };
    let out = run_in(t.path(), &as_str(&batch(&["--out", "out"])));
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let written = std::fs::read_to_string(t.path().join("out/summary.csv")).unwrap();
    let printed = run_in(t.path(), &as_str(&batch(&["--csv"])));
    assert_eq!(String::from_utf8_lossy(&printed.stdout), written);
    let rows = records(&written);
    assert_eq!(rows.len(), 1 + HOSTILE.len());
    let column = |k: &str| rows[0].iter().position(|h| h == k).unwrap();
    let (min, notes) = (column("torque_min_nm"), column("notes"));
    for (row, name) in rows[1..].iter().zip(HOSTILE) {
        assert_eq!(row[0], format!("'{name}"));
        // Numbers are numbers, the negative ones too.
        let x: f64 = row[min].parse().expect("torque_min_nm a number");
        assert!(x < 0.0 && row[min].starts_with('-'), "{}", row[min]);
        assert!(!row[notes].is_empty());
        for cell in row {
            assert!(
                !formula(cell) || cell.parse::<f64>().is_ok(),
                "{name}: {cell:?}"
            );
        }
    }
    // sweep.csv: the diagram's name is its file cell.
    let sweep = run_in(
        t.path(),
        &[
            "sweep",
            "--engine",
            &engine,
            "--diagram",
            HOSTILE[0],
            "--rpm",
            "1000:2000:1000",
            "--csv",
        ],
    );
    let rows = records(&String::from_utf8_lossy(&sweep.stdout));
    assert_eq!(rows.len(), 3, "{rows:?}");
    for row in &rows[1..] {
        assert_eq!(row[0], format!("'{}", HOSTILE[0]));
    }
}

/// A name with a line break stays on its row of the printed table, escaped,
/// and the columns keep their place.
#[test]
fn control_characters_print_escaped_in_tables() {
    let t = tempfile::tempdir().unwrap();
    let names = ["new\nline.csv", "tab\there.csv"];
    diagrams(t.path(), &names);
    let engine = data("single.toml");
    let out = run_in(
        t.path(),
        &["batch", "--engine", &engine, names[0], names[1]],
    );
    assert_eq!(out.status.code(), Some(0));
    let table = String::from_utf8_lossy(&out.stdout).into_owned();
    let rows: Vec<&str> = table
        .lines()
        .filter(|l| l.starts_with("new") || l.starts_with("tab") || l.starts_with("line"))
        .collect();
    assert_eq!(rows.len(), 2, "{table}");
    assert!(rows[0].starts_with("new\\nline.csv "), "{table}");
    assert!(rows[1].starts_with("tab\\there.csv "), "{table}");
    assert_eq!(rows[0].chars().count(), rows[1].chars().count(), "{table}");
    assert!(!table.contains('\t'), "{table}");
    // The heading of a sweep names its diagram on one line too.
    let sweep = run_in(
        t.path(),
        &[
            "sweep",
            "--engine",
            &engine,
            "--diagram",
            names[0],
            "--rpm",
            "1000:2000:1000",
        ],
    );
    let text = String::from_utf8_lossy(&sweep.stdout);
    assert!(text.contains("diagram: new\\nline.csv\n"), "{text}");
}

/// Run folders keep their number; control characters and `<>:"/\|?*`
/// become `_`; index.html links the folder as written and shows the file's
/// own name, escaped.
#[test]
fn run_folders_are_names_every_system_holds() {
    let t = tempfile::tempdir().unwrap();
    let names = [
        "new\nline.csv",
        "<img src=x onerror=alert(1)>.csv",
        "a:b|c?d*\"e\\f.csv",
    ];
    diagrams(t.path(), &names);
    let engine = data("single.toml");
    let mut args = vec!["batch", "--engine", engine.as_str(), "--detail"];
    args.extend(names);
    args.extend(["--out", "out"]);
    let out = run_in(t.path(), &args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let dir = t.path().join("out");
    let mut listed: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    listed.sort();
    let folders = [
        "0001_new_line",
        "0002__img src=x onerror=alert(1)_",
        "0003_a_b_c_d__e_f",
    ];
    assert_eq!(
        listed,
        [
            &[enginedyn_report::MANIFEST][..],
            &folders[..],
            &["index.html", "summary.csv"]
        ]
        .concat()
    );
    for f in folders {
        assert!(dir.join(f).join("summary.json").is_file(), "{f}");
    }
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(
        html.contains("href=\"0002__img%20src%3Dx%20onerror%3Dalert%281%29_/report.html\""),
        "{html}"
    );
    assert!(
        html.contains("<td>&lt;img src=x onerror=alert(1)&gt;.csv</td>"),
        "{html}"
    );
    assert!(!html.contains("<img"), "{html}");
    assert!(
        html.contains("href=\"0001_new_line/report.html\""),
        "{html}"
    );
}
