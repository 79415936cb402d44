//! The analysis against traces whose burn is known exactly: a closed
//! charge with constant γ burning a Wiebe law obeys
//! `d(p V^γ) = (γ − 1) Q V^(γ−1) dxb`, so `p V^γ` is a quadrature of known
//! functions (Simpson at 0.001°), independent of the analysis' own rules.

use enginedyn_combustion::{
    BurnLaw, CycleGrid, DEFAULT_A, GammaModel, Options, Smoothing, Wiebe, analyse, curves,
};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

fn cylinder() -> Cylinder {
    // VAZ-2108 type: R 35.5 mm, λ 0.26, bore 76 mm, ε 9.9.
    let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap()
}

/// The closed-charge trace on the grid `k step` over a 720° cycle: from
/// 1 bar at −180° (BDC) to +180°, burning `heat_j` by `law`; 1 bar on the
/// gas-exchange half. `shift_deg` moves the trace later (a TDC mark
/// early by that much).
fn trace(
    cyl: &Cylinder,
    law: &BurnLaw,
    heat_j: f64,
    gamma: f64,
    step: f64,
    shift_deg: f64,
) -> Vec<f64> {
    let n = (720.0 / step).round() as usize;
    let fine = 0.001;
    let vol = |deg: f64| cyl.volume(deg.to_radians());
    // Running integral I(φ) = ∫ V^(γ−1) dxb from −180°, Simpson per fine step.
    let mut table = Vec::new();
    let (mut i, mut a) = (0.0, -180.0);
    let f = |deg: f64| vol(deg).powf(gamma - 1.0) * law.rate(deg);
    table.push((a, i));
    while a < 180.0 - 1e-12 {
        let b = a + fine;
        i += fine / 6.0 * (f(a) + 4.0 * f(0.5 * (a + b)) + f(b));
        a = b;
        table.push((a, i));
    }
    let c0 = 1e5 * vol(-180.0).powf(gamma);
    (0..n)
        .map(|k| {
            let mut deg = k as f64 * step - shift_deg;
            if deg >= 360.0 {
                deg -= 720.0;
            }
            if !(-180.0..=180.0).contains(&deg) {
                return 1e5;
            }
            let j = (((deg + 180.0) / fine).round() as usize).min(table.len() - 1);
            let pvg = c0 + (gamma - 1.0) * heat_j * table[j].1;
            pvg / vol(deg).powf(gamma)
        })
        .collect()
}

fn grid_of(cyl: &Cylinder, step: f64) -> (Vec<f64>, Vec<f64>) {
    cyl.fill_volume(step.to_radians(), (720.0 / step).round() as usize)
}

fn petrol() -> BurnLaw {
    BurnLaw::single(Wiebe::from_ca50(8.0, 22.0, 2.0, DEFAULT_A).unwrap())
}

/// The true largest dp/dφ (Pa/°) of the closed charge, scanned at 0.001°.
fn true_dp_max(
    cyl: &Cylinder,
    p: impl Fn(f64) -> f64,
    law: &BurnLaw,
    heat: f64,
    gamma: f64,
) -> f64 {
    let mut best = f64::NEG_INFINITY;
    let mut deg: f64 = -30.0;
    while deg < 60.0 {
        let r = deg.to_radians();
        let v = cyl.volume(r);
        let dv = cyl.dvolume(r).to_radians();
        let dp = ((gamma - 1.0) * heat * law.rate(deg) - gamma * p(deg) * dv) / v;
        best = best.max(dp);
        deg += 0.001;
    }
    best
}

#[test]
fn a_single_wiebe_comes_back_within_a_hundredth_of_a_degree() {
    let cyl = cylinder();
    let (step, gamma, heat) = (0.1, 1.32, 600.0);
    let law = petrol();
    let p = trace(&cyl, &law, heat, gamma, step, 0.0);
    let (v, dv) = grid_of(&cyl, step);
    let g = CycleGrid::new(&p, &v, &dv, step);
    let opts = Options::default();
    let r = analyse(&g, &opts).unwrap();
    let b = r.burn.expect("a fired cycle burns");
    for (pct, got) in opts.levels_pct.iter().zip(&b.levels_deg) {
        let want = law.angle_of(pct / 100.0);
        // Measured: 2.9e-4° at worst (CA5); docs/combustion.md quotes it.
        assert!((got - want).abs() < 1e-3, "CA{pct}: {got} against {want}");
    }
    // The heat released: the law's within the window (Q_max − Q_min).
    let want = heat * (law.fraction(120.0) - law.fraction(-90.0));
    assert!(
        (r.heat_released_j - want).abs() < 1e-3 * heat,
        "{} {want}",
        r.heat_released_j
    );
    // The pressure rise within 2 % of the true largest slope.
    let fine = |deg: f64| {
        let k = ((deg / step).round() as i64).rem_euclid(p.len() as i64) as usize;
        p[k]
    };
    let truth = true_dp_max(&cyl, fine, &law, heat, gamma);
    assert!(
        (b.dp_max_pa_deg / truth - 1.0).abs() < 0.02,
        "{} {truth}",
        b.dp_max_pa_deg
    );
}

