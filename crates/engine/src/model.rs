//! The checked engine and the quantities derived from it.

use enginedyn_kinematics::{Cylinder, KinematicsError, Mechanism};
use std::f64::consts::PI;
use std::path::PathBuf;

/// Why an engine description is rejected. Each names the engine-file key.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EngineError {
    /// The TOML itself does not parse or a value has the wrong type.
    #[error("{0}")]
    Toml(String),
    /// A key the engine file does not know.
    #[error("unknown key `{key}` in [{section}]{}{}{}", line.map(|l| format!(" (line {l})")).unwrap_or_default(), suggestion.as_ref().map(|s| format!("; did you mean `{s}`?")).unwrap_or_default(), valid_keys(section, valid))]
    UnknownKey {
        /// The key as written.
        key: String,
        /// `root` or the table's name.
        section: String,
        /// The nearest known key, if any is close.
        suggestion: Option<String>,
        /// With no close key, every key the section takes (the top of
        /// the file: its keys, then the sections).
        valid: Vec<String>,
        /// 1-based line of the key, when found.
        line: Option<usize>,
    },
    /// A required key is absent.
    #[error("missing key `{key}`: {why}")]
    Missing {
        /// The key.
        key: &'static str,
        /// When it is required.
        why: &'static str,
    },
    /// A value outside its bounds.
    #[error("`{key}` = {value}: {expected}")]
    Invalid {
        /// The key.
        key: &'static str,
        /// The value as given.
        value: String,
        /// What is expected, with the bound.
        expected: String,
    },
    /// A value outside its bounds, its key named at run time (an item of
    /// a list: `torsion.journal_stiffness_nm_rad[3]`).
    #[error("`{key}` = {value}: {expected}")]
    InvalidItem {
        /// The key, with the item's 1-based index for a list.
        key: String,
        /// The value as given.
        value: String,
        /// What is expected, with the bound.
        expected: String,
    },
    /// The crank mechanism cannot exist.
    #[error("{keys}: {source}")]
    Mechanism {
        /// The keys that define it.
        keys: &'static str,
        /// The geometric reason.
        source: KinematicsError,
    },
}

impl EngineError {
    /// The engine-file key at fault, when one is (for an unknown key, the
    /// key as written; for a mechanism that cannot exist, its keys).
    pub fn key(&self) -> Option<&str> {
        match self {
            EngineError::Toml(_) => None,
            EngineError::UnknownKey { key, .. } | EngineError::InvalidItem { key, .. } => Some(key),
            EngineError::Missing { key, .. } | EngineError::Invalid { key, .. } => Some(key),
            EngineError::Mechanism { keys, .. } => Some(keys),
        }
    }
}

/// "; [masses] takes: piston_group_kg, rod_kg, …" for an unknown key
/// with no close match, so that the user need not guess.
fn valid_keys(section: &str, valid: &[String]) -> String {
    if valid.is_empty() {
        return String::new();
    }
    let list = valid.join(", ");
    let what = if section == "root" {
        format!(
            "the top of the file takes {list}, then the sections {}",
            crate::keys::SECTIONS
                .iter()
                .map(|s| format!("[{s}]"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    } else {
        format!("[{section}] takes {list}")
    };
    format!(
        "; {what} (docs/engine-file.md gives each key's unit and default; `enginedyn template` prints a commented file)"
    )
}

/// Two-stroke or four-stroke working cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stroke {
    /// One cycle per two revolutions (720°).
    Four,
    /// One cycle per revolution (360°).
    Two,
}

impl Stroke {
    /// The cycle length (rad): 4pi or 2pi.
    pub fn cycle(self) -> f64 {
        match self {
            Stroke::Four => 4.0 * PI,
            Stroke::Two => 2.0 * PI,
        }
    }
    /// As written in the engine file.
    pub fn name(self) -> &'static str {
        match self {
            Stroke::Four => "four-stroke",
            Stroke::Two => "two-stroke",
        }
    }
}

/// Arrangement of the cylinders (numbering and banks as in PHYSICS.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Layout {
    /// One bank; cylinder i on throw i.
    Inline,
    /// Two banks `bank_angle` apart (rad); cylinders i and i + z/2 share throw i.
    Vee {
        /// Angle between the banks (rad).
        bank_angle: f64,
    },
    /// Opposed banks; cylinder i on its own throw i, even cylinders on bank 2.
    Boxer,
}

impl Layout {
    /// As written in the engine file.
    pub fn name(self) -> &'static str {
        match self {
            Layout::Inline => "inline",
            Layout::Vee { .. } => "vee",
            Layout::Boxer => "boxer",
        }
    }
}

/// How the connecting rod's mass is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RodModel {
    /// Two point masses at the bearing centres (static equivalence). Neglects
    /// the couple `-(I_G - m l_A l_B) w^2 d2beta/dphi2`: for a car rod with
    /// `I_G` at 78 % of `m l_A l_B` and `lambda = 0.26` that is 3.0 % of the
    /// inertia torque's amplitude (test `three_mass_equals_rigid`); it also
    /// counts `m_A` with the piston in the rod force.
    #[default]
    TwoMass,
    /// Three point masses (small end, big end, centre of mass) keeping the
    /// rod's mass, centre and moment of inertia: dynamically exact, neglects
    /// nothing; the centre mass may be negative (still exact).
    ThreeMass,
    /// The rod as a planar rigid body (Newton–Euler); exact, the reference.
    /// Agrees with `ThreeMass` to rounding.
    Rigid,
}

impl RodModel {
    /// Every model.
    pub const ALL: [RodModel; 3] = [RodModel::TwoMass, RodModel::ThreeMass, RodModel::Rigid];
    /// As written on the command line and in the engine file.
    pub fn name(self) -> &'static str {
        match self {
            RodModel::TwoMass => "two-mass",
            RodModel::ThreeMass => "three-mass",
            RodModel::Rigid => "rigid",
        }
    }
    /// Parses [`RodModel::name`].
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// Masses of one cylinder's crank train (kg, m, kg m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Masses {
    /// Piston, rings and pin (plus the yoke for a Scotch yoke).
    pub piston_group: f64,
    /// Connecting rod (0 for a Scotch yoke).
    pub rod: f64,
    /// Small-end centre to the rod's centre of mass, `l_A` (m).
    pub rod_cg_from_small_end: f64,
    /// Rod's moment of inertia about its centre of mass, if given.
    pub rod_inertia: Option<f64>,
    /// Crank unbalance per throw, reduced to the crank radius (plus the
    /// slider block for a Scotch yoke).
    pub crank_unbalanced: f64,
}

