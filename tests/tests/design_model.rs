//! Issue 41, part A: the design model from the command line. A
//! spark-ignition engine meets a part load by its throttle (its own
//! pumping loop, a lower peak), a compression-ignition one by its fuel
//! within the air; Chen–Flynn friction gives the brake figures, checked
//! here against the formula computed apart; design inputs no engine runs
//! are refused, naming the key and the limit.

use enginedyn_tests::run;

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The `kind` template (`petrol`, `diesel`), four cylinders, with `edit`
/// applied, in `dir`.
fn template(dir: &std::path::Path, kind: &str, name: &str, edit: &[(&str, &str)]) -> String {
    enginedyn_tests::edited_template(dir, &["--combustion", kind, "--cylinders", "4"], name, edit)
}

/// `run --json` of `engine` at `imep_bar`: the summary (exit 0).
fn at_load(dir: &std::path::Path, kind: &str, imep: f64) -> serde_json::Value {
    let default = if kind == "diesel" { "18.0" } else { "10.0" };
    let engine = template(
        dir,
        kind,
        &format!("{kind}_{imep}.toml"),
        &[(
            &format!("imep_bar = {default}"),
            &format!("imep_bar = {imep}"),
        )],
    );
    let o = run(&["run", "--engine", &engine, "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn num(s: &serde_json::Value, k: &str) -> f64 {
    s[k].as_f64().unwrap_or_else(|| panic!("{k}: {}", s[k]))
}

/// The petrol template throttles to its part loads: the intake pressure
/// falls with the load, the pumping loop deepens (PMEP below −0.5 bar at
/// 3 bar IMEP, the throttled engine's; −0.10 bar when the intake stayed
/// at 1 bar) and the peak pressure falls; the fuel follows the air at λ 1,
/// so the heat released is η_c m_a LHV / (λ AFR) of the air the intake
/// pressure traps, computed here apart.
#[test]
fn a_spark_ignition_engine_meets_part_load_by_its_throttle() {
    let t = tempfile::tempdir().unwrap();
    let loads = [3.0, 6.0, 10.0, 14.0];
    let runs: Vec<serde_json::Value> = loads
        .iter()
        .map(|&i| at_load(t.path(), "petrol", i))
        .collect();
    let mut last: Option<(f64, f64, f64)> = None;
    for (i, s) in loads.iter().zip(&runs) {
        assert!(
            (num(s, "imep_bar") / i - 1.0).abs() < 1e-5,
            "{i}: {}",
            s["imep_bar"]
        );
        let d = &s["design"];
        assert_eq!(d["charge"], "si");
        assert!((d["lambda"].as_f64().unwrap() - 1.0).abs() < 1e-9);
        let p_in = d["intake_pressure_bar"].as_f64().unwrap();
        let (pmep, p_max) = (num(s, "pmep_bar"), num(s, "p_max_bar"));
        assert!(p_in < 1.0, "{i}: intake {p_in}");
        if let Some((p0, m0, x0)) = last {
            assert!(
                p_in > p0 && pmep > m0 && p_max > x0,
                "{i}: {p_in} {pmep} {p_max}"
            );
        }
        last = Some((p_in, pmep, p_max));
    }
    let pmep_3 = num(&runs[0], "pmep_bar");
    assert!(pmep_3 < -0.5 && pmep_3 > -1.2, "PMEP at 3 bar: {pmep_3}");
    // The heat released, from the trapped air: the template's cylinder
    // (bore 76 mm, stroke 71 mm, λ = R/L 0.26, ε 9.9), V at IVC −140°.
    let s = &runs[2];
    let p_in = s["design"]["intake_pressure_bar"].as_f64().unwrap() * 1e5;
    let (bore, stroke, eps) = (0.076, 0.071, 9.9);
    let r = stroke / 2.0;
    let l = r / 0.26;
    let vd = std::f64::consts::FRAC_PI_4 * bore * bore * stroke;
    let vc = vd / (eps - 1.0);
    let phi = (-140.0f64).to_radians();
    let x = r * (1.0 - phi.cos()) + l * (1.0 - (1.0 - (r / l * phi.sin()).powi(2)).sqrt());
    let v_ivc = vc + std::f64::consts::FRAC_PI_4 * bore * bore * x;
    let air = p_in * v_ivc / (287.05 * 320.0);
    let q = 0.98 * air * 43.4e6 / 14.7;
    let notes = s["notes"].to_string();
    let solved = notes
        .split("heat released ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no heat released in {notes}"));
    assert!(
        (solved / q - 1.0).abs() < 2e-5,
        "heat {solved} J, the air's {q} J"
    );
}

/// BMEP = IMEP − FMEP with FMEP by Chen–Flynn computed here from the
/// template's constants, the peak pressure and the mean piston speed; the
/// brake torque is BMEP z V_d / 4π and the effective torque and power are
/// the brake ones.
#[test]
fn brake_figures_are_chen_flynn() {
    let t = tempfile::tempdir().unwrap();
    for kind in ["petrol", "diesel"] {
        let default = if kind == "diesel" { 18.0 } else { 10.0 };
        let s = at_load(t.path(), kind, default);
        let (a, b, c, d) = if kind == "diesel" {
            (0.4, 0.004, 0.08, 0.0009)
        } else {
            (0.4, 0.005, 0.09, 0.0009)
        };
        let cm = num(&s, "piston_speed_mean_m_s");
        let fmep = a + b * num(&s, "p_max_bar") + c * cm + d * cm * cm;
        assert!((num(&s, "fmep_bar") - fmep).abs() < 1e-9, "{kind}");
        let bmep = num(&s, "imep_bar") - fmep;
        assert!((num(&s, "bmep_bar") - bmep).abs() < 1e-9, "{kind}");
        let vd = num(&s, "stroke_m")
            * std::f64::consts::FRAC_PI_4
            * if kind == "diesel" { 0.130f64 } else { 0.076 }.powi(2);
        let torque = bmep * 1e5 * 4.0 * vd / (4.0 * std::f64::consts::PI);
        assert!(
            (num(&s, "brake_torque_nm") / torque - 1.0).abs() < 1e-9,
            "{kind}"
        );
        let power = torque * num(&s, "omega_rad_s") / 1e3;
        assert!((num(&s, "brake_power_kw") / power - 1.0).abs() < 1e-9);
        assert!((num(&s, "mean_torque_nm") / torque - 1.0).abs() < 1e-12);
        assert!((num(&s, "power_kw") / power - 1.0).abs() < 1e-12);
        assert!((num(&s, "mechanical_efficiency") - bmep / num(&s, "imep_bar")).abs() < 1e-12);
    }
}

/// The diesel template is a diesel's: CR 17, 130 × 160 mm, 1,900 rpm,
/// boosted at 2.2 bar; at its 18 bar IMEP the peak is a heavy-duty
/// diesel's (over 120 bar; 81 bar when it kept the petrol's CR 9.9), and
/// λ is above λ_min 1.2.
#[test]
fn the_diesel_template_is_a_diesel() {
    let t = tempfile::tempdir().unwrap();
    let s = at_load(t.path(), "diesel", 18.0);
    assert!((num(&s, "stroke_m") - 0.160).abs() < 1e-12);
    assert!((num(&s, "rpm") - 1900.0).abs() < 1e-9);
    let p_max = num(&s, "p_max_bar");
    assert!(p_max > 120.0 && p_max < 200.0, "{p_max}");
    assert_eq!(s["design"]["charge"], "ci");
    assert!((s["design"]["intake_pressure_bar"].as_f64().unwrap() - 2.2).abs() < 1e-12);
    assert!(s["design"]["lambda"].as_f64().unwrap() > 1.2);
}

/// Loads and burn laws no engine runs are refused (exit 2), naming the key
/// and the limit: a load beyond the trapped air (with the highest IMEP it
/// gives), a CA50 outside −30…60°, a pressure rise over 15 bar/°, a
/// compression-ignition load richer than λ_min.
#[test]
fn impossible_design_inputs_are_refused() {
    let t = tempfile::tempdir().unwrap();
    type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a [&'a str]);
    let cases: [Case; 5] = [
        (
            "petrol",
            &[("imep_bar = 10.0", "imep_bar = 20.0")],
            &[
                "imep_bar = 20",
                "beyond what the trapped air burns",
                "at most IMEP",
                "intake_pressure_bar",
            ],
        ),
        (
            "petrol",
            &[("ca50_deg = 8.0", "ca50_deg = -60.0")],
            &["combustion.ca50_deg", "-30 to 60"],
        ),
        (
            "petrol",
            &[("ca50_deg = 8.0", "ca50_deg = 100.0")],
            &["combustion.ca50_deg", "-30 to 60"],
        ),
        (
            "petrol",
            &[("duration_10_90_deg = 20.0", "duration_10_90_deg = 0.5")],
            &["pressure rise", "15 bar/°", "duration_10_90_deg"],
        ),
        (
            "diesel",
            &[("imep_bar = 18.0", "imep_bar = 38.0")],
            &["imep_bar = 38", "λ_min 1.2", "at most IMEP", "lambda_min"],
        ),
    ];
    for (k, (kind, edit, want)) in cases.iter().enumerate() {
        let engine = template(t.path(), kind, &format!("bad{k}.toml"), edit);
        let o = run(&["run", "--engine", &engine]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{edit:?}: {err}");
        for w in *want {
            assert!(err.contains(w), "{edit:?}: no `{w}` in {err}");
        }
    }
}

/// `sweep --load`: each point's IMEP is its percent of the full-load line
/// at its speed (linear between the line's points); a BMEP line gives
/// BMEP = percent × the line with FMEP on each point's own peak; the
/// highest load's row names the rated-power and peak-torque points, which
/// are the largest brake power and torque of that row.
#[test]
fn a_map_in_percent_of_the_full_load_line() {
    let t = tempfile::tempdir().unwrap();
    let line = |rpm: f64| {
        let (x, y) = (
            [
                1000.0, 2000.0, 3000.0, 3400.0, 4000.0, 5000.0, 5600.0, 6000.0,
            ],
            [9.6, 10.3, 10.8, 10.9, 10.8, 10.3, 9.9, 9.5],
        );
        let k = x.iter().position(|&r| r >= rpm).unwrap().max(1);
        y[k - 1] + (rpm - x[k - 1]) / (x[k] - x[k - 1]) * (y[k] - y[k - 1])
    };
    let engine = template(t.path(), "petrol", "map.toml", &[]);
    let o = run(&[
        "sweep",
        "--engine",
        &engine,
        "--rpm",
        "1500:6000:1500",
        "--load",
        "50:100:50",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let points: Vec<serde_json::Value> = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(points.len(), 8);
    for p in &points {
        let (rpm, pct) = (num(p, "rpm"), num(p, "load_pct"));
        let want = pct / 100.0 * line(rpm);
        assert!(
            (num(p, "imep_target_bar") - want).abs() < 1e-9,
            "{rpm} {pct}"
        );
        assert!(
            (num(p, "imep_bar") / want - 1.0).abs() < 1e-5,
            "{rpm} {pct}"
        );
    }
    let full: Vec<&serde_json::Value> = points
        .iter()
        .filter(|p| num(p, "load_pct") > 99.0)
        .collect();
    let best = |k: &str| {
        full.iter()
            .max_by(|a, b| num(a, k).total_cmp(&num(b, k)))
            .map(|p| (num(p, "rpm"), num(p, k)))
            .unwrap()
    };
    let (r_p, p) = best("brake_power_kw");
    let (r_t, tq) = best("brake_torque_nm");
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "rated power {} kW at {} rpm",
            (p * 100.0).round() / 100.0,
            r_p
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "peak torque {} N m at {} rpm",
            (tq * 10.0).round() / 10.0,
            r_t
        )),
        "{err}"
    );
    // A BMEP line: BMEP is the percent of it, FMEP on each point's peak.
    let engine = template(
        t.path(),
        "petrol",
        "bmep.toml",
        &[(
            "imep_bar = [9.6, 10.3, 10.8, 10.9, 10.8, 10.3, 9.9, 9.5]",
            "bmep_bar = [8.5, 9.0, 9.4, 9.4, 9.2, 8.5, 8.0, 7.5]",
        )],
    );
    let o = run(&[
        "sweep",
        "--engine",
        &engine,
        "--rpm",
        "1000:5000:2000",
        "--load",
        "80:80:1",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let points: Vec<serde_json::Value> = serde_json::from_slice(&o.stdout).unwrap();
    for (p, bmep) in points.iter().zip([8.5, 9.4, 8.5]) {
        assert!((num(p, "bmep_bar") - 0.8 * bmep).abs() < 2e-5, "{p}");
    }
    // Without a full-load line, --load says what is missing.
    let bare = template(
        t.path(),
        "petrol",
        "bare.toml",
        &[("\nfull_load = {", "\n# full_load = {")],
    );
    let o = run(&[
        "sweep",
        "--engine",
        &bare,
        "--rpm",
        "1000:2000:1000",
        "--load",
        "50:100:50",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("[combustion.full_load]"),
        "{}",
        stderr(&o)
    );
}

/// A boost curve over speed: each speed's cycle is made at its own intake
/// pressure, in `run` and in a speed-only `sweep` (linear between the
/// curve's points, held at its ends).
#[test]
fn a_boost_curve_is_taken_at_each_speed() {
    let t = tempfile::tempdir().unwrap();
    let engine = template(
        t.path(),
        "diesel",
        "boost.toml",
        &[(
            "intake_pressure_bar = 2.2",
            "intake_pressure_bar = { rpm = [800.0, 1200.0, 1900.0], bar = [1.6, 2.4, 2.2] }",
        )],
    );
    let o = run(&[
        "sweep",
        "--engine",
        &engine,
        "--rpm",
        "600:2000:200",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let points: Vec<serde_json::Value> = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(points.len(), 8);
    let curve = |rpm: f64| match rpm {
        r if r <= 800.0 => 1.6,
        r if r <= 1200.0 => 1.6 + (r - 800.0) / 400.0 * 0.8,
        r if r <= 1900.0 => 2.4 - (r - 1200.0) / 700.0 * 0.2,
        _ => 2.2,
    };
    let mut peaks = Vec::new();
    for p in &points {
        let rpm = num(p, "rpm");
        let p_in = p["design"]["intake_pressure_bar"].as_f64().unwrap();
        assert!((p_in - curve(rpm)).abs() < 1e-12, "{rpm}: {p_in}");
        assert!((num(p, "imep_bar") / 18.0 - 1.0).abs() < 1e-5);
        peaks.push(num(p, "p_max_bar"));
    }
    // More boost, more compression: the peak follows the curve.
    assert!(peaks[3] > peaks[0] + 10.0, "{peaks:?}");
    let o = run(&["run", "--engine", &engine, "--rpm", "1000", "--json"]);
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!((s["design"]["intake_pressure_bar"].as_f64().unwrap() - 2.0).abs() < 1e-12);
}

/// The idle criterion: with `flywheel.idle_rpm` a map also sizes at idle
/// (the design cycle at the load that overcomes friction, BMEP 0, and
/// `idle_speed_fluctuation`); the flywheel is sized at idle when idle
/// needs more, named in the rows and the notes.
#[test]
fn the_flywheel_is_sized_at_the_worst_of_the_map_and_idle() {
    let t = tempfile::tempdir().unwrap();
    let run_map = |name: &str, delta: &str| {
        let engine = template(
            t.path(),
            "petrol",
            name,
            &[(
                "[flywheel]\n",
                &format!("[flywheel]\nidle_rpm = 800.0\nidle_speed_fluctuation = {delta}\n"),
            )],
        );
        let o = run(&[
            "sweep",
            "--engine",
            &engine,
            "--rpm",
            "1000:3000:1000",
            "--load",
            "50:100:50",
            "--json",
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let points: Vec<serde_json::Value> = serde_json::from_slice(&o.stdout).unwrap();
        (points, stderr(&o))
    };
    // A loose idle δ: the map's worst point sizes it.
    let (points, err) = run_map("loose.toml", "0.05");
    assert!(err.contains("idle criterion: at 800 rpm"), "{err}");
    assert!((num(&points[0], "flywheel_sized_at_rpm") - 1000.0).abs() < 1e-9);
    // A tight one: idle does, above every point's own need.
    let (points, err) = run_map("tight.toml", "0.0005");
    assert!(err.contains("idle, which needs more inertia"), "{err}");
    for p in &points {
        assert!((num(p, "flywheel_sized_at_rpm") - 800.0).abs() < 1e-9);
        let part = num(p, "flywheel_inertia_kg_m2");
        assert!(part > num(p, "required_inertia_kg_m2"), "{p}");
    }
    let idle_imep = num(&points[0], "flywheel_sized_at_imep_bar");
    assert!(idle_imep > 0.3 && idle_imep < 2.0, "{idle_imep}");
}
