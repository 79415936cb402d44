//! Spreadsheets that cannot fool or hold the reader (issue 29;
//! INTERFACE.md, "Hostile input" and "Bounds"): a damaged .xls prints no
//! panic, date-formatted cells in an angle or pressure column are errors
//! naming the cell, formulas never calculated and error cells say what
//! they are, and a ZIP bomb of empty rows neither holds the worker nor
//! hides the diagram before it. The workbooks are written here, at test
//! time (an .xlsx is a ZIP of XML parts), and run on the binary.

use enginedyn_tests::{binary, data};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What one run of the binary did.
struct Ran {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    took: Duration,
}

/// Runs the binary with `args` (no `RUST_BACKTRACE` in its environment),
/// killed after `limit`; asserts that no panic text reached standard error.
fn run(args: &[&str], limit: Duration) -> Ran {
    use std::io::Read as _;
    // Built (or found up to date) before the clock starts.
    let bin = binary();
    let started = Instant::now();
    let mut child = Command::new(bin)
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start enginedyn");
    let drain = |mut r: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            String::from_utf8_lossy(&v).into_owned()
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} did not finish within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let ran = Ran {
        code: status.code(),
        took: started.elapsed(),
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    };
    for panic_text in ["panicked", "RUST_BACKTRACE", "stack backtrace"] {
        assert!(
            !ran.stderr.contains(panic_text),
            "{args:?}: panic text on stderr: {}",
            ran.stderr
        );
    }
    ran
}

const MINUTE: Duration = Duration::from_secs(60);

/// `run --engine single.toml --diagram FILE --json`.
fn run_single(file: &Path, limit: Duration) -> Ran {
    run(
        &[
            "run",
            "--engine",
            &data("single.toml"),
            "--diagram",
            file.to_str().unwrap(),
            "--json",
        ],
        limit,
    )
}

/// The IMEP (bar) a successful run printed.
fn imep(r: &Ran) -> f64 {
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let j: serde_json::Value = serde_json::from_str(&r.stdout).expect("JSON on stdout");
    j["imep_bar"].as_f64().expect("imep_bar")
}