/// The operating point as far as the engine file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Operating {
    /// Speed (rpm), if the file gives one.
    pub rpm: Option<f64>,
    /// Crankcase pressure (Pa, absolute).
    pub crankcase_pressure: f64,
    /// Mechanical efficiency (0, 1].
    pub mechanical_efficiency: f64,
}

/// Flywheel as a disc or a rim.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlywheelShape {
    /// A solid disc.
    Disc,
    /// An annulus (rim) with inner diameter `rim_inner_ratio` × outer.
    Rim,
}

/// Flywheel targets and material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlywheelSpec {
    /// Allowed speed fluctuation `delta`.
    pub speed_fluctuation: f64,
    /// Inertia of the other rotating parts (kg m²).
    pub other_rotating_inertia: f64,
    /// Count the crank train's reduced masses as engine inertia.
    pub include_crank_train: bool,
    /// Allowed rim speed (m/s).
    pub max_rim_speed: f64,
    /// Fixed outer diameter (m), instead of the rim speed.
    pub outer_diameter: Option<f64>,
    /// Material density (kg/m³).
    pub density: f64,
    /// Disc or rim.
    pub shape: FlywheelShape,
    /// Rim inner / outer diameter.
    pub rim_inner_ratio: f64,
    /// The idle criterion: the idle speed (rpm) and the δ allowed there
    /// (`flywheel.idle_rpm`, `flywheel.idle_speed_fluctuation`); a map
    /// sizes the flywheel at the worst of its points and idle.
    pub idle: Option<(f64, f64)>,
}

impl Default for FlywheelSpec {
    fn default() -> Self {
        Self {
            speed_fluctuation: 0.01,
            other_rotating_inertia: 0.0,
            include_crank_train: false,
            max_rim_speed: 60.0,
            outer_diameter: None,
            density: 7850.0,
            shape: FlywheelShape::Rim,
            rim_inner_ratio: 0.8,
            idle: None,
        }
    }
}

/// A checked engine. Build it with [`crate::file::parse`] or [`EngineBuilder`].
#[derive(Debug, Clone, PartialEq)]
pub struct Engine {
    pub(crate) name: String,
    pub(crate) stroke: Stroke,
    pub(crate) layout: Layout,
    pub(crate) z: usize,
    pub(crate) firing_order: Vec<usize>,
    pub(crate) firing_order_given: bool,
    pub(crate) firing_angles: Vec<f64>,
    pub(crate) crank_angles: Vec<f64>,
    pub(crate) pin_angles: Vec<f64>,
    pub(crate) split_pins: bool,
    pub(crate) cylinder: Cylinder,
    pub(crate) cylinder_spacing: f64,
    pub(crate) rod_model: RodModel,
    pub(crate) diagram: Option<PathBuf>,
    pub(crate) masses: Masses,
    pub(crate) operating: Operating,
    pub(crate) flywheel: FlywheelSpec,
    pub(crate) notes: Vec<String>,
    pub(crate) defaults_taken: Vec<TakenDefault>,
    pub(crate) combustion: Option<crate::combustion::CombustionSpec>,
    pub(crate) friction: Option<enginedyn_combustion::friction::ChenFlynn>,
}

/// A default that shapes the results, taken because the engine file left
/// the key out (INTERFACE.md: a default taken is said in a `note:`).
/// Only the engine file's reader knows what was given: an engine built
/// from an [`EngineBuilder`] has none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TakenDefault {
    /// `operating.mechanical_efficiency` = 1: effective = indicated.
    MechanicalEfficiency,
    /// `flywheel.speed_fluctuation` = 0.01, the δ the flywheel is sized for.
    SpeedFluctuation,
    /// `flywheel.max_rim_speed_m_s` = 60 sets the flywheel's diameter
    /// (no `outer_diameter_mm` either).
    RimSpeed,
    /// `masses.crank_unbalanced_kg` = 0: no unbalanced crank mass.
    CrankUnbalance,
}

impl TakenDefault {
    /// The key, with its section.
    pub fn key(self) -> &'static str {
        match self {
            TakenDefault::MechanicalEfficiency => "operating.mechanical_efficiency",
            TakenDefault::SpeedFluctuation => "flywheel.speed_fluctuation",
            TakenDefault::RimSpeed => "flywheel.max_rim_speed_m_s",
            TakenDefault::CrankUnbalance => "masses.crank_unbalanced_kg",
        }
    }

    /// "key = value (what it does)", the value from [`FlywheelSpec::default`]
    /// and the reader's defaults.
    pub fn describe(self) -> String {
        let d = FlywheelSpec::default();
        let value = |x: f64| enginedyn_numerics::format::human(x);
        match self {
            TakenDefault::MechanicalEfficiency => format!(
                "{} = 1 (torque and power are indicated: the effective figures equal them)",
                self.key()
            ),
            TakenDefault::SpeedFluctuation => format!(
                "{} = {} (the δ the flywheel is sized for)",
                self.key(),
                value(d.speed_fluctuation)
            ),
            TakenDefault::RimSpeed => format!(
                "{} = {} m/s (sets the flywheel's diameter; or give flywheel.outer_diameter_mm)",
                self.key(),
                value(d.max_rim_speed)
            ),
            TakenDefault::CrankUnbalance => format!(
                "{} = 0 (no unbalanced crank mass in the main-bearing loads or the crank train's inertia)",
                self.key()
            ),
        }
    }
}

/// Everything an engine is built from, SI, unchecked. Fields left `None`
/// take the defaults of INTERFACE.md.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineBuilder {
    /// Name.
    pub name: String,
    /// Working cycle.
    pub stroke: Stroke,
    /// Layout.
    pub layout: Layout,
    /// Cylinder count.
    pub cylinders: usize,
    /// Firing order (1-based cylinder numbers).
    pub firing_order: Option<Vec<usize>>,
    /// Firing angles per cylinder (rad), if given.
    pub firing_angles: Option<Vec<f64>>,
    /// Throw lags (rad), if given: one per throw, or with `split_pins` one
    /// per crank pin, that is per cylinder.
    pub crank_angles: Option<Vec<f64>>,
    /// A vee whose two rods on a throw sit on pins of their own, each at
    /// its own lag (`crank_angles` then has one angle per cylinder). The
    /// engine file sets it when `crank_angles_deg` has `z` entries.
    pub split_pins: bool,
    /// The mechanism (checked by the kinematics crate).
    pub mechanism: Mechanism,
    /// Bore (m).
    pub bore: f64,
    /// Compression ratio.
    pub compression_ratio: f64,
    /// Throw pitch (m); `None` assumes 1.2 × bore.
    pub cylinder_spacing: Option<f64>,
    /// Rod model.
    pub rod_model: RodModel,
    /// Diagram path.
    pub diagram: Option<PathBuf>,
    /// Masses (their `rod_cg_from_small_end` is set from the field below).
    pub masses: Masses,
    /// The rod's centre of mass from the small end (m); `None`: not given,
    /// 27.5 % of the rod's mass at the small end (PHYSICS.md).
    pub rod_cg_from_small_end: Option<f64>,
    /// Operating point.
    pub operating: Operating,
    /// Flywheel.
    pub flywheel: FlywheelSpec,
}

