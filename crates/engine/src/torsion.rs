//! The `[torsion]` section of the engine file, as given (SI, checked per
//! key): the crankshaft as a chain of inertias on springs. What is left
//! out takes INTERFACE.md's defaults where the chain is built
//! (`enginedyn_pipeline::torsion`), since some come from the analysis
//! (the sized flywheel) or from the engine (the throw inertias).

use crate::{Engine, EngineError, RodModel};
use enginedyn_numerics::format::human;

/// One value for every item, or one per item.
#[derive(Debug, Clone, PartialEq)]
pub enum PerItem {
    /// The same value for each.
    One(f64),
    /// One value per item, in order from the free end.
    Each(Vec<f64>),
}

impl PerItem {
    /// The values for `count` items, or `None` when a list has another
    /// length.
    pub fn expand(&self, count: usize) -> Option<Vec<f64>> {
        match self {
            PerItem::One(v) => Some(vec![*v; count]),
            PerItem::Each(v) if v.len() == count => Some(v.clone()),
            PerItem::Each(_) => None,
        }
    }

    /// The values as given.
    pub fn values(&self) -> &[f64] {
        match self {
            PerItem::One(v) => std::slice::from_ref(v),
            PerItem::Each(v) => v,
        }
    }
}

/// A tuned torsional damper on the front mass (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamperSpec {
    /// Ring inertia (kg m²).
    pub inertia: f64,
    /// Spring between ring and hub (N m/rad).
    pub stiffness: f64,
    /// Viscous damping between ring and hub (N m s/rad).
    pub damping: f64,
}

/// `[torsion]` as given, SI (kg m², N m/rad, m). Every value is finite and
/// in range (checked when the file is read); counts against the throws are
/// checked where the chain is built.
#[derive(Debug, Clone, PartialEq)]
pub struct TorsionSpec {
    /// `throw_inertia_kg_m2`.
    pub throw_inertia: Option<PerItem>,
    /// `journal_stiffness_nm_rad`.
    pub journal_stiffness: Option<PerItem>,
    /// `journal_diameter_mm` (m).
    pub journal_diameter: Option<PerItem>,
    /// `journal_length_mm` (m).
    pub journal_length: Option<PerItem>,
    /// `front_inertia_kg_m2` (0: no front mass).
    pub front_inertia: f64,
    /// `front_stiffness_nm_rad`.
    pub front_stiffness: Option<f64>,
    /// `flywheel_inertia_kg_m2`.
    pub flywheel_inertia: Option<f64>,
    /// `flywheel_stiffness_nm_rad`.
    pub flywheel_stiffness: Option<f64>,
    /// `load_inertia_kg_m2`.
    pub load_inertia: Option<f64>,
    /// `load_stiffness_nm_rad`.
    pub load_stiffness: Option<f64>,
    /// `damping_ratio` (default 0.02).
    pub damping_ratio: f64,
    /// `damper`.
    pub damper: Option<DamperSpec>,
    /// `shaft_diameter_mm` (m).
    pub shaft_diameter: Option<PerItem>,
}

/// Shear modulus of steel for `journal_diameter_mm` and `journal_length_mm`
/// (Pa), INTERFACE.md.
pub const STEEL_SHEAR_MODULUS: f64 = 80.8e9;

/// Stiffness of a plain round steel shaft `G π d⁴ / (32 l)` (N m/rad).
pub fn shaft_stiffness(diameter: f64, length: f64) -> f64 {
    STEEL_SHEAR_MODULUS * std::f64::consts::PI * diameter.powi(4) / (32.0 * length)
}

/// What a `[torsion]` number measures: its unit, and the units it is
/// likely given in by mistake.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// kg m².
    Inertia,
    /// N m/rad.
    Stiffness,
    /// N m s/rad.
    Damping,
    /// mm in the file (m inside).
    Length,
    /// A ratio (the modal damping ratio).
    Ratio,
}