/// The notes a successful run printed.
fn notes(r: &Ran) -> Vec<String> {
    let j: serde_json::Value = serde_json::from_str(&r.stdout).expect("JSON on stdout");
    j["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap().to_string())
        .collect()
}

/// The bundled diagram's IMEP, read from its CSV.
fn csv_imep() -> f64 {
    imep(&run_single(Path::new(&data("single.csv")), MINUTE))
}

/// The bundled single-cylinder diagram's rows, as the CSV writes them:
/// (angle °, pressure bar).
fn single() -> Vec<(String, String)> {
    std::fs::read_to_string(data("single.csv"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("crank_deg"))
        .map(|l| {
            let (a, p) = l.split_once(',').unwrap();
            (a.to_string(), p.to_string())
        })
        .collect()
}

/// A number cell (`style`: 0 plain, 1 a date format, 2 a time format).
fn num(r#ref: &str, v: &str, style: u8) -> String {
    if style == 0 {
        format!(r#"<c r="{ref}"><v>{v}</v></c>"#)
    } else {
        format!(r#"<c r="{ref}" s="{style}"><v>{v}</v></c>"#)
    }
}

/// A text cell.
fn text(r#ref: &str, t: &str) -> String {
    format!(r#"<c r="{ref}" t="inlineStr"><is><t>{t}</t></is></c>"#)
}

/// Row `r` of cells.
fn row(r: usize, cells: &[String]) -> String {
    format!(r#"<row r="{r}">{}</row>"#, cells.concat())
}

/// The speed line and header, then the diagram from sheet row 3 on, each
/// row's cells from `cells(sheet row, angle, pressure)`.
fn diagram_sheet(mut cells: impl FnMut(usize, &str, &str) -> Vec<String>) -> String {
    let mut s = row(1, &[text("A1", "# rpm = 3600")]);
    s += &row(2, &[text("A2", "crank_deg"), text("B2", "pressure_bar")]);
    for (k, (a, p)) in single().iter().enumerate() {
        let r = k + 3;
        s += &row(r, &cells(r, a, p));
    }
    s
}

/// The diagram's plain rows.
fn plain(r: usize, a: &str, p: &str) -> Vec<String> {
    vec![num(&format!("A{r}"), a, 0), num(&format!("B{r}"), p, 0)]
}

const NS: &str = "http://schemas.openxmlformats.org/spreadsheetml/2006/main";
const REL: &str = "http://schemas.openxmlformats.org/officeDocument/2006/relationships";

/// Writes an .xlsx of one sheet to `path`: the workbook's parts, then the
/// sheet's XML, whose `<sheetData>` rows `rows` writes as the part is
/// deflated (a bomb never held whole).
fn xlsx(path: &Path, rows: impl FnOnce(&mut dyn Write)) {
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .large_file(true);
    let mut z = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    let parts = [
        (
            "[Content_Types].xml",
            r#"<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml"/><Override PartName="/xl/worksheets/sheet1.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.worksheet+xml"/><Override PartName="/xl/styles.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.styles+xml"/></Types>"#.to_string(),
        ),
        (
            "_rels/.rels",
            format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{REL}/officeDocument" Target="xl/workbook.xml"/></Relationships>"#
            ),
        ),
        (
            "xl/workbook.xml",
            format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="{NS}" xmlns:r="{REL}"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#
            ),
        ),
        (
            "xl/_rels/workbook.xml.rels",
            format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{REL}/worksheet" Target="worksheets/sheet1.xml"/><Relationship Id="rId2" Type="{REL}/styles" Target="styles.xml"/></Relationships>"#
            ),
        ),
        (
            // Styles 1 and 2: Excel's built-in date (m/d/yyyy) and time
            // (h:mm:ss) formats.
            "xl/styles.xml",
            format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><styleSheet xmlns="{NS}"><fonts count="1"><font/></fonts><fills count="1"><fill/></fills><borders count="1"><border/></borders><cellStyleXfs count="1"><xf/></cellStyleXfs><cellXfs count="3"><xf numFmtId="0"/><xf numFmtId="14" applyNumberFormat="1"/><xf numFmtId="21" applyNumberFormat="1"/></cellXfs></styleSheet>"#
            ),
        ),
    ];
    for (name, xml) in parts {
        z.start_file(name, options).unwrap();
        z.write_all(xml.as_bytes()).unwrap();
    }
    z.start_file("xl/worksheets/sheet1.xml", options).unwrap();
    write!(
        z,
        r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="{NS}"><sheetData>"#
    )
    .unwrap();
    rows(&mut z);
    z.write_all(b"</sheetData></worksheet>").unwrap();
    z.finish().unwrap();
}

/// An .xlsx of the sheet rows `sheet` in `dir`.
fn book(dir: &Path, name: &str, sheet: &str) -> PathBuf {
    let p = dir.join(name);
    xlsx(&p, |w| w.write_all(sheet.as_bytes()).unwrap());
    p
}

/// Item 2: calamine's OLE reader panics on a damaged .xls (a sector chain
/// through a FAT the header no longer lists: an index out of bounds in
/// `cfb.rs`). The file's error is reported, and no panic text reaches
/// standard error, in `run` and in a `batch` reading several such files at
/// once on two threads.
#[test]
fn a_damaged_xls_is_its_error_without_panic_text() {
    let tmp = tempfile::tempdir().unwrap();
    let mut xls = std::fs::read(format!(
        "{}/fixtures/measured/libreoffice_cycles.xls",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    // The header's DIFAT lists the FAT's sectors (0 and 128 here): drop
    // the second, and chains past sector 127 index past the FAT.
    assert_eq!(&xls[80..84], &128u32.to_le_bytes());
    xls[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    let damaged = tmp.path().join("damaged.xls");
    std::fs::write(&damaged, &xls).unwrap();

    let r = run_single(&damaged, MINUTE);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr.contains("damaged.xls: the spreadsheet is damaged"),
        "{}",
        r.stderr
    );

    let mut args: Vec<String> = vec![
        "batch".into(),
        "--engine".into(),
        data("single.toml"),
        "--jobs".into(),
        "2".into(),
    ];
    for k in 0..6 {
        let f = tmp.path().join(format!("damaged_{k}.xls"));
        std::fs::write(&f, &xls).unwrap();
        args.push(f.to_str().unwrap().into());
    }
    args.push(data("single.csv"));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let r = run(&args, MINUTE);
    assert!(matches!(r.code, Some(0 | 1)), "{}", r.stderr);
    for k in 0..6 {
        assert!(
            r.stdout
                .lines()
                .any(|l| l.contains(&format!("damaged_{k}.xls"))
                    && l.contains("error: the spreadsheet is damaged")),
            "{}",
            r.stdout
        );
    }
}

/// Item 3: a date- or time-formatted cell in the angle or pressure column
/// is an error naming the cell and its format (it was read as its serial
/// number: IMEP −21.76 bar instead of 10.47, exit 0); one such angle cell
/// among plain ones too (it gave `cycle 2 has 1 points`). A date cell
/// elsewhere (a timestamp column the reader leaves out, a banner) is no
/// error, and the diagram reads as its CSV.
#[test]
fn date_cells_where_a_measured_value_is_needed_are_errors_naming_the_cell() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    // Dates from 2020-01-01 (Excel's 43831) on in the angle column.
    let dates = diagram_sheet(|r, a, p| {
        let serial = 43831.0 + a.parse::<f64>().unwrap();
        vec![
            num(&format!("A{r}"), &serial.to_string(), 1),
            num(&format!("B{r}"), p, 0),
        ]
    });
    let r = run_single(&book(t, "angle_dates.xlsx", &dates), MINUTE);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr.contains(
            "line 3, column 1: cell A3 is formatted as a date (it shows 2020-01-01, Excel's day number 43831)"
        ),
        "{}",
        r.stderr
    );
    // Times in the pressure column.
    let times = diagram_sheet(|r, a, p| {
        vec![
            num(&format!("A{r}"), a, 0),
            num(
                &format!("B{r}"),
                &(p.parse::<f64>().unwrap() / 100.0).to_string(),
                2,
            ),
        ]
    });
    let r = run_single(&book(t, "pressure_times.xlsx", &times), MINUTE);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr
            .contains("line 3, column 2: cell B3 is formatted as a time of day (it shows 0"),
        "{}",
        r.stderr
    );
    // One date among the angles.
    let one = diagram_sheet(|r, a, p| {
        vec![
            num(&format!("A{r}"), a, if r == 500 { 1 } else { 0 }),
            num(&format!("B{r}"), p, 0),
        ]
    });
    let r = run_single(&book(t, "one_date.xlsx", &one), MINUTE);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr
            .contains("line 500, column 1: cell A500 is formatted as a date"),
        "{}",
        r.stderr
    );
    assert!(!r.stderr.contains("points"), "{}", r.stderr);

    // A date banner above, a timestamp column beside: read as the CSV.
    let mut s = row(1, &[num("A1", "45000", 1)]);
    s += &row(2, &[text("A2", "# rpm = 3600")]);
    s += &row(
        3,
        &[
            text("A3", "timestamp"),
            text("B3", "crank_deg"),
            text("C3", "pressure_bar"),
        ],
    );
    for (k, (a, p)) in single().iter().enumerate() {
        let r = k + 4;
        let stamp = 45000.5 + k as f64 / 86_400.0;
        s += &row(
            r,
            &[
                num(&format!("A{r}"), &stamp.to_string(), 1),
                num(&format!("B{r}"), a, 0),
                num(&format!("C{r}"), p, 0),
            ],
        );
    }
    let r = run_single(&book(t, "timestamps.xlsx", &s), MINUTE);
    let (got, want) = (imep(&r), csv_imep());
    assert!(
        (got - want).abs() <= 1e-9 * want.abs(),
        "IMEP {got} bar, from the CSV {want} bar"
    );
}