pub use enginedyn_kinematics::{MAX_RPM, MIN_RPM};

fn invalid(key: &'static str, value: impl ToString, expected: impl Into<String>) -> EngineError {
    EngineError::Invalid {
        key,
        value: value.to_string(),
        expected: expected.into(),
    }
}

fn deg_list(v: &[f64]) -> String {
    let s: Vec<String> = v
        .iter()
        .map(|a| format!("{}", (a.to_degrees() * 1e6).round() / 1e6))
        .collect();
    format!("[{}]", s.join(", "))
}

/// `a mod m` in `[0, m)`, with values within 1e-9 rad of `m` folded to 0.
fn wrap(a: f64, m: f64) -> f64 {
    let r = a.rem_euclid(m);
    if (m - r).abs() < 1e-9 { 0.0 } else { r }
}

fn same_angle(a: f64, b: f64, m: f64) -> bool {
    let d = wrap(a - b, m);
    d < 1e-6 || m - d < 1e-6
}

impl EngineBuilder {
    /// Checks everything and derives firing angles and crank throws.
    pub fn build(self) -> Result<Engine, EngineError> {
        self.build_checked(false)
    }

    /// [`EngineBuilder::build`] for a search of every crank
    /// (`enginedyn firing-orders --all-cranks`): `firing_order` may be left
    /// out (with neither `firing_angles` nor `crank_angles`). The engine then
    /// fires evenly in numbering order, a vee on split pins so that the
    /// firing fits a crank, and [`Engine::firing_order_given`] is false: its
    /// firing and crank stand for nothing the user said.
    pub fn build_for_crank_search(self) -> Result<Engine, EngineError> {
        self.build_checked(true)
    }

    /// Every size against its hard bound (INTERFACE.md, "Limits"): values
    /// outside are refused naming the key and the range, never computed
    /// into an overflow or a `null`. The bounds lie far outside real
    /// engines; implausible values inside them are computed, with a note
    /// ([`Engine::plausibility_notes`]).
    fn check_sizes(&self) -> Result<(), EngineError> {
        let (r, l, e) = match self.mechanism {
            Mechanism::CrankSlider(cs) => (cs.r(), Some(cs.l()), cs.e()),
            Mechanism::ScotchYoke(y) => (y.r(), None, 0.0),
        };
        let m = &self.masses;
        let f = &self.flywheel;
        // key, value (SI), lowest, highest, display scale, unit.
        let mut sizes: Vec<(&'static str, f64, f64, f64, f64, &str)> = vec![
            ("bore_mm", self.bore, 1e-6, 100.0, 1e3, "mm"),
            ("stroke_mm", 2.0 * r, 1e-6, 100.0, 1e3, "mm"),
            ("pin_offset_mm", e.abs(), 0.0, 100.0, 1e3, "mm"),
            (
                "compression_ratio",
                self.compression_ratio,
                1.0,
                1000.0,
                1.0,
                "",
            ),
            (
                "masses.piston_group_kg",
                m.piston_group,
                0.0,
                1e6,
                1.0,
                "kg",
            ),
            ("masses.rod_kg", m.rod, 0.0, 1e6, 1.0, "kg"),
            (
                "masses.crank_unbalanced_kg",
                m.crank_unbalanced,
                0.0,
                1e6,
                1.0,
                "kg",
            ),
            (
                "masses.rod_inertia_kg_m2",
                m.rod_inertia.unwrap_or(0.0),
                0.0,
                1e6,
                1.0,
                "kg m²",
            ),
            (
                "operating.crankcase_pressure_bar",
                self.operating.crankcase_pressure,
                0.0,
                1e9,
                1e-5,
                "bar",
            ),
            (
                "flywheel.other_rotating_inertia_kg_m2",
                f.other_rotating_inertia,
                0.0,
                1e9,
                1.0,
                "kg m²",
            ),
            (
                "flywheel.max_rim_speed_m_s",
                f.max_rim_speed,
                0.0,
                1e4,
                1.0,
                "m/s",
            ),
            (
                "flywheel.outer_diameter_mm",
                f.outer_diameter.unwrap_or(1.0),
                0.0,
                100.0,
                1e3,
                "mm",
            ),
            ("flywheel.density_kg_m3", f.density, 0.0, 1e6, 1.0, "kg/m³"),
            (
                "flywheel.speed_fluctuation",
                f.speed_fluctuation,
                1e-9,
                1.0,
                1.0,
                "",
            ),
        ];
        if let Some(l) = l {
            sizes.push((
                "lambda (R/L, from lambda or rod_length_mm)",
                r / l,
                1e-3,
                1.0,
                1.0,
                "",
            ));
            sizes.push(("rod_length_mm", l, 1e-6, 1e3, 1e3, "mm"));
            // The rod's centre of mass, when given (a crank-slider's only).
            if let Some(la) = self.rod_cg_from_small_end {
                sizes.push(("masses.rod_cg_from_small_end_mm", la, 1e-6, 1e3, 1e3, "mm"));
            }
        }
        if let Some(rpm) = self.operating.rpm {
            sizes.push(("operating.rpm", rpm, MIN_RPM, MAX_RPM, 1.0, "rpm"));
        }
        if let Some(s) = self.cylinder_spacing {
            sizes.push(("cylinder_spacing_mm", s, 1e-6, 100.0, 1e3, "mm"));
        }
        for (key, v, lo, hi, scale, unit) in sizes {
            if !(v.is_finite() && v >= lo && v <= hi) {
                let h = |x: f64| enginedyn_numerics::format::human(x * scale);
                return Err(invalid(
                    key,
                    h(v),
                    format!(
                        "from {} to {}{}{unit}",
                        h(lo),
                        h(hi),
                        if unit.is_empty() { "" } else { " " }
                    ),
                ));
            }
        }
        Ok(())
    }