impl Quantity {
    /// The units a value of this quantity is likely written in by mistake:
    /// (name, what one of them is in the key's unit).
    fn mistakes(self) -> &'static [(&'static str, f64)] {
        match self {
            Quantity::Inertia => &[
                ("g·cm²", 1e-7),
                ("kg·mm²", 1e-6),
                ("kg·cm²", 1e-4),
                ("lb·in²", 2.926_397e-4),
                ("lb·ft²", 4.214_011e-2),
                ("GD² in kgf·m² (4 J)", 0.25),
                ("t·m²", 1e3),
            ],
            Quantity::Stiffness => &[
                ("N·mm/rad", 1e-3),
                ("lbf·in/rad", 0.112_984_8),
                ("lbf·ft/rad", 1.355_818),
                ("N·m/deg", 57.295_78),
                ("kN·m/rad", 1e3),
                ("kN·m/deg", 57_295.78),
                ("MN·m/rad", 1e6),
            ],
            Quantity::Damping => &[("N·mm·s/rad", 1e-3), ("kN·m·s/rad", 1e3)],
            Quantity::Length => &[
                ("micrometres", 1e-3),
                ("centimetres", 10.0),
                ("inches", 25.4),
                ("metres", 1e3),
            ],
            Quantity::Ratio => &[("a percentage", 0.01)],
        }
    }
}

/// A `[torsion]` key that takes a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// `throw_inertia_kg_m2`.
    ThrowInertia,
    /// `journal_stiffness_nm_rad`.
    JournalStiffness,
    /// `journal_diameter_mm`.
    JournalDiameter,
    /// `journal_length_mm`.
    JournalLength,
    /// `front_inertia_kg_m2`.
    FrontInertia,
    /// `front_stiffness_nm_rad`.
    FrontStiffness,
    /// `flywheel_inertia_kg_m2`.
    FlywheelInertia,
    /// `flywheel_stiffness_nm_rad`.
    FlywheelStiffness,
    /// `load_inertia_kg_m2`.
    LoadInertia,
    /// `load_stiffness_nm_rad`.
    LoadStiffness,
    /// `damping_ratio`.
    DampingRatio,
    /// `damper.inertia_kg_m2`.
    DamperInertia,
    /// `damper.stiffness_nm_rad`.
    DamperStiffness,
    /// `damper.damping_nm_s_rad`.
    DamperDamping,
    /// `shaft_diameter_mm`.
    ShaftDiameter,
}

impl Key {
    /// Every key, in the order of [`BOUNDS`].
    pub const ALL: [Key; 15] = [
        Key::ThrowInertia,
        Key::JournalStiffness,
        Key::JournalDiameter,
        Key::JournalLength,
        Key::FrontInertia,
        Key::FrontStiffness,
        Key::FlywheelInertia,
        Key::FlywheelStiffness,
        Key::LoadInertia,
        Key::LoadStiffness,
        Key::DampingRatio,
        Key::DamperInertia,
        Key::DamperStiffness,
        Key::DamperDamping,
        Key::ShaftDiameter,
    ];

    /// Its bounds.
    pub fn bound(self) -> &'static Bound {
        &BOUNDS[self as usize]
    }

    /// The key as the file spells it, with its section:
    /// `torsion.journal_stiffness_nm_rad`.
    pub fn name(self) -> &'static str {
        self.bound().key
    }

    /// The key of one value: with `Some(i)` (0-based, a value of a list)
    /// the 1-based index, `torsion.journal_stiffness_nm_rad[3]` for the
    /// third.
    pub fn item(self, index: Option<usize>) -> String {
        match index {
            Some(i) => format!("{}[{}]", self.name(), i + 1),
            None => self.name().to_string(),
        }
    }
}

/// One `[torsion]` key's bounds, in the file's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// The key as the file spells it, with its section.
    pub key: &'static str,
    /// What it measures.
    pub quantity: Quantity,
    /// The hard bounds: outside them the command exits 2 naming the key
    /// (the computation would overflow or lose all precision).
    pub hard: (f64, f64),
    /// Whether the upper hard bound itself is refused (`damping_ratio`
    /// below 1).
    pub hard_open: bool,
    /// 0 is accepted besides `hard` (no front mass, no damping).
    pub zero_ok: bool,
    /// What any real engine has: outside, the command runs with a note
    /// naming the key and the likely mistake.
    pub plausible: (f64, f64),
    /// The file's unit.
    pub unit: &'static str,
    /// The file's value times `si` is SI (1e-3 for mm).
    pub si: f64,
}

