//! Issue 41, part C.12: `enginedyn report`, the engine design report. It
//! runs on the template engines as written; its sections are all there,
//! each with its settings; its full-load figures check against Chen–Flynn
//! and the torque–power relation computed here apart; its map is the map
//! `sweep --load` gives; its tables folder is enginedyn's alone.

use enginedyn_tests::run;
use std::path::Path;

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A template engine (`args` to `enginedyn template`) with `edit` applied
/// and `append` added at its end, in `dir`.
fn engine(dir: &Path, args: &[&str], name: &str, edit: &[(&str, &str)], append: &str) -> String {
    let path = enginedyn_tests::edited_template(dir, args, name, edit);
    if !append.is_empty() {
        let mut text = std::fs::read_to_string(&path).unwrap();
        text.push_str(append);
        std::fs::write(&path, text).unwrap();
    }
    path
}

/// `report` of `engine` into `dir/out` with `extra` flags: exit 0, the
/// standard output.
fn report(dir: &Path, engine: &str, extra: &[&str]) -> (String, std::path::PathBuf) {
    let out = dir.join("out");
    let mut args = vec!["report", "--engine", engine, "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = run(&args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    (String::from_utf8_lossy(&o.stdout).into_owned(), out)
}

/// A CSV file as rows of named cells.
fn csv_rows(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let head: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            head.iter()
                .cloned()
                .zip(rec.iter().map(String::from))
                .collect()
        })
        .collect()
}

fn num(row: &std::collections::HashMap<String, String>, k: &str) -> f64 {
    row[k]
        .parse()
        .unwrap_or_else(|_| panic!("{k}: {:?}", row.get(k)))
}

const SECTIONS: [&str; 9] = [
    "engine",
    "full-load",
    "map",
    "flywheel",
    "loads-rated",
    "loads-peak-torque",
    "torsion",
    "firing",
    "tolerances",
];