    fn build_checked(self, search: bool) -> Result<Engine, EngineError> {
        self.check_sizes()?;
        let mut notes = Vec::new();
        let z = self.cylinders;
        if !(1..=24).contains(&z) {
            return Err(invalid("cylinders", z, "1 to 24"));
        }
        check_layout(self.layout, z)?;
        let cylinder =
            Cylinder::new(self.mechanism, self.bore, self.compression_ratio).map_err(|source| {
                EngineError::Mechanism {
                    keys: "bore_mm, compression_ratio",
                    source,
                }
            })?;
        let masses = self.checked_masses()?;
        let op = self.operating;
        check_operating(&op)?;
        check_flywheel(&self.flywheel)?;
        let cylinder_spacing = match self.cylinder_spacing {
            Some(s) if s.is_finite() && s > 0.0 => s,
            Some(s) => {
                return Err(invalid(
                    "cylinder_spacing_mm",
                    s * 1e3,
                    "a positive distance (mm)",
                ));
            }
            None => {
                // The spacing only enters the free moments, which one throw
                // does not have: nothing to note then.
                if throws_of(self.layout, z).1 > 1 {
                    notes.push(format!(
                        "cylinder_spacing_mm not given: assumed 1.2 × bore = {:.1} mm",
                        1.2 * self.bore * 1e3
                    ));
                }
                1.2 * self.bore
            }
        };
        let layout = self.layout;
        if self.split_pins && !matches!(layout, Layout::Vee { .. }) {
            return Err(invalid(
                "crank_angles_deg",
                self.crank_angles.as_deref().map_or("[]".into(), deg_list),
                format!(
                    "one angle per throw ({z}): split crank pins are for a vee, whose throws carry two rods"
                ),
            ));
        }
        let has_angles = self.firing_angles.is_some() || self.crank_angles.is_some();
        let (firing_order, firing_order_given, split_pins) = firing_order_or_default(
            self.firing_order,
            z,
            layout,
            search,
            self.split_pins,
            has_angles,
        )?;
        check_firing_order(&firing_order, z)?;
        let pins = Pins::new(layout, z, split_pins);
        let (firing_angles, crank_angles) = firing(
            self.stroke,
            layout,
            &pins,
            &firing_order,
            self.firing_angles,
            self.crank_angles,
        )?;
        let pin_angles = pins.pin.iter().map(|&p| crank_angles[p]).collect();
        Ok(Engine {
            name: self.name,
            stroke: self.stroke,
            layout,
            z,
            firing_order,
            firing_order_given,
            firing_angles,
            crank_angles,
            pin_angles,
            split_pins,
            cylinder,
            cylinder_spacing,
            rod_model: self.rod_model,
            diagram: self.diagram,
            masses,
            operating: op,
            flywheel: self.flywheel,
            notes,
            defaults_taken: Vec::new(),
            combustion: None,
            friction: None,
        })
    }

    /// The masses checked, with the rod's centre of gravity (0.725 of the
    /// rod from its small end when not given) for a crank-slider.
    fn checked_masses(&self) -> Result<Masses, EngineError> {
        let is_yoke = matches!(self.mechanism, Mechanism::ScotchYoke(_));
        let mut masses = self.masses;
        if !(masses.piston_group.is_finite() && masses.piston_group > 0.0) {
            return Err(invalid(
                "masses.piston_group_kg",
                masses.piston_group,
                "a positive mass (kg)",
            ));
        }
        if !(masses.crank_unbalanced.is_finite() && masses.crank_unbalanced >= 0.0) {
            return Err(invalid(
                "masses.crank_unbalanced_kg",
                masses.crank_unbalanced,
                "a mass of 0 or more (kg)",
            ));
        }
        let rod_len = match self.mechanism {
            Mechanism::CrankSlider(cs) => cs.l(),
            Mechanism::ScotchYoke(_) => 0.0,
        };
        if is_yoke {
            return Ok(masses);
        }
        if !(masses.rod.is_finite() && masses.rod > 0.0) {
            return Err(invalid("masses.rod_kg", masses.rod, "a positive mass (kg)"));
        }
        masses.rod_cg_from_small_end = self.rod_cg_from_small_end.unwrap_or(0.725 * rod_len);
        let la = masses.rod_cg_from_small_end;
        if !(la > 0.0 && la < rod_len) {
            return Err(invalid(
                "masses.rod_cg_from_small_end_mm",
                la * 1e3,
                format!(
                    "inside the rod: between 0 and the rod length {:.3} mm",
                    rod_len * 1e3
                ),
            ));
        }
        if let Some(i) = masses.rod_inertia
            && !(i.is_finite() && i > 0.0)
        {
            return Err(invalid(
                "masses.rod_inertia_kg_m2",
                i,
                "a positive moment of inertia (kg m²)",
            ));
        }
        if self.rod_model != RodModel::TwoMass && masses.rod_inertia.is_none() {
            return Err(EngineError::Missing {
                key: "masses.rod_inertia_kg_m2",
                why: "required for rod_model = \"three-mass\" and \"rigid\"",
            });
        }
        Ok(masses)
    }
}

/// `z` cylinders fit the `layout`: a vee or a boxer has an even number, a
/// vee's bank angle lies between 0 and 180°.
fn check_layout(layout: Layout, z: usize) -> Result<(), EngineError> {
    match layout {
        Layout::Vee { bank_angle } => {
            if !z.is_multiple_of(2) {
                return Err(invalid("cylinders", z, "an even number for a vee"));
            }
            if !(bank_angle > 0.0 && bank_angle < PI) {
                return Err(invalid(
                    "bank_angle_deg",
                    bank_angle.to_degrees(),
                    "between 0 and 180°",
                ));
            }
        }
        Layout::Boxer if !z.is_multiple_of(2) => {
            return Err(invalid("cylinders", z, "an even number for a boxer"));
        }
        _ => {}
    }
    Ok(())
}

/// The operating point's speed, crankcase pressure and mechanical
/// efficiency within their bounds.
fn check_operating(op: &Operating) -> Result<(), EngineError> {
    if let Some(rpm) = op.rpm
        && !(rpm.is_finite() && rpm > 0.0)
    {
        return Err(invalid("operating.rpm", rpm, "a positive speed (rpm)"));
    }
    if !(op.crankcase_pressure.is_finite() && op.crankcase_pressure >= 0.0) {
        return Err(invalid(
            "operating.crankcase_pressure_bar",
            op.crankcase_pressure / 1e5,
            "an absolute pressure of 0 or more (bar)",
        ));
    }
    if !(op.mechanical_efficiency > 0.0 && op.mechanical_efficiency <= 1.0) {
        return Err(invalid(
            "operating.mechanical_efficiency",
            op.mechanical_efficiency,
            "in (0, 1]",
        ));
    }
    Ok(())
}

