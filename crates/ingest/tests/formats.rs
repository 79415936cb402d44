//! Diagram files as tools write them, and bad input as clear errors.

use enginedyn_ingest::{IngestError, Interp, ParseOptions, parse, pressure_unit, resample};

fn opts() -> ParseOptions {
    ParseOptions::new(720.0)
}

/// A smooth periodic pressure (bar) for round trips.
fn p_bar(a: f64) -> f64 {
    let d = (a - 10.0 + 360.0).rem_euclid(720.0) - 360.0;
    1.0 + 50.0 * (-(d / 30.0).powi(2)).exp()
}

fn table(step: f64, delim: &str, unit: &str, factor: f64, comma: bool) -> String {
    let mut s = format!("# a comment\n# rpm = 3000\ncrank_deg{delim}pressure_{unit}\n");
    let n = (720.0 / step) as usize;
    for k in 0..n {
        let a = k as f64 * step;
        let v = format!("{}", p_bar(a) * 1e5 / factor);
        let v = if comma { v.replace('.', ",") } else { v };
        s.push_str(&format!("{a}{delim}{v}\n"));
    }
    s
}

/// Every unit and delimiter reads back to the same pressure (1e-12 relative).
#[test]
fn units_and_delimiters_round_trip() {
    for (unit, name) in [
        ("bar", "pressure_bar"),
        ("mpa", "pressure_mpa"),
        ("kpa", "pressure_kpa"),
        ("pa", "pressure_pa"),
        ("psi", "pressure_psi"),
        ("kgf_cm2", "pressure_kgf_cm2"),
    ] {
        let factor = pressure_unit(name).unwrap();
        for (delim, comma) in [(",", false), (";", true), ("\t", true), ("  ", false)] {
            let text = table(1.0, delim, unit, factor, comma);
            let d = parse(text.as_bytes(), &opts()).unwrap();
            assert_eq!(d.rpm, Some(3000.0));
            let tr = &d.traces[0];
            for (a, p) in tr.angle_deg.iter().zip(&tr.values) {
                assert!(
                    (p - p_bar(*a) * 1e5).abs() < 1e-9 * p,
                    "{unit} {delim:?} at {a}"
                );
            }
        }
    }
}

/// Unit factors from exact definitions.
#[test]
fn unit_factors() {
    assert!((pressure_unit("pressure_psi").unwrap() - 6894.757293168361).abs() < 1e-9);
    assert!((pressure_unit("pressure_kgf_cm2").unwrap() - 98066.5).abs() < 1e-12);
}

/// TDC anywhere, any start, a repeated closing angle: the same diagram.
#[test]
fn tdc_start_and_closing_point() {
    let mut s = String::from("crank_deg,pressure_bar\n");
    // File angles run 100..820 with TDC at 460 (cycle angle 0), closing point repeated.
    for k in 0..=720 {
        let a = 100.0 + k as f64;
        s.push_str(&format!("{a},{}\n", p_bar(a - 460.0)));
    }
    let mut o = opts();
    o.tdc_deg = 460.0;
    let d = parse(s.as_bytes(), &o).unwrap();
    let g = resample(&d, 1.0, Interp::Auto).unwrap();
    assert_eq!(g.interp.name(), "linear", "data on the grid");
    for k in 0..720 {
        assert!((g.pressure[k] - p_bar(k as f64) * 1e5).abs() < 1e-6);
    }
}

/// No header: --columns names the columns; `_` skips one.
#[test]
fn columns_without_header() {
    let s = "0;7;1,5\n180;7;2,5\n360;7;3,5\n540;7;4,5\n";
    let mut o = opts();
    o.columns = Some(vec!["crank_deg".into(), "_".into(), "pressure_bar".into()]);
    let d = parse(s.as_bytes(), &o).unwrap();
    assert_eq!(d.traces[0].values, vec![1.5e5, 2.5e5, 3.5e5, 4.5e5]);
    let e = parse(s.as_bytes(), &opts()).unwrap_err();
    assert!(e.to_string().contains("--columns"), "{e}");
}

/// Uneven samples go through the spline (auto), which matches the smooth
/// curve closely (its error at 2–7° spacing is far below 0.5 % of the peak).
#[test]
fn uneven_samples_use_the_spline() {
    let mut s = String::from("crank_deg,pressure_bar\n");
    let mut a = 0.0;
    let mut k = 0;
    while a < 720.0 {
        s.push_str(&format!("{a},{}\n", p_bar(a)));
        a += if k % 2 == 0 { 2.0 } else { 3.0 };
        k += 1;
    }
    let d = parse(s.as_bytes(), &opts()).unwrap();
    let g = resample(&d, 0.5, Interp::Auto).unwrap();
    assert_eq!(g.interp.name(), "spline");
    let worst = (0..1440)
        .map(|k| (g.pressure[k] - p_bar(k as f64 * 0.5) * 1e5).abs())
        .fold(0.0, f64::max);
    assert!(worst < 0.002 * 51e5, "worst {worst}");
}

