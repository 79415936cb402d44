//! Engine file reading: keys, defaults, errors, firing angles.

use enginedyn_engine::{EngineError, Layout, file::parse};

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

fn deg(v: &[f64]) -> Vec<f64> {
    v.iter()
        .map(|a| (a.to_degrees() * 1e9).round() / 1e9)
        .collect()
}

#[test]
fn inline_four_even_firing_and_defaults() {
    let e = parse(BASE, "vaz").unwrap();
    assert_eq!(e.name(), "vaz");
    // 1-3-4-2 at 180° intervals: cylinder 3 at 180, 4 at 360, 2 at 540.
    assert_eq!(deg(e.firing_angles()), vec![0.0, 540.0, 180.0, 360.0]);
    assert_eq!(deg(e.crank_angles()), vec![0.0, 180.0, 180.0, 0.0]);
    // Default l_A = 0.725 L and p0 = 1.01325 bar; the spacing is assumed and noted.
    let l = 0.0355 / 0.26;
    assert!((e.masses().rod_cg_from_small_end - 0.725 * l).abs() < 1e-12);
    assert!((e.operating().crankcase_pressure - 101325.0).abs() < 1e-9);
    assert!(e.notes().iter().any(|n| n.contains("cylinder_spacing_mm")));
    // Two-mass split: m_A = m l_B / L = 0.275 m.
    let mj = e.reciprocating_mass(enginedyn_engine::RodModel::TwoMass);
    assert!((mj - (0.45 + 0.275 * 0.52)).abs() < 1e-12);
}

#[test]
fn unknown_key_names_the_nearest() {
    let text = BASE.replace("bore_mm", "bore");
    let e = parse(&text, "x").unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("unknown key `bore` in [root]"), "{msg}");
    assert!(msg.contains("did you mean `bore_mm`?"), "{msg}");
    assert!(msg.contains("line 5"), "{msg}");
    let text = BASE.replace("rpm = 4900", "rpms = 4900");
    let msg = parse(&text, "x").unwrap_err().to_string();
    assert!(
        msg.contains("[operating]") && msg.contains("`rpm`"),
        "{msg}"
    );
}

#[test]
fn missing_and_invalid_keys() {
    let e = parse(&BASE.replace("bore_mm = 76.0\n", ""), "x").unwrap_err();
    assert!(matches!(e, EngineError::Missing { key: "bore_mm", .. }));
    let e = parse(
        &BASE.replace("lambda = 0.26", "lambda = 0.26\nrod_length_mm = 136.5"),
        "x",
    );
    assert!(e.unwrap_err().to_string().contains("exactly one"));
    let e = parse(&BASE.replace("[1, 3, 4, 2]", "[1, 3, 3, 2]"), "x").unwrap_err();
    assert!(e.to_string().contains("firing_order"));
    let e = parse(
        &BASE.replace("lambda = 0.26", "lambda = 0.26\npin_offset_mm = 200"),
        "x",
    );
    let msg = e.unwrap_err().to_string();
    assert!(
        msg.contains("pin_offset_mm") && msg.contains("below 1"),
        "{msg}"
    );
    let e = parse(
        &BASE.replace(
            "rod_kg = 0.52",
            "rod_kg = 0.52\nrod_cg_from_small_end_mm = 200",
        ),
        "x",
    );
    assert!(e.unwrap_err().to_string().contains("inside the rod"));
    let e = parse(
        &BASE.replace("cycle = \"four-stroke\"", "cycle = \"4-stroke\""),
        "x",
    );
    assert!(e.unwrap_err().to_string().contains("\"four-stroke\""));
}