#[test]
fn a_diesel_double_wiebe_on_a_half_degree_grid() {
    let cyl = cylinder();
    let (step, gamma, heat) = (0.5, 1.32, 900.0);
    let pre = Wiebe::new(-4.0, 8.0, DEFAULT_A, 2.0).unwrap();
    let diff = Wiebe::new(-1.0, 55.0, DEFAULT_A, 0.8).unwrap();
    let law = BurnLaw::double(pre, diff, 0.8).unwrap();
    let p = trace(&cyl, &law, heat, gamma, step, 0.0);
    let (v, dv) = grid_of(&cyl, step);
    let g = CycleGrid::new(&p, &v, &dv, step);
    let opts = Options::default();
    let b = analyse(&g, &opts).unwrap().burn.unwrap();
    for (pct, tol) in [(10.0, 0.2), (50.0, 0.2), (90.0, 0.4)] {
        let got = b.level(&opts, pct).unwrap();
        let want = law.angle_of(pct / 100.0);
        assert!((got - want).abs() < tol, "CA{pct}: {got} against {want}");
    }
}

/// The closed-charge trace of a γ(T) gas (Brunt's γ, T scaled from the
/// state at IVC): `d(pV)/dφ = (γ − 1)(Q dxb/dφ − p dV/dφ)`, integrated by
/// RK4 at 0.005° from 1 bar at IVC, forwards to +180° and backwards to
/// −180° (independent of the analysis' closed-form energy).
fn brunt_trace(cyl: &Cylinder, law: &BurnLaw, heat_j: f64, gm: GammaModel, step: f64) -> Vec<f64> {
    let GammaModel::Brunt { ivc_deg, .. } = gm else {
        panic!("a Brunt model")
    };
    let vol = |deg: f64| cyl.volume(deg.to_radians());
    let u_ivc = 1e5 * vol(ivc_deg);
    let du = |deg: f64, u: f64| {
        let h = 1e-4;
        let dv = (vol(deg + h) - vol(deg - h)) / (2.0 * h);
        (gm.gamma(u, u_ivc) - 1.0) * (heat_j * law.rate(deg) - u / vol(deg) * dv)
    };
    // pV on the fine grid from −180° to +180°, index (deg + 180) / fine.
    let fine: f64 = 0.005;
    let m = (360.0 / fine).round() as usize;
    let at_ivc = ((ivc_deg + 180.0) / fine).round() as usize;
    let mut u = vec![0.0; m + 1];
    u[at_ivc] = u_ivc;
    let rk4 = |deg: f64, u: f64, h: f64| {
        let k1 = du(deg, u);
        let k2 = du(deg + h / 2.0, u + h / 2.0 * k1);
        let k3 = du(deg + h / 2.0, u + h / 2.0 * k2);
        let k4 = du(deg + h, u + h * k3);
        u + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    };
    for j in at_ivc..m {
        u[j + 1] = rk4(j as f64 * fine - 180.0, u[j], fine);
    }
    for j in (1..=at_ivc).rev() {
        u[j - 1] = rk4(j as f64 * fine - 180.0, u[j], -fine);
    }
    let n = (720.0 / step).round() as usize;
    (0..n)
        .map(|k| {
            let mut deg = k as f64 * step;
            if deg >= 360.0 {
                deg -= 720.0;
            }
            if !(-180.0..=180.0).contains(&deg) {
                return 1e5;
            }
            u[((deg + 180.0) / fine).round() as usize] / vol(deg)
        })
        .collect()
}

/// A γ(T) trace analysed with γ(T) gives back its burn angles within
/// 0.01° (1e-4° measured; the issue asks 0.2°, 0.4° for CA90); analysed
/// with a constant 1.32 the CA90 moves by more than a degree (6.4°
/// measured): the model matters.
#[test]
fn a_brunt_trace_round_trips_with_brunt() {
    let cyl = cylinder();
    let step = 0.1;
    let law = petrol();
    let gm = GammaModel::brunt_default();
    let p = brunt_trace(&cyl, &law, 600.0, gm, step);
    let (v, dv) = grid_of(&cyl, step);
    let g = CycleGrid::new(&p, &v, &dv, step);
    let opts = Options {
        gamma: gm,
        ..Options::default()
    };
    let b = analyse(&g, &opts).unwrap().burn.unwrap();
    let mut worst: f64 = 0.0;
    for pct in [10.0, 50.0, 90.0] {
        let got = b.level(&opts, pct).unwrap();
        let want = law.angle_of(pct / 100.0);
        assert!((got - want).abs() < 0.01, "CA{pct}: {got} vs {want}");
        worst = worst.max((got - want).abs());
    }
    println!("brunt round trip: worst CA10/50/90 error {worst:.4}°");
    let constant = Options::default();
    let c = analyse(&g, &constant).unwrap().burn.unwrap();
    let off = c.level(&constant, 90.0).unwrap() - law.angle_of(0.9);
    println!("brunt trace read with γ 1.32: CA90 off by {off:.3}°");
    assert!(off.abs() > 1.0, "{off}");
}

#[test]
fn a_motored_cycle_has_no_burn_points() {
    let cyl = cylinder();
    let step = 0.1;
    let p = trace(&cyl, &petrol(), 0.0, 1.32, step, 0.0);
    let (v, dv) = grid_of(&cyl, step);
    let g = CycleGrid::new(&p, &v, &dv, step);
    let r = analyse(&g, &Options::default()).unwrap();
    assert!(r.burn.is_none());
    assert!(
        r.heat_released_j < r.bound_j,
        "{} {}",
        r.heat_released_j,
        r.bound_j
    );
    // Gross work of a motored closed charge: 0 to the trapezoid's error.
    assert!(r.gross_work_j.abs() < 1e-3, "{}", r.gross_work_j);
}

