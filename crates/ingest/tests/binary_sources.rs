//! Workbooks and binary files (issue 36, items 10 and 12): the default sheet
//! is the first that holds a diagram, with a note naming it; a workbook
//! whose sheets hold none is an error listing every sheet; a TDMS file is
//! refused with the way through the Python package.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Resampled, load, parse};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
use std::io::{Read, Write};

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(format!(
        "{}/../../tests/fixtures/measured/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// data/single.toml's cylinder: bore 68 mm, stroke 54 mm, rod 84 mm, ε 8.5.
fn cylinder() -> Cylinder {
    let cs = CrankSlider::new(0.027, 0.084, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.068, 8.5).unwrap()
}

fn options() -> (ParseOptions, GridOptions) {
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cylinder());
    o.max_cylinder = 1;
    let mut g = GridOptions::new(0.1, Interp::Auto);
    g.cylinder = Some(cylinder());
    (o, g)
}

fn imep_bar(r: &Resampled) -> f64 {
    r.stats.iter().map(|s| s.imep_pa.unwrap()).sum::<f64>() / r.stats.len() as f64 / 1e5
}

/// expected.json, `excel_title_second_sheet.xlsx --sheet 2`.
const SECOND_SHEET_IMEP: f64 = 9.992166499019;

/// Item 10: a workbook whose sheet 1 is `Info` (metadata, no diagram) reads
/// its sheet 2 by default, with a note naming it, to the IMEP `--sheet 2`
/// gives; as .xlsx (streamed) and as LibreOffice's .ods (calamine's table).
#[test]
fn the_default_sheet_is_the_first_that_holds_a_diagram() {
    let (o, g) = options();
    for name in [
        "excel_title_second_sheet.xlsx",
        "libreoffice_title_second_sheet.ods",
    ] {
        let r = load(&fixture(name)[..], &o, &g).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(r.cycles, 5, "{name}");
        let got = imep_bar(&r);
        assert!(
            (got - SECOND_SHEET_IMEP).abs() <= 1e-9 * SECOND_SHEET_IMEP,
            "{name}: {got}"
        );
        assert!(
            r.notes.iter().any(|n| n
                == "read sheet 2 `Cylinder 1` of 2, the first that holds a diagram (sheet 1 `Info` holds none; --sheet chooses another)"),
            "{name}: {:?}",
            r.notes
        );
    }
    // --sheet 1 still reads sheet 1 alone: its error, no other sheet tried.
    let mut o1 = o.clone();
    o1.sheet = Some(enginedyn_ingest::Sheet::Index(1));
    assert!(parse(&fixture("excel_title_second_sheet.xlsx")[..], &o1).is_err());
}

/// The workbook with its sheet 2 replaced by its sheet 1 (`Info` twice).
fn no_diagram() -> Vec<u8> {
    let bytes = fixture("excel_title_second_sheet.xlsx");
    let mut zin = zip::ZipArchive::new(std::io::Cursor::new(&bytes[..])).unwrap();
    let mut info = String::new();
    zin.by_name("xl/worksheets/sheet1.xml")
        .unwrap()
        .read_to_string(&mut info)
        .unwrap();
    let mut out = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for i in 0..zin.len() {
        let mut f = zin.by_index(i).unwrap();
        let name = f.name().unwrap().into_owned();
        let mut body = Vec::new();
        f.read_to_end(&mut body).unwrap();
        if name == "xl/worksheets/sheet2.xml" {
            body = info.clone().into_bytes();
        }
        out.start_file(name, opts).unwrap();
        out.write_all(&body).unwrap();
    }
    out.finish().unwrap().into_inner()
}

/// Item 10: when no sheet holds a diagram, the error is sheet 1's, with
/// every sheet listed by number and name.
#[test]
fn a_workbook_without_a_diagram_lists_its_sheets() {
    let (o, _) = options();
    let e = parse(&no_diagram()[..], &o).unwrap_err().to_string();
    assert!(
        e.contains(
            "(this is sheet 1 `Info`; no sheet of 2 holds a diagram: 1 `Info`, 2 `Cylinder 1`; --sheet N or --sheet NAME reads another)"
        ),
        "{e}"
    );
}

/// Item 12: a TDMS file is refused with the Python package's reader named.
#[test]
fn a_tdms_file_names_the_python_reader() {
    let (o, _) = options();
    let mut bytes = b"TDSm".to_vec();
    bytes.extend_from_slice(&[0x0E, 0, 0, 0, 0x69, 0x12, 0, 0]);
    bytes.resize(512, 0);
    let e = parse(&bytes[..], &o).unwrap_err().to_string();
    assert!(
        e.starts_with("not a text file: it starts like a National Instruments TDMS file")
            && e.contains(
                "the Python package reads TDMS: `enginedyn.io.read_tdms(path, group, …)`"
            ),
        "{e}"
    );
}
