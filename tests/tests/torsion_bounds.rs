//! `enginedyn torsion` on absurd `[torsion]` values (issue 29, item 11;
//! INTERFACE.md, "Limits"): a copy of a bundled engine with one key
//! changed. A value that would overflow the computation or lose all its
//! precision exits 2 naming the key; an implausible one runs, with a
//! warning naming the key and the likely mistake; the bundled engines run
//! with none.

use enginedyn_tests::{data, run};
use serde_json::Value;
use std::path::Path;

/// A copy of `data/NAME` in `dir` with the `[torsion]` line of `key`
/// replaced by `line` (the diagram made absolute, so the copy finds it).
fn engine_with(dir: &Path, name: &str, key: &str, line: &str) -> String {
    let text = std::fs::read_to_string(data(name)).unwrap();
    let mut replaced = false;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            let k = l.split('=').next().unwrap_or("").trim();
            if k == "diagram" {
                let file = l.split('"').nth(1).unwrap();
                format!("diagram = \"{}\"", data(file))
            } else if k == key {
                replaced = true;
                line.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    assert!(replaced || key.is_empty(), "{key} not in {name}");
    let path = dir.join(name);
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path.to_str().unwrap().to_string()
}

/// Runs `torsion --json` on the engine (a short speed range): exit code,
/// standard error, and the JSON document when it ran.
fn torsion(engine: &str) -> (Option<i32>, String, Option<Value>) {
    let out = run(&[
        "torsion",
        "--engine",
        engine,
        "--json",
        "--rpm",
        "1000:2600:400",
    ]);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!err.contains("panicked"), "{err}");
    let doc = serde_json::from_slice(&out.stdout).ok();
    (out.status.code(), err, doc)
}

fn refused(engine: &str, says: &[&str]) -> String {
    let (code, err, _) = torsion(engine);
    assert_eq!(code, Some(2), "{err}");
    for s in says {
        assert!(err.contains(s), "{s}: {err}");
    }
    assert!(!err.contains("NaN") && !err.contains("inf"), "{err}");
    err
}

/// The cases: an inertia of 1e-300 (frequencies up to 4e152 Hz
/// before, exit 0) and a stiffness of 1e308 (blamed on an undamped
/// resonance before, in a file with a damping ratio).
#[test]
fn overflowing_values_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let e = engine_with(
        dir.path(),
        "i6_diesel.toml",
        "throw_inertia_kg_m2",
        "throw_inertia_kg_m2 = 1e-300",
    );
    refused(
        &e,
        &[
            "`torsion.throw_inertia_kg_m2` = 1e-300",
            "from 1e-12 to 1e9 kg m²",
        ],
    );
    let e = engine_with(
        dir.path(),
        "i6_diesel.toml",
        "journal_stiffness_nm_rad",
        "journal_stiffness_nm_rad = 1e308",
    );
    let err = refused(
        &e,
        &[
            "`torsion.journal_stiffness_nm_rad` = 1e308",
            "from 1e-6 to 1e14 N m/rad",
        ],
    );
    assert!(
        !err.contains("undamped") && !err.contains("damping ratio"),
        "{err}"
    );
    // One item of a list, by its 1-based index.
    let e = engine_with(
        dir.path(),
        "v8_crossplane.toml",
        "journal_stiffness_nm_rad",
        "journal_stiffness_nm_rad = [4.3e5, 4.3e5, 1e308]",
    );
    refused(&e, &["`torsion.journal_stiffness_nm_rad[3]` = 1e308"]);
}

/// Inside every key's bounds, but one mass so light on its springs that
/// the chain's low modes cannot be resolved: exit 2 naming that mass's
/// key and its springs'.
#[test]
fn unresolvable_chain_exits_2_naming_the_keys() {
    let dir = tempfile::tempdir().unwrap();
    let e = engine_with(
        dir.path(),
        "v8_crossplane.toml",
        "throw_inertia_kg_m2",
        "throw_inertia_kg_m2 = [0.016, 1e-12, 0.016, 0.016]",
    );
    refused(
        &e,
        &[
            "`torsion.throw_inertia_kg_m2[2]` = 1e-12 kg m²",
            "torsion.journal_stiffness_nm_rad",
            "cannot be resolved in double precision",
        ],
    );
}

/// An inertia in kg·cm² (5000 for 0.5 kg m²) runs, with a warning naming
/// the key and the unit; the bundled engines run with no warning.
#[test]
fn implausible_value_runs_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["i6_diesel.toml", "v8_crossplane.toml"] {
        let e = engine_with(dir.path(), name, "", "");
        let (code, err, doc) = torsion(&e);
        assert_eq!(code, Some(0), "{err}");
        assert!(!err.contains("warning:"), "{name}: {err}");
        let notes = doc.unwrap()["notes"].clone();
        assert!(
            !notes.to_string().contains("computed as given"),
            "{name}: {notes}"
        );
    }
    let e = engine_with(
        dir.path(),
        "i6_diesel.toml",
        "throw_inertia_kg_m2",
        "throw_inertia_kg_m2 = 5000",
    );
    let (code, err, doc) = torsion(&e);
    assert_eq!(code, Some(0), "{err}");
    let start = "torsion.throw_inertia_kg_m2 = 5000: kg·cm² (0.5 kg m²)?";
    assert!(err.contains(&format!("warning: {start}")), "{err}");
    let doc = doc.unwrap();
    let notes = doc["notes"].as_array().unwrap();
    assert!(
        notes.iter().any(|n| n.as_str().unwrap().starts_with(start)),
        "{notes:?}"
    );
    // Computed as given: finite frequencies.
    let f = doc["natural_frequencies_hz"].as_array().unwrap();
    assert!(f.iter().all(|x| x.as_f64().is_some_and(f64::is_finite)));
}

/// A front spring and a damper on a front mass of zero inertia: a warning
/// for each.
#[test]
fn front_spring_without_front_mass_is_noted() {
    let dir = tempfile::tempdir().unwrap();
    let e = engine_with(
        dir.path(),
        "i6_diesel.toml",
        "front_inertia_kg_m2",
        "front_inertia_kg_m2 = 0",
    );
    let (code, err, doc) = torsion(&e);
    assert_eq!(code, Some(0), "{err}");
    for s in [
        "warning: torsion.front_stiffness_nm_rad = 1500000 is given but torsion.front_inertia_kg_m2 is 0",
        "warning: torsion.damper is on a front mass of zero inertia",
    ] {
        assert!(err.contains(s), "{s}: {err}");
    }
    let notes = doc.unwrap()["notes"].to_string();
    assert!(
        notes.contains("torsion.front_stiffness_nm_rad = 1500000 is given"),
        "{notes}"
    );
}