#[test]
fn a_tdc_shift_of_half_a_degree_moves_ca50_by_half_a_degree() {
    let cyl = cylinder();
    let step = 0.1;
    let law = petrol();
    let (v, dv) = grid_of(&cyl, step);
    let opts = Options::default();
    let ca50 = |shift: f64| {
        let p = trace(&cyl, &law, 600.0, 1.32, step, shift);
        let g = CycleGrid::new(&p, &v, &dv, step);
        analyse(&g, &opts)
            .unwrap()
            .burn
            .unwrap()
            .level(&opts, 50.0)
            .unwrap()
    };
    let moved = ca50(0.5) - ca50(0.0);
    assert!((0.5..=0.6).contains(&moved), "{moved}");
}

/// A deterministic noise of standard deviation `sd` (a linear
/// congruential generator through Box–Muller).
fn noise(n: usize, sd: f64, seed: u64) -> Vec<f64> {
    let mut s = seed;
    let mut u = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| sd * (-2.0 * u().ln()).sqrt() * (2.0 * std::f64::consts::PI * u()).cos())
        .collect()
}

#[test]
fn noise_of_two_hundredths_of_a_bar_moves_the_pressure_rise_under_three_percent() {
    let cyl = cylinder();
    let step = 0.1;
    let law = petrol();
    let clean = trace(&cyl, &law, 600.0, 1.32, step, 0.0);
    let (v, dv) = grid_of(&cyl, step);
    let rise = |p: &[f64], opts: &Options| {
        let g = CycleGrid::new(p, &v, &dv, step);
        analyse(&g, opts).unwrap().burn.unwrap()
    };
    let smooth = Options::default();
    let raw = Options {
        smoothing: Smoothing::Off,
        ..Options::default()
    };
    let base = rise(&clean, &smooth).dp_max_pa_deg;
    let mut worst_smooth: f64 = 0.0;
    let mut worst_raw: f64 = 0.0;
    for seed in 1..=5 {
        let noisy: Vec<f64> = clean
            .iter()
            .zip(noise(clean.len(), 0.02e5, seed))
            .map(|(p, e)| p + e)
            .collect();
        worst_smooth = worst_smooth.max((rise(&noisy, &smooth).dp_max_pa_deg / base - 1.0).abs());
        worst_raw = worst_raw.max((rise(&noisy, &raw).dp_max_pa_deg / base - 1.0).abs());
        let b = rise(&noisy, &smooth);
        let ca50 = b.level(&smooth, 50.0).unwrap();
        assert!((ca50 - 8.0).abs() < 0.2, "CA50 {ca50}");
    }
    assert!(worst_smooth < 0.03, "smoothed: {worst_smooth}");
    assert!(worst_raw > 0.05, "unsmoothed should fail: {worst_raw}");
}

#[test]
fn the_curves_end_where_the_burn_does() {
    let cyl = cylinder();
    let step = 0.5;
    let law = petrol();
    let p = trace(&cyl, &law, 600.0, 1.32, step, 0.0);
    let (v, dv) = grid_of(&cyl, step);
    let g = CycleGrid::new(&p, &v, &dv, step);
    let opts = Options::default();
    let r = analyse(&g, &opts).unwrap();
    let c = curves(&g, &opts, &r).unwrap();
    let mfb = c.mfb.unwrap();
    let at = |deg: f64| ((deg / step).round() as i64).rem_euclid(p.len() as i64) as usize;
    assert!(mfb[at(-100.0)].abs() < 1e-15);
    assert!((mfb[at(150.0)] - 1.0).abs() < 1e-15);
    assert!((mfb[at(8.0)] - 0.5).abs() < 0.01, "{}", mfb[at(8.0)]);
    // The rate integrates to the heat released (trapezoid on the grid).
    let total: f64 = (at(-90.0)..p.len())
        .chain(0..=at(120.0))
        .map(|k| c.rate_j_deg[k] * step)
        .sum();
    assert!(
        (total / r.heat_released_j - 1.0).abs() < 0.01,
        "{total} {}",
        r.heat_released_j
    );
    assert!((c.cumulative_j[at(150.0)] - r.heat_released_j).abs() < 1.0);
}