/// The firing order (given, or for one cylinder `[1]`), whether it was
/// given, and whether the pins are split. With `search` and no angles
/// given (`has_angles`), any crank will be searched: the cylinders fire
/// evenly in numbering order, on split pins in a vee so that any order
/// fits. Otherwise a firing order is required for more than one cylinder.
fn firing_order_or_default(
    given: Option<Vec<usize>>,
    z: usize,
    layout: Layout,
    search: bool,
    split_pins: bool,
    has_angles: bool,
) -> Result<(Vec<usize>, bool, bool), EngineError> {
    match given {
        Some(f) => Ok((f, true, split_pins)),
        None if z == 1 => Ok((vec![1], true, split_pins)),
        None if search && !has_angles => Ok((
            (1..=z).collect(),
            false,
            matches!(layout, Layout::Vee { .. }),
        )),
        None if search => Err(EngineError::Missing {
            key: "firing_order",
            why: "required with `firing_angles_deg` or `crank_angles_deg`; leave those out too to search every crank",
        }),
        None => Err(EngineError::Missing {
            key: "firing_order",
            why: "required for more than one cylinder; `enginedyn firing-orders --all-cranks --engine FILE` runs without it and ranks the cranks and firing orders this layout allows",
        }),
    }
}

/// Each of the `z` cylinders exactly once in `firing_order`.
fn check_firing_order(firing_order: &[usize], z: usize) -> Result<(), EngineError> {
    let mut seen = vec![false; z];
    if firing_order.len() != z {
        return Err(invalid(
            "firing_order",
            format!("{firing_order:?}"),
            format!("each of the {z} cylinders once"),
        ));
    }
    for &c in firing_order {
        if c == 0 || c > z || seen[c - 1] {
            return Err(invalid(
                "firing_order",
                format!("{firing_order:?}"),
                format!("each cylinder 1..{z} exactly once"),
            ));
        }
        seen[c - 1] = true;
    }
    Ok(())
}

fn check_flywheel(f: &FlywheelSpec) -> Result<(), EngineError> {
    if !(f.speed_fluctuation > 0.0 && f.speed_fluctuation < 1.0) {
        return Err(invalid(
            "flywheel.speed_fluctuation",
            f.speed_fluctuation,
            "between 0 and 1 (e.g. 0.01)",
        ));
    }
    if !(f.other_rotating_inertia.is_finite() && f.other_rotating_inertia >= 0.0) {
        return Err(invalid(
            "flywheel.other_rotating_inertia_kg_m2",
            f.other_rotating_inertia,
            "0 or more (kg m²)",
        ));
    }
    if !(f.max_rim_speed.is_finite() && f.max_rim_speed > 0.0) {
        return Err(invalid(
            "flywheel.max_rim_speed_m_s",
            f.max_rim_speed,
            "a positive speed (m/s)",
        ));
    }
    if let Some(d) = f.outer_diameter
        && !(d.is_finite() && d > 0.0)
    {
        return Err(invalid(
            "flywheel.outer_diameter_mm",
            d * 1e3,
            "a positive diameter (mm)",
        ));
    }
    if !(f.density.is_finite() && f.density > 0.0) {
        return Err(invalid(
            "flywheel.density_kg_m3",
            f.density,
            "a positive density (kg/m³)",
        ));
    }
    if !(f.rim_inner_ratio >= 0.0 && f.rim_inner_ratio < 1.0) {
        return Err(invalid(
            "flywheel.rim_inner_ratio",
            f.rim_inner_ratio,
            "in [0, 1)",
        ));
    }
    if let Some((rpm, delta)) = f.idle {
        if !(rpm.is_finite() && (100.0..=5000.0).contains(&rpm)) {
            return Err(invalid("flywheel.idle_rpm", rpm, "100 to 5,000 rpm"));
        }
        if !(delta > 0.0 && delta < 1.0) {
            return Err(invalid(
                "flywheel.idle_speed_fluctuation",
                delta,
                "above 0, below 1",
            ));
        }
    }
    Ok(())
}

/// Throw of each cylinder (0-based) and the number of throws.
fn throws_of(layout: Layout, z: usize) -> (Vec<usize>, usize) {
    match layout {
        Layout::Vee { .. } => ((0..z).map(|i| i % (z / 2)).collect(), z / 2),
        Layout::Inline | Layout::Boxer => ((0..z).collect(), z),
    }
}

/// Bank angle `gamma_i` of each cylinder (rad).
fn gammas(layout: Layout, z: usize) -> Vec<f64> {
    (0..z)
        .map(|i| match layout {
            Layout::Inline => 0.0,
            Layout::Vee { bank_angle } => {
                if i < z / 2 {
                    0.0
                } else {
                    bank_angle
                }
            }
            Layout::Boxer => {
                if i % 2 == 0 {
                    0.0
                } else {
                    PI
                }
            }
        })
        .collect()
}

/// Crank pins: which pin each cylinder's rod runs on. With shared pins a
/// pin is a throw; with split pins (a vee) every cylinder has its own.
struct Pins {
    /// Pin (0-based) of each cylinder.
    pin: Vec<usize>,
    /// Number of pins.
    count: usize,
    /// Throw (0-based) of each cylinder.
    throw: Vec<usize>,
    /// Number of throws.
    throws: usize,
    split: bool,
}

impl Pins {
    fn new(layout: Layout, z: usize, split: bool) -> Pins {
        let (throw, throws) = throws_of(layout, z);
        let (pin, count) = if split {
            ((0..z).collect(), z)
        } else {
            (throw.clone(), throws)
        };
        Pins {
            pin,
            count,
            throw,
            throws,
            split,
        }
    }
}

