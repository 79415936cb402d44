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
    // "Did you mean" only for a close name: a misspelling or a known key's
    // beginning, never a name that merely shares its first letter.
    for (key, nearest) in [
        ("lamda", Some("lambda")),
        ("strok", Some("stroke_mm")),
        ("r", None),
        ("ro", None),
        ("rod_mass_kg", None),
    ] {
        let text = BASE.replace("bore_mm", &format!("{key} = 1\nbore_mm"));
        let msg = parse(&text, "x").unwrap_err().to_string();
        match nearest {
            Some(n) => assert!(msg.contains(&format!("did you mean `{n}`")), "{key}: {msg}"),
            None => assert!(!msg.contains("did you mean"), "{key}: {msg}"),
        }
    }
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

/// A 90° V6 on split pins: throws 0, 120, 240° and each bank-2 pin 30°
/// behind its partner (`crank_angles_deg` per cylinder). PHYSICS.md's rule
/// `theta_i = alpha_i + gamma_i + 360° j_i` with the order 1-4-3-6-2-5 gives
/// 4 = 30 + 90 = 120°, 3 = 240°, 6 = 270 + 90 = 360°, 2 = 120 + 360 = 480°,
/// 5 = 150 + 90 + 360 = 600°: every 120°, exactly.
#[test]
fn split_pin_v6_90_fires_every_120() {
    let text = BASE
        .replace(
            "cylinders = 4",
            "cylinders = 6\nlayout = \"vee\"\nbank_angle_deg = 90\n\
             crank_angles_deg = [0, 120, 240, 30, 150, 270]",
        )
        .replace("[1, 3, 4, 2]", "[1, 4, 3, 6, 2, 5]");
    let e = parse(&text, "v6").unwrap();
    assert!(e.split_pins());
    assert_eq!(e.throws(), 3);
    assert_eq!(
        deg(e.firing_angles()),
        vec![0.0, 480.0, 240.0, 120.0, 600.0, 360.0]
    );
    assert_eq!(
        deg(e.crank_angles()),
        vec![0.0, 120.0, 240.0, 30.0, 150.0, 270.0]
    );
    assert_eq!(
        deg(e.pin_angles()),
        vec![0.0, 120.0, 240.0, 30.0, 150.0, 270.0]
    );
    // The same engine from its firing angles and split pins alone.
    let from_firing = text.replace(
        "crank_angles_deg = [0, 120, 240, 30, 150, 270]",
        "crank_angles_deg = [0, 120, 240, 30, 150, 270]\n\
         firing_angles_deg = [0, 480, 240, 120, 600, 360]",
    );
    assert_eq!(parse(&from_firing, "v6").unwrap(), e);
    // A pin that contradicts the firing is refused by name.
    let wrong = from_firing.replace("30, 150, 270]", "30, 150, 280]");
    let msg = parse(&wrong, "v6").unwrap_err().to_string();
    assert!(
        msg.starts_with("`crank_angles_deg`") && msg.contains("pin of cylinder 6"),
        "{msg}"
    );
    // Neither per throw nor per cylinder: the error says both.
    let short = text.replace("30, 150, 270]", "30]");
    let msg = parse(&short, "v6").unwrap_err().to_string();
    assert!(
        msg.contains("one finite angle per throw (3), or per cylinder (6) for split crank pins"),
        "{msg}"
    );
    // Shared pins of a V8 stay shared (one lag per throw).
    let v8 = BASE
        .replace(
            "cylinders = 4",
            "cylinders = 8\nlayout = \"vee\"\nbank_angle_deg = 90",
        )
        .replace("[1, 3, 4, 2]", "[1, 5, 4, 8, 7, 2, 6, 3]");
    let v8 = parse(&v8, "v8").unwrap();
    assert!(!v8.split_pins());
    assert_eq!(
        deg(v8.pin_angles()),
        vec![0.0, 90.0, 270.0, 180.0, 0.0, 90.0, 270.0, 180.0]
    );
}

/// The bundled 90° V6 is the split-pin engine above.
#[test]
fn bundled_v6_90_even_fire() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/v6_90.toml");
    let e = enginedyn_engine::file::read(std::path::Path::new(path)).unwrap();
    assert!(e.split_pins());
    let mut f = deg(e.firing_angles());
    f.sort_by(f64::total_cmp);
    assert_eq!(f, vec![0.0, 120.0, 240.0, 360.0, 480.0, 600.0]);
    assert!(e.notes().is_empty(), "{:?}", e.notes());
}

/// Split pins are for a vee: an inline engine's `crank_angles_deg` is per
/// throw.
#[test]
fn split_pins_only_on_a_vee() {
    let text = BASE.replace(
        "cylinders = 4",
        "cylinders = 4\ncrank_angles_deg = [0, 180, 180, 0]",
    );
    assert!(!parse(&text, "i4").unwrap().split_pins());
}