/// The sensitivities `docs/combustion.md` quotes (petrol, 0.1° grid, true
/// γ 1.32, ε 9.9): each error's effect on the analysis, with its sign and
/// size checked against PHYSICS.md's. `cargo test -p enginedyn-combustion
/// --test analysis sensitivities -- --nocapture` prints them.
#[test]
fn sensitivities() {
    let cyl = cylinder();
    let step = 0.1;
    let law = petrol();
    let (v, dv) = grid_of(&cyl, step);
    let base_p = trace(&cyl, &law, 600.0, 1.32, step, 0.0);
    let opts = Options::default();
    let run = |p: &[f64], v: &[f64], dv: &[f64], o: &Options| {
        analyse(&CycleGrid::new(p, v, dv, step), o).unwrap()
    };
    let base = run(&base_p, &v, &dv, &opts);
    let bb = base.burn.clone().unwrap();
    let ca = |r: &enginedyn_combustion::CycleBurn, o: &Options, pct| {
        r.burn.as_ref().unwrap().level(o, pct).unwrap()
    };
    let (ca50, ca90) = (ca(&base, &opts, 50.0), ca(&base, &opts, 90.0));
    // A TDC mark 0.1° early: the trace sits 0.1° later on the volume law.
    let early = run(&trace(&cyl, &law, 600.0, 1.32, step, 0.1), &v, &dv, &opts);
    let d_imep = early.gross_work_j / base.gross_work_j - 1.0;
    let d_q = early.heat_released_j / base.heat_released_j - 1.0;
    let d_ca50_tdc = ca(&early, &opts, 50.0) - ca50;
    eprintln!(
        "TDC 0.1° early: IMEP {:+.2} %, Q {:+.2} %, CA50 {:+.3}°",
        100.0 * d_imep,
        100.0 * d_q,
        d_ca50_tdc
    );
    assert!((0.08..0.14).contains(&d_ca50_tdc) && d_imep > 0.0 && d_q > 0.0);
    // γ 1.30 and 1.34 for a true 1.32.
    for (g, sign) in [(1.30, -1.0), (1.34, 1.0)] {
        let o = Options {
            gamma: GammaModel::Constant(g),
            ..Options::default()
        };
        let r = run(&base_p, &v, &dv, &o);
        let (d50, d90) = (ca(&r, &o, 50.0) - ca50, ca(&r, &o, 90.0) - ca90);
        eprintln!("γ {g}: CA50 {d50:+.2}°, CA90 {d90:+.2}°");
        assert!(
            d50 * sign > 0.05 && d50.abs() < 1.5 && d90 * sign > 0.1,
            "γ {g}: {d50} {d90}"
        );
    }
    // A pegging offset of +0.1 bar.
    let pegged: Vec<f64> = base_p.iter().map(|p| p + 0.1e5).collect();
    let r = run(&pegged, &v, &dv, &opts);
    let (d50, d90) = (ca(&r, &opts, 50.0) - ca50, ca(&r, &opts, 90.0) - ca90);
    eprintln!(
        "pegging +0.1 bar: CA50 {d50:+.2}°, CA90 {d90:+.2}°, IMEP {:+.4} %",
        100.0 * (r.gross_work_j / base.gross_work_j - 1.0)
    );
    assert!(d50 > 0.02 && d50 < 1.0 && d90 > d50);
    // The compression ratio 2 % low and high (the volume law the analysis
    // assumes, not the engine's).
    for (eps, sign) in [(9.9 * 0.98, -1.0), (9.9 * 1.02, 1.0)] {
        let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
        let c2 = Cylinder::new(Mechanism::CrankSlider(cs), 0.076, eps).unwrap();
        let (v2, dv2) = grid_of(&c2, step);
        let r = run(&base_p, &v2, &dv2, &opts);
        let d50 = ca(&r, &opts, 50.0) - ca50;
        eprintln!(
            "ε {eps:.2} for 9.9: CA50 {d50:+.2}°, Q {:+.2} %",
            100.0 * (r.heat_released_j / base.heat_released_j - 1.0)
        );
        assert!(d50 * sign > 0.02 && d50.abs() < 1.5, "ε {eps}: {d50}");
    }
    // The filter on a clean trace: what 2° and 4° cost against none.
    for w in [2.0, 4.0] {
        let o = Options {
            smoothing: Smoothing::SavitzkyGolay { width_deg: w },
            ..Options::default()
        };
        let raw = Options {
            smoothing: Smoothing::Off,
            ..Options::default()
        };
        let (s, r) = (run(&base_p, &v, &dv, &o), run(&base_p, &v, &dv, &raw));
        let dp =
            s.burn.as_ref().unwrap().dp_max_pa_deg / r.burn.as_ref().unwrap().dp_max_pa_deg - 1.0;
        let d50 = ca(&s, &o, 50.0) - ca(&r, &raw, 50.0);
        eprintln!(
            "SG {w}° against off, clean trace: max dp/dφ {:+.3} %, CA50 {d50:+.4}°",
            100.0 * dp
        );
        assert!(dp.abs() < 0.02 && d50.abs() < 0.01);
    }
    assert!(bb.dp_max_pa_deg > 0.0);
}

/// A motored trace that loses heat to the walls (40 J around TDC, the
/// loss a small engine's charge gives up at 2000 rpm), read with a γ 0.02
/// off either way (so the apparent release swings both ways): no burn
/// points, whatever the γ.
#[test]
fn a_motored_cycle_losing_heat_has_no_burn_points() {
    let cyl = cylinder();
    let step = 0.1;
    let loss = BurnLaw::single(Wiebe::from_ca50(5.0, 60.0, 1.0, DEFAULT_A).unwrap());
    let p = trace(&cyl, &loss, -40.0, 1.32, step, 0.0);
    let (v, dv) = grid_of(&cyl, step);
    let g = CycleGrid::new(&p, &v, &dv, step);
    for gamma in [1.30, 1.32, 1.34] {
        let opts = Options {
            gamma: GammaModel::Constant(gamma),
            ..Options::default()
        };
        let r = analyse(&g, &opts).unwrap();
        assert!(
            r.burn.is_none(),
            "γ {gamma}: {} J against {} J",
            r.heat_released_j,
            r.bound_j
        );
    }
}