// Hard bounds. Inertias 1e-12 to 1e9 kg m² and stiffnesses 1e-6 to 1e14
// N m/rad: k/J, the square of a natural frequency, stays below 2e26 s⁻²
// (2e12 Hz), far from overflow, and the mass and stiffness matrices, their
// square roots and the modal damping matrix C = M Φ diag(2 ζ ω) Φᵀ M are
// finite; 1e-300 or 1e308 are not (1e308 + 1e308 overflows in K). A chain
// whose values are each within these bounds but so far apart that its
// frequencies in the speed range cannot be resolved is refused where the
// chain is built (`enginedyn_pipeline::torsion`). Lengths as the engine's
// bore: 1 µm to 100 m.
const J_HARD: (f64, f64) = (1e-12, 1e9);
const K_HARD: (f64, f64) = (1e-6, 1e14);
const L_HARD: (f64, f64) = (1e-3, 1e5);

/// The bounds of every `[torsion]` key that takes a number, in [`Key`]'s
/// order: the one table (INTERFACE.md, "Limits").
///
/// The plausible ranges span every real engine, from a model or moped
/// single to the largest two-stroke marine diesel:
///
/// - a throw: a 25 cm³ single's (pin and webs of 0.2 kg at a 20 mm radius
///   of gyration, with its piston's mean) is about 1e-4 kg m², a model
///   engine's 1e-5; a 98 cm bore, 2.66 m stroke marine engine's (a 40 t
///   reciprocating mass at R = 1.33 m: `m_j R²/2` = 3.5e4, webs as much
///   again) about 1e5: 1e-5 to 2e5 kg m²;
/// - a front mass (pulley, hub, a marine engine's tuning wheel) 1e-6 to
///   2e4, a damper ring 1e-5 to 1e5, a flywheel (a moped's magneto rotor
///   1e-3 to a marine flywheel 1e5) 1e-4 to 1e6, a driven load (a model
///   propeller to a ship's propeller with its entrained water) 1e-5 to 1e7;
/// - a journal's stiffness `G π d⁴ / (32 l)`: a model engine's 5 mm pin
///   over 10 mm is 5e2 N m/rad, a marine engine's 1 m journal over a 3 m
///   equivalent length 2.6e9: 1e2 to 2e10 N m/rad, the same for the
///   front and flywheel springs; a coupling (a small generator's highly
///   flexible rubber coupling, some 1e2, to a rigid flange) 1 to 2e10; a
///   damper's spring any small value (a viscous damper has almost none) to
///   1e9 (a large engine's steel-spring damper, some 1e8);
/// - a damper's viscous damping 0 to 1e7 N m s/rad (a large marine
///   engine's viscous damper some 1e6);
/// - a crankshaft's modal damping ratio 0.005 to 0.05 (0.02 typical),
///   with a rubber damper's modes up to about 0.15: above 0.2 a note;
/// - a journal or shaft diameter 5 mm (a model engine) to 1.5 m (a marine
///   engine's 1.1 m journals), a journal length (or the equivalent length
///   between throws) 2 mm to 5 m.
pub const BOUNDS: [Bound; 15] = [
    Bound {
        key: "torsion.throw_inertia_kg_m2",
        quantity: Quantity::Inertia,
        hard: J_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1e-5, 2e5),
        unit: "kg m²",
        si: 1.0,
    },
    Bound {
        key: "torsion.journal_stiffness_nm_rad",
        quantity: Quantity::Stiffness,
        hard: K_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1e2, 2e10),
        unit: "N m/rad",
        si: 1.0,
    },
    Bound {
        key: "torsion.journal_diameter_mm",
        quantity: Quantity::Length,
        hard: L_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (5.0, 1500.0),
        unit: "mm",
        si: 1e-3,
    },
    Bound {
        key: "torsion.journal_length_mm",
        quantity: Quantity::Length,
        hard: L_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (2.0, 5000.0),
        unit: "mm",
        si: 1e-3,
    },
    Bound {
        key: "torsion.front_inertia_kg_m2",
        quantity: Quantity::Inertia,
        hard: J_HARD,
        hard_open: false,
        zero_ok: true,
        plausible: (1e-6, 2e4),
        unit: "kg m²",
        si: 1.0,
    },
    Bound {
        key: "torsion.front_stiffness_nm_rad",
        quantity: Quantity::Stiffness,
        hard: K_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1e2, 2e10),
        unit: "N m/rad",
        si: 1.0,
    },
    Bound {
        key: "torsion.flywheel_inertia_kg_m2",
        quantity: Quantity::Inertia,
        hard: J_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1e-4, 1e6),
        unit: "kg m²",
        si: 1.0,
    },
    Bound {
        key: "torsion.flywheel_stiffness_nm_rad",
        quantity: Quantity::Stiffness,
        hard: K_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1e2, 2e10),
        unit: "N m/rad",
        si: 1.0,
    },
    Bound {
        key: "torsion.load_inertia_kg_m2",
        quantity: Quantity::Inertia,
        hard: J_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1e-5, 1e7),
        unit: "kg m²",
        si: 1.0,
    },
    Bound {
        key: "torsion.load_stiffness_nm_rad",
        quantity: Quantity::Stiffness,
        hard: K_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1.0, 2e10),
        unit: "N m/rad",
        si: 1.0,
    },
    Bound {
        key: "torsion.damping_ratio",
        quantity: Quantity::Ratio,
        hard: (0.0, 1.0),
        hard_open: true,
        zero_ok: true,
        plausible: (0.0, 0.2),
        unit: "",
        si: 1.0,
    },
    Bound {
        key: "torsion.damper.inertia_kg_m2",
        quantity: Quantity::Inertia,
        hard: J_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (1e-5, 1e5),
        unit: "kg m²",
        si: 1.0,
    },
    Bound {
        key: "torsion.damper.stiffness_nm_rad",
        quantity: Quantity::Stiffness,
        hard: K_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (K_HARD.0, 1e9),
        unit: "N m/rad",
        si: 1.0,
    },
    Bound {
        key: "torsion.damper.damping_nm_s_rad",
        quantity: Quantity::Damping,
        hard: (0.0, 1e12),
        hard_open: false,
        zero_ok: true,
        plausible: (0.0, 1e7),
        unit: "N m s/rad",
        si: 1.0,
    },
    Bound {
        key: "torsion.shaft_diameter_mm",
        quantity: Quantity::Length,
        hard: L_HARD,
        hard_open: false,
        zero_ok: false,
        plausible: (5.0, 1500.0),
        unit: "mm",
        si: 1e-3,
    },
];

