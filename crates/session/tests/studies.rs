//! The studies through the session, on the bundled examples (no files):
//! each checked against a closed form or an invariant, and each error's
//! class.

use enginedyn_session::{Bundled, Class, Input, Loaded, Method, Reader};

fn bundled(name: &str) -> (&'static Bundled, Loaded) {
    let b = Bundled::find(name).unwrap();
    (b, Loaded::bundled(b).unwrap())
}

/// `text` without its `[section]` (up to the next section).
fn without(text: &str, section: &str) -> String {
    let mut skip = false;
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with('[') {
            skip = line.trim() == section;
        }
        if !skip {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// A coarse grid keeps the studies quick in a debug build.
fn coarse() -> Method {
    Method {
        step_deg: Some(0.5),
        ..Method::default()
    }
}

#[test]
fn kinematics_table_meets_the_closed_forms() {
    let (_, loaded) = bundled("vaz2108");
    let k = enginedyn_session::kinematics::Kinematics::new(
        &loaded,
        Some(3000.0),
        enginedyn_kinematics::Model::Exact,
    )
    .unwrap();
    // ω = π n / 30, exactly as the rows use it.
    assert!((k.omega - 3000.0 * std::f64::consts::PI / 30.0).abs() < 1e-12);
    assert!(
        k.notes[0].starts_with("speed 3000 rpm from --rpm"),
        "{:?}",
        k.notes
    );
    let t = k.table(30.0).unwrap();
    assert_eq!(t.x.len(), 13, "0..=360 every 30°");
    let mech = loaded.engine.mechanism();
    let (r, lambda) = (mech.r(), mech.lambda());
    // TDC at 0 and 360, BDC at 180 (no pin offset): x = 0 and 2R.
    assert!(t.x[0].abs() < 1e-12 && t.x[12].abs() < 1e-12);
    assert!((t.x[6] - 2.0 * r).abs() < 1e-12 * r);
    // a(0) = R ω² (1 + λ), a(180°) = -R ω² (1 - λ); per ω²: d²x/dφ².
    assert!((t.d2x[0] - r * (1.0 + lambda)).abs() < 1e-12 * r);
    assert!((t.d2x[6] + r * (1.0 - lambda)).abs() < 1e-12 * r);
    // The table report writes: a header and one line per angle.
    let csv = enginedyn_report::kinematics_csv(&t, 30.0, r, k.omega);
    assert_eq!(csv.lines().count(), 14);
    let e = k.table(7.0).unwrap_err();
    assert_eq!(e.class, Class::Usage);
    assert!(e.message.contains("must divide 360°"), "{e}");
}

#[test]
fn tolerance_stack_up_bounds_and_seeded_monte_carlo() {
    let (b, loaded) = bundled("vaz2108");
    let tolerances = enginedyn_session::tolerance::Tolerances::of(&loaded).unwrap();
    assert!(!tolerances.0.is_empty());
    let run = |seed| {
        enginedyn_session::tolerance::study(
            &loaded,
            &tolerances,
            &Reader::default(),
            &coarse(),
            Some(Input::Bundled(b)),
            40,
            seed,
        )
        .unwrap()
    };
    let t = run(7);
    assert_eq!(t.diagram, "data/vaz2108.csv (bundled)");
    assert!((t.rpm - 4900.0).abs() < 1e-9);
    assert!(!t.study.stacks.is_empty());
    for st in &t.study.stacks {
        // worst case Σ|s|t ≥ sqrt(Σ(s t)²) = √3 × RSS σ.
        assert!(
            st.worst_case >= 3f64.sqrt() * st.rss * (1.0 - 1e-12),
            "{:?}: worst {} rss {}",
            st.output,
            st.worst_case,
            st.rss
        );
    }
    // The same seed, the same samples: bit for bit.
    let again = run(7);
    let mc = |t: &enginedyn_session::tolerance::ToleranceStudy| -> Vec<Option<f64>> {
        t.study.stacks.iter().map(|s| s.monte_carlo_std).collect()
    };
    assert_eq!(mc(&t), mc(&again));
    assert!(mc(&t).iter().any(Option::is_some));
    // tolerance.csv: one row per input and result.
    let csv = enginedyn_report::tolerance_csv(&t.study);
    assert_eq!(csv.lines().count(), t.study.rows.len() + 1);
}

#[test]
fn tolerances_missing_is_a_usage_error_and_no_report_section() {
    let (b, loaded) = bundled("vaz2108");
    let text = without(&loaded.text, "[tolerances]");
    let bare = Loaded::from_text(text.clone(), None).unwrap();
    let e = enginedyn_session::tolerance::Tolerances::of(&bare).unwrap_err();
    assert_eq!(e.class, Class::Usage);
    assert!(e.message.contains("no [tolerances] section"), "{e}");
    // run --out: a tolerance section with [tolerances], none without.
    let session = enginedyn_session::Session::new(
        loaded,
        Reader::default(),
        coarse(),
        enginedyn_pipeline::Scope::Full,
    )
    .unwrap();
    let out = session.analyse(&[Input::Bundled(b)]).unwrap();
    let engine = session.engine();
    let extra = enginedyn_session::tolerance::report_extra(
        engine,
        &session.loaded.text,
        &out.analysis,
        out.opts,
    )
    .unwrap()
    .expect("a [tolerances] section");
    assert_eq!(extra.sections[0].0, "Tolerances");
    assert_eq!(extra.charts[0].0, "tolerance.svg");
    assert!(extra.charts[0].1.starts_with("<svg"));
    let none =
        enginedyn_session::tolerance::report_extra(engine, &text, &out.analysis, out.opts).unwrap();
    assert!(none.is_none());
}

#[test]
fn torsion_study_over_given_speeds() {
    let (b, loaded) = bundled("i6_diesel");
    let spec = enginedyn_session::torsion::spec(&loaded).unwrap();
    let rpms: Vec<f64> = (0..12).map(|k| 600.0 + 200.0 * k as f64).collect();
    let t = enginedyn_session::torsion::study(
        &loaded,
        &spec,
        &Reader::default(),
        &coarse(),
        Some(Input::Bundled(b)),
        Some(rpms.clone()),
    )
    .unwrap();
    assert_eq!(t.rpms, rpms);
    assert_eq!(t.study.rows.len(), rpms.len());
    let f: Vec<f64> = (1..t.study.modes.len())
        .map(|m| t.study.modes.frequency_hz(m))
        .collect();
    assert!(!f.is_empty() && f[0] > 0.0);
    assert!(f.windows(2).all(|w| w[0] <= w[1]), "ascending: {f:?}");
    assert_eq!(
        t.all_notes().len(),
        t.warnings.len() + t.notes.len(),
        "warnings first, then notes"
    );
    // chain.json: four speeds, every fifth order; torque only on the throws.
    let dump = enginedyn_session::torsion::chain_dump(&t).unwrap();
    let orders = t.prepared.excitation.orders.len();
    assert_eq!(dump.checks.len(), 4 * orders.div_ceil(5));
    assert_eq!(dump.natural_frequencies_hz, f);
    let driven = dump.checks[0]
        .torque
        .iter()
        .filter(|c| c.norm() > 0.0)
        .count();
    assert!(driven >= 1 && driven <= loaded.engine.throws());
    // The printed tables: modes then resonances.
    let table = enginedyn_report::torsion_table(&t.study);
    assert!(table.starts_with("natural frequencies and mode shapes"));
}

#[test]
fn torsion_default_speeds_and_missing_section() {
    let s = enginedyn_session::torsion::default_speeds(1000.0);
    assert_eq!(s.len(), enginedyn_session::torsion::DEFAULT_SPEEDS);
    assert!((s[0] - 200.0).abs() < 1e-9 && (s[s.len() - 1] - 1200.0).abs() < 1e-9);
    let (_, loaded) = bundled("vaz2108");
    let e = enginedyn_session::torsion::spec(&loaded).unwrap_err();
    assert_eq!(e.class, Class::Usage);
    assert!(e.message.contains("no [torsion] section"), "{e}");
    // Speeds given as numbers are held to the bounds of `--rpm FROM:TO:STEP`.
    use enginedyn_session::torsion::check_speeds;
    assert!(check_speeds(&[500.0, 1000.0]).is_ok());
    for bad in [vec![], vec![1000.0, f64::NAN], vec![0.0], vec![2e5]] {
        assert_eq!(
            check_speeds(&bad).unwrap_err().class,
            Class::Usage,
            "{bad:?}"
        );
    }
}

#[test]
fn firing_orders_of_a_flat_four() {
    let (b, loaded) = bundled("vaz2108");
    let w = enginedyn_session::firing::weights(None).unwrap();
    let f = enginedyn_session::firing::study(
        &loaded.engine,
        &Reader::default(),
        &coarse(),
        Some(Input::Bundled(b)),
        w,
        false,
    )
    .unwrap();
    let crank = &f.study.cranks[0];
    // A flat-crank four-stroke four has two even orders: 1-3-4-2 and 1-2-4-3.
    let mut orders: Vec<Vec<usize>> = crank.orders.iter().map(|o| o.order.order.clone()).collect();
    orders.sort();
    assert_eq!(orders, vec![vec![1, 2, 4, 3], vec![1, 3, 4, 2]]);
    // Its first-order forces cancel; the second-order ones add up.
    assert!(crank.free.free_force_1_n.abs() < 1e-9 * crank.free.free_force_2_n.abs());
    assert!(crank.free.free_force_2_n.abs() > 1.0);
    // With a diagram, every order has its journal torques.
    assert!(crank.orders.iter().all(|o| o.journal.is_some()));
    let csv = enginedyn_report::firing_csv(&f.study);
    assert_eq!(csv.lines().count(), 1 + crank.orders.len());
    let json = enginedyn_report::firing_json(&f.study, false);
    assert_eq!(json["notes"].as_array().unwrap().len(), f.study.notes.len());
    let e = enginedyn_session::firing::weights(Some("bogus=1")).unwrap_err();
    assert_eq!(e.class, Class::Usage);
}

#[test]
fn accuracy_exact_kinematics_closer_than_series2() {
    let (b, loaded) = bundled("single");
    let a =
        enginedyn_session::accuracy::study(&loaded, &Reader::default(), Some(Input::Bundled(b)))
            .unwrap();
    assert!(a.speed_note.is_none());
    let err = |setting: &str| {
        a.study
            .rows
            .iter()
            .find(|r| r.study.name() == "kinematics" && r.setting == setting)
            .and_then(|r| r.max_relative_error())
            .unwrap()
    };
    // Exact kinematics differs from the reference only by the grid
    // (6.8e-7 measured); series2's truncation is far larger (2.4e-3).
    assert!(err("exact") < 1e-4, "{}", err("exact"));
    assert!(err("series2") > 10.0 * err("exact"));
    let table = enginedyn_accuracy::table(&a.study, &loaded.engine, a.rpm);
    assert_eq!(table.lines().count(), 3 + a.study.rows.len());
}