/// PHYSICS "Burn points": on a lossless trace (a flat cumulative before
/// and after the burn, whose extremes are rounding noise) SOC and EOC are
/// the burn's own ends, within a degree of the law's 0.5 % and 99.5 %
/// points, never the window's edges (−84.9° and 117° before the banded
/// rule).
#[test]
fn soc_and_eoc_of_a_lossless_trace_are_the_burns_own_ends() {
    let cyl = cylinder();
    let (v1, dv1) = grid_of(&cyl, 0.1);
    let (v5, dv5) = grid_of(&cyl, 0.5);
    for (law, step) in [
        (petrol(), 0.1),
        (petrol(), 0.5),
        (
            BurnLaw::single(Wiebe::from_ca50(2.0, 30.0, 1.5, DEFAULT_A).unwrap()),
            0.1,
        ),
    ] {
        let p = trace(&cyl, &law, 600.0, 1.32, step, 0.0);
        let (v, dv) = if step < 0.2 { (&v1, &dv1) } else { (&v5, &dv5) };
        let b = analyse(&CycleGrid::new(&p, v, dv, step), &Options::default())
            .unwrap()
            .burn
            .unwrap();
        let (soc, eoc) = (law.angle_of(0.005), law.angle_of(0.995));
        assert!((b.soc_deg - soc).abs() < 1.0, "SOC {} for {soc}", b.soc_deg);
        assert!((b.eoc_deg - eoc).abs() < 1.0, "EOC {} for {eoc}", b.eoc_deg);
        assert!(!b.cut_at_start && !b.cut_at_end);
    }
}

/// The largest slope of the least-squares cubic through `2m + 1` points
/// around each grid index of `lo..=hi` (deg), fitted afresh at each point
/// by its normal equations in the raw index (not the filter's weights).
fn brute_force_slope_max(p: &[f64], step: f64, m: i64, lo: f64, hi: f64) -> (f64, f64) {
    let n = p.len() as i64;
    let mut best = (f64::NEG_INFINITY, 0.0);
    let mut k = (lo / step).round() as i64;
    while (k as f64) * step <= hi {
        // Normal equations of p ≈ c0 + c1 i + c2 i² + c3 i³, i = −m..m.
        let mut a = [[0.0f64; 4]; 4];
        let mut r = [0.0f64; 4];
        for i in -m..=m {
            let y = p[(k + i).rem_euclid(n) as usize];
            let pw = [1.0, i as f64, (i * i) as f64, (i * i * i) as f64];
            for x in 0..4 {
                r[x] += pw[x] * y;
                for z in 0..4 {
                    a[x][z] += pw[x] * pw[z];
                }
            }
        }
        // Gauss–Jordan without pivoting (the matrix is positive definite).
        for c in 0..4 {
            let d = a[c][c];
            for z in 0..4 {
                a[c][z] /= d;
            }
            r[c] /= d;
            for x in 0..4 {
                if x != c {
                    let f = a[x][c];
                    for z in 0..4 {
                        a[x][z] -= f * a[c][z];
                    }
                    r[x] -= f * r[c];
                }
            }
        }
        let slope = r[1] / step;
        if slope > best.0 {
            best = (slope, k as f64 * step);
        }
        k += 1;
    }
    best
}

/// PHYSICS "Pressure rise": a diesel's premixed spike of a degree or two
/// is found where the filter's own slope is largest, at every grid point
/// (a box difference across the filter's width prefers a long rise to a
/// short steep one and stepped over it).
#[test]
fn the_pressure_rise_finds_a_premixed_spike() {
    let cyl = cylinder();
    let step = 0.2;
    // A short premixed burn (2 % of the heat in 1°) just before TDC, then
    // a long diffusion burn: the steepest rise (1.96 bar/° at −0.6°) is
    // the spike's, narrower than the filter; the box difference found
    // the diffusion burn's long rise instead (1.88 bar/° at +5.3°).
    let pre = Wiebe::new(-1.0, 1.0, DEFAULT_A, 1.0).unwrap();
    let diff = Wiebe::new(-3.0, 40.0, DEFAULT_A, 1.0).unwrap();
    let law = BurnLaw::double(pre, diff, 0.98).unwrap();
    let p = trace(&cyl, &law, 500.0, 1.32, step, 0.0);
    let (v, dv) = grid_of(&cyl, step);
    let opts = Options::default();
    let b = analyse(&CycleGrid::new(&p, &v, &dv, step), &opts)
        .unwrap()
        .burn
        .unwrap();
    let m = opts.smoothing.half_points(step) as i64;
    let (want, at) = brute_force_slope_max(&p, step, m, b.soc_deg, b.eoc_deg);
    eprintln!(
        "spike: {:.4} bar/° at {:.2}° (brute force {:.4} at {at})",
        b.dp_max_pa_deg / 1e5,
        b.dp_max_angle_deg,
        want / 1e5
    );
    // The parabola refines the grid point's value upwards, by little
    // (measured 0.03 %).
    assert!(
        b.dp_max_pa_deg >= want * (1.0 - 1e-9) && b.dp_max_pa_deg < want * 1.005,
        "{} against {want}",
        b.dp_max_pa_deg
    );
    assert!(
        (b.dp_max_angle_deg - at).abs() <= step,
        "{} against {at}",
        b.dp_max_angle_deg
    );
}

fn noisy(p: &[f64], sd_bar: f64, seed: u64) -> Vec<f64> {
    p.iter()
        .zip(noise(p.len(), sd_bar * 1e5, seed))
        .map(|(p, e)| p + e)
        .collect()
}

