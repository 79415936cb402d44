//! `[torsion]` plausibility (issue 29, item 11; INTERFACE.md, "Limits"):
//! values inside the hard bounds but outside what real engines have, or
//! far from this engine's own scale, are computed with a note naming the
//! key (with a list item's 1-based index) and the likely mistake; so is a
//! front spring or damper on a front mass of zero inertia.

use enginedyn_engine::file::{parse, parse_torsion};
use enginedyn_engine::torsion::{BOUNDS, Key};

const I6: &str = include_str!("../../../data/i6_diesel.toml");
const V8: &str = include_str!("../../../data/v8_crossplane.toml");

/// The notes of `text` with `key`'s line in `[torsion]` replaced by
/// `line` (or `line` added when the key is not there).
fn notes_with(text: &str, key: &str, line: &str) -> Vec<String> {
    let mut found = false;
    let mut out: Vec<String> = text
        .lines()
        .map(|l| {
            if l.split('=').next().is_some_and(|k| k.trim() == key) {
                found = true;
                line.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    if !found {
        out.push(line.to_string());
    }
    notes(&out.join("\n"))
}

fn notes(text: &str) -> Vec<String> {
    let engine = parse(text, "t").unwrap();
    let spec = parse_torsion(text).unwrap().unwrap();
    spec.plausibility_notes(&engine, engine.rod_model())
}

fn one_note(notes: &[String], starts: &str, says: &str) {
    let hits: Vec<&String> = notes.iter().filter(|n| n.starts_with(starts)).collect();
    assert_eq!(hits.len(), 1, "{starts}: {notes:?}");
    assert!(
        hits[0].contains(says) && hits[0].contains("computed as given"),
        "{}",
        hits[0]
    );
}

/// The bundled engines' `[torsion]` sections are plausible: no note.
#[test]
fn bundled_engines_have_no_notes() {
    assert_eq!(notes(I6), Vec::<String>::new());
    assert_eq!(notes(V8), Vec::<String>::new());
}

/// The unit mistakes: an inertia in kg·cm², a stiffness in
/// N·mm/rad (one item of a list), a diameter in metres, a damping ratio
/// in percent.
#[test]
fn unit_mistakes_are_named() {
    let n = notes_with(I6, "throw_inertia_kg_m2", "throw_inertia_kg_m2 = 5000");
    one_note(
        &n,
        "torsion.throw_inertia_kg_m2 = 5000:",
        "kg·cm² (0.5 kg m²)?",
    );
    let n = notes_with(
        I6,
        "journal_stiffness_nm_rad",
        "journal_stiffness_nm_rad = [2e6, 2e6, 2e9, 2e6, 2e6]",
    );
    one_note(
        &n,
        "torsion.journal_stiffness_nm_rad[3] = 2e9:",
        "N·mm/rad (2000000 N m/rad)?",
    );
    let n = notes_with(
        V8,
        "journal_stiffness_nm_rad",
        "journal_stiffness_nm_rad = 430",
    );
    one_note(
        &n,
        "torsion.journal_stiffness_nm_rad = 430:",
        "kN·m/rad (430000 N m/rad)",
    );
    let n = notes_with(I6, "shaft_diameter_mm", "shaft_diameter_mm = 0.11");
    one_note(&n, "torsion.shaft_diameter_mm = 0.11:", "metres (110 mm)?");
    let n = notes_with(I6, "damping_ratio", "damping_ratio = 0.5");
    one_note(&n, "torsion.damping_ratio = 0.5:", "a percentage (0.005)?");
    let n = notes_with(V8, "throw_inertia_kg_m2", "throw_inertia_kg_m2 = 16000");
    one_note(
        &n,
        "torsion.throw_inertia_kg_m2 = 16000:",
        "kg·mm² (0.016 kg m²)",
    );
}

/// Every key, far outside what real engines have (but inside its hard
/// bound), gets a note naming it.
#[test]
fn every_key_has_a_plausible_range() {
    let cases = [
        ("throw_inertia_kg_m2", "throw_inertia_kg_m2 = 1e8"),
        (
            "journal_stiffness_nm_rad",
            "journal_stiffness_nm_rad = 1e13",
        ),
        ("front_inertia_kg_m2", "front_inertia_kg_m2 = 1e8"),
        ("front_stiffness_nm_rad", "front_stiffness_nm_rad = 1e-3"),
        ("flywheel_inertia_kg_m2", "flywheel_inertia_kg_m2 = 1e-8"),
        (
            "flywheel_stiffness_nm_rad",
            "flywheel_stiffness_nm_rad = 1e13",
        ),
        (
            "load_inertia_kg_m2",
            "load_inertia_kg_m2 = 1e8\nload_stiffness_nm_rad = 1e5",
        ),
        (
            "load_stiffness_nm_rad",
            "load_stiffness_nm_rad = 1e-3\nload_inertia_kg_m2 = 1",
        ),
        ("damping_ratio", "damping_ratio = 0.9"),
        ("shaft_diameter_mm", "shaft_diameter_mm = 50000"),
        (
            "damper",
            "damper = { inertia_kg_m2 = 1e7, stiffness_nm_rad = 1e12, damping_nm_s_rad = 1e10 }",
        ),
    ];
    for (key, line) in cases {
        let n = notes_with(I6, key, line);
        let head = line.split(" = ").next().unwrap();
        if key == "damper" {
            for k in ["inertia_kg_m2", "stiffness_nm_rad", "damping_nm_s_rad"] {
                let name = format!("torsion.damper.{k} = ");
                assert!(n.iter().any(|x| x.starts_with(&name)), "{name}: {n:?}");
            }
        } else {
            let name = format!("torsion.{head} = ");
            assert!(n.iter().any(|x| x.starts_with(&name)), "{name}: {n:?}");
        }
    }
    // Journal diameter and length (the geometric stiffness).
    let geometric = I6.replace(
        "journal_stiffness_nm_rad = 2.0e6",
        "journal_diameter_mm = 0.09\njournal_length_mm = 90000",
    );
    let n = notes(&geometric);
    for name in [
        "torsion.journal_diameter_mm = 0.09:",
        "torsion.journal_length_mm = 90000:",
    ] {
        assert!(n.iter().any(|x| x.starts_with(name)), "{name}: {n:?}");
    }
}

/// A front spring, or a damper, with no front mass: the chain cannot use
/// them as given, and says so.
#[test]
fn front_spring_and_damper_without_front_mass() {
    let n = notes_with(I6, "front_inertia_kg_m2", "front_inertia_kg_m2 = 0");
    assert_eq!(n.len(), 2, "{n:?}");
    assert!(
        n[0].starts_with(
            "torsion.front_stiffness_nm_rad = 1500000 is given but torsion.front_inertia_kg_m2 is 0"
        ),
        "{}",
        n[0]
    );
    assert!(
        n[1].starts_with("torsion.damper is on a front mass of zero inertia"),
        "{}",
        n[1]
    );
    // Without the key at all (the default 0) the same.
    let n = notes(&I6.replace("front_inertia_kg_m2 = 0.08\n", ""));
    assert_eq!(n.len(), 2, "{n:?}");
}

/// The one table: in `Key`'s order, each plausible range inside its hard
/// range, each key one the engine file knows.
#[test]
fn bounds_table_is_consistent() {
    assert_eq!(Key::ALL.len(), BOUNDS.len());
    for (k, b) in Key::ALL.iter().zip(&BOUNDS) {
        assert_eq!(k.bound().key, b.key);
        assert!(
            b.hard.0 <= b.plausible.0 && b.plausible.1 <= b.hard.1,
            "{}",
            b.key
        );
        assert!(b.key.starts_with("torsion."));
        assert_eq!(k.item(Some(2)), format!("{}[3]", b.key));
    }
}
