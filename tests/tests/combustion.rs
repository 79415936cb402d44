//! Issue 35, the analysis half from the command line: every fired cycle's
//! burn points reach `summary.json`, `curves.csv`, the charts and the
//! report; a motored cycle gets none, with a note; the flags are bounded.

use enginedyn_tests::{data, data_rows, run};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn single_rows() -> Vec<(String, f64)> {
    data_rows("single.csv")
}

/// The bundled single's engine: its motored trace, a closed charge from 1
/// bar at BDC along `p V^1.32`, with the gas exchange at 1 bar.
fn motored_rows() -> Vec<(String, f64)> {
    let e = enginedyn_engine::file::read(std::path::Path::new(&data("single.toml"))).unwrap();
    let c = e.cylinder();
    let v_bdc = c.volume(std::f64::consts::PI);
    single_rows()
        .into_iter()
        .map(|(a, _)| {
            let mut deg: f64 = a.parse().unwrap();
            if deg >= 360.0 {
                deg -= 720.0;
            }
            let p = if deg.abs() <= 180.0 {
                (v_bdc / c.volume(deg.to_radians())).powf(1.32)
            } else {
                1.0
            };
            (a, p)
        })
        .collect()
}

#[test]
fn a_fired_run_reports_its_burn_everywhere() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("r");
    let o = run(&[
        "run",
        "--engine",
        &data("single.toml"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let num = |k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k}: {}", s[k]));
    // The bundled single burns from about 20° before TDC (its synthesis);
    // the burn points rise in order and the duration is their difference.
    let (ca5, ca10, ca50, ca90) = (
        num("ca5_deg"),
        num("ca10_deg"),
        num("ca50_deg"),
        num("ca90_deg"),
    );
    assert!(
        ca5 < ca10 && ca10 < ca50 && ca50 < ca90,
        "{ca5} {ca10} {ca50} {ca90}"
    );
    assert!((-10.0..25.0).contains(&ca50), "{ca50}");
    assert!((num("burn_10_90_deg") - (ca90 - ca10)).abs() < 1e-9);
    assert!(num("heat_released_j") > 0.0 && num("dp_dphi_max_bar_deg") > 0.0);
    // PMEP = net − gross, to rounding.
    assert!((num("pmep_bar") - (num("imep_bar") - num("imep_gross_bar"))).abs() < 1e-9);
    assert_eq!(s["models"]["gamma"], "1.32");
    assert_eq!(s["models"]["burn_window"], "-90:120");
    let curves = std::fs::read_to_string(out.join("curves.csv")).unwrap();
    let header: Vec<&str> = curves.lines().next().unwrap().split(',').collect();
    for c in ["heat_release_rate_j_deg", "heat_release_j", "mfb"] {
        assert!(header.contains(&c), "{c} not in {header:?}");
    }
    let svg = std::fs::read_to_string(out.join("heat_release.svg")).unwrap();
    assert!(
        svg.contains("CA50") && svg.contains("Savitzky-Golay"),
        "the chart marks CA50 and names its filter"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("<h2>Combustion</h2>") && html.contains("id=\"heat_release\""));
}

#[test]
fn a_motored_cycle_has_no_burn_points_and_says_so() {
    let t = tempfile::tempdir().unwrap();
    let mut s = String::from("cycle,crank_deg,pressure_bar\n");
    for c in 1..=6 {
        let rows = if c == 4 {
            motored_rows()
        } else {
            single_rows()
        };
        for (a, p) in &rows {
            s.push_str(&format!("{c},{a},{p:.6}\n"));
        }
    }
    let f = t.path().join("fuel_cut.csv");
    std::fs::write(&f, s).unwrap();
    let out = t.path().join("r");
    let o = run(&[
        "run",
        "--engine",
        &data("single.toml"),
        "--diagram",
        f.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("note: no combustion in cycle 4: heat released"),
        "{e}"
    );
    assert!(
        out.join("ca50_imep.svg").exists(),
        "five burning cycles: the scatter"
    );
    // Motored alone: every burn key null, with the note.
    let mut m = String::from("crank_deg,pressure_bar\n");
    for (a, p) in motored_rows() {
        m.push_str(&format!("{a},{p:.6}\n"));
    }
    let f = t.path().join("motored.csv");
    std::fs::write(&f, m).unwrap();
    let o = run(&[
        "run",
        "--engine",
        &data("single.toml"),
        "--diagram",
        f.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for k in [
        "ca10_deg",
        "ca50_deg",
        "ca90_deg",
        "soc_deg",
        "heat_released_j",
        "dp_dphi_max_bar_deg",
    ] {
        assert!(j[k].is_null(), "{k}: {}", j[k]);
    }
    assert!(
        j["imep_gross_bar"].is_number(),
        "the gross IMEP exists without a burn"
    );
    assert!(
        stderr(&o).contains("no combustion in the mean trace"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn burn_flags_are_read_and_bounded() {
    let o = run(&[
        "run",
        "--engine",
        &data("single.toml"),
        "--json",
        "--burn-points",
        "25,50,75",
        "--burn-window",
        "-60:100",
        "--gamma",
        "brunt",
        "--smooth",
        "off",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(j["ca25_deg"].is_number() && j["ca75_deg"].is_number());
    assert!(j["ca10_deg"].is_null(), "a level not asked for is null");
    assert!(j["models"]["gamma"].as_str().unwrap().starts_with("brunt"));
    assert_eq!(j["models"]["smoothing"], "off (central differences)");
    for (flag, value, says) in [
        ("--gamma", "2.5", "--gamma"),
        ("--burn-points", "0,50", "1 to 99"),
        ("--burn-window", "100:90", "--burn-window"),
        ("--smooth", "SG:50", "--smooth"),
    ] {
        let o = run(&[
            "run",
            "--engine",
            &data("single.toml"),
            "--json",
            flag,
            value,
        ]);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{flag} {value}: {}", stderr(&o));
    }
}