/// `firing_order` may be left out only for the crank search; elsewhere the
/// error names the key and the command that finds one.
#[test]
fn firing_order_optional_for_the_crank_search() {
    let text = BASE
        .replace(
            "cylinders = 4",
            "cylinders = 6\nlayout = \"vee\"\nbank_angle_deg = 90",
        )
        .replace("firing_order = [1, 3, 4, 2]\n", "");
    let err = parse(&text, "v6").unwrap_err();
    assert!(matches!(
        err,
        EngineError::Missing {
            key: "firing_order",
            ..
        }
    ));
    let msg = err.to_string();
    assert!(
        msg.contains("missing key `firing_order`")
            && msg.contains("enginedyn firing-orders --all-cranks"),
        "{msg}"
    );
    let e = enginedyn_engine::file::parse_for_crank_search(&text, "v6").unwrap();
    assert!(!e.firing_order_given());
    assert!(e.split_pins(), "a placeholder vee fires on split pins");
    assert_eq!(e.firing_order(), &[1, 2, 3, 4, 5, 6]);
    // With a crank or firing angles, the order is still needed.
    let with_crank = text.replace(
        "bank_angle_deg = 90",
        "bank_angle_deg = 90\ncrank_angles_deg = [0, 120, 240]",
    );
    let msg = enginedyn_engine::file::parse_for_crank_search(&with_crank, "v6")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("missing key `firing_order`"), "{msg}");
    // A file with its order reads the same either way.
    assert_eq!(
        enginedyn_engine::file::parse_for_crank_search(BASE, "vaz").unwrap(),
        parse(BASE, "vaz").unwrap()
    );
}

/// The assumed-spacing note only where the spacing matters (free moments,
/// more than one throw).
#[test]
fn no_spacing_note_on_one_cylinder() {
    let single = BASE
        .replace("cylinders = 4", "cylinders = 1")
        .replace("firing_order = [1, 3, 4, 2]\n", "");
    let e = parse(&single, "one").unwrap();
    assert!(e.notes().is_empty(), "{:?}", e.notes());
    let four = parse(BASE, "four").unwrap();
    assert_eq!(
        four.notes(),
        &["cylinder_spacing_mm not given: assumed 1.2 × bore = 91.2 mm".to_string()]
    );
}

/// Implausible data is built, and noted with the key and the likely
/// mistake, numbers as people write them.
#[test]
fn plausibility_notes_name_key_and_mistake() {
    let plain = parse(BASE, "vaz").unwrap();
    // 4900 rpm × 71 mm / 30 = 11.6 m/s; λ = 0.26.
    assert!(plain.plausibility_notes(Some(4900.0)).is_empty());
    let metres = BASE
        .replace("bore_mm = 76.0", "bore_mm = 0.086")
        .replace("lambda = 0.26", "rod_length_mm = 136.5");
    let e = parse(&metres, "m").unwrap();
    let notes = e.plausibility_notes(None);
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].starts_with("bore_mm = 0.086: metres?"),
        "{notes:?}"
    );
    let cm = BASE.replace("stroke_mm = 71.0", "stroke_mm = 7.1");
    let notes = parse(&cm, "cm").unwrap().plausibility_notes(None);
    assert!(
        notes[0].starts_with("stroke_mm = 7.1: centimetres?"),
        "{notes:?}"
    );
    let huge = BASE.replace("bore_mm = 76.0", "bore_mm = 76000");
    let notes = parse(&huge, "um").unwrap().plausibility_notes(None);
    assert!(notes[0].starts_with("bore_mm = 76000: "), "{notes:?}");
    // λ = 35.5 / 50 = 0.71: a rod this short.
    let short = BASE.replace("lambda = 0.26", "rod_length_mm = 50");
    let notes = parse(&short, "short").unwrap().plausibility_notes(None);
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].contains("λ = R/L = 0.71 (stroke_mm = 71, rod length 50 mm) is above 0.5"),
        "{notes:?}"
    );
    let long = BASE.replace("lambda = 0.26", "lambda = 0.05");
    let notes = parse(&long, "long").unwrap().plausibility_notes(None);
    assert!(
        notes[0].contains("λ = R/L = 0.05 ") && notes[0].contains("below 0.1"),
        "{notes:?}"
    );
    // 71 mm at 18000 rpm: 0.071 × 18000 / 30 = 42.6 m/s, over 40.
    let notes = plain.plausibility_notes(Some(18000.0));
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0]
            .starts_with("mean piston speed 42.6 m/s (stroke_mm = 71 at 18000 rpm) is over 40 m/s"),
        "{notes:?}"
    );
    // 16900 rpm gives 40.0 m/s: not over.
    assert!(plain.plausibility_notes(Some(16900.0)).is_empty());
    // Never exponent notation (`4.26e1`).
    for n in notes
        .iter()
        .chain(&parse(&metres, "m").unwrap().plausibility_notes(None))
    {
        let b = n.as_bytes();
        assert!(
            !b.windows(2).any(|w| w[0].is_ascii_digit() && w[1] == b'e'),
            "{n}"
        );
    }
}

/// Found by the property tests of `tests/tests/fuzz_paths.rs`: a subnormal
/// distance passed the "above 0" check and made the rod's mass split
/// infinite. Every size has a hard bound now, named in the error.
#[test]
fn subnormal_sizes_are_refused() {
    let text = BASE.replace("[masses]", "[masses]\nrod_cg_from_small_end_mm = 1e-310");
    let msg = parse(&text, "x").unwrap_err().to_string();
    assert!(
        msg.contains("masses.rod_cg_from_small_end_mm") && msg.contains("from 0.001 to"),
        "{msg}"
    );
}
