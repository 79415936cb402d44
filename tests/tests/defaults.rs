//! Defaults that shape the result are said (issue 30, item 11): η_m, δ,
//! the rim speed and the crank's unbalanced mass in one note when the
//! engine file leaves them out, none when it gives them; a flywheel
//! thinner than 2 % of its diameter gets a warning naming
//! `outer_diameter_mm`.

use enginedyn_tests::{data, ok_json};

fn notes(j: &serde_json::Value) -> Vec<String> {
    j["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap().to_string())
        .collect()
}

const DEFAULTS: &str = "defaults taken (not in the engine file): ";

/// The bundled engine file with the lines of `keys` taken out.
fn bundled_without(dir: &std::path::Path, keys: &[&str]) -> String {
    let text = std::fs::read_to_string(data("vaz2108.toml")).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| !keys.iter().any(|k| l.starts_with(&format!("{k} ="))))
        .collect();
    let path = dir.join("engine.toml");
    std::fs::write(&path, kept.join("\n")).unwrap();
    std::fs::copy(data("vaz2108.csv"), dir.join("vaz2108.csv")).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn defaults_left_out_are_named_in_one_note() {
    let dir = tempfile::tempdir().unwrap();
    let engine = bundled_without(
        dir.path(),
        &[
            "mechanical_efficiency",
            "speed_fluctuation",
            "max_rim_speed_m_s",
            "crank_unbalanced_kg",
        ],
    );
    let j = ok_json(&["run", "--engine", &engine, "--json"]);
    let n = notes(&j);
    let said: Vec<&String> = n.iter().filter(|n| n.starts_with(DEFAULTS)).collect();
    assert_eq!(said.len(), 1, "{n:?}");
    let note = said[0];
    for part in [
        "operating.mechanical_efficiency = 1 (",
        "flywheel.speed_fluctuation = 0.01 (",
        "flywheel.max_rim_speed_m_s = 60 m/s (",
        "masses.crank_unbalanced_kg = 0 (",
    ] {
        assert!(note.contains(part), "{part}: {note}");
    }
    // η_m = 1: effective equals indicated.
    assert!(j["mean_torque_nm"].is_f64(), "{}", j["mean_torque_nm"]);
    assert_eq!(j["mean_torque_nm"], j["indicated_mean_torque_nm"]);
    // Some given: only the others named.
    let engine = bundled_without(dir.path(), &["mechanical_efficiency"]);
    let j = ok_json(&["run", "--engine", &engine, "--json"]);
    let n = notes(&j);
    let note = n.iter().find(|n| n.starts_with(DEFAULTS)).unwrap();
    assert_eq!(
        note.as_str(),
        "defaults taken (not in the engine file): operating.mechanical_efficiency = 1 (torque and power are indicated: the effective figures equal them)"
    );
}

#[test]
fn a_file_giving_every_key_has_no_defaults_note() {
    // The bundled example gives all four, run bare or as a file.
    for args in [
        vec!["run", "--json"],
        vec!["run", "--engine", &data("vaz2108.toml"), "--json"],
    ] {
        let args: Vec<&str> = args.iter().map(|s| &**s).collect();
        let n = notes(&ok_json(&args));
        assert!(!n.iter().any(|n| n.contains("defaults taken")), "{n:?}");
    }
}

/// The 570 mm × 3.4 mm flywheel: the bundled engine at 2000 rpm
/// sizes a 570 mm rim about 6 mm wide from the default-valued rim speed.
#[test]
fn thin_flywheel_is_warned_naming_outer_diameter() {
    let j = ok_json(&["run", "--rpm", "2000", "--json"]);
    let d = j["flywheel_outer_diameter_m"].as_f64().unwrap();
    let w = j["flywheel_width_m"].as_f64().unwrap();
    assert!((d - 0.570).abs() < 0.001 && w < 0.02 * d, "{d} {w}");
    let n = notes(&j);
    let warn = n
        .iter()
        .find(|n| n.contains("under 2 % of it"))
        .unwrap_or_else(|| panic!("{n:?}"));
    assert!(
        warn.starts_with("the flywheel (rim) is 6 mm wide at 570 mm diameter"),
        "{warn}"
    );
    assert!(
        warn.contains("set flywheel.outer_diameter_mm smaller"),
        "{warn}"
    );
    // The suggested diameter, given, sizes a part a tenth of it wide (±1 mm).
    let suggested = warn
        .split("(outer_diameter_mm = ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .unwrap()
        .to_string();
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(data("vaz2108.toml"))
        .unwrap()
        .replace(
            "max_rim_speed_m_s = 60.0",
            &format!("outer_diameter_mm = {suggested}"),
        )
        .replace("\"vaz2108.csv\"", &format!("{:?}", data("vaz2108.csv")));
    let path = dir.path().join("d.toml");
    std::fs::write(&path, text).unwrap();
    let j = ok_json(&[
        "run",
        "--engine",
        path.to_str().unwrap(),
        "--rpm",
        "2000",
        "--json",
    ]);
    let d = j["flywheel_outer_diameter_m"].as_f64().unwrap();
    let w = j["flywheel_width_m"].as_f64().unwrap();
    assert!((w / d - 0.1).abs() < 0.002, "{d} {w}");
    assert!(!notes(&j).iter().any(|n| n.contains("under 2 %")));
    // The bundled example at its own speed: a practical part, no warning.
    let n = notes(&ok_json(&["run", "--json"]));
    assert!(!n.iter().any(|n| n.contains("under 2 %")), "{n:?}");
}
