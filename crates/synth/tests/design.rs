//! Synthesis for design: the IMEP target met, and the burn read back from
//! the trace by the analysis' first law gives the Wiebe angles.

use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
use enginedyn_synth::{
    BurnLaw, DEFAULT_A, DesignModel, GammaModel, Load, SynthError, Wiebe, design, design_trace,
    indicated_work,
};

/// VAZ-2108 type cylinder: R = 35.5 mm, lambda = 0.26, bore 76 mm, CR 9.9.
fn vaz() -> Cylinder {
    let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap()
}

/// A 2 l diesel cylinder: bore 130 mm, stroke 150 mm, CR 17.
fn diesel() -> Cylinder {
    let cs = CrankSlider::new(0.075, 0.265, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.130, 17.0).unwrap()
}

fn petrol_burn() -> BurnLaw {
    BurnLaw::single(Wiebe::from_ca50(8.0, 20.0, 2.0, DEFAULT_A).unwrap())
}

fn diesel_burn() -> BurnLaw {
    let pre = Wiebe::new(-4.0, 10.0, DEFAULT_A, 2.0).unwrap();
    let diff = Wiebe::new(-2.0, 60.0, DEFAULT_A, 0.8).unwrap();
    BurnLaw::double(pre, diff, 0.8).unwrap()
}

fn brunt(ivc_deg: f64) -> GammaModel {
    GammaModel::Brunt {
        ivc_deg,
        intake_temp_k: 320.0,
    }
}

/// The cumulative heat release of a trace as the analysis defines it
/// (PHYSICS.md): `Q(φ) = ∫ p dV + E(pV) − E(p_s V_s)`, `E` the γ model's
/// antiderivative of `d(pV)/(γ−1)`, the trapezoid on `p dV`; then the
/// angle where `Q` reaches `x` of its rise from `from` to `to`,
/// interpolated linearly.
fn burn_angle(
    cyl: &Cylinder,
    trace: &[(f64, f64)],
    g: GammaModel,
    ivc: f64,
    (from, to): (f64, f64),
    x: f64,
) -> f64 {
    let pts: Vec<(f64, f64)> = trace
        .iter()
        .map(|&(d, p)| if d >= 360.0 { (d - 720.0, p) } else { (d, p) })
        .filter(|&(d, _)| d >= from - 1e-9 && d <= to + 1e-9)
        .collect::<Vec<_>>();
    let mut pts = pts;
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let v = |d: f64| cyl.volume(d.to_radians());
    let p_ivc = trace
        .iter()
        .map(|&(d, p)| if d >= 360.0 { (d - 720.0, p) } else { (d, p) })
        .find(|&(d, _)| (d - ivc).abs() < 1e-9)
        .unwrap()
        .1;
    let pv_ivc = p_ivc * v(ivc);
    let mut q = vec![0.0];
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let work = 0.5 * (a.1 + b.1) * (v(b.0) - v(a.0));
        let de = g.energy(b.1 * v(b.0), pv_ivc) - g.energy(a.1 * v(a.0), pv_ivc);
        q.push(q.last().unwrap() + work + de);
    }
    let total = *q.last().unwrap();
    let k = q.iter().position(|&y| y >= x * total).unwrap();
    let t = (x * total - q[k - 1]) / (q[k] - q[k - 1]);
    pts[k - 1].0 + t * (pts[k].0 - pts[k - 1].0)
}

#[test]
fn the_imep_target_is_met() {
    for (cyl, burn, g, imep) in [
        (vaz(), petrol_burn(), GammaModel::Constant(1.32), 9.0e5),
        (vaz(), petrol_burn(), brunt(-140.0), 4.0e5),
        (diesel(), diesel_burn(), GammaModel::Constant(1.32), 18.0e5),
        (diesel(), diesel_burn(), brunt(-140.0), 12.0e5),
    ] {
        let m = DesignModel::new(burn, Load::Imep { pa: imep }, g, false);
        let d = design(&cyl, &m).unwrap();
        assert!(
            (d.imep_pa / imep - 1.0).abs() < 1e-9,
            "{} vs {imep}",
            d.imep_pa
        );
        assert!(d.evaluations <= 8, "{} cycles", d.evaluations);
        // The trace at 0.1° by the trapezoid agrees to 1e-5.
        let t = design_trace(&cyl, &m, 0.1).unwrap();
        let w = indicated_work(&cyl, &t, 720.0) / cyl.swept_volume();
        assert!((w / imep - 1.0).abs() < 1e-5, "{w} vs {imep}");
        // The heat it took is plausible: 25–50 % indicated efficiency.
        let eta = imep * cyl.swept_volume() / d.heat_released_j;
        assert!((0.25..0.6).contains(&eta), "efficiency {eta}");
    }
}

