//! Uniformity and the flywheel: excess energy `E(phi)`, excess work and its
//! coefficient, torque non-uniformity, the required moment of inertia for a
//! speed fluctuation `delta`, the flywheel's size, and the speed trace that
//! inertia gives (PHYSICS.md, "Flywheel").
//!
//! ```
//! use enginedyn_engine::FlywheelSpec;
//! use enginedyn_flywheel::{analyse, Uniformity};
//! use enginedyn_numerics::integrate::Rule;
//! // M = 100 + 50 cos(2 phi) over one revolution: E = 25 sin(2 phi), dE = 50 J.
//! let n = 3600;
//! let h = 2.0 * std::f64::consts::PI / n as f64;
//! let m: Vec<f64> = (0..n).map(|k| 100.0 + 50.0 * (2.0 * k as f64 * h).cos()).collect();
//! let u = Uniformity::new(&m, h, Rule::Trapezoid);
//! assert!((u.excess_work - 50.0).abs() < 1e-3);
//! let f = analyse(&u, &FlywheelSpec::default(), 300.0, 0.0).unwrap();
//! assert!((f.speed_fluctuation_achieved - 0.01).abs() < 1e-12);
//! ```

use enginedyn_engine::{FlywheelShape, FlywheelSpec};
use enginedyn_numerics::{extremes, extremes::periodic_min_max, integrate, integrate::Rule, roots};

/// Standard gravity (m/s²), for GD².
pub const G: f64 = 9.806_65;

/// What the torque curve says about uniformity, before any flywheel.
#[derive(Debug, Clone, PartialEq)]
pub struct Uniformity {
    /// Mean torque `M_m` (N m).
    pub mean: f64,
    /// Largest and smallest torque (N m).
    pub max: f64,
    /// Smallest torque (N m).
    pub min: f64,
    /// Excess energy `E(phi)` (J) on the grid.
    pub excess_energy: Vec<f64>,
    /// `dE = max E - min E` (J).
    pub excess_work: f64,
    /// Cycle length (rad).
    pub cycle: f64,
}

impl Uniformity {
    /// From a torque sampled at `n` points `h` apart over one cycle.
    pub fn new(torque: &[f64], h: f64, rule: Rule) -> Self {
        let mean = integrate::periodic_mean(rule, torque);
        let dev: Vec<f64> = torque.iter().map(|m| m - mean).collect();
        let mut e = vec![0.0; torque.len()];
        integrate::cumulative(rule, &dev, h, &mut e);
        // Refined between samples: the extremes of the curves, not of the grid.
        let (emin, emax) = periodic_min_max(&e);
        let (min, max) = periodic_min_max(torque);
        Self {
            mean,
            max,
            min,
            excess_energy: e,
            excess_work: emax - emin,
            cycle: h * torque.len() as f64,
        }
    }
    /// True when the engine delivers no work: `M_m <= 0`, or a mean so
    /// small against the torque swing (below 1e-9 of it) that it is rounding.
    pub fn is_motoring(&self) -> bool {
        let swing = self.max.abs().max(self.min.abs());
        self.mean <= 1e-9 * swing
    }
    /// Torque non-uniformity `mu = (M_max - M_min) / M_m`; `None` when motoring.
    pub fn nonuniformity(&self) -> Option<f64> {
        (!self.is_motoring()).then(|| (self.max - self.min) / self.mean)
    }
    /// Excess-work coefficient `psi = dE / (M_m Phi)`; `None` when motoring.
    pub fn excess_work_coefficient(&self) -> Option<f64> {
        (!self.is_motoring()).then(|| self.excess_work / (self.mean * self.cycle))
    }
}

/// Why no flywheel figures exist.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FlywheelError {
    /// The engine absorbs work on average (motoring).
    #[error(
        "the mean torque is {} N m, not positive (motored engine): no flywheel, non-uniformity or excess-work coefficient",
        enginedyn_numerics::format::sig(*.0, 4)
    )]
    Motoring(f64),
    /// The torque is perfectly uniform.
    #[error("the torque is uniform (excess work 0): no flywheel is needed")]
    Uniform,
}

