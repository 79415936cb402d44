//! Runs the `enginedyn` binary as a user would and checks what it writes.

use enginedyn_tests::run;

const CURVE_COLUMNS: &[&str] = &[
    "crank_deg",
    "pressure_bar",
    "volume_m3",
    "piston_x_m",
    "piston_v_m_s",
    "piston_a_m_s2",
    "rod_angle_deg",
    "force_gas_n",
    "force_inertia_n",
    "force_total_n",
    "force_side_n",
    "force_rod_n",
    "force_radial_n",
    "force_tangential_n",
    "crankpin_load_n",
    "crankpin_load_angle_deg",
    "torque_cylinder_nm",
    "torque_engine_nm",
    "excess_energy_j",
    "torque_journal_1_nm",
    "torque_journal_4_nm",
];

/// The bundled example with --out: every required key present and finite
/// (the example is a firing engine, so nothing may be null), every curve
/// column present, the energy balance within 1e-4 (issue 3's bound).
#[test]
fn bundled_example_writes_everything() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["run", "--out", dir.path().to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(printed, s, "--json prints the summary.json object");
    // The keys as INTERFACE.md lists them, in its order, each a finite
    // number (the example fires, so nothing is null).
    let keys = enginedyn_tests::contract_summary_keys().unwrap_or_default();
    if keys.is_empty() {
        eprintln!("../shared/spec/INTERFACE.md not beside the checkout: key list not checked");
    } else {
        assert!(
            keys.len() >= 34 && keys.contains(&"indicated_power_kw".to_string()),
            "{keys:?}"
        );
    }
    let order: Vec<&String> = s.as_object().unwrap().keys().collect();
    let mut last = 0;
    for k in &keys {
        let v = &s[k.as_str()];
        assert!(v.as_f64().is_some_and(f64::is_finite), "{k} = {v}");
        let at = order.iter().position(|o| *o == k).unwrap();
        assert!(at >= last, "{k} out of INTERFACE.md's order");
        last = at;
    }
    for k in [
        "kinematics",
        "rod_model",
        "interpolation",
        "grid_step_deg",
        "integration",
    ] {
        assert!(!s["models"][k].is_null(), "models.{k}");
    }
    assert!(s["notes"].is_array());
    assert!(s["energy_balance_error"].as_f64().unwrap() < 1e-4);
    // The example's engine file has [tolerances]: the page carries the table
    // and the tornado chart.
    let page = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    assert!(page.contains("<h2>Tolerances</h2>") && page.contains("id=\"tolerance\""));
    assert!(page.contains("<th>mean_torque_nm</th>"));
    assert!(dir.path().join("tolerance.svg").exists());
    let curves = std::fs::read_to_string(dir.path().join("curves.csv")).unwrap();
    let header: Vec<&str> = curves.lines().next().unwrap().split(',').collect();
    for c in CURVE_COLUMNS {
        assert!(header.contains(c), "curves.csv lacks {c}");
    }
    // 0.1° over 720°: 7200 rows plus the header; every cell a finite number.
    assert_eq!(curves.lines().count(), 7201);
    for line in curves.lines().skip(1) {
        for cell in line.split(',') {
            assert!(cell.parse::<f64>().is_ok_and(f64::is_finite), "cell {cell}");
        }
    }
    for f in ["torque.svg", "harmonics.csv"] {
        assert!(dir.path().join(f).exists(), "{f}");
    }
    // No temporary files left behind: the manifest is the one hidden name.
    for e in std::fs::read_dir(dir.path()).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        assert!(
            !name.starts_with('.') || name == enginedyn_report::MANIFEST,
            "leftover {name}"
        );
    }
}

/// An unknown engine key exits 2 and names the key and its nearest neighbour.
#[test]
fn unknown_engine_key_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        "cycle = \"four-stroke\"\ncylinders = 1\nbore = 80.0\n",
    )
    .unwrap();
    let out = run(&["run", "--engine", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("`bore`") && err.contains("bore_mm") && err.contains("bad.toml"),
        "{err}"
    );
    assert!(!err.contains("panicked"));
}

/// A diagram with a non-numeric cell exits 1, naming file, line and column,
/// and writes no output folder.
#[test]
fn bad_diagram_exits_1_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("d.csv");
    std::fs::write(&csv, "crank_deg,pressure_bar\n0,10\n90,abc\n180,1\n").unwrap();
    let out_dir = dir.path().join("out");
    let out = run(&[
        "run",
        "--diagram",
        csv.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("d.csv") && err.contains("line 3") && err.contains("column 2"),
        "{err}"
    );
    assert!(!out_dir.exists());
}