/// Several cycles are averaged.
#[test]
fn cycles_are_averaged() {
    let mut s = String::from("cycle,crank_deg,pressure_bar\n");
    for c in 0..3 {
        for k in 0..72 {
            s.push_str(&format!("{c},{},{}\n", k * 10, 1.0 + c as f64));
        }
    }
    let d = parse(s.as_bytes(), &opts()).unwrap();
    assert_eq!(d.traces.len(), 3);
    let g = resample(&d, 10.0, Interp::Linear).unwrap();
    assert_eq!(g.cycles, 3);
    assert!(g.pressure.iter().all(|p| (p - 2e5).abs() < 1e-9));
}

fn err(text: &str) -> String {
    parse(text.as_bytes(), &opts()).unwrap_err().to_string()
}

/// Every bad input is an error naming line and column where there is one.
#[test]
fn bad_input_is_a_clear_error() {
    let e = err("crank_deg,pressure_bar\n0,1\n10,x\n");
    assert!(e.contains("line 3, column 2") && e.contains("`x`"), "{e}");
    let e = err("crank_deg,pressure_bar\n0,1\n10,NaN\n");
    assert!(
        e.contains("line 3, column 2") && e.contains("finite"),
        "{e}"
    );
    let e = err("crank_deg,pressure_bar\n0,1\n10,inf\n");
    assert!(e.contains("finite"), "{e}");
    let e = err("crank_deg,pressure_bar\n0,1\n10,2\n10,3\n");
    assert!(e.contains("line 4, column 1") && e.contains("rise"), "{e}");
    let e = err("crank_deg,pressure_bar\n0,1\n10,2\n5,3\n");
    assert!(e.contains("line 4") && e.contains("rise"), "{e}");
    let e = err("crank_deg,pressure_bars\n0,1\n");
    assert!(
        e.contains("unknown column `pressure_bars`") && e.contains("pressure_bar"),
        "{e}"
    );
    // Below zero over more than half the cycle: gauge data.
    let mut s = String::from("crank_deg,pressure_bar\n0,40\n");
    for k in 1..72 {
        s.push_str(&format!("{},-0.5\n", k * 10));
    }
    let e = err(&s);
    assert!(
        e.contains("below zero absolute pressure over 99 %") && e.contains("--gauge"),
        "{e}"
    );
    let e = err("");
    assert!(e.contains("no data"), "{e}");
    let e = err("# only comments\n");
    assert!(e.contains("no data"), "{e}");
    // A cycle that stops short of the full 720°.
    let mut s = String::from("crank_deg,pressure_bar\n");
    for k in 0..=600 {
        s.push_str(&format!("{k},2\n"));
    }
    let e = err(&s);
    assert!(
        e.contains("a gap of 120° from 600°") && e.contains("--max-gap 120"),
        "{e}"
    );
    // Bar values of 1e5: the unit is wrong.
    let mut s = String::from("crank_deg,pressure_bar\n");
    for k in 0..72 {
        s.push_str(&format!("{},{}\n", k * 10, 1e5 * 50.0));
    }
    let e = err(&s);
    assert!(e.contains("above the 1000 bar a cylinder reaches"), "{e}");
    assert!(matches!(
        parse("a,b\n".as_bytes(), &opts()),
        Err(IngestError::At { .. })
    ));
}