/// Firing angles per cylinder and throw lags per pin (rad: per throw, or
/// per cylinder with split pins), from what the file gives: PHYSICS.md,
/// `theta_i = alpha_i + gamma_i + 360° j_i` with `alpha_i` the lag of
/// cylinder i's pin.
fn firing(
    stroke: Stroke,
    layout: Layout,
    pins: &Pins,
    order: &[usize],
    given_firing: Option<Vec<f64>>,
    given_crank: Option<Vec<f64>>,
) -> Result<(Vec<f64>, Vec<f64>), EngineError> {
    let cycle = stroke.cycle();
    let rev = 2.0 * PI;
    let z = order.len();
    let pin = &pins.pin;
    let gamma = gammas(layout, z);
    if let Some(f) = &given_firing
        && (f.len() != z || f.iter().any(|a| !a.is_finite()))
    {
        return Err(invalid(
            "firing_angles_deg",
            deg_list(f),
            format!("one finite angle per cylinder ({z})"),
        ));
    }
    if let Some(c) = &given_crank
        && (c.len() != pins.count || c.iter().any(|a| !a.is_finite()))
    {
        let expected = match layout {
            Layout::Vee { .. } => format!(
                "one finite angle per throw ({}), or per cylinder ({z}) for split crank pins",
                pins.throws
            ),
            _ => format!("one finite angle per throw ({})", pins.throws),
        };
        return Err(invalid("crank_angles_deg", deg_list(c), expected));
    }
    let firing_given = given_firing.is_some();
    let crank_of = |firing: &[f64]| -> Result<Vec<f64>, EngineError> {
        let mut crank: Vec<Option<f64>> = vec![None; pins.count];
        for i in 0..z {
            let a = wrap(firing[i] - gamma[i], rev);
            match crank[pin[i]] {
                None => crank[pin[i]] = Some(a),
                Some(b) if same_angle(a, b, rev) => {}
                Some(b) => {
                    return Err(shared_pin_conflict(
                        layout,
                        &gamma,
                        firing,
                        firing_given,
                        order,
                        (throw_partner(i, z), i, pins.throw[i]),
                        (b, a),
                    ));
                }
            }
        }
        let base = crank[0].unwrap_or(0.0);
        Ok(crank
            .into_iter()
            .map(|c| wrap(c.unwrap_or(0.0) - base, rev))
            .collect())
    };
    let firing_angles = match (given_firing, &given_crank) {
        (Some(f), _) => {
            let shift = f[0];
            let f: Vec<f64> = f.iter().map(|a| wrap(a - shift, cycle)).collect();
            check_order(&f, order, cycle)?;
            f
        }
        (None, None) => {
            let mut f = vec![0.0; z];
            let start = order.iter().position(|&c| c == 1).unwrap_or(0);
            for (j, &c) in order.iter().enumerate() {
                let k = (j + z - start) % z;
                f[c - 1] = k as f64 * cycle / z as f64;
            }
            f
        }
        (None, Some(crank)) => from_crank(stroke, &gamma, pin, crank, order)?,
    };
    let crank = crank_of(&firing_angles)?;
    if let Some(given) = given_crank {
        let base = given[0];
        for (k, (&c, &g)) in crank.iter().zip(&given).enumerate() {
            if !same_angle(c, g - base, rev) {
                let what = if pins.split {
                    "pin of cylinder"
                } else {
                    "throw"
                };
                return Err(invalid(
                    "crank_angles_deg",
                    deg_list(&given),
                    format!(
                        "throws that agree with the firing angles {}: {what} {} would lag {}°",
                        deg_list(&firing_angles),
                        k + 1,
                        human(c.to_degrees())
                    ),
                ));
            }
        }
    }
    Ok((firing_angles, crank))
}

/// Two cylinders on one shared pin that the firing would need at two
/// angles. The error names the key the firing came from, and gives the
/// split-pin crank that fires exactly so (one lag per cylinder,
/// `alpha_i = theta_i - gamma_i` mod 360°), ready to paste.
fn shared_pin_conflict(
    layout: Layout,
    gamma: &[f64],
    firing: &[f64],
    firing_given: bool,
    order: &[usize],
    (first, second, throw): (usize, usize, usize),
    (need_first, need_second): (f64, f64),
) -> EngineError {
    let rev = 2.0 * PI;
    let base = wrap(firing[0] - gamma[0], rev);
    let split: Vec<f64> = firing
        .iter()
        .zip(gamma)
        .map(|(f, g)| wrap(f - g - base, rev))
        .collect();
    let bank = match layout {
        Layout::Vee { bank_angle } => format!("{}° vee", plain(bank_angle.to_degrees(), 3)),
        other => other.name().to_string(),
    };
    let (key, value) = if firing_given {
        ("firing_angles_deg", deg_list(firing))
    } else {
        ("firing_order", format!("{order:?}"))
    };
    let how = if firing_given {
        "these firing angles".to_string()
    } else {
        format!(
            "evenly (every {}°)",
            plain((firing_angles_step(firing)).to_degrees(), 3)
        )
    };
    EngineError::Invalid {
        key,
        value,
        expected: format!(
            "cylinders {} and {} share throw {} but would need it at {}° and {}°: a shared-pin {bank} \
             cannot fire {how}. With split crank pins (each rod on its own pin, as in 90° and 60° V6s) \
             give one throw lag per cylinder: `crank_angles_deg = {}` fires so. Or give \
             `firing_angles_deg` the shared-pin crank allows (throw lag + bank angle + 0 or 360°); \
             `enginedyn firing-orders --all-cranks` ranks the cranks and orders this layout allows",
            first + 1,
            second + 1,
            throw + 1,
            plain(need_first.to_degrees(), 1),
            plain(need_second.to_degrees(), 1),
            deg_list(&split),
        ),
    }
}

/// A number to four significant digits, as people write it (`0.086`,
/// `86000`, `1365`; exponent form only below 1e-4 and from 1e9).
pub(crate) fn human(x: f64) -> String {
    enginedyn_numerics::format::sig(x, 4)
}

/// The smallest positive gap between sorted firing angles (rad).
fn firing_angles_step(firing: &[f64]) -> f64 {
    let mut f = firing.to_vec();
    f.sort_by(f64::total_cmp);
    f.windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 1e-9)
        .fold(f64::INFINITY, f64::min)
}

/// A number as people write it with at most `digits` decimals.
pub(crate) fn plain(x: f64, digits: usize) -> String {
    enginedyn_numerics::format::trimmed(x, digits)
}

fn throw_partner(i: usize, z: usize) -> usize {
    if i >= z / 2 { i - z / 2 } else { i + z / 2 }
}

/// Cylinders must fire in `order`: sorted by firing angle from cylinder 1 on.
fn check_order(f: &[f64], order: &[usize], cycle: f64) -> Result<(), EngineError> {
    let start = order.iter().position(|&c| c == 1).unwrap_or(0);
    let z = order.len();
    let mut prev = -1.0;
    for j in 0..z {
        let c = order[(start + j) % z];
        let a = f[c - 1];
        if a <= prev || a >= cycle {
            return Err(invalid(
                "firing_angles_deg",
                deg_list(f),
                format!("angles that rise in the firing order {order:?}, within one cycle"),
            ));
        }
        prev = a;
    }
    Ok(())
}

/// Firing angles from given throws: each cylinder fires at the first
/// admissible angle (throw lag + bank + 0 or 360°) after the one before it.
fn from_crank(
    stroke: Stroke,
    gamma: &[f64],
    pin: &[usize],
    crank: &[f64],
    order: &[usize],
) -> Result<Vec<f64>, EngineError> {
    let cycle = stroke.cycle();
    let rev = 2.0 * PI;
    let z = order.len();
    let base = crank[pin[0]] + gamma[0];
    let mut f = vec![0.0; z];
    let start = order.iter().position(|&c| c == 1).unwrap_or(0);
    let mut prev = -1e-9;
    for j in 0..z {
        let c = order[(start + j) % z] - 1;
        let b = wrap(crank[pin[c]] + gamma[c] - base, rev);
        let cands: &[f64] = match stroke {
            Stroke::Four => &[b, b + rev],
            Stroke::Two => &[b],
        };
        let Some(&a) = cands
            .iter()
            .find(|&&a| a > prev + 1e-9 || (j == 0 && a.abs() < 1e-9))
        else {
            return Err(invalid(
                "crank_angles_deg",
                deg_list(crank),
                format!(
                    "a crank on which the firing order {order:?} fits in one {:.0}° cycle",
                    cycle.to_degrees()
                ),
            ));
        };
        f[c] = a;
        prev = a;
    }
    Ok(f)
}

