//! Synthesis for design end to end (issue 35, section 3): a template with
//! `[combustion]` reads and synthesises; `synth` writes a diagram `run`
//! reads back at the IMEP asked for; `run` without a diagram uses it with a
//! note; `sweep --imep` maps speed × load with the flywheel sized at the
//! worst point; bounds name the key.

use enginedyn_tests::{data, ok_json, run};

fn text(out: &std::process::Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `template --combustion petrol` without its `diagram`: an engine file
/// whose only diagram is the synthesised one.
fn petrol_engine(dir: &std::path::Path) -> std::path::PathBuf {
    let out = run(&["template", "--combustion", "petrol"]);
    assert!(out.status.success());
    let t = String::from_utf8(out.stdout).unwrap();
    assert!(
        t.contains("\n[combustion]\n") && t.contains("\nca50_deg = 8.0\n"),
        "{t}"
    );
    let path = dir.join("petrol.toml");
    std::fs::write(&path, t).unwrap();
    path
}

fn imep(v: &serde_json::Value) -> f64 {
    v["imep_bar"].as_f64().unwrap()
}

#[test]
fn synth_writes_a_diagram_run_reads_at_the_imep_asked() {
    let dir = tempfile::tempdir().unwrap();
    let engine = petrol_engine(dir.path());
    let e = engine.to_str().unwrap();
    let csv = dir.path().join("p.csv");
    let out = run(&[
        "synth",
        "--engine",
        e,
        "--imep",
        "9",
        "--rpm",
        "3000",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(stdout.contains("IMEP 9 bar"), "{stdout}");
    let written = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = written.lines().take_while(|l| l.starts_with('#')).collect();
    assert!(header[0].starts_with("# synthetic indicator diagram, not measured"));
    for want in [
        "start_deg = ",
        "wiebe_a = 6.908",
        "wiebe_m = 2",
        "CA50 8°",
        "imep_bar = 9 (target)",
        "gamma = 1.32",
        "intake_pressure_bar = 1",
        "ivc_deg = -140",
        "evo_deg = 130",
        "# rpm = 3000",
    ] {
        assert!(
            header.iter().any(|l| l.contains(want)),
            "{want}: {header:?}"
        );
    }
    assert_eq!(
        written.lines().filter(|l| !l.starts_with('#')).count(),
        7201
    );
    // `run` reads it like any diagram: the IMEP asked for within 0.2 %.
    let v = ok_json(&[
        "run",
        "--engine",
        e,
        "--diagram",
        csv.to_str().unwrap(),
        "--json",
    ]);
    assert!((imep(&v) / 9.0 - 1.0).abs() < 2e-3, "{}", imep(&v));
    assert!((v["rpm"].as_f64().unwrap() - 3000.0).abs() < 1e-9);
    // The file's own load (imep_bar = 10) without --imep; `-` prints it.
    let out = run(&["synth", "--engine", e, "--step", "0.5", "--out", "-"]);
    let (stdout, _) = text(&out);
    assert!(stdout.contains("imep_bar = 10 (target)"));
    assert_eq!(stdout.lines().filter(|l| !l.starts_with('#')).count(), 1441);
}

#[test]
fn run_without_a_diagram_uses_the_synthesised_one() {
    let dir = tempfile::tempdir().unwrap();
    let engine = petrol_engine(dir.path());
    let out = run(&["run", "--engine", engine.to_str().unwrap(), "--json"]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("note: diagram synthesised from [combustion]"),
        "{stderr}"
    );
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!((imep(&v) / 10.0 - 1.0).abs() < 2e-3, "{}", imep(&v));
    // The bundled engine keeps its bundled diagram.
    let bundled = ok_json(&["run", "--engine", &data("vaz2108.toml"), "--json"]);
    assert!((imep(&bundled) - 10.47).abs() < 0.05, "{}", imep(&bundled));
}

#[test]
fn diesel_template_synthesises() {
    let out = run(&["template", "--combustion", "diesel"]);
    assert!(out.status.success());
    let t = String::from_utf8(out.stdout).unwrap();
    assert!(
        t.contains("\n[combustion.second]\nfraction = 0.8") || t.contains("\nfraction = 0.8\n"),
        "{t}"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.toml");
    std::fs::write(&path, t).unwrap();
    let v = ok_json(&["run", "--engine", path.to_str().unwrap(), "--json"]);
    assert!((imep(&v) / 18.0 - 1.0).abs() < 2e-3, "{}", imep(&v));
}

#[test]
fn sweep_maps_speed_and_load_with_the_worst_point_named() {
    let dir = tempfile::tempdir().unwrap();
    let engine = petrol_engine(dir.path());
    let out_dir = dir.path().join("map");
    let out = run(&[
        "sweep",
        "--engine",
        engine.to_str().unwrap(),
        "--rpm",
        "1000:4000:1000",
        "--imep",
        "4:10:3",
        "--step",
        "0.5",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let (_, stderr) = text(&out);
    assert!(out.status.success(), "{stderr}");
    // The flywheel is sized at the point needing most: low speed, high load.
    assert!(
        stderr.contains("flywheel sized once at 1000 rpm and IMEP 10 bar"),
        "{stderr}"
    );
    let csv = std::fs::read_to_string(out_dir.join("sweep.csv")).unwrap();
    let mut lines = csv.lines();
    // The columns are appended: the target, then the sizing point named
    // apart, the last of each row (notes hold commas).
    let header = lines.next().unwrap();
    assert!(
        header.ends_with(",imep_target_bar,flywheel_sized_at_rpm,flywheel_sized_at_imep_bar"),
        "{header}"
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 4 * 3);
    for r in &rows {
        assert!(r.ends_with(",1000,10"), "{r}");
    }
    let loads: Vec<&str> = rows.iter().map(|r| r.rsplit(',').nth(2).unwrap()).collect();
    assert_eq!(
        loads,
        [
            "4", "4", "4", "4", "7", "7", "7", "7", "10", "10", "10", "10"
        ]
    );
    let svg = std::fs::read_to_string(out_dir.join("sweep.svg")).unwrap();
    assert!(svg.contains("IMEP 4 bar") && svg.contains("IMEP 10 bar"));
    // --json: one object per point, with its target.
    let v = ok_json(&[
        "sweep",
        "--engine",
        engine.to_str().unwrap(),
        "--rpm",
        "2000:3000:1000",
        "--imep",
        "5:6:1",
        "--step",
        "0.5",
        "--json",
    ]);
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), 4);
    for p in a {
        let target = p["imep_target_bar"].as_f64().unwrap();
        assert!(
            (imep(p) / target - 1.0).abs() < 2e-3,
            "{} vs {target}",
            imep(p)
        );
    }
}

#[test]
fn bounds_name_the_key_or_flag() {
    let dir = tempfile::tempdir().unwrap();
    let engine = petrol_engine(dir.path());
    let t = std::fs::read_to_string(&engine).unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        t.replace("\nca50_deg = 8.0\n", "\nca50_deg = 300.0\n"),
    )
    .unwrap();
    let out = run(&["synth", "--engine", bad.to_str().unwrap(), "--out", "-"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out).1.contains("`combustion.ca50_deg`"),
        "{}",
        text(&out).1
    );
    for (flag, value) in [("--imep", "0"), ("--imep", "-3"), ("--step", "0.7")] {
        let out = run(&[
            "synth",
            "--engine",
            engine.to_str().unwrap(),
            flag,
            value,
            "--out",
            "-",
        ]);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}");
        assert!(text(&out).1.contains(flag), "{}", text(&out).1);
    }
    // No [combustion]: said, exit 2.
    let out = run(&["synth", "--engine", &data("vaz2108.toml"), "--out", "-"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out).1.contains("no [combustion] section"),
        "{}",
        text(&out).1
    );
    let out = run(&[
        "sweep",
        "--engine",
        engine.to_str().unwrap(),
        "--rpm",
        "1000:2000:500",
        "--imep",
        "9:4:1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out).1.contains("--imep 9:4:1"), "{}", text(&out).1);
}