/// PHYSICS "Burn points need data that resolve them": a motored trace
/// with 0.05–0.1 bar of noise has no CA50 (the cumulative's noise at large
/// volume beat the no-combustion bound taken at TDC: 7 of 8 got one), and
/// 5 bar of noise on a fired trace gives null burn points, never −74°.
#[test]
fn noise_gives_no_burn_points_where_it_hides_the_burn() {
    let cyl = cylinder();
    let step = 0.1;
    let (v, dv) = grid_of(&cyl, step);
    let opts = Options::default();
    let motored = trace(&cyl, &petrol(), 0.0, 1.32, step, 0.0);
    for (seed, sd) in (1..=8).zip([0.05, 0.1].into_iter().cycle()) {
        let p = noisy(&motored, sd, seed);
        let r = analyse(&CycleGrid::new(&p, &v, &dv, step), &opts).unwrap();
        assert!(
            r.burn.is_none(),
            "motored, {sd} bar noise (seed {seed}): CA50 {:?}",
            r.burn.map(|b| b.level(&opts, 50.0))
        );
        assert!(
            (r.noise_pa / (sd * 1e5) - 1.0).abs() < 0.1,
            "noise {}",
            r.noise_pa
        );
    }
    let fired = trace(&cyl, &petrol(), 600.0, 1.32, step, 0.0);
    for seed in 1..=3 {
        let p = noisy(&fired, 5.0, seed);
        let r = analyse(&CycleGrid::new(&p, &v, &dv, step), &opts).unwrap();
        assert!(r.burn.is_none(), "5 bar noise: {:?}", r.burn);
        assert!(r.unresolved || r.heat_released_j < r.bound_j);
    }
}

/// A fired trace with 0.1 bar of noise keeps its burn points: CA10/50/90
/// within 0.75° of the law (measured: CA10 −0.2…−0.4°, CA50 ±0.1°, CA90
/// +0.4…+0.7°, the extremes' noise; CA90 moved +0.7–1.5° when they were
/// taken on the cumulative as read), SOC within 2° and EOC within 4° of
/// the law's 0.5 % and 99.5 % points (the bands widen by the noise: 0.1
/// bar is 0.6 % of this small cylinder's heat), whatever a single sample
/// at the window's start does (a low first sample pinned SOC there).
#[test]
fn noisy_cycles_keep_their_burn_points() {
    let cyl = cylinder();
    let step = 0.1;
    let (v, dv) = grid_of(&cyl, step);
    let opts = Options::default();
    let law = petrol();
    let fired = trace(&cyl, &law, 600.0, 1.32, step, 0.0);
    let start = ((-90.0f64 / step).round() as i64).rem_euclid(fired.len() as i64) as usize;
    let mut worst = [0.0f64; 5];
    for seed in 1..=8 {
        let mut p = noisy(&fired, 0.1, seed);
        if seed % 2 == 0 {
            p[start] -= 0.5e5;
        }
        let r = analyse(&CycleGrid::new(&p, &v, &dv, step), &opts).unwrap();
        let b = r.burn.expect("a fired trace with 0.1 bar noise burns");
        let got = [
            b.level(&opts, 10.0).unwrap() - law.angle_of(0.1),
            b.level(&opts, 50.0).unwrap() - law.angle_of(0.5),
            b.level(&opts, 90.0).unwrap() - law.angle_of(0.9),
            b.soc_deg - law.angle_of(0.005),
            b.eoc_deg - law.angle_of(0.995),
        ];
        for (w, g) in worst.iter_mut().zip(got) {
            *w = w.max(g.abs());
        }
    }
    eprintln!("0.1 bar noise, worst CA10/50/90, SOC, EOC error: {worst:.3?}");
    assert!(worst[..3].iter().all(|e| *e < 0.75), "{worst:?}");
    assert!(worst[3] < 2.0 && worst[4] < 4.0, "{worst:?}");
}

/// A burn that runs past the window's end (CA50 100°, 10–90 in 40°) is
/// said to: EOC lies on the window's edge and the flag is up.
#[test]
fn a_burn_past_the_window_is_flagged() {
    let cyl = cylinder();
    let step = 0.1;
    let (v, dv) = grid_of(&cyl, step);
    let law = BurnLaw::single(Wiebe::from_ca50(100.0, 40.0, 2.0, DEFAULT_A).unwrap());
    let p = trace(&cyl, &law, 600.0, 1.32, step, 0.0);
    let opts = Options::default();
    let b = analyse(&CycleGrid::new(&p, &v, &dv, step), &opts)
        .unwrap()
        .burn
        .unwrap();
    assert!(b.cut_at_end && !b.cut_at_start, "{b:?}");
    assert!((b.eoc_deg - 120.0).abs() < 1.0, "{}", b.eoc_deg);
    // Widened to take it whole, it comes back.
    let wide = Options {
        window_deg: (-90.0, 179.0),
        ..Options::default()
    };
    let b = analyse(&CycleGrid::new(&p, &v, &dv, step), &wide)
        .unwrap()
        .burn
        .unwrap();
    assert!(!b.cut_at_end);
    assert!((b.level(&wide, 50.0).unwrap() - 100.0).abs() < 0.05);
}

/// Brunt's γ(T) scales its temperature from the state at IVC: a 0-bar
/// dropout there is an error naming `--ivc-deg` (CA50 8.05° became 43.75°
/// and the heat 751 J 413 J without a word).
#[test]
fn brunt_refuses_an_implausible_ivc_state() {
    let cyl = cylinder();
    let step = 0.1;
    let gm = GammaModel::brunt_default();
    let mut p = brunt_trace(&cyl, &petrol(), 600.0, gm, step);
    let n = p.len() as i64;
    for k in ((-150.0 / step) as i64)..=((-130.0 / step) as i64) {
        p[k.rem_euclid(n) as usize] = 0.0;
    }
    let (v, dv) = grid_of(&cyl, step);
    let opts = Options {
        gamma: gm,
        ..Options::default()
    };
    let e = analyse(&CycleGrid::new(&p, &v, &dv, step), &opts).unwrap_err();
    assert!(e.to_string().contains("--ivc-deg"), "{e}");
}