impl Engine {
    /// The engine as it computes, in words (its `Debug` form without the
    /// notes its file's reading gave, which name lines, nor its `diagram`
    /// key): what a campaign compares, so that a blank line more in the
    /// engine file is the same engine.
    pub fn meaning(&self) -> String {
        let mut e = self.clone();
        e.notes.clear();
        e.diagram = None;
        format!("{e:?}")
    }

    /// The engine's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Two- or four-stroke.
    pub fn stroke_kind(&self) -> Stroke {
        self.stroke
    }
    /// Cycle length (rad).
    pub fn cycle(&self) -> f64 {
        self.stroke.cycle()
    }
    /// Layout.
    pub fn layout(&self) -> Layout {
        self.layout
    }
    /// Number of cylinders `z`.
    pub fn cylinders(&self) -> usize {
        self.z
    }
    /// Number of crank throws.
    pub fn throws(&self) -> usize {
        throws_of(self.layout, self.z).1
    }
    /// Throw (0-based) carrying cylinder `i` (0-based).
    pub fn throw_of(&self, i: usize) -> usize {
        throws_of(self.layout, self.z).0[i]
    }
    /// Firing order (1-based cylinder numbers).
    pub fn firing_order(&self) -> &[usize] {
        &self.firing_order
    }
    /// Firing angle `theta_i` of cylinder `i` (0-based), rad in `[0, cycle)`.
    pub fn firing_angle(&self, i: usize) -> f64 {
        self.firing_angles[i]
    }
    /// All firing angles (rad), per cylinder.
    pub fn firing_angles(&self) -> &[f64] {
        &self.firing_angles
    }
    /// Throw lags `alpha_k` (rad) as the engine file writes them: per
    /// throw, or with split pins per cylinder (cylinders 1..z/2 then the
    /// other bank, so entry `k < z/2` is throw k's bank-1 pin either way).
    /// Use [`Engine::pin_angle`] for the lag of a cylinder's own pin.
    pub fn crank_angles(&self) -> &[f64] {
        &self.crank_angles
    }
    /// Lag `alpha_i` (rad) of the crank pin cylinder `i` (0-based) runs on,
    /// behind cylinder 1's: its throw's lag, or with split pins its own.
    /// PHYSICS.md: `theta_i = alpha_i + gamma_i + 360° j_i`.
    pub fn pin_angle(&self, i: usize) -> f64 {
        self.pin_angles[i]
    }
    /// [`Engine::pin_angle`] of every cylinder.
    pub fn pin_angles(&self) -> &[f64] {
        &self.pin_angles
    }
    /// A vee whose throws carry each rod on a pin of its own
    /// (`crank_angles_deg` with one angle per cylinder).
    pub fn split_pins(&self) -> bool {
        self.split_pins
    }
    /// Whether the firing order came from the user. False only for an
    /// engine built by [`EngineBuilder::build_for_crank_search`] without
    /// one: its firing and crank are placeholders.
    pub fn firing_order_given(&self) -> bool {
        self.firing_order_given
    }
    /// Bank angle `gamma_i` of cylinder `i` (rad).
    pub fn bank_angle_of(&self, i: usize) -> f64 {
        gammas(self.layout, self.z)[i]
    }
    /// The cylinder (mechanism, bore, volume law).
    pub fn cylinder(&self) -> &Cylinder {
        &self.cylinder
    }
    /// The mechanism.
    pub fn mechanism(&self) -> &Mechanism {
        self.cylinder.mechanism()
    }
    /// Throw pitch (m).
    pub fn cylinder_spacing(&self) -> f64 {
        self.cylinder_spacing
    }
    /// Rod model from the file.
    pub fn rod_model(&self) -> RodModel {
        self.rod_model
    }
    /// The engine file's `[combustion]` section: the burn law and load of a
    /// synthesised diagram, when it has one.
    pub fn combustion(&self) -> Option<&crate::combustion::CombustionSpec> {
        self.combustion.as_ref()
    }

    /// The engine file's `[friction]` (Chen–Flynn), when it has one:
    /// FMEP, BMEP and the brake figures replace the constant
    /// `operating.mechanical_efficiency`.
    pub fn friction(&self) -> Option<&enginedyn_combustion::friction::ChenFlynn> {
        self.friction.as_ref()
    }
    /// Diagram path from the file (already resolved against the file's folder).
    pub fn diagram(&self) -> Option<&std::path::Path> {
        self.diagram.as_deref()
    }
    /// Masses.
    pub fn masses(&self) -> &Masses {
        &self.masses
    }
    /// Operating point from the file.
    pub fn operating(&self) -> &Operating {
        &self.operating
    }
    /// Flywheel targets.
    pub fn flywheel(&self) -> &FlywheelSpec {
        &self.flywheel
    }
    /// What was assumed while reading the file.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }
    /// The defaults that shape the results which the engine file left to
    /// enginedyn (empty for an engine not read from a file).
    pub fn defaults_taken(&self) -> &[TakenDefault] {
        &self.defaults_taken
    }
    /// One note listing [`Engine::defaults_taken`]: "defaults taken (not in
    /// the engine file): operating.mechanical_efficiency = 1 (…), …";
    /// `None` when the file gives every one of them.
    pub fn defaults_note(&self) -> Option<String> {
        if self.defaults_taken.is_empty() {
            return None;
        }
        let list: Vec<String> = self.defaults_taken.iter().map(|d| d.describe()).collect();
        Some(format!(
            "defaults taken (not in the engine file): {}",
            list.join(", ")
        ))
    }
    /// Notes on data that is physically implausible but still computed
    /// (INTERFACE.md, "Limits"), each naming the key and the likely
    /// mistake: a bore or stroke (`stroke_mm`, 2R) under 10 mm or over 2 m
    /// (`bore_mm = 0.086: metres?`), a crank-slider's λ = R/L outside
    /// 0.1–0.5, and at `rpm` (the speed the analysis uses, if known) a mean
    /// piston speed `stroke × rpm / 30` over 40 m/s. Numbers are written as
    /// people write them (`0.086`, `45.2 m/s`). Empty for a plausible engine.
    pub fn plausibility_notes(&self, rpm: Option<f64>) -> Vec<String> {
        let mut notes = Vec::new();
        let mech = self.mechanism();
        let stroke_mm = 2.0 * mech.r() * 1e3;
        for (key, mm) in [
            ("bore_mm", self.cylinder.bore() * 1e3),
            ("stroke_mm", stroke_mm),
        ] {
            let mistake = if mm < 1.0 {
                "metres?"
            } else if mm < 10.0 {
                "centimetres?"
            } else if mm > 2000.0 {
                "micrometres, or a slipped decimal point?"
            } else {
                continue;
            };
            notes.push(format!(
                "{key} = {}: {mistake} (a {} of {} mm is outside 10 mm to 2 m; computed as given)",
                human(mm),
                if key == "bore_mm" { "bore" } else { "stroke" },
                human(mm)
            ));
        }
        if let Mechanism::CrankSlider(cs) = mech {
            let lambda = cs.lambda();
            let l_mm = cs.l() * 1e3;
            let shown = format!(
                "λ = R/L = {} (stroke_mm = {}, rod length {} mm)",
                human(lambda),
                human(stroke_mm),
                human(l_mm)
            );
            if lambda > 0.5 {
                notes.push(format!(
                    "rod_length_mm or lambda: {shown} is above 0.5: a rod this short for the stroke? \
                     rod_length_mm is centre to centre and stroke_mm twice the crank radius; computed as given"
                ));
            } else if lambda < 0.1 {
                notes.push(format!(
                    "rod_length_mm or lambda: {shown} is below 0.1: a rod this long for the stroke? \
                     is stroke_mm the stroke (2R), in mm, and lambda R/L, not L/R?; computed as given"
                ));
            }
        }
        if let Some(rpm) = rpm.filter(|r| r.is_finite() && *r > 0.0) {
            let cm = mech.stroke() * rpm / 30.0;
            if cm > 40.0 {
                notes.push(format!(
                    "mean piston speed {} m/s (stroke_mm = {} at {} rpm) is over 40 m/s, \
                     beyond racing engines (about 25 m/s): is the speed in rpm and the stroke in mm?; computed as given",
                    plain(cm, 1),
                    human(stroke_mm),
                    human(rpm)
                ));
            }
        }
        notes
    }