/// Flywheel figures (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct Flywheel {
    /// Required total moment of inertia `I_0 = dE / (delta w_m^2)` (kg m²).
    pub required_inertia: f64,
    /// The inertia the engine brings itself (kg m²).
    pub engine_inertia: f64,
    /// Flywheel inertia `I_f = I_0 - I_engine`, at least 0 (kg m²).
    pub inertia: f64,
    /// Outer diameter (m); `None` when no flywheel is needed.
    pub outer_diameter: Option<f64>,
    /// Mass (kg).
    pub mass: f64,
    /// Disc thickness or rim width (m); `None` when no flywheel is needed.
    pub width: Option<f64>,
    /// Flywheel moment `GD^2 = 4 g I_f` (N m²); `None` when no flywheel is needed.
    pub gd2: Option<f64>,
    /// Speed trace `w(phi)` (rad/s) with `I_0`.
    pub speed: Vec<f64>,
    /// `delta` that trace gives.
    pub speed_fluctuation_achieved: f64,
    /// Warnings.
    pub notes: Vec<String>,
}

/// The outer diameter, mass and width (m, kg, m) of a flywheel of inertia
/// `i_f` (kg m²) whose rim runs at most at `spec.max_rim_speed` at the mean
/// speed `omega` (rad/s; its top `omega (1 + δ/2)`), or of the diameter the
/// spec gives; a note when its shape is odd.
fn dimensions(
    spec: &FlywheelSpec,
    i_f: f64,
    omega: f64,
    notes: &mut Vec<String>,
) -> (f64, f64, f64) {
    let delta = spec.speed_fluctuation;
    let d = spec
        .outer_diameter
        .unwrap_or(2.0 * spec.max_rim_speed / (omega * (1.0 + delta / 2.0)));
    let area = std::f64::consts::PI * d * d / 4.0;
    let (mass, width) = match spec.shape {
        FlywheelShape::Disc => {
            let m = 8.0 * i_f / (d * d);
            (m, m / (spec.density * area))
        }
        FlywheelShape::Rim => {
            let r = spec.rim_inner_ratio;
            let m = 8.0 * i_f / (d * d * (1.0 + r * r));
            (m, m / (spec.density * area * (1.0 - r * r)))
        }
    };
    if width > d {
        notes.push(format!(
            "the flywheel is wider ({:.0} mm) than its diameter ({:.0} mm): allow a higher rim speed or a larger diameter",
            width * 1e3,
            d * 1e3
        ));
    } else if width < THIN * d {
        notes.push(thin_note(spec, i_f, d, width));
    }
    (d, mass, width)
}

/// The part `f` (sized at one speed) made to run up to the mean speed
/// `top_omega` (rad/s), the highest it meets (a map's or a sweep's): the
/// same inertia, its outer diameter set by the rim speed limit at that
/// speed (a diameter the spec gives stays), its mass and width to match.
/// A part sized at idle and made for the idle speed's rim would burst at
/// rated speed.
pub fn for_top_speed(f: &Flywheel, spec: &FlywheelSpec, top_omega: f64) -> Flywheel {
    if f.inertia <= 0.0 || !(top_omega.is_finite() && top_omega > 0.0) {
        return f.clone();
    }
    let mut notes = Vec::new();
    let (d, mass, width) = dimensions(spec, f.inertia, top_omega, &mut notes);
    Flywheel {
        outer_diameter: Some(d),
        mass,
        width: Some(width),
        notes,
        ..f.clone()
    }
}

/// Sizes the flywheel for the mean speed `omega` (rad/s); `engine_inertia`
/// is what the engine's own rotating parts contribute (kg m²).
pub fn analyse(
    u: &Uniformity,
    spec: &FlywheelSpec,
    omega: f64,
    engine_inertia: f64,
) -> Result<Flywheel, FlywheelError> {
    if u.is_motoring() {
        return Err(FlywheelError::Motoring(u.mean));
    }
    if u.excess_work <= 0.0 {
        return Err(FlywheelError::Uniform);
    }
    let delta = spec.speed_fluctuation;
    let i0 = u.excess_work / (delta * omega * omega);
    let mut notes = Vec::new();
    let i_f = i0 - engine_inertia;
    let (inertia, outer_diameter, mass, width, gd2) = if i_f <= 0.0 {
        notes.push(format!(
            "the engine's own rotating inertia ({engine_inertia:.4} kg m²) exceeds the {i0:.4} kg m² required: no flywheel needed"
        ));
        (0.0, None, 0.0, None, None)
    } else {
        let (d, mass, width) = dimensions(spec, i_f, omega, &mut notes);
        (i_f, Some(d), mass, Some(width), Some(4.0 * G * i_f))
    };
    let (speed, achieved) = speed_trace(&u.excess_energy, i0, omega);
    Ok(Flywheel {
        required_inertia: i0,
        engine_inertia,
        inertia,
        outer_diameter,
        mass,
        width,
        gd2,
        speed,
        speed_fluctuation_achieved: achieved,
        notes,
    })
}

