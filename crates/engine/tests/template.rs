//! `enginedyn template` (issue 30, item 8): for every cylinder count and
//! layout the commented engine file reads back as an engine that passes
//! the crank checks, writes every key of the one key table, and says
//! which defaults it leaves to enginedyn.

use enginedyn_engine::file::parse;
use enginedyn_engine::keys::KEYS;
use enginedyn_engine::template::{
    CombustionKind, TemplateError, TemplateLayout, TemplateOptions, template,
};
use enginedyn_engine::{Layout, TakenDefault};

/// With `torsion`, the diesel `[combustion]` section too (every key).
fn opts(cylinders: usize, layout: TemplateLayout, torsion: bool) -> TemplateOptions {
    TemplateOptions {
        cylinders,
        layout,
        torsion,
        combustion: torsion.then_some(CombustionKind::Diesel),
    }
}

/// Every count a layout can have reads back, fires evenly in the order
/// written, and carries the layout asked for.
#[test]
fn every_count_and_layout_reads_back_and_fires_evenly() {
    for layout in [
        TemplateLayout::Inline,
        TemplateLayout::Vee,
        TemplateLayout::Boxer,
    ] {
        for z in 1..=24 {
            let o = opts(z, layout, z % 3 == 0);
            let text = match template(&o) {
                Ok(t) => t,
                Err(TemplateError::Cylinders { .. }) if layout != TemplateLayout::Inline => {
                    assert!(z % 2 == 1, "{z} {layout:?} refused");
                    continue;
                }
                Err(e) => panic!("{z} {layout:?}: {e}"),
            };
            let e = parse(&text, "t").unwrap_or_else(|e| panic!("{z} {layout:?}: {e}\n{text}"));
            assert_eq!(e.cylinders(), z);
            let ok_layout = matches!(
                (e.layout(), layout),
                (Layout::Inline, TemplateLayout::Inline)
                    | (Layout::Vee { .. }, TemplateLayout::Vee)
                    | (Layout::Boxer, TemplateLayout::Boxer)
            );
            assert!(ok_layout, "{z} {layout:?}");
            // Even firing: sorted firing angles 720/z apart.
            let mut f: Vec<f64> = e.firing_angles().iter().map(|a| a.to_degrees()).collect();
            f.sort_by(f64::total_cmp);
            for w in f.windows(2) {
                assert!(
                    (w[1] - w[0] - 720.0 / z as f64).abs() < 1e-6,
                    "{z} {layout:?}: {f:?}"
                );
            }
        }
    }
}

/// The template writes every key of the table (`key = ` set or commented
/// out), required ones first, each with its unit and default in the
/// comment above it.
#[test]
fn every_key_is_written_with_unit_and_default() {
    let text = template(&opts(4, TemplateLayout::Inline, true)).unwrap();
    for k in KEYS {
        if k.path() == "combustion.second" {
            // A table of its own.
            assert!(text.contains("\n[combustion.second]\n"), "{text}");
            continue;
        }
        if k.section == "combustion.full_load" {
            // An inline table, `full_load = { rpm = [...], imep_bar = [...] }`.
            assert!(text.contains("\nfull_load = { rpm = "), "{text}");
            continue;
        }
        let line = format!("{} = ", k.key);
        assert!(text.contains(&line), "{} missing:\n{text}", k.path());
        if k.section != "torsion.damper" {
            let head = format!("# {}", k.key);
            assert!(text.contains(&head), "{} has no comment", k.path());
        }
    }
    // Required first: `cycle` is set before any commented-out key of the top.
    let cycle = text.find("\ncycle = ").unwrap();
    let name = text.find("# name = ").unwrap();
    assert!(cycle < name);
    // Without --torsion no [torsion] table, but a pointer to it.
    let plain = template(&TemplateOptions::default()).unwrap();
    assert!(!plain.contains("\n[torsion]"));
    assert!(plain.contains("enginedyn template --torsion"));
    // The layouts' cranks the brief names.
    let v8 = template(&opts(8, TemplateLayout::Vee, false)).unwrap();
    assert!(v8.contains("bank_angle_deg = 90"), "{v8}");
    assert!(v8.contains("firing_order = [1, 5, 4, 8, 7, 2, 6, 3]"));
    let v6 = template(&opts(6, TemplateLayout::Vee, false)).unwrap();
    assert!(
        v6.contains("crank_angles_deg = [0.0, 120.0, 240.0, 30.0, 150.0, 270.0]"),
        "{v6}"
    );
    assert!(v6.contains("firing_order = [1, 4, 3, 6, 2, 5]"));
    let v12 = template(&opts(12, TemplateLayout::Vee, false)).unwrap();
    assert!(v12.contains("bank_angle_deg = 60"));
    assert!(v12.contains("firing_order = [1, 7, 5, 11, 3, 9, 6, 12, 2, 8, 4, 10]"));
}

#[test]
fn odd_vee_or_boxer_is_refused_naming_the_flag() {
    for layout in [TemplateLayout::Vee, TemplateLayout::Boxer] {
        let e = template(&opts(5, layout, false)).unwrap_err().to_string();
        assert!(e.contains("--cylinders 5") && e.contains("even"), "{e}");
    }
    let e = template(&opts(25, TemplateLayout::Inline, false))
        .unwrap_err()
        .to_string();
    assert!(e.contains("1 to 24"), "{e}");
}

/// The template leaves the four result-shaping defaults to enginedyn, and
/// the engine says so; uncommenting them silences the note.
#[test]
fn template_takes_the_shaping_defaults() {
    let text = template(&TemplateOptions::default()).unwrap();
    let e = parse(&text, "t").unwrap();
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
    assert!(note.starts_with("defaults taken"), "{note}");
    for key in [
        "operating.mechanical_efficiency = 1",
        "flywheel.speed_fluctuation = 0.01",
        "flywheel.max_rim_speed_m_s = 60 m/s",
        "masses.crank_unbalanced_kg = 0",
    ] {
        assert!(note.contains(key), "{key}: {note}");
    }
    let given = text
        .replace("# mechanical_efficiency = ", "mechanical_efficiency = ")
        .replace("# speed_fluctuation = ", "speed_fluctuation = ")
        .replace("# outer_diameter_mm = ", "outer_diameter_mm = ")
        .replace("# crank_unbalanced_kg = ", "crank_unbalanced_kg = ");
    let e = parse(&given, "t").unwrap();
    assert!(e.defaults_taken().is_empty(), "{:?}", e.defaults_taken());
    assert_eq!(e.defaults_note(), None);
}
