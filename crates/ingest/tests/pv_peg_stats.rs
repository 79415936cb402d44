//! p–V data, pegging and cycle statistics against closed forms.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Peg, load, load_timed};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

fn cylinder(offset: f64) -> Cylinder {
    let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, offset).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap()
}

/// A smooth periodic pressure (Pa) over 720°.
fn p_of(deg: f64) -> f64 {
    let d = (deg - 12.0 + 360.0).rem_euclid(720.0) - 360.0;
    1e5 + 50e5 * (-(d / 30.0).powi(2)).exp()
}

/// p–V → p–φ against the p–φ it came from: a p–V loop written at 1° in cycle
/// order (from firing TDC, or from the BDC before it), read back with the
/// volume law, matches p(φ) on the 0.5° grid to 0.2 % of the peak (the
/// spline's error at 1° spacing), with and without a pin offset.
#[test]
fn pv_round_trip() {
    for (offset, bdc) in [(0.0, false), (0.002, false), (0.0, true)] {
        let cyl = cylinder(offset);
        let mut s = String::from("volume_cm3,pressure_bar\n");
        for k in 0..720 {
            let deg = if bdc { k as f64 - 180.0 } else { k as f64 };
            let v = cyl.volume(deg.to_radians());
            s.push_str(&format!("{:.9},{:.9}\n", v * 1e6, p_of(deg) / 1e5));
        }
        let mut o = ParseOptions::new(720.0);
        o.cylinder = Some(cyl);
        o.pv_start_bdc = bdc;
        let g = load(s.as_bytes(), &o, &GridOptions::new(0.5, Interp::Auto)).unwrap();
        assert!(g.pv);
        let worst = (0..1440)
            .map(|k| (g.pressure[k] - p_of(k as f64 * 0.5)).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 0.002 * 51e5,
            "offset {offset} bdc {bdc}: worst {worst}"
        );
    }
}

/// `load_timed` is `load` (the same result to the bit, p–V and p–φ, pegged
/// and not) and measures some time on the grid, less than the whole call.
#[test]
fn load_timed_is_load() {
    let cyl = cylinder(0.0);
    let mut pv = String::from("volume_cm3,pressure_bar\n");
    let mut phi = String::from("cycle,crank_deg,pressure_bar\n");
    for k in 0..720 {
        let deg = k as f64;
        pv.push_str(&format!(
            "{:.9},{:.9}\n",
            cyl.volume(deg.to_radians()) * 1e6,
            p_of(deg) / 1e5
        ));
    }
    for c in 0..3 {
        for k in 0..720 {
            let p = p_of(k as f64) / 1e5 + 0.01 * c as f64;
            phi.push_str(&format!("{c},{k},{p:.6}\n"));
        }
    }
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cyl);
    for (text, step, peg) in [
        (&pv, 0.5, None),
        (&phi, 1.0, None),
        (&phi, 0.5, Some(Peg::Bar(1.0))),
    ] {
        let mut grid = GridOptions::new(step, Interp::Auto);
        grid.cylinder = Some(cyl);
        grid.peg = peg;
        let mut on_grid = std::time::Duration::ZERO;
        let started = std::time::Instant::now();
        let timed = load_timed(text.as_bytes(), &o, &grid, &mut on_grid).unwrap();
        let whole = started.elapsed();
        assert_eq!(timed, load(text.as_bytes(), &o, &grid).unwrap());
        assert!(
            on_grid > std::time::Duration::ZERO && on_grid < whole,
            "{on_grid:?} of {whole:?}"
        );
    }
}

/// Volumes outside the cylinder (beyond 1 % of the swept volume) are an error
/// that says so; the crowded points near the dead centres get a note.
#[test]
fn pv_outside_the_cylinder_and_crowding() {
    let cyl = cylinder(0.0);
    let mut s = String::from("volume_l,pressure_bar\n");
    for k in 0..720 {
        let v = cyl.volume((k as f64).to_radians()) * 1e3 * 1.2;
        s.push_str(&format!("{v},2\n"));
    }
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cyl);
    let e = load(s.as_bytes(), &o, &GridOptions::new(1.0, Interp::Auto)).unwrap_err();
    assert!(e.to_string().contains("outside the cylinder"), "{e}");
    let mut s = String::from("volume_m3,pressure_bar\n");
    for k in 0..720 {
        s.push_str(&format!(
            "{},{}\n",
            cyl.volume((k as f64).to_radians()),
            p_of(k as f64) / 1e5
        ));
    }
    let g = load(s.as_bytes(), &o, &GridOptions::new(1.0, Interp::Auto)).unwrap();
    assert!(
        g.notes.iter().any(|n| n.contains("p–V inversion")),
        "{:?}",
        g.notes
    );
}