/// A step that does not divide the cycle is a usage error (exit 2).
#[test]
fn bad_step_exits_2() {
    let out = run(&["run", "--step", "0.7"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--step"));
}

/// The readable table names the key figures with units.
#[test]
fn readable_table() {
    let out = run(&["run"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for s in [
        "IMEP",
        "bar",
        "mean torque",
        "N m",
        "required inertia",
        "kg m²",
    ] {
        assert!(text.contains(s), "{s} missing from\n{text}");
    }
}

/// `enginedyn` with no arguments at all is `enginedyn run` (the README's
/// `cargo run --release`): the bundled example's table, exit 0, and one
/// line on stderr pointing to `--help`.
#[test]
fn bare_binary_runs_the_example() {
    let out = run(&[]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("VAZ-2108"), "{text}");
    assert_eq!(text, String::from_utf8_lossy(&run(&["run"]).stdout));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.lines().filter(|l| l.contains("--help")).count(),
        1,
        "{err}"
    );
}

/// `kinematics --csv` prints the seed table's columns; at 0° the exact
/// acceleration coefficient is 1 + lambda = 1.26.
#[test]
fn kinematics_csv() {
    let engine = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.toml");
    let out = run(&["kinematics", "--engine", engine, "--csv", "--step", "10"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "crank_deg,coef_a,coef_b,coef_c,piston_x_m,piston_v_m_s,piston_a_m_s2,rod_angle_deg"
    );
    let first: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|c| c.parse().unwrap())
        .collect();
    assert!((first[3] - 1.26).abs() < 1e-12);
    assert_eq!(text.lines().count(), 1 + 37);
}

/// Turning-moment input: the cylinder torque that a pressure run writes,
/// fed back with --torque on the same grid, gives the same mean torque,
/// excess work and flywheel to rounding (1e-9 relative); the pressure keys
/// are null with a note.
#[test]
fn torque_input_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["run", "--out", dir.path().to_str().unwrap(), "--json"]);
    assert!(out.status.success());
    let first: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let curves = std::fs::read_to_string(dir.path().join("curves.csv")).unwrap();
    let mut lines = curves.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = header
        .iter()
        .position(|h| *h == "torque_cylinder_nm")
        .unwrap();
    let mut t = String::from("# rpm = 4900\ncrank_deg,torque_cylinder_nm\n");
    for l in lines {
        let c: Vec<&str> = l.split(',').collect();
        t.push_str(&format!("{},{}\n", c[0], c[i]));
    }
    let tf = dir.path().join("t.csv");
    std::fs::write(&tf, t).unwrap();
    let out = run(&["run", "--torque", tf.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let second: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for k in [
        "mean_torque_nm",
        "excess_work_j",
        "required_inertia_kg_m2",
        "torque_max_nm",
        "flywheel_mass_kg",
    ] {
        let (a, b) = (first[k].as_f64().unwrap(), second[k].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * a.abs(), "{k}: {a} vs {b}");
    }
    for k in [
        "imep_bar",
        "indicated_work_per_cylinder_j",
        "energy_balance_error",
        "gas_force_max_n",
        "crankpin_load_max_n",
    ] {
        assert!(second[k].is_null(), "{k} should be null");
    }
    assert!(
        second["notes"]
            .as_array()
            .unwrap()
            .iter()
            .any(|n| n.as_str().unwrap().contains("turning-moment"))
    );
}

/// Every bundled engine end to end, with PHYSICS.md's invariants checked on
/// what the binary writes: the energy balance (mean torque = z W_i / Phi),
/// the last journal carrying the engine torque, T R = P dx/dphi (two-mass
/// rod: T times R equals the cylinder torque), the speed trace giving the
/// delta asked for, and the harmonics (orders up to 24) rebuilding the
/// engine torque to within the truncation of the series.
#[test]
fn every_bundled_engine_keeps_the_invariants() {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");
    let mut engines: Vec<_> = std::fs::read_dir(data)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    engines.sort();
    assert!(engines.len() >= 6, "bundled engines: {engines:?}");
    for engine in engines {
        let dir = tempfile::tempdir().unwrap();
        let out = run(&[
            "run",
            "--engine",
            engine.to_str().unwrap(),
            "--out",
            dir.path().to_str().unwrap(),
            "--json",
        ]);
        assert!(
            out.status.success(),
            "{engine:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let name = engine.display().to_string();
        assert!(s["energy_balance_error"].as_f64().unwrap() < 1e-9, "{name}");
        let text = std::fs::read_to_string(&engine).unwrap();
        let delta: f64 = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("speed_fluctuation = "))
            .map_or(0.01, |v| v.trim().parse().unwrap());
        assert!(
            (s["speed_fluctuation_achieved"].as_f64().unwrap() - delta).abs() < 1e-9,
            "{name}"
        );
        let r = s["stroke_m"].as_f64().unwrap() / 2.0;
        let curves = std::fs::read_to_string(dir.path().join("curves.csv")).unwrap();
        let mut lines = curves.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
        let last_journal = header
            .iter()
            .rposition(|h| h.starts_with("torque_journal_"))
            .unwrap();
        let (ct, et, tt, deg) = (
            col("torque_cylinder_nm"),
            col("torque_engine_nm"),
            col("force_tangential_n"),
            col("crank_deg"),
        );
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
            .collect();
        let scale = rows
            .iter()
            .fold(0.0_f64, |m, r| m.max(r[et].abs()).max(r[ct].abs()));
        for row in &rows {
            assert!(
                (row[last_journal] - row[et]).abs() <= 1e-9 * scale,
                "{name}: last journal"
            );
            assert!(
                (row[tt] * r - row[ct]).abs() <= 1e-9 * scale,
                "{name}: T R = M"
            );
        }
        let harmonics = std::fs::read_to_string(dir.path().join("harmonics.csv")).unwrap();
        let h: Vec<Vec<f64>> = harmonics
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
            .collect();
        let (lo, hi) = rows.iter().fold((f64::MAX, f64::MIN), |(a, b), r| {
            (a.min(r[et]), b.max(r[et]))
        });
        let mut worst = 0.0_f64;
        for row in rows.iter().step_by(7) {
            let phi = row[deg].to_radians();
            let rebuilt: f64 = h
                .iter()
                .map(|x| {
                    if x[0].abs() < 1e-12 {
                        x[3]
                    } else {
                        x[3] * (x[0] * phi + x[4].to_radians()).cos()
                    }
                })
                .sum();
            worst = worst.max((rebuilt - row[et]).abs());
        }
        // Orders above 24 are cut off: a few percent of the swing at most.
        assert!(
            worst < 0.03 * (hi - lo),
            "{name}: harmonics rebuild within {worst} of a {} swing",
            hi - lo
        );
    }
}

fn bundled_csv() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.csv")).unwrap()
}

/// Measured-data keys: several cycles give the cycle statistics and
/// pegging its report. The trace is fired, so there is no TDC offset
/// estimate (it needs a motored or fuel-cut cycle): the key is absent and
/// one note says why.
#[test]
fn measured_data_keys() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = String::from("# rpm = 4900\ncycle,crank_deg,pressure_bar\n");
    for (c, f) in [0.95, 1.0, 1.05].iter().enumerate() {
        for l in bundled_csv()
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("crank"))
        {
            let (a, p) = l.split_once(',').unwrap();
            let p: f64 = p.parse().unwrap();
            s.push_str(&format!("{c},{a},{}\n", 1.0 + (p - 1.0) * f - 0.4));
        }
    }
    let f = dir.path().join("cycles.csv");
    std::fs::write(&f, s).unwrap();
    let out = run(&[
        "run",
        "--diagram",
        f.to_str().unwrap(),
        "--peg-bar",
        "0.95",
        "--tdc-deg",
        "1",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["cycles"], 3);
    for k in [
        "imep_std_bar",
        "imep_cov",
        "p_max_mean_bar",
        "p_max_cov",
        "p_max_angle_mean_deg",
        "p_max_angle_std_deg",
    ] {
        assert!(j[k].as_f64().is_some_and(f64::is_finite), "{k}: {}", j[k]);
    }
    assert_eq!(j["pegging"]["method"], "bar");
    assert!((j["pegging"]["offset_bar"].as_f64().unwrap() - 0.4).abs() < 0.06);
    assert!(j.get("tdc_offset_estimate_deg").is_none(), "{j}");
    let why: Vec<&str> = j["notes"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|n| n.as_str())
        .filter(|n| n.contains("TDC offset"))
        .collect();
    assert_eq!(why.len(), 1, "{why:?}");
    assert!(
        why[0]
            .starts_with("no TDC offset estimate: the estimate needs a motored or fuel-cut cycle"),
        "{}",
        why[0]
    );
}

/// A motored (fuel-cut) diagram whose firing TDC lies 1.3° after the
/// file's 0, written at 0.5° as the bundled one is, with Woschni wall heat
/// and blow-by: `run` finds the offset within 0.2° and says to add it to
/// `--tdc-deg`; run again with that `--tdc-deg`, it finds less than 0.1°
/// and says nothing more.
#[test]
fn tdc_offset_estimate_round_trip() {
    use enginedyn_synth::{CycleModel, CycleSolution, Losses, write_csv};
    let engine = enginedyn_tests::data("vaz2108.toml");
    let text = std::fs::read_to_string(&engine).unwrap();
    let e = enginedyn_engine::file::parse(&text, "vaz2108.toml").unwrap();
    let m = CycleModel {
        heat_released_j: 0.0,
        losses: Losses::warm_engine(1500.0),
        ..CycleModel::petrol_full_load()
    };
    let sol = CycleSolution::new(e.cylinder(), &m).unwrap();
    let trace: Vec<(f64, f64)> = (0..1440)
        .map(|k| {
            let a = k as f64 * 0.5;
            (a, sol.pressure(a - 1.3))
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("motored.csv");
    let mut bytes = Vec::new();
    write_csv(&mut bytes, &trace, Some(1500.0), &["motored, TDC at 1.3"]).unwrap();
    std::fs::write(&f, bytes).unwrap();
    let f = f.to_str().unwrap();
    let j = enginedyn_tests::ok_json(&["run", "--engine", &engine, "--diagram", f, "--json"]);
    let d = j["tdc_offset_estimate_deg"].as_f64().unwrap();
    assert!((d - 1.3).abs() < 0.2, "estimate {d}");
    let notes = j["notes"].as_array().unwrap();
    assert!(
        notes
            .iter()
            .filter_map(|n| n.as_str())
            .any(|n| n.starts_with("the trace suggests firing TDC lies +1.")
                && n.contains("add it to --tdc-deg")),
        "{notes:?}"
    );
    let tdc = format!("{d}");
    let again = enginedyn_tests::ok_json(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        f,
        "--tdc-deg",
        &tdc,
        "--json",
    ]);
    let rest = again["tdc_offset_estimate_deg"].as_f64().unwrap();
    assert!(rest.abs() < 0.1, "after --tdc-deg {tdc}: {rest}");
    assert!(
        !again["notes"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|n| n.as_str())
            .any(|n| n.contains("TDC")),
        "{}",
        again["notes"]
    );
}

/// One file per cylinder: four files for the four cylinders; equal files
/// give the same result as the single diagram; a wrong count exits 2.
#[test]
fn one_file_per_cylinder() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("c.csv");
    std::fs::write(&f, bundled_csv()).unwrap();
    let p = f.to_str().unwrap();
    let out = run(&["run", "--diagram", p, p, p, p, "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let four: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let one: serde_json::Value = serde_json::from_slice(&run(&["run", "--json"]).stdout).unwrap();
    for k in [
        "mean_torque_nm",
        "imep_bar",
        "excess_work_j",
        "crankpin_load_max_n",
    ] {
        let (a, b) = (four[k].as_f64().unwrap(), one[k].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * a.abs(), "{k}: {a} vs {b}");
    }
    let out = run(&["run", "--diagram", p, p]);
    assert_eq!(out.status.code(), Some(2));
}

/// `batch`: rows in input order whatever the scheduling, a bad file's error
/// in its row and on stderr while the others finish, exit 1; the header is
/// `file,error` then the summary keys in INTERFACE.md's order; with
/// `--tolerance` each row carries its estimated error, and a tolerance no
/// setting meets is refused with exit 2.
#[test]
fn batch_rows_in_input_order() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.csv");
    std::fs::write(&good, bundled_csv()).unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "crank_deg,pressure_bar\n0,1\n1,x\n").unwrap();
    let engine = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.toml");
    let g = good.to_str().unwrap();
    let out_dir = dir.path().join("out");
    let out = run(&[
        "batch",
        "--engine",
        engine,
        g,
        bad.to_str().unwrap(),
        g,
        g,
        "--jobs",
        "2",
        "--out",
        out_dir.to_str().unwrap(),
        "--detail",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.csv: line 3, column 2"));
    let csv = std::fs::read_to_string(out_dir.join("summary.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(
        lines[0].starts_with("file,error,rpm,omega_rad_s,imep_bar,"),
        "{}",
        lines[0]
    );
    assert!(lines[0].contains(",models.kinematics,") && lines[0].contains(",notes"));
    assert_eq!(lines.len(), 5);
    assert!(lines[1].starts_with(g) && lines[2].contains("bad.csv,") && lines[3].starts_with(g));
    assert!(lines[2].contains("is not a number"));
    // Run folders and index rows count from 1, the same way.
    assert!(out_dir.join("0001_good/report.html").exists() && out_dir.join("index.html").exists());
    assert!(!out_dir.join("0000_good").exists());
    let index = std::fs::read_to_string(out_dir.join("index.html")).unwrap();
    assert!(
        index.contains("<tr><td>4</td><td>") && index.contains("href=\"0004_good/report.html\"")
    );
    // Each row shows its speed (a campaign spans speeds); a failed row's
    // error spans the figures' columns.
    let rpm: f64 = lines[1].split(',').nth(2).unwrap().parse().unwrap();
    assert!(index.contains(&format!("<td>{g}</td><td class=\"v\">{rpm:.0}</td>")));
    assert!(index.contains("<th>speed (rpm)</th>") && index.contains("colspan=\"11\""));
    let out = run(&[
        "batch",
        "--engine",
        engine,
        g,
        "--tolerance",
        "0.01",
        "--csv",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let csv = String::from_utf8_lossy(&out.stdout);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let row = csv_cells(csv.lines().nth(1).unwrap());
    let col = header
        .iter()
        .position(|h| *h == "estimated_relative_error")
        .expect("estimated_relative_error column");
    let e: f64 = row[col].parse().unwrap();
    assert!(e > 0.0 && e <= 0.01, "{e}");
    let out = run(&["batch", "--engine", engine, g, "--tolerance", "0.9"]);
    assert_eq!(out.status.code(), Some(2));
}

/// The hidden `--stage-times` of `batch` (the bench script reads it): one
/// stderr line in the format the script parses, both stages measured
/// (above zero) and together less than the whole process took.
#[test]
fn batch_stage_times() {
    let g = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.csv");
    let engine = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.toml");
    let started = std::time::Instant::now();
    let out = run(&[
        "batch",
        "--engine",
        engine,
        g,
        g,
        g,
        "--jobs",
        "1",
        "--stage-times",
    ]);
    let wall = started.elapsed().as_secs_f64();
    assert_eq!(out.status.code(), Some(0));
    let err = String::from_utf8_lossy(&out.stderr);
    let line = err
        .lines()
        .find_map(|l| l.strip_prefix("stage times over 3 diagrams: grid "))
        .unwrap_or_else(|| panic!("no stage-times line in {err}"));
    let (grid, rest) = line.split_once(" s, analysis ").expect("analysis time");
    let grid: f64 = grid.parse().unwrap();
    let analysis: f64 = rest.strip_suffix(" s").unwrap().parse().unwrap();
    assert!(grid > 0.0 && analysis > 0.0, "{line}");
    assert!(grid + analysis < wall, "{line} against {wall} s");
}

/// `sweep`: one row per speed, TO included when on the step; the mean
/// torque does not depend on speed (same pressures), the crank-pin load does;
/// the chart has one unit per panel.
#[test]
fn sweep_over_speed() {
    let dir = tempfile::tempdir().unwrap();
    let engine = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.toml");
    let out = run(&[
        "sweep",
        "--engine",
        engine,
        "--rpm",
        "1000:5000:1000",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.path().join("sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), 6);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let (r, m) = (
        header.iter().position(|h| *h == "rpm").unwrap(),
        header.iter().position(|h| *h == "mean_torque_nm").unwrap(),
    );
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows[4][r], "5000");
    let m0: f64 = rows[0][m].parse().unwrap();
    for row in &rows {
        let mi: f64 = row[m].parse().unwrap();
        assert!((mi - m0).abs() < 1e-9 * m0.abs());
    }
    // One unit per panel (forces and the flywheel inertia were once one
    // axis, the forces flattened by the inertia's numbers).
    let svg = std::fs::read_to_string(dir.path().join("sweep.svg")).unwrap();
    for label in [
        "torque (N m)",
        "force (kN)",
        "speed fluctuation δ with the flywheel sized once",
        "crank-pin load max",
        "gas force max",
    ] {
        assert!(svg.contains(label), "sweep.svg lacks {label:?}");
    }
    // One flywheel for the sweep: its keys equal on every row, sized at the
    // engine file's 4900 rpm; δ is what it gives at each speed. The
    // inertia each speed needs is its own (issue 41: the sizing point's
    // stood on every row): ΔE / (δ ω²) with the file's δ of 0.01.
    let col = |k: &str| header.iter().position(|h| *h == k).unwrap();
    let num = |r: &Vec<&str>, k: &str| r[col(k)].parse::<f64>().unwrap();
    for r in &rows {
        let w = num(r, "omega_rad_s");
        let want = num(r, "excess_work_j") / (0.01 * w * w);
        let got = num(r, "required_inertia_kg_m2");
        assert!((got / want - 1.0).abs() < 1e-9, "{got} for {want}");
    }
    for k in [
        "flywheel_inertia_kg_m2",
        "flywheel_outer_diameter_m",
        "flywheel_mass_kg",
        "flywheel_width_m",
    ] {
        assert!(
            rows.iter().all(|r| r[col(k)] == rows[0][col(k)]),
            "{k} differs between rows"
        );
    }
    let delta: Vec<f64> = rows
        .iter()
        .map(|r| r[col("speed_fluctuation_achieved")].parse().unwrap())
        .collect();
    assert!(delta[0] > 10.0 * delta[3], "{delta:?}");
    let at = run(&[
        "sweep",
        "--engine",
        engine,
        "--rpm",
        "4900:4900:100",
        "--csv",
    ]);
    let text = String::from_utf8_lossy(&at.stdout);
    let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    let k = head
        .iter()
        .position(|h| *h == "speed_fluctuation_achieved")
        .unwrap();
    let i0 = head
        .iter()
        .position(|h| *h == "flywheel_inertia_kg_m2")
        .unwrap();
    assert!(
        (row[k].parse::<f64>().unwrap() - 0.01).abs() < 1e-9,
        "{text}"
    );
    // The part of the sweep is the one sized at 4900 rpm.
    assert_eq!(row[i0], rows[0][col("flywheel_inertia_kg_m2")]);
    // Without --out and --csv: a readable table, one row per speed.
    let out = run(&["sweep", "--engine", engine, "--rpm", "1000:3000:1000"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("flywheel sized once at 4900 rpm"), "{text}");
    assert!(text.lines().any(|l| l.starts_with("2000 ")), "{text}");
    assert!(
        text.contains("mean torque, effective (η_m = 0.80) (N m)"),
        "{text}"
    );
    assert!(!text.contains("omega_rad_s"), "{text}");
}

/// `batch` without --out prints a readable table, one row per diagram with
/// its key figures; `--csv` prints summary.csv instead.
#[test]
fn batch_readable_table() {
    let engine = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.toml");
    let diagram = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/vaz2108.csv");
    let out = run(&["batch", "--engine", engine, diagram]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("[2] IMEP (bar)") && text.contains("10.471"),
        "{text}"
    );
    assert!(!text.contains("omega_rad_s"), "{text}");
    let out = run(&["batch", "--engine", engine, diagram, "--csv"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("file,error,rpm,omega_rad_s,"), "{text}");
}

/// Effective and indicated figures: `mean_torque_nm` is the indicated mean
/// times η_m, μ follows from the printed indicated torques, and the table
/// labels each figure.
#[test]
fn effective_and_indicated() {
    let out = run(&["run", "--json"]);
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f = |k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k}"));
    let eta = 0.80; // data/vaz2108.toml
    assert!(
        (f("mean_torque_nm") - eta * f("indicated_mean_torque_nm")).abs()
            < 1e-12 * f("mean_torque_nm")
    );
    assert!((f("power_kw") - eta * f("indicated_power_kw")).abs() < 1e-12 * f("power_kw"));
    let mu = (f("torque_max_nm") - f("torque_min_nm")) / f("indicated_mean_torque_nm");
    assert!((mu - f("torque_nonuniformity")).abs() < 1e-12 * mu);
    let text = String::from_utf8_lossy(&run(&["run"]).stdout).to_string();
    let value = |label: &str| -> f64 {
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with(label))
            .unwrap_or_else(|| panic!("{label}\n{text}"));
        line[label.len()..]
            .split_whitespace()
            .find_map(|t| t.parse().ok())
            .unwrap()
    };
    let printed_mu = (value("torque max, indicated") - value("torque min, indicated"))
        / value("mean torque, indicated");
    assert!(
        (printed_mu - value("non-uniformity μ")).abs() < 1e-3,
        "{text}"
    );
    assert!(
        text.contains("mean torque, effective (η_m = 0.80)"),
        "{text}"
    );
    // Units stay in the unit column: the journal's number ends its line.
    let journal = text
        .lines()
        .find(|l| l.contains("most loaded main journal"))
        .unwrap();
    assert!(
        journal
            .split_whitespace()
            .last()
            .unwrap()
            .parse::<usize>()
            .is_ok(),
        "{journal}"
    );
}

/// A speed other than the engine file's is said in the notes, with where it
/// came from; a negative or absurd `--rpm` is refused with its reason.
#[test]
fn speed_notes_and_bounds() {
    let out = run(&["run", "--rpm", "3000", "--json"]);
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let notes = s["notes"].to_string();
    assert!(
        notes.contains("speed 3000 rpm from --rpm, not the engine file's operating.rpm = 4900 rpm"),
        "{notes}"
    );
    let plain: serde_json::Value = serde_json::from_slice(&run(&["run", "--json"]).stdout).unwrap();
    assert!(!plain["notes"].to_string().contains("speed"));
    for (rpm, says) in [
        ("-100", "above 0"),
        ("1e12", "from 0.001 to 100000 rpm"),
        ("1e-300", "from 0.001 to 100000 rpm"),
        ("nan", "from 0.001 to 100000 rpm"),
    ] {
        let out = run(&["run", "--rpm", rpm]);
        assert_eq!(out.status.code(), Some(2), "{rpm}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--rpm") && err.contains(says), "{rpm}: {err}");
    }
}

/// Typed flags: each value of --peg, --pv-start and --angles is accepted
/// and a wrong one is a usage error naming the flag.
#[test]
fn typed_flags() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let out = run(&["run", "--angles", "centered", "--out", d]);
    assert_eq!(out.status.code(), Some(0));
    let curves = std::fs::read_to_string(dir.path().join("curves.csv")).unwrap();
    assert!(curves.lines().nth(1).unwrap().starts_with("-360,"));
    // Every CSV number in shortest form, exponent only when tiny or huge.
    for cell in curves.lines().skip(1).flat_map(|l| l.split(',')) {
        let digits = cell.trim_start_matches('-');
        assert!(!digits.starts_with("0.00000"), "{cell}");
        assert!(digits.split('.').next().unwrap().len() <= 16, "{cell}");
    }
    for args in [
        &["--peg", "polytropic"][..],
        &["--peg", "polytropic=1.3"],
        &["--peg-bar", "1.0"],
        &["--pv-start", "tdc"],
        &["--angles", "cycle"],
    ] {
        let out = run(&[&["run", "--json"][..], args].concat());
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let pegged: serde_json::Value =
        serde_json::from_slice(&run(&["run", "--json", "--peg", "polytropic=1.3"]).stdout).unwrap();
    assert_eq!(pegged["pegging"]["method"], "polytropic");
    assert_eq!(pegged["pegging"]["polytropic_n"], 1.3);
    for (flag, value) in [
        ("--peg", "polytropic=3"),
        ("--peg", "linear"),
        ("--pv-start", "middle"),
        ("--angles", "degrees"),
        ("--kinematics", "series3"),
    ] {
        let out = run(&["run", flag, value]);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(flag),
            "{flag} {value}"
        );
    }
    let out = run(&["run", "--peg", "polytropic", "--peg-bar", "1"]);
    assert_eq!(out.status.code(), Some(2));
}

/// `--tolerance` keeps a method flag given beside it and chooses the rest
/// around it; one that cannot meet it is refused (exit 2) naming the flag.
/// On the single cylinder (λ ≈ 0.32) the piston's acceleration extremes
/// stay within REL of exact kinematics (series2 missed them by 1.1e-2).
#[test]
fn tolerance_keeps_given_flags() {
    let engine = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/single.toml");
    let json = |args: &[&str]| -> serde_json::Value {
        let out = run(&[&["run", "--engine", engine, "--json"][..], args].concat());
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let exact = json(&[]);
    let chosen = json(&["--tolerance", "1e-2"]);
    for k in [
        "piston_accel_min_m_s2",
        "piston_accel_max_m_s2",
        "piston_speed_max_m_s",
    ] {
        let (a, b) = (chosen[k].as_f64().unwrap(), exact[k].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-2 * b.abs(), "{k}: {a} against {b}");
    }
    let kept = json(&[
        "--tolerance",
        "1e-2",
        "--step",
        "1",
        "--rod-model",
        "two-mass",
    ]);
    assert_eq!(kept["models"]["grid_step_deg"], 1.0);
    assert_eq!(kept["models"]["rod_model"], "two-mass");
    let out = run(&[
        "run",
        "--engine",
        engine,
        "--tolerance",
        "1e-2",
        "--kinematics",
        "series2",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--kinematics series2 cannot meet --tolerance 0.01"),
        "{err}"
    );
}

/// The cells of one CSV line, quotes honoured (notes hold commas).
fn csv_cells(line: &str) -> Vec<String> {
    let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cell.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => cells.push(std::mem::take(&mut cell)),
            _ => cell.push(c),
        }
    }
    cells.push(cell);
    cells
}

/// report.html's tolerance table shows the run's own I₀ as nominal (the
/// tolerance study runs on a coarser grid), as the summary does.
#[test]
fn tolerance_table_nominal_is_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["run", "--out", dir.path().to_str().unwrap(), "--json"]);
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let html = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    let cell = "required_inertia_kg_m2</th><td class=\"v\">";
    let at = html.find(cell).expect("tolerance row") + cell.len();
    let text = html[at..].split('<').next().unwrap();
    let shown: f64 = text.parse().unwrap();
    let i0 = s["required_inertia_kg_m2"].as_f64().unwrap();
    // Within half a unit of the last digit shown: the run's own value
    // rounded. The tolerance study's 0.5° grid gave 0.08451 for the run's
    // 0.0845165 (a 3e-5 difference that the looser bound let pass).
    let decimals = text.split('.').nth(1).map_or(0, str::len) as i32;
    let half = 0.5 * 10f64.powi(-decimals);
    assert!(
        (shown - i0).abs() <= half * (1.0 + 1e-9),
        "{text} against {i0}"
    );
}

/// An engine file with `[torsion]` gives `run`'s report.html a torsion
/// section with the Campbell and response charts; the Campbell legend
/// names modes and orders, not every resonance.
#[test]
fn run_report_has_the_torsion_section() {
    let dir = tempfile::tempdir().unwrap();
    let engine = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/i6_diesel.toml");
    let out = run(&[
        "run",
        "--engine",
        engine,
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    assert!(page.contains("<h2>Torsional vibration</h2>") && page.contains("id=\"campbell\""));
    let campbell = std::fs::read_to_string(dir.path().join("campbell.svg")).unwrap();
    assert!(campbell.contains("resonance (order × mode"));
    assert!(
        !campbell.contains(" at 1804 rpm"),
        "one legend entry per resonance"
    );
    let plain = tempfile::tempdir().unwrap();
    let vaz = run(&["run", "--out", plain.path().to_str().unwrap()]);
    assert_eq!(vaz.status.code(), Some(0));
    assert!(!plain.path().join("campbell.svg").exists());
}

/// `modes.csv` as README and INTERFACE.md say: one row per elastic mode,
/// a column per mass from the free end with the damper ring first, each
/// mode normalised to the free end (the front mass) = 1; the V8's modes are
/// those data/README.md quotes.
#[test]
fn modes_csv_is_normalised_to_the_free_end() {
    for (stem, first_hz) in [("i6_diesel", 45.1), ("v8_crossplane", 273.7)] {
        let dir = tempfile::tempdir().unwrap();
        let engine = enginedyn_tests::data(&format!("{stem}.toml"));
        let out = run(&[
            "torsion",
            "--engine",
            &engine,
            "--out",
            dir.path().to_str().unwrap(),
        ]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(dir.path().join("modes.csv")).unwrap();
        let mut lines = text.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(
            &head[..5],
            &["mode", "frequency_hz", "damper_ring", "front", "throw_1"]
        );
        assert_eq!(head.last(), Some(&"flywheel"));
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        assert_eq!(
            rows.len(),
            head.len() - 3,
            "{stem}: one row per elastic mode"
        );
        for r in &rows {
            // The free end (column "front") reads 1 to the last bit printed.
            assert!((r[3] - 1.0).abs() < 1e-12, "{stem} mode {}: {}", r[0], r[3]);
        }
        // The first natural frequency to the 0.1 Hz data/README.md prints.
        assert!(
            (rows[0][1] - first_hz).abs() < 0.05,
            "{stem}: {}",
            rows[0][1]
        );
    }
}