impl Bound {
    fn inside_hard(&self, x: f64) -> bool {
        let (lo, hi) = self.hard;
        x.is_finite()
            && ((self.zero_ok && x == 0.0)
                || (x >= lo && if self.hard_open { x < hi } else { x <= hi }))
    }

    fn range_text(&self, (lo, hi): (f64, f64), open: bool) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        let to = if open { "to below" } else { "to" };
        format!("from {} {to} {}{unit}", human(lo), human(hi))
    }
}

impl Key {
    /// A value as the file gives it (file units) against its hard bounds:
    /// the value in SI, or the error naming the key (with the 1-based
    /// index of `index`, a 0-based item of a list) and the range.
    ///
    /// # Errors
    ///
    /// [`EngineError::InvalidItem`] outside the bounds or not finite.
    pub fn check(self, index: Option<usize>, value: f64) -> Result<f64, EngineError> {
        let b = self.bound();
        if b.inside_hard(value) {
            return Ok(value * b.si);
        }
        let mut expected = b.range_text(b.hard, b.hard_open);
        if b.zero_ok && b.hard.0 > 0.0 {
            expected = format!("0, or {expected}");
        }
        if self == Key::DampingRatio {
            expected.push_str(" (0.02 is typical of a crankshaft)");
        } else if value > 0.0 {
            expected.push_str(": beyond, the computation overflows or loses all precision");
        }
        let hints = unit_hints(self, value, b.plausible);
        if !hints.is_empty() && value.is_finite() {
            expected.push_str(&format!("; {hints}"));
        }
        Err(EngineError::InvalidItem {
            key: self.item(index),
            value: human(value),
            expected,
        })
    }
}

/// The units `value` (in `key`'s unit) may have been written in, those
/// that bring it inside `window` (file units) and its hard bounds, the
/// likeliest first (nearest the window's middle), at most two:
/// `kg·cm² (0.5 kg m²)?`. Empty when none does.
fn unit_hints(key: Key, value: f64, window: (f64, f64)) -> String {
    let b = key.bound();
    if !(value.is_finite() && value > 0.0) {
        return String::new();
    }
    let middle = if window.0 > 0.0 {
        (window.0 * window.1).sqrt()
    } else {
        window.1 * 1e-2
    };
    let mut fits: Vec<(f64, String)> = b
        .quantity
        .mistakes()
        .iter()
        .filter_map(|&(name, factor)| {
            let x = value * factor;
            let inside = x >= window.0 && x <= window.1 && b.inside_hard(x);
            inside.then(|| {
                let shown = if b.unit.is_empty() {
                    human(x)
                } else {
                    format!("{} {}", human(x), b.unit)
                };
                ((x / middle).ln().abs(), format!("{name} ({shown})"))
            })
        })
        .collect();
    fits.sort_by(|a, b| a.0.total_cmp(&b.0));
    let names: Vec<String> = fits.into_iter().take(2).map(|(_, s)| s).collect();
    if names.is_empty() {
        String::new()
    } else {
        format!("{}?", names.join(" or "))
    }
}

