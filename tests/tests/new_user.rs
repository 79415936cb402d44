//! What a new user tripped on (issue 30, items 1–4, 9 and 10), each with a
//! file written the way the other tool writes it and an IMEP computed
//! independently here: the four-cylinder export of
//! `data/vaz2108.csv`'s cycle, each cylinder scaled by its own factor about
//! 1 bar (so its IMEP is the factor times the bundled cycle's, ∮ p dV being
//! linear in p and ∮ dV zero).

use enginedyn_tests::{data, run};
use std::path::{Path, PathBuf};
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    assert_eq!(o.status.code(), Some(0), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).expect("JSON on stdout")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The bundled cycle: angles (0.5° steps from firing TDC) and bar.
fn cycle() -> (Vec<f64>, Vec<f64>) {
    std::fs::read_to_string(data("vaz2108.csv"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .map(|l| {
            let (a, p) = l.split_once(',').unwrap();
            (a.parse::<f64>().unwrap(), p.parse::<f64>().unwrap())
        })
        .unzip()
}

/// The bundled engine's firing angles (order 1-3-4-2, deg).
const THETA: [f64; 4] = [0.0, 540.0, 180.0, 360.0];
/// Each cylinder's scale about 1 bar: unequal cylinders.
const SCALE: [f64; 4] = [1.0, 0.9, 1.1, 0.95];

/// Cylinder i's pressure at grid index k on cylinder 1's axis (`shared`)
/// or on its own.
fn p_cyl(p: &[f64], i: usize, k: usize, shared: bool) -> f64 {
    let n = p.len();
    let shift = if shared { (THETA[i] / 0.5) as usize } else { 0 };
    1.0 + SCALE[i] * (p[(k + n - shift) % n] - 1.0)
}

/// The bundled example's IMEP, and the independent mean over the cylinders.
fn expected() -> f64 {
    let r = json(&run(&["run", "--engine", &data("vaz2108.toml"), "--json"]));
    r["imep_bar"].as_f64().unwrap() * SCALE.iter().sum::<f64>() / 4.0
}

fn engine_run(files: &[&Path], flags: &[&str]) -> Output {
    let engine = data("vaz2108.toml");
    let mut args: Vec<String> = vec![
        "run".into(),
        "--engine".into(),
        engine,
        "--json".into(),
        "--diagram".into(),
    ];
    args.extend(files.iter().map(|f| f.display().to_string()));
    args.extend(flags.iter().map(|s| s.to_string()));
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    run(&a)
}

/// Item 1: cylinders exported on one shared axis (IMEP 1.32 bar instead
/// of 10.35 with exit 0 before): as columns, as a `cylinder` column and as
/// four files; each cylinder on its own axis reads the same.
#[test]
fn cylinders_on_one_shared_axis() {
    let t = tempfile::tempdir().unwrap();
    let (a, p) = cycle();
    let want = expected();
    let head = "CA [deg],P_Cyl1 [bar],P_Cyl2 [bar],P_Cyl3 [bar],P_Cyl4 [bar]\n";
    let table = |shared: bool| -> String {
        let mut s = String::from(head);
        for k in 0..a.len() {
            s.push_str(&format!("{}", a[k]));
            for i in 0..4 {
                s.push_str(&format!(",{:.6}", p_cyl(&p, i, k, shared)));
            }
            s.push('\n');
        }
        s
    };
    let shared = write(t.path(), "shared.csv", &table(true));
    let own = write(t.path(), "own.csv", &table(false));
    let mut long = String::from("cylinder,crank_deg,pressure_bar\n");
    for i in 0..4 {
        for k in 0..a.len() {
            long.push_str(&format!(
                "{},{},{:.6}\n",
                i + 1,
                a[k],
                p_cyl(&p, i, k, true)
            ));
        }
    }
    let long = write(t.path(), "long.csv", &long);
    let files: Vec<PathBuf> = (0..4)
        .map(|i| {
            let mut s = String::from("crank_deg,pressure_bar\n");
            for k in 0..a.len() {
                s.push_str(&format!("{},{:.6}\n", a[k], p_cyl(&p, i, k, true)));
            }
            write(t.path(), &format!("cyl{}.csv", i + 1), &s)
        })
        .collect();
    let file_refs: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    for (what, out, axis) in [
        (
            "columns",
            engine_run(&[&shared], &[]),
            "one shared crank angle",
        ),
        (
            "cylinder column",
            engine_run(&[&long], &[]),
            "one shared crank angle",
        ),
        (
            "four files",
            engine_run(&file_refs, &[]),
            "one shared crank angle",
        ),
        (
            "own axes",
            engine_run(&[&own], &[]),
            "each on its own crank angle",
        ),
        (
            "forced",
            engine_run(&[&shared], &["--cylinder-axis", "shared"]),
            "--cylinder-axis shared",
        ),
    ] {
        let j = json(&out);
        let imep = j["imep_bar"].as_f64().unwrap();
        // The 6-decimal file values: agreement to 1e-6 relative.
        assert!(
            (imep / want - 1.0).abs() < 1e-6,
            "{what}: {imep} against {want}"
        );
        let notes = j["notes"].to_string();
        assert!(notes.contains(axis), "{what}: {notes}");
        assert!(!notes.contains("near idle"), "{what}: {notes}");
    }
    // The spread is said to be over cylinders.
    let j = json(&engine_run(&[&shared], &[]));
    assert!(
        j["notes"]
            .to_string()
            .contains("over 4 cylinders, one cycle each"),
        "{}",
        j["notes"]
    );
    // Forced the wrong way, the result is visibly off; a trace that fits
    // neither axis is an error naming the cylinder.
    let wrong = json(&engine_run(&[&shared], &["--cylinder-axis", "own"]));
    assert!(wrong["imep_bar"].as_f64().unwrap() < 0.5 * want);
    let mut bad = String::from(head);
    for k in 0..a.len() {
        s_push(
            &mut bad,
            a[k],
            &[
                p_cyl(&p, 0, k, true),
                p_cyl(&p, 1, (k + 200) % a.len(), true),
                p_cyl(&p, 2, k, true),
                p_cyl(&p, 3, k, true),
            ],
        );
    }
    let bad = write(t.path(), "bad.csv", &bad);
    let o = engine_run(&[&bad], &[]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("cylinder 2's pressure peak"),
        "{}",
        stderr(&o)
    );
}

fn s_push(s: &mut String, a: f64, v: &[f64]) {
    s.push_str(&format!("{a}"));
    for x in v {
        s.push_str(&format!(",{x:.6}"));
    }
    s.push('\n');
}

/// Item 2: a names row over a units row (`CA, PCYL1 …` over `deg, bar …`)
/// was read as four cycles of one cylinder.
#[test]
fn a_units_row_keeps_cylinders_cylinders() {
    let t = tempfile::tempdir().unwrap();
    let (a, p) = cycle();
    let mut s = String::from("CA,PCYL1,PCYL2,PCYL3,PCYL4\ndeg,bar,bar,bar,bar\n");
    for k in 0..a.len() {
        s_push(
            &mut s,
            a[k],
            &(0..4).map(|i| p_cyl(&p, i, k, false)).collect::<Vec<_>>(),
        );
    }
    let f = write(t.path(), "units.csv", &s);
    let j = json(&engine_run(&[&f], &[]));
    let notes = j["notes"].to_string();
    assert!(notes.contains("one per cylinder"), "{notes}");
    assert!((j["imep_bar"].as_f64().unwrap() / expected() - 1.0).abs() < 1e-6);
}

/// Item 3: a 0–720° file from the intake TDC (firing TDC at 360°): the
/// curves and charts put the peak at 377° before; now it follows 0°.
#[test]
fn firing_tdc_at_360_in_a_0_720_file() {
    let t = tempfile::tempdir().unwrap();
    let (a, p) = cycle();
    let n = a.len();
    let mut s = String::from("crank_deg,pressure_bar\n");
    for k in 0..n {
        // File angle a[k] holds the pressure 360° before (firing TDC at 360).
        s.push_str(&format!("{},{}\n", a[k], p[(k + n / 2) % n]));
    }
    let f = write(t.path(), "from_intake.csv", &s);
    let out = t.path().join("out");
    let engine = data("vaz2108.toml");
    let o = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        f.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("firing TDC at the file's 360°"),
        "{}",
        stderr(&o)
    );
    let curves = std::fs::read_to_string(out.join("curves.csv")).unwrap();
    let (mut best, mut at) = (f64::MIN, 0.0);
    for l in curves.lines().skip(1) {
        let c: Vec<f64> = l.split(',').take(2).map(|x| x.parse().unwrap()).collect();
        if c[1] > best {
            best = c[1];
            at = c[0];
        }
    }
    assert!((0.0..60.0).contains(&at), "the peak at {at}°");
    // --tdc-deg 0 keeps the file's angles: its peak then lies a
    // revolution from firing TDC, which the peak-angle rule refuses, naming
    // the flag and the phasing (issue 36, item 3) unless
    // --no-compression-check lifts it.
    let o = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        f.to_str().unwrap(),
        "--tdc-deg",
        "0",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--tdc-deg") && stderr(&o).contains("phasing"),
        "{}",
        stderr(&o)
    );
    let j = json(&run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        f.to_str().unwrap(),
        "--tdc-deg",
        "0",
        "--no-compression-check",
        "--json",
    ]));
    assert!(!j["notes"].to_string().contains("360°: the pressure peak"));
}

