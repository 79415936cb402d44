//! `[torsion]` hard bounds (issue 29, item 11; INTERFACE.md, "Limits"):
//! a value that would overflow the computation or lose all its precision
//! is refused when the file is read, naming the key as the file spells it
//! (a list's item with its 1-based index) and the range.

use enginedyn_engine::file::parse_torsion;

/// A `[torsion]` section with `lines` (an engine's other keys are not
/// read by `parse_torsion`).
fn torsion(lines: &str) -> Result<(), String> {
    let text = format!("[torsion]\njournal_stiffness_nm_rad = 2e6\n{lines}\n");
    parse_torsion(&text).map(|_| ()).map_err(|e| e.to_string())
}

/// The same, without the default journal line (for the journal keys).
fn bare(lines: &str) -> Result<(), String> {
    parse_torsion(&format!("[torsion]\n{lines}\n"))
        .map(|_| ())
        .map_err(|e| e.to_string())
}

fn refused(result: Result<(), String>, key: &str, range: &str) -> String {
    let msg = result.expect_err(&format!("{key} should be refused"));
    assert!(
        msg.contains(&format!("`{key}`")) && msg.contains(range),
        "{key}: {msg}"
    );
    msg
}

/// The issue's two cases: an inertia of 1e-300 and a stiffness of 1e308.
#[test]
fn issue_cases_are_refused_naming_the_key() {
    let msg = refused(
        torsion("throw_inertia_kg_m2 = 1e-300"),
        "torsion.throw_inertia_kg_m2",
        "from 1e-12 to 1e9 kg m²",
    );
    assert!(msg.contains("1e-300"), "{msg}");
    let msg = refused(
        bare("journal_stiffness_nm_rad = 1e308"),
        "torsion.journal_stiffness_nm_rad",
        "from 1e-6 to 1e14 N m/rad",
    );
    assert!(msg.contains("1e308") && !msg.contains("damping"), "{msg}");
}

/// Every key that takes a number has a hard bound on both sides (0 is
/// accepted where it means none).
#[test]
fn every_numeric_key_has_hard_bounds() {
    let inertias = [
        "throw_inertia_kg_m2",
        "front_inertia_kg_m2",
        "flywheel_inertia_kg_m2",
        "load_inertia_kg_m2",
    ];
    for k in inertias {
        for v in ["1e-300", "1e-13", "2e9", "1e300"] {
            refused(
                torsion(&format!("{k} = {v}")),
                &format!("torsion.{k}"),
                "1e-12 to 1e9 kg m²",
            );
        }
    }
    let stiffnesses = [
        "front_stiffness_nm_rad",
        "flywheel_stiffness_nm_rad",
        "load_stiffness_nm_rad",
    ];
    for k in stiffnesses {
        for v in ["1e-300", "1e-7", "2e14", "1e308"] {
            refused(
                torsion(&format!("{k} = {v}")),
                &format!("torsion.{k}"),
                "1e-6 to 1e14 N m/rad",
            );
        }
    }
    for k in [
        "journal_diameter_mm",
        "journal_length_mm",
        "shaft_diameter_mm",
    ] {
        for v in ["1e-300", "1e-4", "2e5", "1e300"] {
            refused(
                torsion(&format!("{k} = {v}")),
                &format!("torsion.{k}"),
                "from 0.001 to 100000 mm",
            );
        }
    }
    let damper = |i: &str, k: &str, c: &str| {
        torsion(&format!(
            "damper = {{ inertia_kg_m2 = {i}, stiffness_nm_rad = {k}, damping_nm_s_rad = {c} }}"
        ))
    };
    refused(
        damper("1e-300", "2e4", "150"),
        "torsion.damper.inertia_kg_m2",
        "1e-12 to 1e9 kg m²",
    );
    refused(
        damper("0.25", "1e308", "150"),
        "torsion.damper.stiffness_nm_rad",
        "1e-6 to 1e14 N m/rad",
    );
    refused(
        damper("0.25", "2e4", "1e300"),
        "torsion.damper.damping_nm_s_rad",
        "from 0 to 1e12 N m s/rad",
    );
    // The bounds themselves are accepted, and 0 where it means none.
    for ok in [
        "throw_inertia_kg_m2 = 1e-12",
        "flywheel_inertia_kg_m2 = 1e9",
        "front_inertia_kg_m2 = 0",
        "load_stiffness_nm_rad = 1e14\nload_inertia_kg_m2 = 1",
        "damper = { inertia_kg_m2 = 0.25, stiffness_nm_rad = 1e-6, damping_nm_s_rad = 0 }",
    ] {
        torsion(ok).unwrap_or_else(|e| panic!("{ok}: {e}"));
    }
}

/// A list's item is named with its 1-based index.
#[test]
fn list_items_are_named_with_their_index() {
    refused(
        bare("journal_stiffness_nm_rad = [2e6, 2e6, 1e308, 2e6, 2e6]"),
        "torsion.journal_stiffness_nm_rad[3]",
        "1e-6 to 1e14 N m/rad",
    );
    refused(
        torsion("throw_inertia_kg_m2 = [0.12, 1e-300, 0.12]"),
        "torsion.throw_inertia_kg_m2[2]",
        "1e-12 to 1e9 kg m²",
    );
    refused(
        torsion("shaft_diameter_mm = [110, 110, 110, 110, 110, 1e300]"),
        "torsion.shaft_diameter_mm[6]",
        "mm",
    );
}

/// A damping ratio given as a percentage is refused with the ratio it
/// likely means, one its own bound accepts.
#[test]
fn damping_ratio_as_a_percentage() {
    let msg = refused(
        torsion("damping_ratio = 2"),
        "torsion.damping_ratio",
        "from 0 to below 1",
    );
    assert!(msg.contains("a percentage (0.02)?"), "{msg}");
    // 150 % would be 1.5, which the bound refuses: no hint then.
    let msg = refused(
        torsion("damping_ratio = 150"),
        "torsion.damping_ratio",
        "from 0 to below 1",
    );
    assert!(!msg.contains("percentage"), "{msg}");
}