/// A 90° cross-plane V8 in this project's numbering (bank 1 = 1–4): throws
/// lag 0, 90, 270, 180°; the order 1-5-4-8-7-2-6-3 fires every 90°.
/// Hand check: cylinder 5 = throw 1 + bank 90° = 90°; 4 = throw 4 = 180°;
/// 8 = throw 4 + 90° = 270°; 7 = throw 3 + 90° = 360°; 2 = throw 2 + 360° = 450°.
#[test]
fn cross_plane_v8() {
    let text = BASE
        .replace(
            "cylinders = 4",
            "cylinders = 8\nlayout = \"vee\"\nbank_angle_deg = 90",
        )
        .replace("[1, 3, 4, 2]", "[1, 5, 4, 8, 7, 2, 6, 3]");
    let e = parse(&text, "v8").unwrap();
    assert!(matches!(e.layout(), Layout::Vee { .. }));
    assert_eq!(
        deg(e.firing_angles()),
        vec![0.0, 450.0, 630.0, 180.0, 90.0, 540.0, 360.0, 270.0]
    );
    assert_eq!(deg(e.crank_angles()), vec![0.0, 90.0, 270.0, 180.0]);
    // The same crank given explicitly gives the same firing.
    let text2 = text.replace(
        "bank_angle_deg = 90",
        "bank_angle_deg = 90\ncrank_angles_deg = [0, 90, 270, 180]",
    );
    assert_eq!(
        parse(&text2, "v8").unwrap().firing_angles(),
        e.firing_angles()
    );
    // A crank that contradicts the firing angles is refused.
    let text3 = text.replace("bank_angle_deg = 90", "bank_angle_deg = 90\ncrank_angles_deg = [0, 90, 270, 180]\nfiring_angles_deg = [0, 450, 630, 180, 90, 540, 360, 300]");
    assert!(parse(&text3, "v8").is_err());
}

/// A shared-pin 60° V6 cannot fire every 120°: the error says what would work.
#[test]
fn shared_pin_v6_even_firing_refused() {
    let text = BASE
        .replace(
            "cylinders = 4",
            "cylinders = 6\nlayout = \"vee\"\nbank_angle_deg = 60",
        )
        .replace("[1, 3, 4, 2]", "[1, 4, 2, 5, 3, 6]");
    let msg = parse(&text, "v6").unwrap_err().to_string();
    assert!(
        msg.contains("shared-pin") && msg.contains("split crank pins"),
        "{msg}"
    );
    // It names the key the firing came from and gives the split-pin crank
    // to paste: 1-4-2-5-3-6 every 120° with bank 2 at 60° puts cylinder
    // 4's pin at 120 - 60 = 60°, 2's at 240°, 5's at 360 - 60 = 300°,
    // 3's at 480 - 360 = 120°, 6's at 600 - 60 - 360 = 180°.
    assert!(
        msg.starts_with("`firing_order` = [1, 4, 2, 5, 3, 6]"),
        "{msg}"
    );
    assert!(
        msg.contains("`crank_angles_deg = [0, 240, 120, 60, 300, 180]`"),
        "{msg}"
    );
    assert!(msg.contains("firing-orders --all-cranks"), "{msg}");
    // Pasted, it fires evenly.
    let fixed = text.replace(
        "bank_angle_deg = 60",
        "bank_angle_deg = 60\ncrank_angles_deg = [0, 240, 120, 60, 300, 180]",
    );
    let e = parse(&fixed, "v6").unwrap();
    assert!(e.split_pins());
    assert_eq!(
        deg(e.firing_angles()),
        vec![0.0, 240.0, 480.0, 120.0, 360.0, 600.0]
    );
}

/// The bundled 60° V12 (bank 1 = 1–6): it fires every 60° in the order
/// 1-7-5-11-3-9-6-12-2-8-4-10 on the six-throw crank 0-120-240-240-120-0.
/// Hand check: 7 shares throw 1 and sits 60° (the bank) after 1; 11 shares
/// throw 5 (120°) and fires at 120 + 60 = 180°; 12 shares throw 6 (0°) and
/// fires at 0 + 60 + 360 = 420°.
#[test]
fn bundled_v12_firing_angles() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/v12_60.toml");
    let e = enginedyn_engine::file::read(std::path::Path::new(path)).unwrap();
    assert_eq!(
        deg(e.firing_angles()),
        vec![
            0.0, 480.0, 240.0, 600.0, 120.0, 360.0, 60.0, 540.0, 300.0, 660.0, 180.0, 420.0
        ]
    );
    assert_eq!(
        deg(e.crank_angles()),
        vec![0.0, 120.0, 240.0, 240.0, 120.0, 0.0]
    );
}

/// The bundled three-cylinder two-stroke fires every 120° (1-3-2).
#[test]
fn bundled_two_stroke_triple() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/i3_two_stroke.toml");
    let e = enginedyn_engine::file::read(std::path::Path::new(path)).unwrap();
    assert_eq!(deg(e.firing_angles()), vec![0.0, 240.0, 120.0]);
    assert_eq!(deg(e.crank_angles()), vec![0.0, 240.0, 120.0]);
}