/// Pegging: a trace offset by -0.6 bar (a drifting piezo sensor) is restored
/// by --peg-bar to the true pressure at intake BDC, and by --peg polytropic
/// when compression is an exact polytrope (p V^1.32 = const), to 1e-6 bar.
#[test]
fn pegging_restores_the_offset() {
    let cyl = cylinder(0.0);
    let n = 1.32;
    let v0 = cyl.volume((-100.0_f64).to_radians());
    let p_true = |deg: f64| {
        let a = if deg >= 360.0 { deg - 720.0 } else { deg };
        if (-110.0..=-20.0).contains(&a) {
            1.5e5 * (v0 / cyl.volume(a.to_radians())).powf(n)
        } else {
            p_of(deg).max(1.0e5)
        }
    };
    let mut s = String::from("cycle,crank_deg,pressure_bar\n");
    for c in 0..3 {
        for k in 0..720 {
            s.push_str(&format!("{c},{k},{}\n", (p_true(k as f64) - 0.6e5) / 1e5));
        }
    }
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cyl);
    let mut g = GridOptions::new(1.0, Interp::Linear);
    g.cylinder = Some(cyl);
    g.peg = Some(Peg::Polytropic(n));
    let r = load(s.as_bytes(), &o, &g).unwrap();
    let peg = r.pegging.unwrap();
    assert!(
        (peg.mean_offset - 0.6e5).abs() < 0.1,
        "polytropic offset {}",
        peg.mean_offset
    );
    g.peg = Some(Peg::Bar(p_true(540.0)));
    let r = load(s.as_bytes(), &o, &g).unwrap();
    // The ±5° mean around BDC of the true trace equals its value at 540° here (flat there).
    assert!((r.pegging.unwrap().mean_offset - 0.6e5).abs() < 1.0);
    assert!((r.pressure[540] - p_true(540.0)).abs() < 1.0);
}

/// Cycle statistics: three cycles whose peaks are 40, 50 and 60 bar give a
/// mean of 50 bar and a sample standard deviation of 10 bar; IMEP per cycle
/// comes from the volume law.
#[test]
fn cycle_statistics() {
    let cyl = cylinder(0.0);
    let mut s = String::from("cycle,crank_deg,pressure_bar\n");
    for (c, peak) in [40.0, 50.0, 60.0].iter().enumerate() {
        for k in 0..720 {
            let d = (k as f64 - 12.0 + 360.0).rem_euclid(720.0) - 360.0;
            s.push_str(&format!(
                "{c},{k},{}\n",
                1.0 + (peak - 1.0) * (-(d / 30.0).powi(2)).exp()
            ));
        }
    }
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cyl);
    let mut g = GridOptions::new(1.0, Interp::Linear);
    g.cylinder = Some(cyl);
    let r = load(s.as_bytes(), &o, &g).unwrap();
    assert_eq!(r.cycles, 3);
    let (m, sd) = enginedyn_ingest::mean_std(r.stats.iter().map(|x| x.p_max));
    assert!((m - 50e5).abs() < 1e-6 && (sd - 10e5).abs() < 1e-6);
    assert!(
        r.stats
            .iter()
            .all(|x| (x.p_max_angle_deg - 12.0).abs() < 1e-9)
    );
    assert!(r.stats.iter().all(|x| x.imep_pa.is_some_and(|i| i > 0.0)));
}

/// A cylinder column gives one mean trace per cylinder, numbered from 1.
#[test]
fn per_cylinder_traces() {
    let mut s = String::from("cylinder,crank_deg,pressure_bar\n");
    for c in 1..=3 {
        for k in 0..72 {
            s.push_str(&format!("{c},{},{}\n", k * 10, c as f64));
        }
    }
    let r = load(
        s.as_bytes(),
        &ParseOptions::new(720.0),
        &GridOptions::new(10.0, Interp::Linear),
    )
    .unwrap();
    assert_eq!(r.cylinders.len(), 3);
    for (i, c) in r.cylinders.iter().enumerate() {
        assert!(c.iter().all(|p| (p - (i + 1) as f64 * 1e5).abs() < 1e-9));
    }
    let bad = "cylinder,crank_deg,pressure_bar\n0,0,1\n";
    assert!(
        load(
            bad.as_bytes(),
            &ParseOptions::new(720.0),
            &GridOptions::new(10.0, Interp::Linear)
        )
        .is_err()
    );
}