/// The synthesised trace, read back by the analysis' first law with the
/// same γ model at 0.1°, gives the Wiebe law's CA10, CA50 and CA90 within
/// 0.01° (the window IVC … EVO holds the whole burn).
#[test]
fn the_trace_gives_back_its_wiebe_angles() {
    for (cyl, burn, g) in [
        (vaz(), petrol_burn(), GammaModel::Constant(1.32)),
        (vaz(), petrol_burn(), brunt(-140.0)),
        (diesel(), diesel_burn(), GammaModel::Constant(1.32)),
        (diesel(), diesel_burn(), brunt(-140.0)),
    ] {
        let m = DesignModel::new(burn, Load::Imep { pa: 10.0e5 }, g, false);
        let t = design_trace(&cyl, &m, 0.1).unwrap();
        // Q(EOC) is at EVO, where the law has burnt 1 − ε: the fraction of
        // the heat released there.
        let at_evo = burn.fraction(m.evo_deg);
        for x in [0.1, 0.5, 0.9] {
            let got = burn_angle(&cyl, &t, g, m.ivc_deg, (m.ivc_deg, m.evo_deg), x * at_evo);
            let want = burn.angle_of(x);
            assert!(
                (got - want).abs() < 0.01,
                "CA{}: {got} vs {want}",
                x * 100.0
            );
        }
    }
}

#[test]
fn a_heat_given_is_used_as_it_is() {
    let m = DesignModel::new(
        petrol_burn(),
        Load::Heat { j: 600.0 },
        GammaModel::Constant(1.32),
        false,
    );
    let d = design(&vaz(), &m).unwrap();
    assert!((d.heat_released_j - 600.0).abs() < 1e-12);
    assert_eq!(d.evaluations, 1);
    assert!(d.imep_pa > 8e5 && d.imep_pa < 14e5, "{}", d.imep_pa);
}

#[test]
fn two_stroke_design() {
    let m = DesignModel::new(
        BurnLaw::single(Wiebe::from_ca50(6.0, 22.0, 2.0, DEFAULT_A).unwrap()),
        Load::Imep { pa: 6.0e5 },
        GammaModel::Constant(1.32),
        true,
    );
    let t = design_trace(&vaz(), &m, 0.5).unwrap();
    assert_eq!(t.len(), 720);
    let w = indicated_work(&vaz(), &t, 360.0) / vaz().swept_volume();
    assert!((w / 6.0e5 - 1.0).abs() < 1e-4, "{w}");
}

#[test]
fn refusals_name_what_is_wrong() {
    let g = GammaModel::Constant(1.32);
    // Below the motored cycle's IMEP (boost 2 bar over an exhaust of
    // 1.72 bar: the pumping loop gives work): nothing burns to it.
    let mut m = DesignModel::new(petrol_burn(), Load::Imep { pa: 0.1e5 }, g, false);
    m.intake_pressure_pa = 2e5;
    m.exhaust_pressure_pa = enginedyn_synth::exhaust_pressure_for(2e5);
    let e = design(&vaz(), &m).unwrap_err();
    assert!(matches!(e, SynthError::Load(_)), "{e}");
    assert!(e.to_string().contains("motored"), "{e}");
    let m = DesignModel::new(petrol_burn(), Load::Imep { pa: -1e5 }, g, false);
    let e = design(&vaz(), &m).unwrap_err();
    assert!(e.to_string().starts_with("imep_bar"), "{e}");
    // γ(T) from another IVC than the cycle's.
    let mut m = DesignModel::new(petrol_burn(), Load::Imep { pa: 9e5 }, brunt(-140.0), false);
    m.ivc_deg = -130.0;
    let e = design(&vaz(), &m).unwrap_err();
    assert!(e.to_string().starts_with("ivc_deg"), "{e}");
    // A burn starting before IVC.
    let early = BurnLaw::single(Wiebe::new(-150.0, 40.0, DEFAULT_A, 2.0).unwrap());
    let m = DesignModel::new(early, Load::Imep { pa: 9e5 }, g, false);
    let e = design(&vaz(), &m).unwrap_err();
    assert!(e.to_string().starts_with("start_deg"), "{e}");
    // A step that does not divide the cycle.
    let m = DesignModel::new(petrol_burn(), Load::Imep { pa: 9e5 }, g, false);
    assert!(design_trace(&vaz(), &m, 0.7).is_err());
}