/// The window of `key` for this engine, as ratios to a reference the
/// engine's own data give, with what the reference is; `None` where no
/// engine datum sets a scale (the damping keys).
///
/// - Inertias against the throw inertia estimated from the masses
///   ([`Engine::throw_inertia`]: rotating masses and the reciprocating
///   mean, without webs and counterweights, which add 0.5 to 3 times as
///   much): a throw 0.3 to 30 times it; a front mass or damper ring (a
///   small pulley to a heavy damper, the bundled engines 0.4 to 5 times)
///   3e-3 to 30 times; a flywheel (a racing flywheel a few throws, a
///   generator set's thousands) 0.3 to 1e4 times; a load 1e-3 to 1e5.
/// - Stiffnesses against a plain steel shaft of 0.7 bore over two throw
///   pitches (Carter's equivalent length of a throw is 1.5 to 3.5
///   pitches, journals 0.55 to 0.85 bore: a factor of 10 either way): a
///   journal or flywheel spring 0.03 to 30 times, a front spring (a long
///   nose) 0.01 to 30, a coupling (rubber) 1e-6 to 30, a damper's spring
///   at most 30.
/// - Journal and shaft diameters 0.2 to 2 bores, journal lengths 0.05 to
///   20 bores.
fn engine_window(key: Key, engine: &Engine, throw_j: f64) -> Option<(f64, f64, f64, String)> {
    let bore = engine.cylinder().bore();
    let k_ref = shaft_stiffness(0.7 * bore, 2.0 * engine.cylinder_spacing());
    let j = |lo: f64, hi: f64| {
        (throw_j.is_finite() && throw_j > 0.0).then(|| {
            (
                lo,
                hi,
                throw_j,
                format!(
                    "this engine's throw inertia from its masses, {} kg m² without webs",
                    human(throw_j)
                ),
            )
        })
    };
    let k = |lo: f64, hi: f64| {
        Some((
            lo,
            hi,
            k_ref,
            format!(
                "a plain steel shaft of 0.7 bore over two throw pitches, {} N m/rad",
                human(k_ref)
            ),
        ))
    };
    let d = |lo: f64, hi: f64| {
        Some((
            lo,
            hi,
            bore * 1e3,
            format!("the bore, {} mm", human(bore * 1e3)),
        ))
    };
    match key {
        Key::ThrowInertia => j(0.3, 30.0),
        Key::FrontInertia | Key::DamperInertia => j(3e-3, 30.0),
        Key::FlywheelInertia => j(0.3, 1e4),
        Key::LoadInertia => j(1e-3, 1e5),
        Key::JournalStiffness | Key::FlywheelStiffness => k(0.03, 30.0),
        Key::FrontStiffness => k(0.01, 30.0),
        Key::LoadStiffness => k(1e-6, 30.0),
        Key::DamperStiffness => k(0.0, 30.0),
        Key::JournalDiameter | Key::ShaftDiameter => d(0.2, 2.0),
        Key::JournalLength => d(0.05, 20.0),
        Key::DampingRatio | Key::DamperDamping => None,
    }
}

