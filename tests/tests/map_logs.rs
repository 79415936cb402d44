//! A map's size and a long run's log (issues 44.8, 43.9, 41.11): a map is
//! capped by its points (speeds × loads), not by each axis alone; a
//! batch's and a sweep's notes are grouped by kind, one line a kind with
//! its count and the range of its numbers; `batch --quiet` keeps one line
//! on standard output (INTERFACE.md, "A batch's log is read by people and
//! by job schedulers").

use enginedyn_tests::{data, run};
use std::path::{Path, PathBuf};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// `template --combustion petrol`, written to `dir`.
fn petrol_engine(dir: &Path) -> PathBuf {
    let out = run(&["template", "--combustion", "petrol"]);
    assert!(out.status.success());
    let path = dir.join("petrol.toml");
    std::fs::write(&path, &out.stdout).unwrap();
    path
}

/// The map: 1,000 speeds × 100 loads, each axis within its own
/// cap, 100,000 points (its loads 0.4–40 bar: the 1–100 bar now
/// stops at the IMEP bound of 40 bar). Refused before any work (it took 2 GB and
/// aborted), exit 2, naming both flags and the cap.
#[test]
fn a_map_past_the_cap_of_its_points_is_refused_naming_both_flags() {
    let dir = tempfile::tempdir().unwrap();
    let engine = petrol_engine(dir.path());
    let started = std::time::Instant::now();
    let out = run(&[
        "sweep",
        "--engine",
        engine.to_str().unwrap(),
        "--rpm",
        "1000:10999:10",
        "--imep",
        "0.4:40:0.4",
    ]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--rpm 1000:10999:10")
            && err.contains("--imep 0.4:40:0.4")
            && err.contains("100000 points")
            && err.contains("at most 10000"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(started.elapsed().as_secs_f64() < 10.0);
    // One speed past the cap (101 × 100) is refused too; the message
    // counts the points.
    let out = run(&[
        "sweep",
        "--engine",
        engine.to_str().unwrap(),
        "--rpm",
        "1000:1100:1",
        "--imep",
        "0.4:40:0.4",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("10100 points"));
}

/// A map's points say each kind of note once: the speed note of 15 points
/// is one line with the range of its speeds (it was 15 lines).
#[test]
fn a_sweeps_notes_are_grouped_by_kind_over_its_points() {
    let dir = tempfile::tempdir().unwrap();
    let engine = petrol_engine(dir.path());
    let out = run(&[
        "sweep",
        "--engine",
        engine.to_str().unwrap(),
        "--rpm",
        "1000:3000:500",
        "--imep",
        "4:12:4",
        "--step",
        "0.5",
        "--csv",
    ]);
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.lines()
            .any(|l| l == "note: 15 of 15 points: speed 1000–3000 rpm from --rpm 1000:3000:500"),
        "{err}"
    );
    assert!(!err.contains("note: speed 1500 rpm"), "{err}");
    let kinds: Vec<&str> = err.lines().collect();
    assert!(kinds.len() < 12, "{} lines: {err}", kinds.len());
    // Each kind once: no two lines the same once their numbers are set aside.
    let mut seen: Vec<String> = kinds
        .iter()
        .map(|l| enginedyn_pipeline::notes::kind(l))
        .collect();
    seen.sort();
    seen.dedup();
    assert_eq!(seen.len(), kinds.len(), "{err}");
    // A speed-only sweep groups its speeds' notes the same way.
    let out = run(&[
        "sweep",
        "--engine",
        &data("vaz2108.toml"),
        "--rpm",
        "1000:6000:500",
        "--csv",
    ]);
    let err = text(&out.stderr);
    assert!(
        err.contains("note: 11 of 11 points: speed 1000–6000 rpm from --rpm 1000:6000:500"),
        "{err}"
    );
}

/// 63 files, each at its own speed (its `# rpm` line, 800 to 3900 rpm),
/// two of them unreadable, run by an engine without a flywheel diameter:
/// most of them warn of a thin flywheel rim, each with its own numbers.
fn sixty_three_files(dir: &Path) -> (PathBuf, Vec<PathBuf>) {
    let src = std::fs::read_to_string(data("vaz2108.csv")).unwrap();
    let files: Vec<PathBuf> = (0..63)
        .map(|k| {
            let p = dir.join(format!("d{k:02}.csv"));
            if k == 7 || k == 40 {
                std::fs::write(&p, "crank_deg,pressure_bar\n").unwrap();
            } else {
                let rpm = 800 + 50 * k;
                let t: String = src
                    .lines()
                    .map(|l| {
                        if l.starts_with("# rpm") {
                            format!("# rpm = {rpm}\n")
                        } else {
                            format!("{l}\n")
                        }
                    })
                    .collect();
                std::fs::write(&p, t).unwrap();
            }
            p
        })
        .collect();
    let engine = std::fs::read_to_string(data("vaz2108.toml"))
        .unwrap()
        .replace("rpm = 4900", "rpm = 1000")
        .replace("diagram = \"vaz2108.csv\"", "");
    let e = dir.join("engine.toml");
    std::fs::write(&e, engine).unwrap();
    (e, files)
}

/// The rim's diameter at `rpm` from the rim speed (60 m/s) and δ 0.01:
/// `D = 2 v / (ω (1 + δ/2))`, in mm.
fn rim_mm(rpm: f64) -> f64 {
    let omega = rpm * std::f64::consts::PI / 30.0;
    2.0 * 60.0 / (omega * 1.005) * 1e3
}

#[test]
fn a_batch_log_is_one_line_a_kind_and_quiet_keeps_one_stdout_line() {
    let dir = tempfile::tempdir().unwrap();
    let (engine, files) = sixty_three_files(dir.path());
    let pq = dir.path().join("pq");
    let mut args: Vec<String> = vec![
        "batch".to_string(),
        "--engine".into(),
        engine.display().to_string(),
        "--parquet".into(),
        pq.display().to_string(),
        "--quiet".into(),
    ];
    args.extend(files.iter().map(|f| f.display().to_string()));
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = run(&argv);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    // Standard output: one line, never the table.
    assert!(stdout.lines().count() < 5, "{stdout}");
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    assert!(
        stdout.starts_with("63 files read, 2 failed; wrote ")
            && stdout.contains("part-00000-of-00001.parquet"),
        "{stdout}"
    );
    // Standard error: the errors, one a file, and the grouped warnings.
    assert!(stderr.lines().count() < 25, "{stderr}");
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    assert_eq!(errors.len(), 2, "{stderr}");
    assert!(
        errors.iter().any(|l| l.contains("d07.csv"))
            && errors.iter().any(|l| l.contains("d40.csv"))
    );
    assert!(!stderr.lines().any(|l| l.starts_with("note:")), "{stderr}");
    let thin: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains("the flywheel (rim) is "))
        .collect();
    assert_eq!(thin.len(), 1, "{stderr}");
    // `warning: K of 63 files: the flywheel (rim) is A–B mm wide at C–D mm …`
    let line = thin[0];
    let k: usize = line["warning: ".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        (40..=61).contains(&k) && line.contains(&format!("{k} of 63 files: ")),
        "{line}"
    );
    let at = line.split(" mm wide at ").nth(1).unwrap();
    let (lo, hi) = at.split(" mm").next().unwrap().split_once('–').unwrap();
    let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
    // The widest rim is at the slowest file, 800 rpm (±1 mm: rounded).
    assert!(
        (hi - rim_mm(800.0)).abs() <= 1.0,
        "{hi} vs {}",
        rim_mm(800.0)
    );
    assert!(lo < hi && lo >= rim_mm(3900.0) - 1.0, "{line}");
    let (wlo, whi) = line
        .split("(rim) is ")
        .nth(1)
        .unwrap()
        .split(" mm")
        .next()
        .unwrap()
        .split_once('–')
        .unwrap();
    assert!(
        wlo.parse::<f64>().unwrap() < whi.parse::<f64>().unwrap(),
        "{line}"
    );

    // Without --quiet: the table on stdout, the notes grouped on stderr
    // (no note a file).
    let argv: Vec<&str> = argv.into_iter().filter(|a| *a != "--quiet").collect();
    let out = run(&argv);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(stdout.lines().count() > 63, "{stdout}");
    assert!(stderr.lines().count() < 25, "{stderr}");
    assert!(
        // 60 files: not the two unreadable ones, nor the one at the
        // engine file's own 1000 rpm.
        stderr.lines().any(
            |l| l.starts_with("note: 60 of 63 files: speed 800–3900 rpm from the diagram file")
        ),
        "{stderr}"
    );
    assert!(
        !stderr
            .lines()
            .any(|l| l.starts_with("note: ") && l.contains(".csv: speed")),
        "{stderr}"
    );
}