/// The flywheel `part` (sized at another speed) on this torque curve at the
/// mean speed `omega`: the same part and figures, with the speed trace and
/// the `delta` it gives here (total inertia: the part plus the engine's own).
pub fn same_part(u: &Uniformity, part: &Flywheel, omega: f64) -> Flywheel {
    let total = part.inertia + part.engine_inertia;
    let (speed, achieved) = speed_trace(&u.excess_energy, total, omega);
    Flywheel {
        speed,
        speed_fluctuation_achieved: achieved,
        notes: Vec::new(),
        ..part.clone()
    }
}

/// What a flywheel sized elsewhere needs of a torque curve to give its δ
/// there ([`same_part_at`]): the excess energy's refined extremes and the
/// five samples around each sample that may hold the speed's extreme; a few
/// numbers in place of `E(φ)` on the whole grid, so that a sweep or map
/// keeps no curve per point. The speed is an increasing function of `E`, so
/// its extremes lie at the samples where `E` has its own, or (rounding) at
/// another sample within [`TIE`] of it, as the equal peaks of identical
/// cylinders are: each such sample is kept, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergySpan {
    /// Smallest `E` (J), refined between samples.
    pub min: f64,
    /// Largest `E` (J), refined between samples.
    pub max: f64,
    at_min: Vec<[f64; 5]>,
    at_max: Vec<[f64; 5]>,
}

/// How close (a fraction of `max E − min E`) a sample's `E` must come to
/// the extreme sample's for [`EnergySpan`] to keep it: far above where the
/// speed's rounding could tie two samples (1e-16 of the range over δ).
pub const TIE: f64 = 1e-9;

/// The most samples [`EnergySpan`] keeps at each extreme.
const MOST_TIED: usize = 64;

impl EnergySpan {
    /// From `E(φ)` over one cycle.
    pub fn of(e: &[f64]) -> Self {
        let (min, max) = periodic_min_max(e);
        if e.len() < 4 {
            // Too few samples to refine: the extremes as they are.
            return Self {
                min,
                max,
                at_min: vec![[min; 5]],
                at_max: vec![[max; 5]],
            };
        }
        let (lo, hi) = enginedyn_numerics::scan::min_max(e);
        let tie = TIE * (hi - lo);
        let near = |pick: &dyn Fn(f64) -> bool| -> Vec<[f64; 5]> {
            (0..e.len())
                .filter(|&k| pick(e[k]))
                .take(MOST_TIED)
                .map(|k| extremes::window(e, k))
                .collect()
        };
        Self {
            min,
            max,
            at_min: near(&|x| x <= lo + tie),
            at_max: near(&|x| x >= hi - tie),
        }
    }
}

impl Uniformity {
    /// What a flywheel sized elsewhere needs of this curve ([`EnergySpan`]).
    pub fn span(&self) -> EnergySpan {
        EnergySpan::of(&self.excess_energy)
    }
}

/// [`same_part`] from an [`EnergySpan`]: the same part and figures with the
/// `delta` it gives at the mean speed `omega` (the same number
/// [`same_part`] gives), without the speed trace.
pub fn same_part_at(span: &EnergySpan, part: &Flywheel, omega: f64) -> Flywheel {
    let inertia = part.inertia + part.engine_inertia;
    let w0 = base_speed(span.min, span.max, inertia, omega);
    let w = |x: &f64| (w0 * w0 + 2.0 * x / inertia).max(0.0).sqrt();
    // The first sample of the speed's extreme (as `periodic_min_max` takes
    // it of the whole trace), refined from its window.
    let refined = |kept: &[[f64; 5]], sign: f64| {
        let mut best: Option<(f64, &[f64; 5])> = None;
        for c in kept {
            let v = sign * w(&c[2]);
            if best.is_none_or(|(b, _)| v > b) {
                best = Some((v, c));
            }
        }
        best.map_or(f64::NAN, |(_, c)| {
            sign * extremes::window_max(&c.each_ref().map(w), sign)
        })
    };
    let (wmin, wmax) = (refined(&span.at_min, -1.0), refined(&span.at_max, 1.0));
    Flywheel {
        speed: Vec::new(),
        speed_fluctuation_achieved: (wmax - wmin) / (0.5 * (wmax + wmin)),
        notes: Vec::new(),
        ..part.clone()
    }
}

/// A flywheel thinner than this fraction of its diameter is no real part
/// (a 570 mm rim 3.4 mm wide): it gets a warning.
pub const THIN: f64 = 0.02;