    /// The same engine with another rod model (checked).
    pub fn with_rod_model(&self, rod_model: RodModel) -> Result<Engine, EngineError> {
        if rod_model != RodModel::TwoMass
            && self.masses.rod_inertia.is_none()
            && !matches!(self.mechanism(), Mechanism::ScotchYoke(_))
        {
            return Err(EngineError::Missing {
                key: "masses.rod_inertia_kg_m2",
                why: "required for rod_model = \"three-mass\" and \"rigid\"",
            });
        }
        Ok(Engine {
            rod_model,
            ..self.clone()
        })
    }

    /// The rod split into point masses for `model`: `(m_A, m_B, m_0)` at the
    /// small end, the big end and the centre of mass (PHYSICS.md). The rigid
    /// rod is the two-mass split plus a couple, so it returns that split.
    pub fn rod_masses(&self, model: RodModel) -> RodMasses {
        let m = &self.masses;
        let l = match self.mechanism() {
            Mechanism::CrankSlider(cs) => cs.l(),
            Mechanism::ScotchYoke(_) => return RodMasses::default(),
        };
        let la = m.rod_cg_from_small_end;
        let lb = l - la;
        match (model, m.rod_inertia) {
            (RodModel::ThreeMass, Some(ig)) => {
                let ma = ig / (la * l);
                let mb = ig / (lb * l);
                RodMasses {
                    small_end: ma,
                    big_end: mb,
                    centre: m.rod - ma - mb,
                }
            }
            _ => RodMasses {
                small_end: m.rod * lb / l,
                big_end: m.rod * la / l,
                centre: 0.0,
            },
        }
    }

    /// Reciprocating mass per cylinder `m_j` = piston group + `m_A` (kg).
    pub fn reciprocating_mass(&self, model: RodModel) -> f64 {
        self.masses.piston_group + self.rod_masses(model).small_end
    }

    /// Rotating mass on throw `k` (0-based) at the crank radius, `m_r` =
    /// crank unbalance + the big-end masses of the rods on it (kg).
    pub fn rotating_mass(&self, k: usize, model: RodModel) -> f64 {
        let rods = self.cylinders_on_throw(k) as f64;
        self.masses.crank_unbalanced + rods * self.rod_masses(model).big_end
    }

    /// Cylinders whose rods run on throw `k` (0-based): one inline, two on a
    /// shared vee throw.
    pub fn cylinders_on_throw(&self, k: usize) -> usize {
        (0..self.z).filter(|&i| self.throw_of(i) == k).count()
    }

    /// The reciprocating mass's mean reduced inertia per cylinder,
    /// `m_j R² (1/2 + λ²/8)` (kg m²): the cycle mean of `m_j (dx/dφ)²`
    /// to second order in λ (PHYSICS.md, "Flywheel"); its variation
    /// over the cycle is neglected.
    pub fn reciprocating_inertia(&self, model: RodModel) -> f64 {
        let mech = self.mechanism();
        let r = mech.r();
        let lambda = mech.lambda();
        self.reciprocating_mass(model) * r * r * (0.5 + lambda * lambda / 8.0)
    }

    /// Reduced inertia of throw `k` (0-based) about the crank axis (kg m²):
    /// its rotating masses `m_r R²` plus [`Engine::reciprocating_inertia`]
    /// for each cylinder on it. The webs and the pin beyond
    /// `crank_unbalanced_kg` are not in it.
    pub fn throw_inertia(&self, k: usize, model: RodModel) -> f64 {
        let r = self.mechanism().r();
        self.rotating_mass(k, model) * r * r
            + self.cylinders_on_throw(k) as f64 * self.reciprocating_inertia(model)
    }

    /// The whole crank train's reduced inertia (kg m²): `Σ m_r R²` over
    /// the throws plus `z m_j R² (1/2 + λ²/8)`, what
    /// `flywheel.include_crank_train` counts (PHYSICS.md, "Flywheel").
    pub fn crank_train_inertia(&self, model: RodModel) -> f64 {
        let mech = self.mechanism();
        let r = mech.r();
        let lambda = mech.lambda();
        let z = self.z as f64;
        let rot: f64 = (0..self.throws())
            .map(|k| self.rotating_mass(k, model) * r * r)
            .sum();
        rot + z * self.reciprocating_mass(model) * r * r * (0.5 + lambda * lambda / 8.0)
    }
}

/// A rod split into point masses (kg).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RodMasses {
    /// At the small end, moving with the piston.
    pub small_end: f64,
    /// At the big end, rotating with the crank pin.
    pub big_end: f64,
    /// At the centre of mass (three-mass model; may be negative).
    pub centre: f64,
}
