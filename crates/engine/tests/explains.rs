//! The engine file explains itself (issue 30, items 8 and 11): an unknown
//! key with no close match lists the keys its section takes, and the
//! defaults that shape the results are said when the file leaves them out.

use enginedyn_engine::TakenDefault;
use enginedyn_engine::file::parse;

const BASE: &str = r#"
cycle = "four-stroke"
cylinders = 4
firing_order = [1, 3, 4, 2]
bore_mm = 76.0
stroke_mm = 71.0
lambda = 0.26
compression_ratio = 9.9
[masses]
piston_group_kg = 0.45
rod_kg = 0.52
[operating]
rpm = 4900
"#;

#[test]
fn unknown_key_without_a_near_match_lists_the_section() {
    // At the top of the file: its keys, then the sections.
    let msg = parse(&BASE.replace("bore_mm", "displacement_l = 1\nbore_mm"), "x")
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("unknown key `displacement_l` in [root] (line 5)"),
        "{msg}"
    );
    assert!(!msg.contains("did you mean"), "{msg}");
    assert!(
        msg.contains("the top of the file takes name, cycle, mechanism, cylinders, layout,"),
        "{msg}"
    );
    assert!(!msg.contains("shaft_diameter_mm"), "{msg}");
    assert!(
        msg.contains(
            "then the sections [masses], [operating], [flywheel], [tolerances], [torsion]"
        ),
        "{msg}"
    );
    assert!(msg.contains("docs/engine-file.md"), "{msg}");
    // In a section: that section's keys, all of them.
    let msg = parse(
        &BASE.replace("rod_kg = 0.52", "rod_kg = 0.52\nweight = 3"),
        "x",
    )
    .unwrap_err()
    .to_string();
    assert!(
        msg.contains(
            "[masses] takes piston_group_kg, rod_kg, rod_cg_from_small_end_mm, rod_inertia_kg_m2, crank_unbalanced_kg, yoke_kg, slider_block_kg"
        ),
        "{msg}"
    );
    // A close match still gets its suggestion, and no list.
    let msg = parse(&BASE.replace("rod_kg", "rod_kgs"), "x")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("did you mean `rod_kg`?"), "{msg}");
    assert!(!msg.contains("takes"), "{msg}");
    // The damper's inline table: its three keys, at its line.
    let text = format!(
        "{BASE}[torsion]\njournal_stiffness_nm_rad = 3e5\ndamper = {{ mass = 1.0, stiffness_nm_rad = 2e4 }}\n"
    );
    let msg = parse(&text, "x").unwrap_err().to_string();
    assert!(
        msg.contains("unknown key `mass` in [torsion.damper] (line 16)"),
        "{msg}"
    );
    assert!(
        msg.contains("[torsion.damper] takes inertia_kg_m2, stiffness_nm_rad, damping_nm_s_rad"),
        "{msg}"
    );
    // A [torsion.damper] table reads as the inline one does.
    let text = format!(
        "{BASE}[torsion]\njournal_stiffness_nm_rad = 3e5\n[torsion.damper]\ninertia_kg_m2 = 0.003\nstiffness_nm_rad = 2e4\n"
    );
    let spec = enginedyn_engine::file::parse_torsion(&text)
        .unwrap()
        .unwrap();
    assert!(spec.damper.is_some());
    parse(&text, "x").unwrap();
}

#[test]
fn defaults_that_shape_the_results_are_said() {
    let e = parse(BASE, "x").unwrap();
    assert_eq!(
        e.defaults_taken(),
        &[
            TakenDefault::MechanicalEfficiency,
            TakenDefault::SpeedFluctuation,
            TakenDefault::RimSpeed,
            TakenDefault::CrankUnbalance
        ]
    );
    let note = e.defaults_note().unwrap();
    assert!(
        note.starts_with(
            "defaults taken (not in the engine file): operating.mechanical_efficiency = 1 ("
        ),
        "{note}"
    );
    // The outer diameter settles the rim speed; each key given drops out.
    let text = BASE.replace(
        "[operating]",
        "crank_unbalanced_kg = 0.6\n[flywheel]\nouter_diameter_mm = 280\n[operating]",
    );
    let e = parse(&text, "x").unwrap();
    assert_eq!(
        e.defaults_taken(),
        &[
            TakenDefault::MechanicalEfficiency,
            TakenDefault::SpeedFluctuation
        ]
    );
    let note = e.defaults_note().unwrap();
    assert!(
        !note.contains("max_rim_speed") && !note.contains("crank_unbalanced"),
        "{note}"
    );
    // The bundled example gives all four: no note.
    let bundled = parse(include_str!("../../../data/vaz2108.toml"), "vaz").unwrap();
    assert!(bundled.defaults_taken().is_empty());
    assert_eq!(bundled.defaults_note(), None);
}