/// The width a flywheel of this shape and inertia takes at diameter `d`
/// (m): `32 I / (ρ π d⁴ (1 − r⁴))`, `r` the rim's inner ratio (0 for a
/// disc).
pub fn width_at(spec: &FlywheelSpec, inertia: f64, d: f64) -> f64 {
    let r = match spec.shape {
        FlywheelShape::Disc => 0.0,
        FlywheelShape::Rim => spec.rim_inner_ratio,
    };
    32.0 * inertia / (spec.density * std::f64::consts::PI * d.powi(4) * (1.0 - r.powi(4)))
}

/// The warning for a flywheel thinner than [`THIN`] of its diameter: it
/// names `outer_diameter_mm` and the diameter at which the same inertia is
/// a tenth of the diameter wide (the width goes as `1/d⁴`).
fn thin_note(spec: &FlywheelSpec, inertia: f64, d: f64, width: f64) -> String {
    let h = enginedyn_numerics::format::human;
    // width(D) / D = 0.1: D = d (width / (0.1 d))^(1/5).
    let target = d * (width / (0.1 * d)).powf(0.2);
    let target_mm = (target * 1e3).round().max(1.0);
    let why = match spec.outer_diameter {
        Some(_) => "flywheel.outer_diameter_mm".to_string(),
        None => format!(
            "the rim speed (flywheel.max_rim_speed_m_s = {} m/s)",
            h(spec.max_rim_speed)
        ),
    };
    let shape = match spec.shape {
        FlywheelShape::Rim => "rim",
        FlywheelShape::Disc => "disc",
    };
    format!(
        "the flywheel ({shape}) is {} mm wide at {} mm diameter, under {} % of it: no practical part. Its diameter comes from {why}; set flywheel.outer_diameter_mm smaller (outer_diameter_mm = {} gives {} mm, a tenth of it){}",
        h((width * 1e3 * 10.0).round() / 10.0),
        h((d * 1e3).round()),
        h(THIN * 100.0),
        h(target_mm),
        h((width_at(spec, inertia, target_mm * 1e-3) * 1e3).round()),
        match spec.shape {
            FlywheelShape::Disc => "; a rim (shape = \"rim\") is wider for the same inertia",
            FlywheelShape::Rim => "",
        }
    )
}

/// `w(phi) = sqrt(w_0^2 + 2 E(phi) / I)` with `w_0` such that
/// `(w_max + w_min)/2 = omega`; returns the trace and its `delta`.
pub fn speed_trace(e: &[f64], inertia: f64, omega: f64) -> (Vec<f64>, f64) {
    let (emin, emax) = periodic_min_max(e);
    let w0 = base_speed(emin, emax, inertia, omega);
    let speed: Vec<f64> = e
        .iter()
        .map(|&x| (w0 * w0 + 2.0 * x / inertia).max(0.0).sqrt())
        .collect();
    let (wmin, wmax) = periodic_min_max(&speed);
    (speed, (wmax - wmin) / (0.5 * (wmax + wmin)))
}