/// Item 3: a formula cell with no value stored says it was never
/// calculated and how to fix that (it was called "an empty cell").
#[test]
fn a_formula_never_calculated_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let s = diagram_sheet(|r, a, p| {
        if r == 10 {
            vec![
                num(&format!("A{r}"), a, 0),
                format!(r#"<c r="B{r}"><f>B9*1</f></c>"#),
            ]
        } else {
            plain(r, a, p)
        }
    });
    let r = run_single(&book(tmp.path(), "formula.xlsx", &s), MINUTE);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr.contains(
            "line 10, column 2: cell B10 holds a formula that was never calculated (the file stores no value for it): open the file in a spreadsheet program and save it"
        ),
        "{}",
        r.stderr
    );
    assert!(!r.stderr.contains("empty cell"), "{}", r.stderr);
}

/// Item 3: error cells read as the spreadsheet shows them (`#DIV/0!`, not
/// calamine's `#Div0`).
#[test]
fn error_cells_read_as_the_spreadsheet_shows_them() {
    let tmp = tempfile::tempdir().unwrap();
    for (k, shown) in [
        "#DIV/0!",
        "#N/A",
        "#VALUE!",
        "#REF!",
        "#NAME?",
        "#NUM!",
        "#NULL!",
        "#GETTING_DATA",
    ]
    .into_iter()
    .enumerate()
    {
        let s = diagram_sheet(|r, a, p| {
            if r == 20 {
                vec![
                    num(&format!("A{r}"), a, 0),
                    format!(r#"<c r="B{r}" t="e"><v>{shown}</v></c>"#),
                ]
            } else {
                plain(r, a, p)
            }
        });
        let r = run_single(&book(tmp.path(), &format!("error_{k}.xlsx"), &s), MINUTE);
        assert_eq!(r.code, Some(1), "{shown}: {}", r.stderr);
        assert!(
            r.stderr.contains(&format!("`{shown}`")),
            "{shown}: {}",
            r.stderr
        );
        if shown != "#GETTING_DATA" {
            assert!(
                r.stderr.contains(&format!(
                    "line 20, column 2: cell B20 holds `{shown}`, an error value of the spreadsheet"
                )),
                "{}",
                r.stderr
            );
        }
    }
}

/// 1 GiB.
const GIB: usize = 1 << 30;

/// Item 4: a whole diagram, then 1 GiB of empty `<row/>` elements
/// (deflated about 1000:1): the run of empty rows ends the data with a
/// note, the diagram gives its true IMEP, and the run takes under 2 s (it
/// took minutes, reading the whole GiB).
#[test]
fn an_empty_row_bomb_after_a_diagram_reads_the_diagram() {
    let tmp = tempfile::tempdir().unwrap();
    let bomb = tmp.path().join("bomb.xlsx");
    xlsx(&bomb, |w| {
        w.write_all(diagram_sheet(plain).as_bytes()).unwrap();
        let chunk = "<row/>".repeat((1 << 20) / 6);
        let mut written = 0;
        while written < GIB {
            w.write_all(chunk.as_bytes()).unwrap();
            written += chunk.len();
        }
    });
    let packed = std::fs::metadata(&bomb).unwrap().len();
    assert!(packed < 20 << 20, "the bomb packs to {packed} bytes");
    let r = run_single(&bomb, MINUTE);
    let (got, want) = (imep(&r), csv_imep());
    assert!(
        (got - want).abs() <= 1e-9 * want.abs(),
        "IMEP {got} bar, from the CSV {want} bar"
    );
    assert!(
        notes(&r).iter().any(|n| n
            == &format!(
                "the sheet's data ends at row {}: more than 10,000 empty rows follow, and the rest of the sheet is not read",
                single().len() + 2
            )),
        "{:?}",
        notes(&r)
    );
    // The binary's own time (a release build, as in CI); a debug build
    // unpacks several times slower.
    let limit = if cfg!(debug_assertions) { 10.0 } else { 2.0 };
    assert!(r.took.as_secs_f64() < limit, "took {:?}", r.took);
}

/// Item 4: a sheet past 1 GiB of another shape (rows of empty cells, each
/// padded to 1 MiB, after the diagram) is an error naming the bound, and so
/// is one text of more than 16 MiB (calamine would hold it whole).
#[test]
fn a_sheet_past_its_bounds_is_an_error_naming_the_bound() {
    let tmp = tempfile::tempdir().unwrap();
    let big = tmp.path().join("big.xlsx");
    let first = single().len() + 3;
    xlsx(&big, |w| {
        w.write_all(diagram_sheet(plain).as_bytes()).unwrap();
        let pad = "x".repeat(1 << 20);
        for k in 0..(GIB >> 20) + 8 {
            let r = first + k;
            write!(w, r#"<row r="{r}"><c r="C{r}" pad="{pad}"/></row>"#).unwrap();
        }
    });
    let r = run_single(&big, MINUTE);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr
            .contains("unpacks to more than 1 GiB, the bound on one sheet"),
        "{}",
        r.stderr
    );

    let long = tmp.path().join("long.xlsx");
    xlsx(&long, |w| {
        w.write_all(diagram_sheet(plain).as_bytes()).unwrap();
        write!(
            w,
            r#"<row r="{first}"><c r="C{first}" t="inlineStr"><is><t>"#
        )
        .unwrap();
        let chunk = "x".repeat(1 << 20);
        for _ in 0..17 {
            w.write_all(chunk.as_bytes()).unwrap();
        }
        w.write_all(b"</t></is></c></row>").unwrap();
    });
    let r = run_single(&long, MINUTE);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr
            .contains("a text or tag of more than 16 MiB, the bound on one"),
        "{}",
        r.stderr
    );
}
