//! `[combustion]` of the engine file: both forms of the burn law, the
//! second burn, the defaults, and every bound refused naming its key.

use enginedyn_engine::EngineError;
use enginedyn_engine::combustion::{CombustionLoad, GammaModel};
use enginedyn_engine::file::parse;
use enginedyn_engine::template::{CombustionKind, TemplateOptions, template};

const ENGINE: &str = include_str!("../../../data/vaz2108.toml");

fn with(section: &str) -> Result<enginedyn_engine::Engine, EngineError> {
    parse(&format!("{ENGINE}\n{section}"), "t")
}

fn error(section: &str) -> String {
    with(section).unwrap_err().to_string()
}

#[test]
fn ca50_form_with_defaults() {
    let e = with(
        "[combustion]\nca50_deg = 8.0\nduration_10_90_deg = 20.0\nwiebe_m = 2\nimep_bar = 9\n",
    )
    .unwrap();
    let c = e.combustion().unwrap();
    assert!((c.burn.angle_of(0.5) - 8.0).abs() < 1e-12);
    assert!((c.burn.angle_of(0.9) - c.burn.angle_of(0.1) - 20.0).abs() < 1e-12);
    assert!((c.burn.first().a() - 6.908).abs() < 1e-15);
    assert_eq!(c.load, Some(CombustionLoad::Imep(9.0e5)));
    assert!((c.intake_pressure_pa - 1.0e5).abs() < 1e-9);
    assert!((c.intake_temp_k - 320.0).abs() < 1e-12);
    assert_eq!(c.gamma, GammaModel::Constant(1.32));
    assert_eq!(
        (c.ivc_deg.to_bits(), c.evo_deg.to_bits()),
        ((-140f64).to_bits(), 130f64.to_bits())
    );
    // No section, no combustion.
    assert!(parse(ENGINE, "t").unwrap().combustion().is_none());
}

#[test]
fn wiebe_form_second_burn_and_brunt() {
    let e = with(
        "[combustion]\nstart_deg = -6.0\nduration_deg = 12.0\nwiebe_a = 6.908\nwiebe_m = 2.0\n\
         heat_released_j = 700\ngamma = \"brunt\"\nivc_deg = -135\nintake_temp_k = 330\n\
         [combustion.second]\nfraction = 0.75\nstart_deg = -2.0\nduration_deg = 60.0\nwiebe_a = 6.908\nwiebe_m = 0.8\n",
    )
    .unwrap();
    let c = e.combustion().unwrap();
    assert_eq!(c.load, Some(CombustionLoad::Heat(700.0)));
    assert_eq!(
        c.gamma,
        GammaModel::Brunt {
            ivc_deg: -135.0,
            intake_temp_k: 330.0
        }
    );
    let (w, f) = c.burn.second().unwrap();
    assert!((f - 0.75).abs() < 1e-15);
    assert!((w.start_deg() + 2.0).abs() < 1e-15);
    assert!((c.burn.start_deg() + 6.0).abs() < 1e-15);
}

/// Every bound and rule refused naming its key (exit 2: an engine-file error).
#[test]
fn bounds_name_the_key() {
    let law = "[combustion]\nca50_deg = 8.0\nduration_10_90_deg = 20.0\nwiebe_m = 2.0\n";
    for (extra, key) in [
        ("imep_bar = 0", "combustion.imep_bar"),
        ("imep_bar = 900", "combustion.imep_bar"),
        ("heat_released_j = -1", "combustion.heat_released_j"),
        (
            "imep_bar = 9\nheat_released_j = 600",
            "combustion.heat_released_j",
        ),
        (
            "intake_pressure_bar = 0.01",
            "combustion.intake_pressure_bar",
        ),
        ("intake_temp_k = 5000", "combustion.intake_temp_k"),
        ("gamma = 1.0", "combustion.gamma"),
        ("gamma = \"air\"", "combustion.gamma"),
        ("ivc_deg = 10", "combustion.ivc_deg"),
        ("ivc_deg = -300", "combustion.ivc_deg"),
        ("evo_deg = 400", "combustion.evo_deg"),
        ("evo_deg = 5", "combustion.evo_deg"),
        ("ivc_deg = -5", "combustion.ca50_deg"),
        ("wiebe_a = 50", "combustion.wiebe_a"),
        ("start_deg = -10", "combustion.start_deg"),
        ("duration_deg = 40", "combustion.duration_deg"),
        ("bogus = 1", "bogus"),
    ] {
        let e = error(&format!("{law}{extra}\n"));
        assert!(e.contains(&format!("`{key}`")), "{extra}: {e}");
    }
    for (section, key) in [
        (
            "[combustion]\nca50_deg = 200\nduration_10_90_deg = 20\nwiebe_m = 2\n",
            "combustion.ca50_deg",
        ),
        (
            "[combustion]\nduration_10_90_deg = 20\nwiebe_m = 2\n",
            "combustion.ca50_deg",
        ),
        (
            "[combustion]\nca50_deg = 8\nwiebe_m = 2\n",
            "combustion.duration_10_90_deg",
        ),
        (
            "[combustion]\nca50_deg = 8\nduration_10_90_deg = 20\n",
            "combustion.wiebe_m",
        ),
        (
            "[combustion]\nca50_deg = 8\nduration_10_90_deg = 20\nwiebe_m = 20\n",
            "combustion.wiebe_m",
        ),
        (
            "[combustion]\nstart_deg = -10\nduration_deg = 40\nwiebe_m = 2\n",
            "combustion.wiebe_a",
        ),
        (
            "[combustion]\nstart_deg = -10\nwiebe_a = 6.9\nwiebe_m = 2\n",
            "combustion.duration_deg",
        ),
        (
            &format!(
                "{law}[combustion.second]\nca50_deg = 20\nduration_10_90_deg = 40\nwiebe_m = 0.8\n"
            ),
            "combustion.second.fraction",
        ),
        (
            &format!(
                "{law}[combustion.second]\nfraction = 2\nca50_deg = 20\nduration_10_90_deg = 40\nwiebe_m = 0.8\n"
            ),
            "combustion.second.fraction",
        ),
        (
            &format!(
                "{law}[combustion.second]\nfraction = 0.5\nca50_deg = 20\nduration_10_90_deg = 40\n"
            ),
            "combustion.second.wiebe_m",
        ),
        (
            &format!(
                "{law}[combustion.second]\nfraction = 0.5\nca50_deg = 20\nduration_10_90_deg = 40\nwiebe_m = 1\nfoo = 2\n"
            ),
            "foo",
        ),
    ] {
        let e = error(section);
        assert!(e.contains(&format!("`{key}`")), "{section}: {e}");
    }
}