/// A speed line is read in any case, with `=` or `:` and a unit after the
/// number; one whose value is not a positive number is an error at its
/// line (it once fell back to the engine's speed unnoticed), and so is a
/// second line with another speed. Comments that only begin with "rpm"
/// are comments.
#[test]
fn speed_lines() {
    let body = "crank_deg,pressure_bar\n0,40\n180,2\n360,1\n540,1\n";
    let read = |head: &str| parse(format!("{head}{body}").as_bytes(), &opts());
    for (head, rpm) in [
        ("# rpm = 2200\n", Some(2200.0)),
        ("# RPM = 1800\n", Some(1800.0)),
        ("#rpm:1500.5 1/min\n", Some(1500.5)),
        ("# rpm = 2200;;\n", Some(2200.0)),
        ("# rpm = 1,800\n", Some(1800.0)),
        ("# rpm = 4.9e3\n", Some(4900.0)),
        ("# rpm = 4 900 rpm\n", Some(4900.0)),
        ("# rpm = 2200\n# rpm = 2200.0\n", Some(2200.0)),
        ("# rpms = 3\n", None),
        ("# rpm_target = 3\n", None),
        ("# speed in rpm = 3\n", None),
    ] {
        assert_eq!(read(head).unwrap().rpm, rpm, "{head:?}");
    }
    for (head, line, says) in [
        ("# rpm = abc\n", 1, "from 0.001 to 100000"),
        ("# a comment\n# rpm = -5\n", 2, "from 0.001 to 100000"),
        ("# rpm =\n", 1, "from 0.001 to 100000"),
        ("# rpm = 1e999\n", 1, "from 0.001 to 100000"),
        ("# rpm = 1e300\n", 1, "from 0.001 to 100000"),
        ("# rpm = 1,8\n", 1, "thousands separator"),
        ("# rpm = 4900rpms\n", 1, "is not a number"),
        ("# rpm = 2200\n# rpm = 2000\n", 2, "a second speed line"),
    ] {
        match read(head) {
            Err(IngestError::At {
                line: l, message, ..
            }) => {
                assert_eq!(l, line, "{head:?}");
                assert!(message.contains(says), "{head:?}: {message}");
            }
            other => panic!("{head:?}: {other:?}"),
        }
    }
}

/// Spreadsheet exports: Excel's `sep=;` line above the header (after a
/// byte-order mark, with CRLF line ends) names the delimiter, and a
/// delimiter closing every row leaves an empty last column that is
/// skipped. Both read back the same pressures as the plain file (to the
/// bit); an unknown `sep=` delimiter is an error at its line.
#[test]
fn spreadsheet_exports() {
    let plain = table(1.0, ",", "bar", 1e5, false);
    let want = parse(plain.as_bytes(), &opts()).unwrap();
    let semicolon = table(1.0, ";", "bar", 1e5, true).replace('\n', "\r\n");
    let tab = table(1.0, "\t", "bar", 1e5, true);
    let trailing: String = plain.lines().map(|l| format!("{l},\n")).collect();
    for text in [
        format!("\u{feff}sep=;\r\n{semicolon}"),
        format!("SEP=\t\n{tab}"),
        trailing,
    ] {
        let got = parse(text.as_bytes(), &opts()).unwrap();
        assert_eq!(
            got.traces[0].values,
            want.traces[0].values,
            "{:?}",
            &text[..40]
        );
        assert_eq!(got.rpm, Some(3000.0));
    }
    match parse(format!("sep=|\n{plain}").as_bytes(), &opts()) {
        Err(IngestError::At {
            line: 1, message, ..
        }) => assert!(message.contains("sep=|")),
        other => panic!("{other:?}"),
    }
}

/// An unknown column gets a "did you mean" only when a known name is close.
#[test]
fn did_you_mean_only_when_close() {
    let read = |head: &str| {
        parse(format!("{head}\n0,1\n").as_bytes(), &opts())
            .unwrap_err()
            .to_string()
    };
    let typo = read("crank_deg,pressur_bar");
    assert!(typo.contains("did you mean `pressure_bar`?"), "{typo}");
    let far = read("crank_deg,foo");
    assert!(
        far.contains("unknown column `foo`") && !far.contains("did you mean"),
        "{far}"
    );
}

/// UTF-16 text (Excel's "Unicode text", LabVIEW) reads as its UTF-8 twin,
/// little- and big-endian, split across read blocks anywhere.
#[test]
fn utf16_text() {
    let mut s = String::from("\u{feff}# rpm = 2000\r\nKurbelwinkel [°KW]\tDruck [bar]\r\n");
    for k in 0..720 {
        s.push_str(&format!("{k}\t{:.3}\r\n", p_bar(k as f64)));
    }
    let want = parse(s.trim_start_matches('\u{feff}').as_bytes(), &opts()).unwrap();
    for little in [true, false] {
        let bytes: Vec<u8> = s
            .encode_utf16()
            .flat_map(|u| {
                if little {
                    u.to_le_bytes()
                } else {
                    u.to_be_bytes()
                }
            })
            .collect();
        // A reader that hands over 7 bytes at a time: surrogates and code
        // units split across reads.
        let got = parse(
            std::io::BufReader::with_capacity(7, bytes.as_slice()),
            &opts(),
        )
        .unwrap();
        assert_eq!(got.traces, want.traces);
        assert_eq!(got.rpm, Some(2000.0));
    }
}