/// The filter's cost is bounded: SG 20° at a 0.001° step (20,001
/// points, 39 s a cycle) is refused naming the flag; the default passes.
#[test]
fn the_filter_is_bounded() {
    let wide = Options {
        smoothing: Smoothing::SavitzkyGolay { width_deg: 20.0 },
        ..Options::default()
    };
    let e = wide.check_grid(0.001, 720.0).unwrap_err();
    assert!(e.to_string().contains("--smooth"), "{e}");
    assert!(wide.check_grid(0.1, 720.0).is_ok());
    assert!(Options::default().check_grid(0.001, 720.0).is_err());
    assert!(Options::default().check_grid(0.005, 720.0).is_ok());
    // A window that holds under five grid points.
    let narrow = Options {
        window_deg: (0.0, 10.0),
        ..Options::default()
    };
    assert!(narrow.check_grid(5.0, 720.0).is_err());
}

/// A closed charge from 1 bar at IVC (−140°, 320 K) that burns `heat_j`
/// by `law` and loses heat to the walls by `h(p, T, V)` (W/m²K; its own
/// code here, from PHYSICS's formulas, not the crate's), RK4 at 0.01° to
/// +180°; 1 bar elsewhere. Constant γ 1.32, 2000 rpm, VAZ chamber.
fn walled_trace(
    cyl: &Cylinder,
    law: &BurnLaw,
    heat_j: f64,
    h: &dyn Fn(f64, f64, f64, f64) -> f64,
    step: f64,
) -> Vec<f64> {
    let (gamma, rpm, b) = (1.32, 2000.0, 0.076);
    let vol = |deg: f64| cyl.volume(deg.to_radians());
    let dvol = |deg: f64| cyl.dvolume(deg.to_radians()).to_radians();
    let (ivc, p0, t_ivc) = (-140.0, 1e5, 320.0);
    let mr = p0 * vol(ivc) / t_ivc;
    let loss = |deg: f64, p: f64| {
        let v = vol(deg);
        let t = p * v / mr;
        let area = std::f64::consts::PI * b * b / 2.0 + 4.0 * v / b;
        h(p, t, v, deg) * area * (t - 450.0) / (6.0 * rpm)
    };
    let dp = |deg: f64, p: f64| {
        ((gamma - 1.0) * (heat_j * law.rate(deg) - loss(deg, p)) - gamma * p * dvol(deg)) / vol(deg)
    };
    let fine = 0.01;
    let m = ((180.0 - ivc) / fine).round() as usize;
    let mut ps = vec![p0; m + 1];
    for j in 0..m {
        let (a, p) = (ivc + j as f64 * fine, ps[j]);
        let k1 = dp(a, p);
        let k2 = dp(a + fine / 2.0, p + fine / 2.0 * k1);
        let k3 = dp(a + fine / 2.0, p + fine / 2.0 * k2);
        let k4 = dp(a + fine, p + fine * k3);
        ps[j + 1] = p + fine / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    let n = (720.0 / step).round() as usize;
    (0..n)
        .map(|k| {
            let mut deg = k as f64 * step;
            if deg >= 360.0 {
                deg -= 720.0;
            }
            if !(ivc..=180.0).contains(&deg) {
                return p0;
            }
            ps[((deg - ivc) / fine).round() as usize]
        })
        .collect()
}

fn wall(model: enginedyn_combustion::WallModel) -> enginedyn_combustion::WallHeat {
    enginedyn_combustion::WallHeat {
        model,
        wall_temp_k: 450.0,
        intake_temp_k: 320.0,
        ivc_deg: -140.0,
        bore_m: 0.076,
        stroke_m: 0.071,
        swept_m3: cylinder().swept_volume(),
    }
}

/// Hohenberg (1979), PHYSICS's units: V m³, p bar, c_m 4.73 m/s at 2000 rpm.
fn hohenberg(p: f64, t: f64, v: f64, _deg: f64) -> f64 {
    let cm: f64 = 2.0 * 0.071 * 2000.0 / 60.0;
    130.0 * v.powf(-0.06) * (p / 1e5).powf(0.8) * t.powf(-0.4) * (cm + 1.4).powf(0.8)
}

/// Woschni (1967) before combustion (C2 = 0): B m, p kPa.
fn woschni_motored(p: f64, t: f64, _v: f64, _deg: f64) -> f64 {
    let cm: f64 = 2.0 * 0.071 * 2000.0 / 60.0;
    3.26 * 0.076f64.powf(-0.2) * (p / 1e3).powf(0.8) * t.powf(-0.55) * (2.28 * cm).powf(0.8)
}

/// PHYSICS "Wall heat": a motored trace that loses heat by the same law
/// has a gross heat release of about 0 (under 1 % of the charge's energy
/// at TDC), where the net one shows the loss.
#[test]
fn a_motored_trace_losing_heat_by_the_law_has_no_gross_release() {
    let cyl = cylinder();
    let step = 0.1;
    let (v, dv) = grid_of(&cyl, step);
    for (model, h) in [
        (
            enginedyn_combustion::WallModel::Woschni,
            &woschni_motored as &dyn Fn(f64, f64, f64, f64) -> f64,
        ),
        (enginedyn_combustion::WallModel::Hohenberg, &hohenberg),
    ] {
        let p = walled_trace(&cyl, &petrol(), 0.0, h, step);
        let mut g = CycleGrid::new(&p, &v, &dv, step);
        g.rpm = Some(2000.0);
        let net = analyse(&g, &Options::default()).unwrap();
        let opts = Options {
            wall_heat: Some(wall(model)),
            ..Options::default()
        };
        let r = analyse(&g, &opts).unwrap();
        let charge = p[0] * v[0] / 0.32;
        let gross = r.heat_released_gross_j.unwrap();
        eprintln!(
            "{model:?} motored: net {:.2} J, gross {gross:.3} J ({:.3} % of {charge:.0} J)",
            net.heat_released_j,
            100.0 * gross / charge
        );
        assert!(gross.abs() < 0.01 * charge, "{gross} of {charge}");
        assert!(r.burn.is_none());
    }
}

/// PHYSICS "Wall heat": a fired closed-charge trace built with a known
/// wall loss (Hohenberg) gives back its gross burn within 0.2°, where the
/// net analysis of the same trace misses the late burn.
#[test]
fn a_fired_trace_with_a_known_wall_loss_gives_back_its_gross_burn() {
    let cyl = cylinder();
    let step = 0.1;
    let (v, dv) = grid_of(&cyl, step);
    let law = petrol();
    let p = walled_trace(&cyl, &law, 600.0, &hohenberg, step);
    let mut g = CycleGrid::new(&p, &v, &dv, step);
    g.rpm = Some(2000.0);
    let opts = Options {
        wall_heat: Some(wall(enginedyn_combustion::WallModel::Hohenberg)),
        ..Options::default()
    };
    let r = analyse(&g, &opts).unwrap();
    let b = r.burn.as_ref().unwrap();
    let net = analyse(&g, &Options::default()).unwrap();
    let nb = net.burn.unwrap();
    for pct in [10.0, 50.0, 90.0] {
        let want = law.angle_of(pct / 100.0);
        let got = b.level(&opts, pct).unwrap();
        eprintln!(
            "CA{pct}: gross {got:.3}°, net {:.3}°, law {want:.3}°",
            nb.level(&opts, pct).unwrap()
        );
        // PHYSICS asks 0.2°; measured under 0.001°.
        assert!((got - want).abs() < 0.01, "CA{pct}: {got} for {want}");
    }
    let wall_j = r.wall_heat_j.unwrap();
    eprintln!(
        "heat: net {:.1} J, gross {:.1} J, wall {wall_j:.1} J",
        r.heat_released_j,
        r.heat_released_gross_j.unwrap()
    );
    assert!((r.heat_released_gross_j.unwrap() / 600.0 - 1.0).abs() < 0.02);
    assert!(wall_j > 0.0 && r.heat_released_j < r.heat_released_gross_j.unwrap());
    assert!((nb.level(&opts, 90.0).unwrap() - law.angle_of(0.9)).abs() > 0.2);
}

/// PHYSICS "Knock": a damped 7 kHz oscillation of known amplitude added
/// after the peak is recovered within 3 %; a clean trace with 0.02 bar of
/// noise stays under 0.1 bar; 0.1° data at 1,000–6,000 rpm and a 100 kHz
/// time record's step at 2000 rpm all work.
#[test]
fn knock_is_measured_in_its_band() {
    use enginedyn_combustion::{Knock, knock};
    let cyl = cylinder();
    let step = 0.1;
    let clean = trace(&cyl, &petrol(), 600.0, 1.32, step, 0.0);
    let n = clean.len();
    let k = Knock::default();
    for rpm in [1000.0, 2000.0, 4000.0, 6000.0] {
        // Knock onset at +15°, 7 kHz, 2 bar, decaying with 2 ms. (A
        // damped oscillation carries a slow part of about A/(2π f τ),
        // 2.3 % here, that a band's low edge removes: with 1 ms MAPO is
        // 4.5 % under the first crest, at every speed and step.)
        let amp = 2e5;
        const TAU: f64 = 2e-3;
        let knocking: Vec<f64> = (0..n)
            .map(|i| {
                let deg = if i >= n / 2 {
                    i as f64 * step - 720.0
                } else {
                    i as f64 * step
                };
                let t = (deg - 15.0) / (6.0 * rpm);
                let osc = if t >= 0.0 {
                    amp * (-t / TAU).exp() * (2.0 * std::f64::consts::PI * 7e3 * t).sin()
                } else {
                    0.0
                };
                clean[i] + osc
            })
            .collect();
        let got = knock(&knocking, step, step, rpm, &k).unwrap();
        // The oscillation's own largest |value| (its first crest).
        let truth = (0..100_000)
            .map(|j| {
                let t = j as f64 * 1e-8;
                amp * (-t / TAU).exp() * (2.0 * std::f64::consts::PI * 7e3 * t).sin().abs()
            })
            .fold(0.0f64, f64::max);
        let noisy: Vec<f64> = clean
            .iter()
            .zip(noise(n, 0.02e5, rpm as u64))
            .map(|(p, e)| p + e)
            .collect();
        let quiet = knock(&noisy, step, step, rpm, &k).unwrap();
        eprintln!(
            "{rpm} rpm: MAPO {:.4} bar for {:.4} at {:.1}°, clean + 0.02 bar noise {:.4} bar",
            got.mapo_pa / 1e5,
            truth / 1e5,
            got.mapo_angle_deg,
            quiet.mapo_pa / 1e5
        );
        assert!(
            (got.mapo_pa / truth - 1.0).abs() < 0.03,
            "{rpm}: {}",
            got.mapo_pa
        );
        assert!(quiet.mapo_pa < 0.1e5, "{rpm}: {}", quiet.mapo_pa);
    }
    // A time record at 100 kHz and 2000 rpm: 0.12° a sample.
    assert!(knock(&clean, step, 0.12, 2000.0, &k).is_ok());
}