/// One value's note, if it is implausible: first against every real
/// engine ([`Bound::plausible`]), then against `engine`'s own scale.
fn value_note(
    key: Key,
    index: Option<usize>,
    si: f64,
    engine: &Engine,
    throw_j: f64,
) -> Option<String> {
    let b = key.bound();
    let x = si / b.si;
    if b.zero_ok && x == 0.0 {
        return None;
    }
    let item = key.item(index);
    let unit = if b.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", b.unit)
    };
    let (lo, hi) = b.plausible;
    let (window, why) = if x < lo || x > hi {
        (
            b.plausible,
            format!(
                "outside {}, the range of real engines",
                b.range_text(b.plausible, false).trim_start_matches("from ")
            ),
        )
    } else {
        let (rlo, rhi, reference, what) = engine_window(key, engine, throw_j)?;
        let ratio = x / reference;
        if ratio >= rlo && ratio <= rhi {
            return None;
        }
        let window = (rlo * reference, rhi * reference);
        (
            window,
            format!(
                "{} times {what}: for this engine {}",
                human(ratio),
                if rlo > 0.0 {
                    format!("{} to {} times it", human(rlo), human(rhi))
                } else {
                    format!("at most {} times it", human(rhi))
                }
            ),
        )
    };
    let mut mistake = unit_hints(key, x, window);
    if mistake.is_empty() {
        mistake = match (b.quantity, x > window.1) {
            (Quantity::Length, true) => "micrometres, or a slipped decimal point?".into(),
            (Quantity::Length, false) => "metres or centimetres?".into(),
            (Quantity::Ratio, _) => "a percentage or a loss factor (2ζ)?".into(),
            _ => format!("a slipped decimal point, or a unit other than{unit}?"),
        };
    }
    Some(format!(
        "{item} = {}: {mistake} ({why}; computed as given)",
        human(x)
    ))
}

impl TorsionSpec {
    /// Notes on `[torsion]` values that are physically implausible but
    /// still computed (INTERFACE.md, "Limits"), each naming the key (with
    /// the 1-based index of a list's item) and the likely mistake, from
    /// [`BOUNDS`]' plausible ranges and the engine's own scale (its throw
    /// inertia from the masses, its bore and throw pitch); and on parts
    /// the chain cannot use: a front spring or a damper with no front mass.
    /// Empty for plausible data.
    pub fn plausibility_notes(&self, engine: &Engine, rod_model: RodModel) -> Vec<String> {
        let t = engine.throws();
        let est: Vec<f64> = (0..t).map(|k| engine.throw_inertia(k, rod_model)).collect();
        let largest = est.iter().copied().fold(0.0, f64::max);
        let mut notes = Vec::new();
        let mut note = |key: Key, index: Option<usize>, v: f64, throw_j: f64| {
            if let Some(n) = value_note(key, index, v, engine, throw_j) {
                notes.push(n);
            }
        };
        let lists = [
            (Key::ThrowInertia, &self.throw_inertia),
            (Key::JournalStiffness, &self.journal_stiffness),
            (Key::JournalDiameter, &self.journal_diameter),
            (Key::JournalLength, &self.journal_length),
            (Key::ShaftDiameter, &self.shaft_diameter),
        ];
        for (key, list) in lists {
            match list {
                None => {}
                Some(PerItem::One(v)) => note(key, None, *v, largest),
                Some(PerItem::Each(vs)) => {
                    for (i, v) in vs.iter().enumerate() {
                        let j = if key == Key::ThrowInertia {
                            est.get(i).copied().unwrap_or(largest)
                        } else {
                            largest
                        };
                        note(key, Some(i), *v, j);
                    }
                }
            }
        }
        let singles = [
            (Key::FrontInertia, Some(self.front_inertia)),
            (Key::FrontStiffness, self.front_stiffness),
            (Key::FlywheelInertia, self.flywheel_inertia),
            (Key::FlywheelStiffness, self.flywheel_stiffness),
            (Key::LoadInertia, self.load_inertia),
            (Key::LoadStiffness, self.load_stiffness),
            (Key::DampingRatio, Some(self.damping_ratio)),
            (Key::DamperInertia, self.damper.map(|d| d.inertia)),
            (Key::DamperStiffness, self.damper.map(|d| d.stiffness)),
            (Key::DamperDamping, self.damper.map(|d| d.damping)),
        ];
        for (key, v) in singles {
            if let Some(v) = v {
                note(key, None, v, largest);
            }
        }
        if self.front_inertia == 0.0 {
            if let Some(k) = self.front_stiffness {
                notes.push(format!(
                    "{} = {} is given but {} is 0 (no front mass): the spring joins nothing and is left out; give the front mass's inertia, or leave the spring out",
                    Key::FrontStiffness.name(),
                    human(k),
                    Key::FrontInertia.name()
                ));
            }
            if self.damper.is_some() {
                notes.push(format!(
                    "torsion.damper is on a front mass of zero inertia ({} is 0): it is hung on throw 1 instead; give the hub's {} and {} for a damper on the pulley",
                    Key::FrontInertia.name(),
                    Key::FrontInertia.name(),
                    Key::FrontStiffness.name()
                ));
            }
        }
        notes
    }
}