/// `template --combustion petrol|diesel` reads back with the section.
#[test]
fn template_sections_read_back() {
    for kind in [CombustionKind::Petrol, CombustionKind::Diesel] {
        let text = template(&TemplateOptions {
            combustion: Some(kind),
            ..TemplateOptions::default()
        })
        .unwrap();
        assert!(text.contains("\n[combustion]\n"), "{text}");
        let e = parse(&text, "t").unwrap();
        let c = e.combustion().expect("the section is read");
        assert!(c.load.is_some());
        assert_eq!(c.burn.second().is_some(), kind == CombustionKind::Diesel);
    }
    let plain = template(&TemplateOptions::default()).unwrap();
    assert!(!plain.contains("\n[combustion]"));
    assert!(plain.contains("--combustion petrol|diesel"));
}

/// The design model's keys: `charge` and its defaults, curves over speed
/// (linear between points, held at the ends), the full-load line and
/// `[friction]` (each key left out the kind's default).
#[test]
fn design_model_keys() {
    use enginedyn_engine::combustion::OverSpeed;
    let e = with(
        "[combustion]\nca50_deg = 8.0\nwiebe_m = 2\nimep_bar = 9\ncharge = \"ci\"\n\
         duration_10_90_deg = { rpm = [1000.0, 3000.0], deg = [20.0, 30.0] }\n\
         intake_pressure_bar = { rpm = [1000, 2000, 3000], bar = [1.5, 2.5, 2.0] }\n\
         full_load = { rpm = [1000.0, 3000.0], bmep_bar = [12.0, 14.0] }\n\
         [friction]\na_bar = 0.5\n",
    )
    .unwrap();
    let c = e.combustion().unwrap();
    let charge = c.charge.unwrap();
    assert_eq!(charge.kind.name(), "ci");
    assert_eq!(
        (charge.lambda_min, charge.lhv_j_kg, charge.afr_stoich),
        (1.2, 42.7e6, 14.5)
    );
    assert!(matches!(c.intake, OverSpeed::Curve(_)));
    assert!((c.intake_at(Some(1500.0)) - 2.0e5).abs() < 1e-6);
    assert!((c.intake_at(Some(500.0)) - 1.5e5).abs() < 1e-6);
    assert!((c.intake_at(Some(9000.0)) - 2.0e5).abs() < 1e-6);
    let law = c.burn_at(Some(2000.0)).unwrap();
    assert!((law.angle_of(0.9) - law.angle_of(0.1) - 25.0).abs() < 1e-9);
    assert!((law.angle_of(0.5) - 8.0).abs() < 1e-9);
    assert!(c.varies_with_speed());
    let fl = c.full_load.as_ref().unwrap();
    assert!(fl.brake && (fl.curve.at(2000.0) - 13.0e5).abs() < 1e-6);
    let f = e.friction().unwrap();
    // a given; the rest the diesel's.
    assert_eq!((f.a_pa, f.b, f.c_pa_s_m), (0.5e5, 0.004, 0.08e5));
}

#[test]
fn design_model_keys_are_checked() {
    let base =
        "[combustion]\nca50_deg = 8.0\nduration_10_90_deg = 20.0\nwiebe_m = 2\nimep_bar = 9\n";
    for (extra, want) in [
        ("charge = \"otto\"\n", "combustion.charge"),
        (
            "lambda = 1.0\n",
            "combustion.lambda` = given without charge",
        ),
        ("charge = \"si\"\nlambda = 5.0\n", "combustion.lambda"),
        (
            "intake_pressure_bar = { rpm = [2000.0, 1000.0], bar = [1.0, 1.0] }\n",
            "rising speeds",
        ),
        (
            "intake_pressure_bar = { rpm = [1000.0, 2000.0], bar = [1.0] }\n",
            "one value for each speed",
        ),
        (
            "intake_pressure_bar = { rpm = [1000.0], boost = [1.0] }\n",
            "combustion.intake_pressure_bar.boost",
        ),
        (
            "full_load = { rpm = [1000.0], bmep_bar = [10.0] }\n",
            "friction",
        ),
        (
            "full_load = { rpm = [1000.0], imep_bar = [90.0] }\n",
            "combustion.full_load.imep_bar",
        ),
    ] {
        let e = error(&format!("{base}{extra}"));
        assert!(e.contains(want), "{extra}: {e}");
    }
    let e = error(&format!("{base}[friction]\nb = 2.0\n"));
    assert!(e.contains("friction.b"), "{e}");
    // A CA50 outside a running engine's, in the Wiebe form too.
    let e = error(
        "[combustion]\nstart_deg = 40.0\nduration_deg = 60.0\nwiebe_a = 6.908\nwiebe_m = 2\nimep_bar = 9\n",
    );
    assert!(
        e.contains("combustion.start_deg") && e.contains("-30 to 60"),
        "{e}"
    );
}
