//! The `[torsion]` section of the engine file, as given (SI, checked per
//! key): the crankshaft as a chain of inertias on springs. What is left
//! out takes INTERFACE.md's defaults where the chain is built
//! (`enginedyn_pipeline::torsion`), since some come from the analysis
//! (the sized flywheel) or from the engine (the throw inertias).

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