/// Multi-cycle data without a cycle column: continuous angles (two
/// windows, −360..1080) or angles restarting at 0 are split into cycles.
#[test]
fn cycles_without_a_cycle_column() {
    let mut s = String::from("crank_deg,pressure_bar\n");
    for k in 0..144 {
        s.push_str(&format!("{},{}\n", k * 10 - 360, 2.0));
    }
    let r = load(
        s.as_bytes(),
        &ParseOptions::new(720.0),
        &GridOptions::new(10.0, Interp::Linear),
    )
    .unwrap();
    assert_eq!(r.cycles, 2);
    let mut s = String::from("crank_deg,pressure_bar\n");
    for _ in 0..3 {
        for k in 0..72 {
            s.push_str(&format!("{},{}\n", k * 10, 2.0));
        }
    }
    let r = load(
        s.as_bytes(),
        &ParseOptions::new(720.0),
        &GridOptions::new(10.0, Interp::Linear),
    )
    .unwrap();
    assert_eq!(r.cycles, 3);
}

/// A volume law built once for many files gives every file what its own
/// would: the same curve, cycle statistics and pegging, bit for bit; a law
/// for another grid or cylinder is not used.
#[test]
fn shared_volume_law_changes_nothing() {
    let cyl = cylinder(0.0);
    let mut s = String::from("cycle,crank_deg,pressure_bar\n");
    for c in 0..3 {
        for k in 0..1440 {
            let a = k as f64 * 0.5;
            s.push_str(&format!(
                "{c},{a},{}\n",
                p_of(a) * (1.0 + 0.01 * c as f64) / 1e5 - 0.4
            ));
        }
    }
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cyl);
    for peg in [None, Some(Peg::Polytropic(1.32))] {
        let mut own = GridOptions::new(0.5, Interp::Auto);
        own.cylinder = Some(cyl);
        own.peg = peg;
        let reference = load(s.as_bytes(), &o, &own).unwrap();
        let mut shared = own.clone();
        shared.share_volume_law(720.0);
        assert!(shared.volume_law.is_some());
        let mut other_step = GridOptions::new(1.0, Interp::Auto);
        other_step.cylinder = Some(cyl);
        other_step.share_volume_law(720.0);
        let mut other_cylinder = GridOptions::new(0.5, Interp::Auto);
        other_cylinder.cylinder = Some(cylinder(0.003));
        other_cylinder.share_volume_law(720.0);
        for law in [&shared, &other_step, &other_cylinder] {
            let g = GridOptions {
                volume_law: law.volume_law.clone(),
                ..own.clone()
            };
            let r = load(s.as_bytes(), &o, &g).unwrap();
            assert_eq!(r.pressure, reference.pressure, "{peg:?}");
            assert_eq!(r.stats, reference.stats, "{peg:?}");
            assert_eq!(r.pegging, reference.pegging, "{peg:?}");
        }
    }
}

/// A note is said once, with a count, never once per cycle: twenty cycles
/// whose spline overshoots each by a different amount give one note.
#[test]
fn notes_once_with_a_count() {
    let mut csv = String::from("cycle,crank_deg,pressure_bar\n");
    for c in 1..=20 {
        for k in 0..72 {
            let a = k as f64 * 10.0;
            // A sharp peak the spline rings around, a bit taller each cycle.
            let p = if k == 36 {
                60.0 + c as f64
            } else {
                1.0 + 0.01 * k as f64
            };
            csv.push_str(&format!("{c},{a},{p}\n"));
        }
    }
    let opts = ParseOptions::new(720.0);
    let r = enginedyn_ingest::load(csv.as_bytes(), &opts, &GridOptions::new(1.0, Interp::Auto))
        .unwrap();
    let over: Vec<&String> = r
        .notes
        .iter()
        .filter(|n| n.contains("overshoots"))
        .collect();
    assert_eq!(over.len(), 1, "{:?}", r.notes);
    assert!(
        over[0].contains("overshoots the data by up to ")
            && over[0].contains(" % of the peak (20 of 20 traces): pchip used instead"),
        "{}",
        over[0]
    );
    let sparse: Vec<&String> = r
        .notes
        .iter()
        .filter(|n| n.contains("a point every"))
        .collect();
    assert_eq!(sparse.len(), 1, "{:?}", r.notes);
    assert!(
        sparse[0].contains("a point every 10° on average (20 of 20 traces)"),
        "{}",
        sparse[0]
    );
}