/// The petrol template with `[torsion]`, friction constants of its own
/// and a `[tolerances]` section: every section is there with its settings
/// and what it studied (no "Not studied"); the full-load line's FMEP is
/// Chen–Flynn on each row's own peak pressure and mean piston speed, BMEP
/// = IMEP − FMEP, the brake torque BMEP V_d / 4π and the power T ω, all
/// computed here apart; rated power and peak torque are the line's
/// largest, as the summary at the top says.
#[test]
fn the_design_report_has_every_section_and_its_figures_check() {
    let t = tempfile::tempdir().unwrap();
    let (a, b, c, d) = (0.5, 0.006, 0.1, 0.001);
    let e = engine(
        t.path(),
        &["--combustion", "petrol", "--torsion"],
        "p4.toml",
        &[
            ("a_bar = 0.4", "a_bar = 0.5"),
            ("b = 0.005", "b = 0.006"),
            ("c_bar_s_m = 0.09", "c_bar_s_m = 0.1"),
            ("d_bar_s2_m2 = 0.0009", "d_bar_s2_m2 = 0.001"),
        ],
        "\n[tolerances]\nstroke_mm = 0.05\nbore_mm = 0.01\n",
    );
    let (text, out) = report(
        t.path(),
        &e,
        &["--rpm", "1000:6000:1000", "--load", "25:100:25"],
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for id in SECTIONS {
        let at = html
            .find(&format!("<h2 id=\"{id}\">"))
            .unwrap_or_else(|| panic!("no section {id}"));
        let next = html[at + 4..]
            .find("<h2")
            .map_or(html.len(), |k| at + 4 + k);
        let body = &html[at..next];
        assert!(!body.contains("Not studied"), "{id}: {body:.300}");
        if id != "firing" && id != "engine" {
            assert!(
                body.contains("class=\"settings\""),
                "{id} names no settings"
            );
        }
    }
    // Every chart the page shows is a file beside it, and the reverse.
    for f in std::fs::read_dir(&out).unwrap() {
        let name = f.unwrap().file_name().into_string().unwrap();
        if let Some(stem) = name.strip_suffix(".svg") {
            assert!(html.contains(&format!("<figure id=\"{stem}\">")), "{name}");
        }
    }
    // The full-load line against Chen–Flynn computed here.
    let (bore, stroke) = (0.076, 0.071);
    let vd = 4.0 * std::f64::consts::PI / 4.0 * bore * bore * stroke;
    let rows = csv_rows(&out.join("tables/full_load.csv"));
    assert_eq!(rows.len(), 6);
    let (mut best_p, mut best_t) = ((0.0, 0.0), (0.0, 0.0));
    for r in &rows {
        let n = num(r, "rpm");
        let cm = 2.0 * stroke * n / 60.0;
        let fmep = a + b * num(r, "p_max_bar") + c * cm + d * cm * cm;
        assert!((num(r, "fmep_bar") - fmep).abs() < 1e-9, "{n}: FMEP");
        let bmep = num(r, "imep_bar") - fmep;
        assert!((num(r, "bmep_bar") - bmep).abs() < 1e-9, "{n}: BMEP");
        let torque = bmep * 1e5 * vd / (4.0 * std::f64::consts::PI);
        assert!(
            (num(r, "torque_nm") / torque - 1.0).abs() < 1e-9,
            "{n}: torque"
        );
        let power = torque * n * std::f64::consts::PI / 30.0 / 1e3;
        assert!(
            (num(r, "power_kw") / power - 1.0).abs() < 1e-9,
            "{n}: power"
        );
        if power > best_p.1 {
            best_p = (n, power);
        }
        if torque > best_t.1 {
            best_t = (n, torque);
        }
    }
    let rated = format!(
        "rated power (brake): {:.1} kW (at {} rpm)",
        best_p.1, best_p.0
    );
    let peak = format!(
        "peak torque (brake): {:.1} N m (at {} rpm)",
        best_t.1, best_t.0
    );
    assert!(text.contains(&rated), "{rated} not in\n{text}");
    assert!(text.contains(&peak), "{peak} not in\n{text}");
    // The headline cards link to sections that exist.
    for id in html
        .split("<a href=\"#")
        .skip(1)
        .map(|s| &s[..s.find('"').unwrap()])
    {
        assert!(html.contains(&format!("id=\"{id}\"")), "#{id}");
    }
}

/// The report's map is the map `sweep --load` gives: its table equals
/// `sweep --csv` of the same speeds and loads, byte for byte.
#[test]
fn the_report_map_is_the_sweep_map() {
    let t = tempfile::tempdir().unwrap();
    let e = engine(
        t.path(),
        &["--combustion", "diesel", "--cylinders", "6"],
        "d6.toml",
        &[],
        "",
    );
    let (_, out) = report(
        t.path(),
        &e,
        &["--rpm", "800:2000:400", "--load", "50:100:50"],
    );
    let o = run(&[
        "sweep",
        "--engine",
        &e,
        "--rpm",
        "800:2000:400",
        "--load",
        "50:100:50",
        "--csv",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let map = std::fs::read(out.join("tables/map.csv")).unwrap();
    assert!(map == o.stdout, "tables/map.csv differs from sweep --csv");
}

/// Every template with a burn law reports as written, in seconds, and a
/// measured diagram gives the report at its one operating point.
#[test]
fn every_template_reports_as_written() {
    let t = tempfile::tempdir().unwrap();
    let cases: [&[&str]; 4] = [
        &["--combustion", "petrol"],
        &["--combustion", "diesel", "--torsion"],
        &[
            "--combustion",
            "petrol",
            "--cylinders",
            "8",
            "--layout",
            "vee",
        ],
        &["--combustion", "diesel", "--cylinders", "1"],
    ];
    for (k, args) in cases.iter().enumerate() {
        let dir = t.path().join(format!("c{k}"));
        std::fs::create_dir(&dir).unwrap();
        let e = engine(&dir, args, "e.toml", &[], "");
        let started = std::time::Instant::now();
        let (text, out) = report(&dir, &e, &[]);
        assert!(started.elapsed().as_secs_f64() < 60.0, "{args:?}");
        assert!(text.contains("rated power"), "{args:?}: {text}");
        assert!(out.join("tables/README.txt").is_file());
    }
    // A plain template as written: the bundled example's diagram, which
    // was measured on its cylinder, at its one operating point, said so.
    let dir = t.path().join("plain");
    std::fs::create_dir(&dir).unwrap();
    let e = engine(&dir, &["--cylinders", "6"], "e.toml", &[], "");
    let (text, out) = report(&dir, &e, &[]);
    assert!(text.contains("power: "), "{text}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("the bundled example&#39;s diagram")
            || html.contains("the bundled example's diagram")
    );
    // A plain template and a measured diagram: one operating point.
    let dir = t.path().join("point");
    std::fs::create_dir(&dir).unwrap();
    let e = engine(&dir, &["--torsion"], "e.toml", &[], "");
    let diagram = enginedyn_tests::data("vaz2108.csv");
    let (text, out) = report(&dir, &e, &["--diagram", &diagram]);
    assert!(text.contains("power: "), "{text}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("A measured diagram is one operating point"));
    assert!(html.contains("<h2 id=\"torsion\">"));
}

/// What a report refuses, before any work: a map's flags without a design
/// model, no diagram and no `[combustion]`, and a `tables` folder that is
/// not an earlier report's (left as it was).
#[test]
fn a_report_refuses_what_it_cannot_do() {
    let t = tempfile::tempdir().unwrap();
    // Not the bundled example's cylinder: its diagram does not fit.
    let plain = engine(
        t.path(),
        &[],
        "plain.toml",
        &[("bore_mm = 76.0", "bore_mm = 80.0")],
        "",
    );
    let out = t.path().join("out");
    let o = run(&["report", "--engine", &plain, "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("[combustion]"), "{}", stderr(&o));
    let diagram = enginedyn_tests::data("vaz2108.csv");
    let o = run(&[
        "report",
        "--engine",
        &plain,
        "--diagram",
        &diagram,
        "--rpm",
        "1000:2000:500",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--rpm and --load"), "{}", stderr(&o));
    // The user's own folder named `tables` stays as it was.
    let petrol = engine(t.path(), &["--combustion", "petrol"], "p.toml", &[], "");
    let mine = t.path().join("mine");
    std::fs::create_dir_all(mine.join("tables")).unwrap();
    std::fs::write(mine.join("tables/notes.txt"), "mine").unwrap();
    let o = run(&[
        "report",
        "--engine",
        &petrol,
        "--out",
        mine.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("README.txt"), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(mine.join("tables/notes.txt")).unwrap(),
        "mine"
    );
    assert!(!mine.join("report.html").exists());
    // A file where the folder goes is in the way: exit 2, left as it was.
    let file = t.path().join("a_file");
    std::fs::write(&file, "mine").unwrap();
    let o = run(&[
        "report",
        "--engine",
        &petrol,
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a file is in the way"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    // An earlier report's folder is replaced whole.
    let again = t.path().join("again");
    for _ in 0..2 {
        let o = run(&[
            "report",
            "--engine",
            &petrol,
            "--out",
            again.to_str().unwrap(),
            "--rpm",
            "2000:4000:1000",
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    }
}

/// A chart of a synthesised diagram says so and gives its load; a measured
/// one does not.
#[test]
fn charts_of_a_synthesised_diagram_say_so() {
    let t = tempfile::tempdir().unwrap();
    let e = engine(t.path(), &["--combustion", "petrol"], "p.toml", &[], "");
    let out = t.path().join("run");
    let o = run(&["run", "--engine", &e, "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    for chart in [
        "pressure.svg",
        "forces.svg",
        "torque.svg",
        "heat_release.svg",
    ] {
        let svg = std::fs::read_to_string(out.join(chart)).unwrap();
        assert!(svg.contains("synthesised at IMEP 10 bar"), "{chart}");
    }
    let measured = t.path().join("measured");
    let o = run(&["run", "--out", measured.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let svg = std::fs::read_to_string(measured.join("pressure.svg")).unwrap();
    assert!(!svg.contains("synthesised"));
}