/// `w_0` of [`speed_trace`]: `(w_max + w_min)/2 = omega` for the excess
/// energy's extremes `emin`, `emax`.
fn base_speed(emin: f64, emax: f64, inertia: f64, omega: f64) -> f64 {
    let mid = |w0: f64| {
        let hi = (w0 * w0 + 2.0 * emax / inertia).max(0.0).sqrt();
        let lo = (w0 * w0 + 2.0 * emin / inertia).max(0.0).sqrt();
        0.5 * (hi + lo) - omega
    };
    // mid is increasing in w0; bracket it from the smallest w0 that keeps w real.
    let lo = (-2.0 * emin / inertia).max(0.0).sqrt();
    roots::brent(mid, lo, 2.0 * omega + lo, 1e-14 * omega).unwrap_or(omega)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part sized elsewhere gives the same δ from the span alone as from
    /// the whole excess-energy curve, bit for bit.
    #[test]
    fn the_span_gives_the_same_part_as_the_curve() {
        let n = 7200;
        let h = 4.0 * std::f64::consts::PI / n as f64;
        let m: Vec<f64> = (0..n)
            .map(|k| {
                let x = k as f64 * h;
                120.0 + 300.0 * (2.0 * x + 0.3).cos() + 80.0 * (4.0 * x).sin()
            })
            .collect();
        let u = Uniformity::new(&m, h, Rule::Trapezoid);
        let part = analyse(&u, &FlywheelSpec::default(), 200.0, 0.05).unwrap();
        for omega in [100.0, 314.0, 600.0] {
            let whole = same_part(&u, &part, omega);
            let kept = same_part_at(&u.span(), &part, omega);
            assert_eq!(
                whole.speed_fluctuation_achieved.to_bits(),
                kept.speed_fluctuation_achieved.to_bits()
            );
            assert_eq!(kept.inertia.to_bits(), whole.inertia.to_bits());
        }
    }

    /// The issue's case: a rim sized by the default rim speed at about
    /// 2000 rpm, 570 mm in diameter and 3.4 mm wide, gets the warning that
    /// names outer_diameter_mm, and the diameter it suggests gives a width
    /// of a tenth of itself; a practical part gets none.
    #[test]
    fn thin_flywheel_is_warned() {
        let n = 3600;
        let h = 2.0 * std::f64::consts::PI / n as f64;
        let spec = FlywheelSpec::default();
        let omega: f64 = 2.0 * 60.0 / (0.57 * 1.005);
        // I_f = 32 I / ... : choose dE so that the rim is 3.4 mm wide.
        let inertia = 0.0034 * width_at(&spec, 1.0, 0.57).recip();
        let de = inertia * spec.speed_fluctuation * omega * omega;
        let m: Vec<f64> = (0..n)
            .map(|k| 100.0 + de * (2.0 * k as f64 * h).cos())
            .collect();
        let u = Uniformity::new(&m, h, Rule::Trapezoid);
        let f = analyse(&u, &spec, omega, 0.0).unwrap();
        let d = f.outer_diameter.unwrap();
        let w = f.width.unwrap();
        assert!((d - 0.57).abs() < 1e-9, "{d}");
        assert!((w - 0.0034).abs() < 2e-5, "{w}");
        let note = f.notes.iter().find(|n| n.contains("under 2 %")).unwrap();
        assert!(
            note.starts_with(
                "the flywheel (rim) is 3.4 mm wide at 570 mm diameter, under 2 % of it"
            ),
            "{note}"
        );
        assert!(
            note.contains("flywheel.max_rim_speed_m_s = 60 m/s"),
            "{note}"
        );
        assert!(
            note.contains("set flywheel.outer_diameter_mm smaller"),
            "{note}"
        );
        // The suggested diameter: width 10 % of it (to the rounding of 1 mm).
        let suggested: f64 = note
            .split("(outer_diameter_mm = ")
            .nth(1)
            .and_then(|s| s.split(' ').next())
            .unwrap()
            .parse()
            .unwrap();
        let ratio = width_at(&spec, f.inertia, suggested * 1e-3) / (suggested * 1e-3);
        assert!((ratio - 0.1).abs() < 0.002, "{suggested} mm: {ratio}");
        // A given diameter is named as the cause.
        let given = FlywheelSpec {
            outer_diameter: Some(0.57),
            ..spec
        };
        let f = analyse(&u, &given, omega, 0.0).unwrap();
        assert!(
            f.notes
                .iter()
                .any(|n| n.contains("comes from flywheel.outer_diameter_mm")),
            "{:?}",
            f.notes
        );
        // 280 mm: about 60 mm wide, no warning.
        let small = FlywheelSpec {
            outer_diameter: Some(0.28),
            ..spec
        };
        let f = analyse(&u, &small, omega, 0.0).unwrap();
        assert!(f.notes.is_empty(), "{:?}", f.notes);
    }

    /// The part sized at one speed gives that speed's δ there, and about a
    /// quarter of it at twice the speed (δ ≈ ΔE / (I ω²), to O(δ²)); its
    /// figures stay the part's.
    #[test]
    fn same_part_over_speed() {
        let n = 3600;
        let h = 2.0 * std::f64::consts::PI / n as f64;
        let m: Vec<f64> = (0..n)
            .map(|k| 100.0 + 50.0 * (2.0 * k as f64 * h).cos())
            .collect();
        let u = Uniformity::new(&m, h, Rule::Trapezoid);
        let spec = FlywheelSpec::default();
        let part = analyse(&u, &spec, 300.0, 0.0).unwrap();
        let here = same_part(&u, &part, 300.0);
        assert!((here.speed_fluctuation_achieved - 0.01).abs() < 1e-12);
        let fast = same_part(&u, &part, 600.0);
        assert!((fast.speed_fluctuation_achieved / 0.0025 - 1.0).abs() < 1e-4);
        assert_eq!(fast.outer_diameter, part.outer_diameter);
        assert_eq!(
            fast.required_inertia.to_bits(),
            part.required_inertia.to_bits()
        );
    }
}