/// Item 4: a gauge trace read as absolute (1 bar low) was called noise.
#[test]
fn gauge_data_read_as_absolute_gets_a_warning() {
    let t = tempfile::tempdir().unwrap();
    let (a, p) = cycle();
    let mut s = String::from("crank_deg,pressure_bar\n");
    for k in 0..a.len() {
        s.push_str(&format!("{},{}\n", a[k], p[k] - 1.01325));
    }
    let f = write(t.path(), "gauge.csv", &s);
    let o = engine_run(&[&f], &[]);
    let e = stderr(&o);
    assert!(
        e.contains("warning:") && e.contains("intake BDC") && e.contains("--gauge"),
        "{e}"
    );
    // With --gauge: no such warning, and the bundled IMEP.
    let o = engine_run(&[&f], &["--gauge"]);
    assert!(!stderr(&o).contains("intake BDC"), "{}", stderr(&o));
}

/// Item 9: dynamometer torque files.
#[test]
fn torque_files_as_dynamometers_write_them() {
    let t = tempfile::tempdir().unwrap();
    let engine = data("vaz2108.toml");
    for head in ["Torque [Nm]", "Drehmoment [N m]", "M [Nm]"] {
        let mut s = format!("Crank Angle [deg],{head}\n");
        for k in 0..720 {
            let a = k as f64;
            s.push_str(&format!(
                "{a},{}\n",
                100.0 + 80.0 * (a.to_radians() * 2.0).sin()
            ));
        }
        let f = write(t.path(), "torque.csv", &s);
        let j = json(&run(&[
            "run",
            "--engine",
            &engine,
            "--torque",
            f.to_str().unwrap(),
            "--json",
        ]));
        let m = j["indicated_mean_torque_nm"].as_f64().unwrap();
        assert!((m - 100.0).abs() < 1e-6, "{head}: {m}");
    }
    // No torque column: the error speaks of torque.
    let f = write(t.path(), "p.csv", "crank_deg,speed_rpm\n0,1\n1,2\n");
    let o = run(&["run", "--engine", &engine, "--torque", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no torque column"), "{}", stderr(&o));
}

/// Item 10: `note:` for what was decided, `warning:` for what may be
/// wrong, each once; the bundled example prints no warning.
#[test]
fn notes_and_warnings() {
    let o = run(&["run"]);
    assert_eq!(o.status.code(), Some(0));
    let e = stderr(&o);
    assert!(!e.contains("warning:"), "{e}");
    assert!(e.contains("note: no TDC offset estimate"), "{e}");
    let o = run(&["firing-orders", "--engine", &data("vaz2108.toml")]);
    let e = stderr(&o);
    let mut lines: Vec<&str> = e
        .lines()
        .filter(|l| l.starts_with("note:") || l.starts_with("warning:"))
        .collect();
    let n = lines.len();
    lines.sort_unstable();
    lines.dedup();
    assert_eq!(lines.len(), n, "a note printed twice: {e}");
}
