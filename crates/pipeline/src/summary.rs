//! The summary figures of one operating point, in INTERFACE.md's key order.

use crate::column::{ColumnType, Group};

/// Summary figures (SI units as named by each key). `None` is JSON `null`.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)] // each field is the summary.json key of the same name (INTERFACE.md)
pub struct Summary {
    pub rpm: f64,
    pub omega_rad_s: f64,
    pub imep_bar: Option<f64>,
    pub indicated_work_per_cylinder_j: Option<f64>,
    pub mean_torque_nm: Option<f64>,
    pub power_kw: Option<f64>,
    pub indicated_mean_torque_nm: Option<f64>,
    pub indicated_power_kw: Option<f64>,
    pub torque_max_nm: Option<f64>,
    pub torque_min_nm: Option<f64>,
    pub torque_nonuniformity: Option<f64>,
    pub excess_work_j: Option<f64>,
    pub excess_work_coefficient: Option<f64>,
    pub required_inertia_kg_m2: Option<f64>,
    pub flywheel_inertia_kg_m2: Option<f64>,
    pub flywheel_gd2_n_m2: Option<f64>,
    pub flywheel_outer_diameter_m: Option<f64>,
    pub flywheel_mass_kg: Option<f64>,
    pub flywheel_width_m: Option<f64>,
    pub speed_fluctuation_achieved: Option<f64>,
    pub stroke_m: f64,
    pub lambda: f64,
    pub piston_speed_mean_m_s: f64,
    pub piston_speed_max_m_s: f64,
    pub piston_accel_max_m_s2: f64,
    pub piston_accel_min_m_s2: f64,
    pub gas_force_max_n: Option<f64>,
    pub side_force_max_n: Option<f64>,
    pub rod_force_max_n: Option<f64>,
    pub crankpin_load_max_n: Option<f64>,
    pub crankpin_load_mean_n: Option<f64>,
    pub journal_torque_max_nm: f64,
    pub journal_most_loaded: usize,
    pub energy_balance_error: Option<f64>,
    /// `models.kinematics`.
    pub kinematics: &'static str,
    /// `models.rod_model`.
    pub rod_model: &'static str,
    /// `models.interpolation`: the interpolant, or each with its count
    /// where `auto` chose trace by trace.
    pub interpolation: String,
    /// `models.grid_step_deg`.
    pub grid_step_deg: f64,
    /// `models.integration`.
    pub integration: &'static str,
    /// Number of measured cycles averaged, when more than one were measured.
    pub cycles: Option<usize>,
    /// Measured cycles left out of the averages (each for a reason in `notes`).
    pub cycles_skipped: Option<usize>,
    /// Cycle-to-cycle statistics, when several cycles were measured.
    pub cycle_stats: Option<CycleSummary>,
    /// Pegging applied to relative traces.
    pub pegging: Option<Pegging>,
    /// The TDC offset a measured p–φ trace suggests (deg).
    pub tdc_offset_estimate_deg: Option<f64>,
    /// With `--tolerance`: the largest estimated relative error of the key
    /// results for the methods chosen.
    pub estimated_relative_error: Option<f64>,
    /// The mechanical efficiency η_m the effective figures carry (not a
    /// key: the labels of the readable tables show it).
    pub mechanical_efficiency: f64,
    /// The combustion figures, when a pressure diagram was analysed for them.
    pub combustion: Option<crate::CombustionSummary>,
    /// The peak of the mean trace (cylinder 1's), bar, when a pressure
    /// diagram was read.
    pub p_max_bar: Option<f64>,
    /// Its angle (deg from firing TDC, in `[-cycle/2, cycle/2)`).
    pub p_max_angle_deg: Option<f64>,
    /// The brake figures, with the engine file's `[friction]`.
    pub brake: Option<BrakeSummary>,
    /// How a synthesised diagram met its load (the design model).
    pub design: Option<DesignSummary>,
    pub notes: Vec<String>,
}

/// The brake figures of a point (PHYSICS "Friction and brake figures").
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)] // each field is the summary.json key of the same name
pub struct BrakeSummary {
    pub fmep_bar: f64,
    pub bmep_bar: f64,
    pub brake_torque_nm: f64,
    pub brake_power_kw: f64,
    pub mechanical_efficiency: Option<f64>,
}

/// The design model's figures of a synthesised diagram: `design.*`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignSummary {
    /// `"si"` or `"ci"`; `None` without `charge` in the engine file.
    pub charge: Option<&'static str>,
    /// The intake pressure of the cycle (bar).
    pub intake_pressure_bar: f64,
    /// The air ratio (with `charge`).
    pub lambda: Option<f64>,
}

/// Cycle-to-cycle statistics (INTERFACE.md's keys of the same names).
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub struct CycleSummary {
    pub cycles: usize,
    pub imep_std_bar: Option<f64>,
    pub imep_cov: Option<f64>,
    pub p_max_mean_bar: f64,
    pub p_max_cov: f64,
    pub p_max_angle_mean_deg: f64,
    pub p_max_angle_std_deg: f64,
}

/// Pegging as `summary.json` reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pegging {
    /// `"bar"` or `"polytropic"`.
    pub method: &'static str,
    /// Mean offset added (bar).
    pub offset_bar: f64,
    /// The exponent of polytropic pegging.
    pub polytropic_n: Option<f64>,
}

/// A summary value, as the report writers need it.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A number or null.
    Num(Option<f64>),
    /// A whole number.
    Int(usize),
    /// Text.
    Text(&'static str),
    /// Text made at run time (a model's description).
    Str(String),
    /// A nested object, in key order.
    Map(Vec<(&'static str, Value)>),
    /// A list of strings.
    List(Vec<String>),
}

impl Summary {
    /// The mean effective pressure the effective torque stands for (bar):
    /// BMEP with `[friction]`, else IMEP × `mechanical_efficiency`; `None`
    /// without an IMEP (a torque file).
    pub fn effective_mep_bar(&self) -> Option<f64> {
        match &self.brake {
            Some(b) => Some(b.bmep_bar),
            None => self.imep_bar.map(|i| i * self.mechanical_efficiency),
        }
    }

    /// A summary with every fixed key and nothing measured: lists the
    /// columns of `summary.csv`.
    pub fn empty() -> Self {
        Summary {
            rpm: 0.0,
            omega_rad_s: 0.0,
            imep_bar: None,
            indicated_work_per_cylinder_j: None,
            mean_torque_nm: None,
            power_kw: None,
            indicated_mean_torque_nm: None,
            indicated_power_kw: None,
            torque_max_nm: None,
            torque_min_nm: None,
            torque_nonuniformity: None,
            excess_work_j: None,
            excess_work_coefficient: None,
            required_inertia_kg_m2: None,
            flywheel_inertia_kg_m2: None,
            flywheel_gd2_n_m2: None,
            flywheel_outer_diameter_m: None,
            flywheel_mass_kg: None,
            flywheel_width_m: None,
            speed_fluctuation_achieved: None,
            stroke_m: 0.0,
            lambda: 0.0,
            piston_speed_mean_m_s: 0.0,
            piston_speed_max_m_s: 0.0,
            piston_accel_max_m_s2: 0.0,
            piston_accel_min_m_s2: 0.0,
            gas_force_max_n: None,
            side_force_max_n: None,
            rod_force_max_n: None,
            crankpin_load_max_n: None,
            crankpin_load_mean_n: None,
            journal_torque_max_nm: 0.0,
            journal_most_loaded: 0,
            energy_balance_error: None,
            kinematics: "",
            rod_model: "",
            interpolation: String::new(),
            grid_step_deg: 0.0,
            integration: "",
            cycles: None,
            cycles_skipped: None,
            cycle_stats: None,
            pegging: None,
            tdc_offset_estimate_deg: None,
            estimated_relative_error: None,
            mechanical_efficiency: 1.0,
            combustion: None,
            p_max_bar: None,
            p_max_angle_deg: None,
            brake: None,
            design: None,
            notes: Vec::new(),
        }
    }

    /// Every key in INTERFACE.md's order, then the optional keys present
    /// (built from [`KEYS`]).
    pub fn fields(&self) -> Vec<(&'static str, Value)> {
        let mut f: Vec<(&'static str, Value)> = KEYS
            .iter()
            .filter_map(|k| (k.get)(self).map(|v| (k.key, v)))
            .collect();
        // Burn levels asked for beyond the four of KEYS: `caK_deg`.
        f.extend(crate::combustion::extra_levels(self).map(|(k, deg)| (k, Value::Num(deg))));
        f
    }

    /// The descriptor of `key`, if it is a summary key.
    pub fn key(key: &str) -> Option<&'static Key> {
        KEYS.iter().find(|k| k.key == key)
    }
}

/// Whether a torque or power figure is indicated or effective (times the
/// mechanical efficiency): the readable tables label it so.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Basis {
    /// Neither: a figure of another kind.
    None,
    /// Before the mechanical efficiency.
    Indicated,
    /// Times `operating.mechanical_efficiency`.
    Effective,
}

/// How a figure is shown in the readable tables (the printed table,
/// `report.html`, batch's `index.html`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shown {
    /// The section it is listed under.
    pub section: &'static str,
    /// What it is, as an engineer names it.
    pub label: &'static str,
    /// Display unit (empty for a pure number).
    pub unit: &'static str,
    /// Display value = SI value × `scale`.
    pub scale: f64,
    /// Decimals shown; 10 and more: scientific notation with two decimals.
    pub digits: usize,
    /// Indicated or effective, for torque and power.
    pub basis: Basis,
}

/// One summary key: its name in `summary.json` (and `summary.csv`), how it
/// is shown, and its value in a summary (`None`: absent, for the optional
/// keys). [`KEYS`] is the one list every writer and table is built from.
#[derive(Debug, Clone, Copy)]
pub struct Key {
    /// The key, as INTERFACE.md names it.
    pub key: &'static str,
    /// How it is shown in readable tables; `None` for keys shown otherwise
    /// (`rpm` in the heading, `models`, `notes`).
    pub shown: Option<Shown>,
    /// The value; `None` when the key is absent from this summary.
    pub get: fn(&Summary) -> Option<Value>,
    /// Its columns in `summary/4` and `summary.csv`.
    pub columns: Columns,
}

/// The columns a summary key makes in the tables (`summary/4`,
/// `summary.csv`): [`schema::SUMMARY`](crate::schema::SUMMARY) is built
/// from these, so a key and its column cannot drift apart.
#[derive(Debug, Clone, Copy)]
pub enum Columns {
    /// One column named as the key, of this type, in this group.
    One(ColumnType, Group),
    /// An object (`models`, `pegging`): one column per field,
    /// `key.field`.
    Object(&'static [Field]),
}

/// One field of an object key (`models.kinematics`): its column and its
/// value.
#[derive(Debug, Clone, Copy)]
pub struct Field {
    /// The field's name in the object.
    pub field: &'static str,
    /// Its column, `key.field`.
    pub column: &'static str,
    /// The column's type.
    pub ty: ColumnType,
    /// Where the column stands.
    pub group: Group,
    /// The value; `None` when the field is absent from this summary.
    pub get: fn(&Summary) -> Option<Value>,
}

/// An object key's value: its fields present, in order; absent when none
/// is.
fn object(s: &Summary, fields: &[Field]) -> Option<Value> {
    let m: Vec<(&'static str, Value)> = fields
        .iter()
        .filter_map(|f| (f.get)(s).map(|v| (f.field, v)))
        .collect();
    (!m.is_empty()).then_some(Value::Map(m))
}

/// A [`Field`] of object `$key`.
macro_rules! field {
    ($key:literal . $field:literal, $ty:ident, $group:ident, $get:expr) => {
        Field {
            field: $field,
            column: concat!($key, ".", $field),
            ty: ColumnType::$ty,
            group: Group::$group,
            get: $get,
        }
    };
}

/// `models`: the methods used (text, and the grid step), and the
/// combustion analysis's when it ran.
const MODELS: &[Field] = &[
    field!("models"."kinematics", Utf8, ModelsText, |s| Some(Value::Text(s.kinematics))),
    field!("models"."rod_model", Utf8, ModelsText, |s| Some(Value::Text(s.rod_model))),
    field!("models"."interpolation", Utf8, ModelsText, |s| Some(Value::Str(
        s.interpolation.clone()
    ))),
    field!("models"."grid_step_deg", Float64, ModelsNumber, |s| Some(
        Value::Num(Some(s.grid_step_deg))
    )),
    field!("models"."integration", Utf8, ModelsText, |s| Some(Value::Text(
        s.integration
    ))),
    field!("models"."gamma", Utf8, Combustion, |s| s
        .combustion
        .as_ref()
        .map(|c| Value::Str(c.gamma.clone()))),
    field!("models"."smoothing", Utf8, Combustion, |s| s
        .combustion
        .as_ref()
        .map(|c| Value::Str(c.smoothing.clone()))),
    field!("models"."burn_window", Utf8, Combustion, |s| s
        .combustion
        .as_ref()
        .map(|c| Value::Str(c.burn_window.clone()))),
    field!("models"."wall_heat", Utf8, Appended3, |s| s
        .combustion
        .as_ref()
        .map(|c| Value::Str(c.wall_heat.clone()))),
];

/// `pegging`, when relative traces were pegged.
const PEGGING: &[Field] = &[
    field!("pegging"."method", Utf8, Pegging, |s| s
        .pegging
        .map(|p| Value::Text(p.method))),
    field!("pegging"."offset_bar", Float64, Pegging, |s| s
        .pegging
        .map(|p| Value::Num(Some(p.offset_bar)))),
    field!("pegging"."polytropic_n", Float64, Pegging, |s| s
        .pegging
        .map(|p| Value::Num(p.polytropic_n))),
];

/// A fixed number key's column.
const FIXED: Columns = Columns::One(ColumnType::Float64, Group::Fixed);
/// An optional number key's column.
const OPTIONAL: Columns = Columns::One(ColumnType::Float64, Group::Optional);
/// A combustion number key's column (appended in `summary/2`).
const COMBUSTION: Columns = Columns::One(ColumnType::Float64, Group::Combustion);
/// A number key's column appended in `summary/3`.
const APPENDED_3: Columns = Columns::One(ColumnType::Float64, Group::Appended3);
/// A number key's column appended in `summary/4`.
const APPENDED_4: Columns = Columns::One(ColumnType::Float64, Group::Appended4);

/// `design`: how a synthesised diagram met its load.
const DESIGN: &[Field] = &[
    field!("design"."charge", Utf8, Appended4, |s| s
        .design
        .and_then(|d| d.charge.map(Value::Text))),
    field!("design"."intake_pressure_bar", Float64, Appended4, |s| s
        .design
        .map(|d| Value::Num(Some(d.intake_pressure_bar)))),
    field!("design"."lambda", Float64, Appended4, |s| s
        .design
        .map(|d| Value::Num(d.lambda))),
];

/// A brake figure, present with `[friction]`.
fn brake(s: &Summary, get: fn(&BrakeSummary) -> Option<f64>) -> Option<Value> {
    s.brake.as_ref().map(|b| Value::Num(get(b)))
}

/// The summary key named `name`, found when the program is compiled: for
/// the lists of figures other crates choose (`report::KEY_FIGURES`,
/// `accuracy::KEYS`), so that a name not in [`KEYS`] does not build.
///
/// ```
/// const IMEP: &enginedyn_pipeline::Key = enginedyn_pipeline::key("imep_bar");
/// assert_eq!(IMEP.key, "imep_bar");
/// ```
///
/// A misspelt name is a compile error:
///
/// ```compile_fail
/// const IMEP: &enginedyn_pipeline::Key = enginedyn_pipeline::key("imep");
/// ```
///
/// At run time, where a name comes from the user, use
/// [`Summary::key`], which returns `None` for an unknown name.
pub const fn key(name: &str) -> &'static Key {
    let mut i = 0;
    while i < KEYS.len() {
        if same(KEYS[i].key.as_bytes(), name.as_bytes()) {
            return &KEYS[i];
        }
        i += 1;
    }
    panic!("not a summary key (enginedyn_pipeline::KEYS)")
}

/// Byte-wise equality, usable in a `const fn`.
const fn same(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

impl Value {
    /// A number or whole number as a number (`Some(None)`: null); `None`
    /// for text, lists and objects.
    pub fn as_number(&self) -> Option<Option<f64>> {
        match self {
            Value::Num(x) => Some(*x),
            Value::Int(i) => Some(Some(*i as f64)),
            _ => None,
        }
    }
}

/// The key's name, as `summary.json` writes it.
impl std::fmt::Display for Key {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.key)
    }
}

impl Key {
    /// The key's number in SI units, when it is one and present.
    pub fn number(&self, s: &Summary) -> Option<f64> {
        (self.get)(s)?.as_number().flatten()
    }
}

const fn shown(
    section: &'static str,
    label: &'static str,
    unit: &'static str,
    scale: f64,
    digits: usize,
    basis: Basis,
) -> Option<Shown> {
    Some(Shown {
        section,
        label,
        unit,
        scale,
        digits,
        basis,
    })
}

const WORK: &str = "Work and torque";
const FLY: &str = "Flywheel";
const KIN: &str = "Kinematics";
const FORCES: &str = "Forces (largest magnitude over the cylinders)";
const DATA: &str = "Data and method";
const BURN: &str = "Combustion";

/// A combustion key: present when the analysis ran, null where the figure
/// does not exist (no combustion, or a level not asked for).
fn burn(s: &Summary, get: fn(&crate::CombustionSummary) -> Option<f64>) -> Option<Value> {
    s.combustion.as_ref().map(|c| Value::Num(get(c)))
}

/// A combustion key null with the analysis and absent without its model
/// (the wall heat's: `null when off`, INTERFACE "Wall heat and knock").
fn burn_opt(
    s: &Summary,
    get: fn(&crate::CombustionSummary) -> Option<Option<f64>>,
) -> Option<Value> {
    s.combustion.as_ref().map(|c| Value::Num(get(c).flatten()))
}

macro_rules! num {
    ($field:ident) => {
        |s: &Summary| Some(Value::Num(s.$field))
    };
}
macro_rules! always {
    ($field:ident) => {
        |s: &Summary| Some(Value::Num(Some(s.$field)))
    };
}
macro_rules! stat {
    ($field:ident) => {
        |s: &Summary| s.cycle_stats.map(|c| Value::Num(c.$field.into()))
    };
}

/// Every summary key in INTERFACE.md's order: the fixed keys, `models` and
/// `notes`, then the optional keys (present when they apply).
pub const KEYS: &[Key] = &[
    Key {
        key: "rpm",
        shown: None,
        get: always!(rpm),
        columns: FIXED,
    },
    Key {
        key: "omega_rad_s",
        shown: None,
        get: always!(omega_rad_s),
        columns: FIXED,
    },
    Key {
        key: "imep_bar",
        shown: shown(WORK, "IMEP", "bar", 1.0, 3, Basis::None),
        get: num!(imep_bar),
        columns: FIXED,
    },
    Key {
        key: "indicated_work_per_cylinder_j",
        shown: shown(
            WORK,
            "indicated work per cylinder",
            "J",
            1.0,
            2,
            Basis::None,
        ),
        get: num!(indicated_work_per_cylinder_j),
        columns: FIXED,
    },
    Key {
        key: "mean_torque_nm",
        shown: shown(WORK, "mean torque", "N m", 1.0, 2, Basis::Effective),
        get: num!(mean_torque_nm),
        columns: FIXED,
    },
    Key {
        key: "power_kw",
        shown: shown(WORK, "power", "kW", 1.0, 2, Basis::Effective),
        get: num!(power_kw),
        columns: FIXED,
    },
    Key {
        key: "indicated_mean_torque_nm",
        shown: shown(WORK, "mean torque", "N m", 1.0, 2, Basis::Indicated),
        get: num!(indicated_mean_torque_nm),
        columns: FIXED,
    },
    Key {
        key: "indicated_power_kw",
        shown: shown(WORK, "power", "kW", 1.0, 2, Basis::Indicated),
        get: num!(indicated_power_kw),
        columns: FIXED,
    },
    Key {
        key: "torque_max_nm",
        shown: shown(WORK, "torque max", "N m", 1.0, 2, Basis::Indicated),
        get: num!(torque_max_nm),
        columns: FIXED,
    },
    Key {
        key: "torque_min_nm",
        shown: shown(WORK, "torque min", "N m", 1.0, 2, Basis::Indicated),
        get: num!(torque_min_nm),
        columns: FIXED,
    },
    Key {
        key: "torque_nonuniformity",
        shown: shown(
            WORK,
            "non-uniformity μ = (max − min) / mean",
            "",
            1.0,
            3,
            Basis::None,
        ),
        get: num!(torque_nonuniformity),
        columns: FIXED,
    },
    Key {
        key: "excess_work_j",
        shown: shown(FLY, "excess work ΔE", "J", 1.0, 2, Basis::None),
        get: num!(excess_work_j),
        columns: FIXED,
    },
    Key {
        key: "excess_work_coefficient",
        shown: shown(FLY, "excess work coefficient ψ", "", 1.0, 4, Basis::None),
        get: num!(excess_work_coefficient),
        columns: FIXED,
    },
    Key {
        key: "required_inertia_kg_m2",
        shown: shown(FLY, "required inertia I₀", "kg m²", 1.0, 5, Basis::None),
        get: num!(required_inertia_kg_m2),
        columns: FIXED,
    },
    Key {
        key: "flywheel_inertia_kg_m2",
        shown: shown(FLY, "flywheel inertia I_f", "kg m²", 1.0, 5, Basis::None),
        get: num!(flywheel_inertia_kg_m2),
        columns: FIXED,
    },
    Key {
        key: "flywheel_gd2_n_m2",
        shown: shown(FLY, "flywheel GD²", "N m²", 1.0, 3, Basis::None),
        get: num!(flywheel_gd2_n_m2),
        columns: FIXED,
    },
    Key {
        key: "flywheel_outer_diameter_m",
        shown: shown(FLY, "flywheel outer diameter", "mm", 1e3, 1, Basis::None),
        get: num!(flywheel_outer_diameter_m),
        columns: FIXED,
    },
    Key {
        key: "flywheel_mass_kg",
        shown: shown(FLY, "flywheel mass", "kg", 1.0, 2, Basis::None),
        get: num!(flywheel_mass_kg),
        columns: FIXED,
    },
    Key {
        key: "flywheel_width_m",
        shown: shown(FLY, "flywheel width", "mm", 1e3, 1, Basis::None),
        get: num!(flywheel_width_m),
        columns: FIXED,
    },
    Key {
        key: "speed_fluctuation_achieved",
        shown: shown(FLY, "speed fluctuation achieved δ", "", 1.0, 5, Basis::None),
        get: num!(speed_fluctuation_achieved),
        columns: FIXED,
    },
    Key {
        key: "stroke_m",
        shown: shown(KIN, "stroke", "mm", 1e3, 3, Basis::None),
        get: always!(stroke_m),
        columns: FIXED,
    },
    Key {
        key: "lambda",
        shown: shown(KIN, "λ = R/L", "", 1.0, 4, Basis::None),
        get: always!(lambda),
        columns: FIXED,
    },
    Key {
        key: "piston_speed_mean_m_s",
        shown: shown(KIN, "mean piston speed", "m/s", 1.0, 2, Basis::None),
        get: always!(piston_speed_mean_m_s),
        columns: FIXED,
    },
    Key {
        key: "piston_speed_max_m_s",
        shown: shown(KIN, "max piston speed", "m/s", 1.0, 2, Basis::None),
        get: always!(piston_speed_max_m_s),
        columns: FIXED,
    },
    Key {
        key: "piston_accel_max_m_s2",
        shown: shown(KIN, "max piston acceleration", "m/s²", 1.0, 0, Basis::None),
        get: always!(piston_accel_max_m_s2),
        columns: FIXED,
    },
    Key {
        key: "piston_accel_min_m_s2",
        shown: shown(KIN, "min piston acceleration", "m/s²", 1.0, 0, Basis::None),
        get: always!(piston_accel_min_m_s2),
        columns: FIXED,
    },
    Key {
        key: "gas_force_max_n",
        shown: shown(FORCES, "gas force max", "N", 1.0, 0, Basis::None),
        get: num!(gas_force_max_n),
        columns: FIXED,
    },
    Key {
        key: "side_force_max_n",
        shown: shown(FORCES, "side thrust max", "N", 1.0, 0, Basis::None),
        get: num!(side_force_max_n),
        columns: FIXED,
    },
    Key {
        key: "rod_force_max_n",
        shown: shown(FORCES, "rod force max", "N", 1.0, 0, Basis::None),
        get: num!(rod_force_max_n),
        columns: FIXED,
    },
    Key {
        key: "crankpin_load_max_n",
        shown: shown(FORCES, "crank-pin load max", "N", 1.0, 0, Basis::None),
        get: num!(crankpin_load_max_n),
        columns: FIXED,
    },
    Key {
        key: "crankpin_load_mean_n",
        shown: shown(FORCES, "crank-pin load mean", "N", 1.0, 0, Basis::None),
        get: num!(crankpin_load_mean_n),
        columns: FIXED,
    },
    Key {
        key: "journal_torque_max_nm",
        shown: shown(
            FORCES,
            "main-journal torque max",
            "N m",
            1.0,
            1,
            Basis::None,
        ),
        get: always!(journal_torque_max_nm),
        columns: FIXED,
    },
    Key {
        key: "journal_most_loaded",
        shown: shown(
            FORCES,
            "most loaded main journal (after throw K)",
            "",
            1.0,
            0,
            Basis::None,
        ),
        get: |s| Some(Value::Int(s.journal_most_loaded)),
        columns: Columns::One(ColumnType::Int32, Group::Fixed),
    },
    Key {
        key: "energy_balance_error",
        shown: shown(DATA, "energy balance error", "", 1.0, 12, Basis::None),
        get: num!(energy_balance_error),
        columns: FIXED,
    },
    Key {
        key: "models",
        shown: None,
        get: |s| object(s, MODELS),
        columns: Columns::Object(MODELS),
    },
    Key {
        key: "notes",
        shown: None,
        get: |s| Some(Value::List(s.notes.clone())),
        columns: Columns::One(ColumnType::Utf8, Group::Notes),
    },
    Key {
        key: "cycles",
        shown: shown(DATA, "measured cycles averaged", "", 1.0, 0, Basis::None),
        get: |s| s.cycles.map(Value::Int),
        columns: Columns::One(ColumnType::Int64, Group::Optional),
    },
    Key {
        key: "cycles_skipped",
        shown: shown(
            DATA,
            "measured cycles left out (a gap)",
            "",
            1.0,
            0,
            Basis::None,
        ),
        get: |s| s.cycles_skipped.map(Value::Int),
        columns: Columns::One(ColumnType::Int64, Group::Optional),
    },
    Key {
        key: "imep_std_bar",
        shown: shown(DATA, "IMEP standard deviation", "bar", 1.0, 4, Basis::None),
        get: stat!(imep_std_bar),
        columns: OPTIONAL,
    },
    Key {
        key: "imep_cov",
        shown: shown(
            DATA,
            "IMEP CoV (over cycles, or cylinders)",
            "%",
            100.0,
            2,
            Basis::None,
        ),
        get: stat!(imep_cov),
        columns: OPTIONAL,
    },
    Key {
        key: "p_max_mean_bar",
        shown: shown(DATA, "peak pressure, mean", "bar", 1.0, 2, Basis::None),
        get: stat!(p_max_mean_bar),
        columns: OPTIONAL,
    },
    Key {
        key: "p_max_cov",
        shown: shown(DATA, "peak pressure CoV", "%", 100.0, 2, Basis::None),
        get: stat!(p_max_cov),
        columns: OPTIONAL,
    },
    Key {
        key: "p_max_angle_mean_deg",
        shown: shown(
            DATA,
            "peak pressure angle, mean",
            "deg",
            1.0,
            2,
            Basis::None,
        ),
        get: stat!(p_max_angle_mean_deg),
        columns: OPTIONAL,
    },
    Key {
        key: "p_max_angle_std_deg",
        shown: shown(DATA, "peak pressure angle, std", "deg", 1.0, 2, Basis::None),
        get: stat!(p_max_angle_std_deg),
        columns: OPTIONAL,
    },
    Key {
        key: "pegging",
        shown: None,
        get: |s| object(s, PEGGING),
        columns: Columns::Object(PEGGING),
    },
    Key {
        key: "tdc_offset_estimate_deg",
        shown: shown(
            DATA,
            "TDC offset the trace suggests",
            "deg",
            1.0,
            2,
            Basis::None,
        ),
        get: |s| s.tdc_offset_estimate_deg.map(|t| Value::Num(Some(t))),
        columns: OPTIONAL,
    },
    Key {
        key: "estimated_relative_error",
        shown: shown(
            DATA,
            "estimated relative error (--tolerance)",
            "",
            1.0,
            10,
            Basis::None,
        ),
        get: |s| s.estimated_relative_error.map(|e| Value::Num(Some(e))),
        columns: OPTIONAL,
    },
    Key {
        key: "ca5_deg",
        shown: shown(BURN, "CA5", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.level(5.0)),
        columns: COMBUSTION,
    },
    Key {
        key: "ca10_deg",
        shown: shown(BURN, "CA10", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.level(10.0)),
        columns: COMBUSTION,
    },
    Key {
        key: "ca50_deg",
        shown: shown(BURN, "CA50", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.level(50.0)),
        columns: COMBUSTION,
    },
    Key {
        key: "ca90_deg",
        shown: shown(BURN, "CA90", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.level(90.0)),
        columns: COMBUSTION,
    },
    Key {
        key: "burn_10_90_deg",
        shown: shown(BURN, "burn duration 10–90 %", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.burn_10_90_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "soc_deg",
        shown: shown(BURN, "start of combustion", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.soc_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "eoc_deg",
        shown: shown(BURN, "end of combustion", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.eoc_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "heat_released_j",
        shown: shown(
            BURN,
            "net heat released per cylinder",
            "J",
            1.0,
            1,
            Basis::None,
        ),
        get: |s| burn(s, |c| c.heat_released_j),
        columns: COMBUSTION,
    },
    Key {
        key: "dp_dphi_max_bar_deg",
        shown: shown(
            BURN,
            "max pressure rise dp/dφ",
            "bar/deg",
            1.0,
            3,
            Basis::None,
        ),
        get: |s| burn(s, |c| c.dp_dphi_max_bar_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "dp_dphi_max_angle_deg",
        shown: shown(BURN, "max pressure rise at", "deg", 1.0, 2, Basis::None),
        get: |s| burn(s, |c| c.dp_dphi_max_angle_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "imep_gross_bar",
        shown: shown(BURN, "IMEP gross (−180…180°)", "bar", 1.0, 3, Basis::None),
        get: |s| burn(s, |c| c.imep_gross_bar),
        columns: COMBUSTION,
    },
    Key {
        key: "pmep_bar",
        shown: shown(BURN, "PMEP = net − gross", "bar", 1.0, 3, Basis::None),
        get: |s| burn(s, |c| c.pmep_bar),
        columns: COMBUSTION,
    },
    Key {
        key: "ca50_std_deg",
        shown: shown(BURN, "CA50 std over cycles", "deg", 1.0, 3, Basis::None),
        get: |s| burn(s, |c| c.ca50_std_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "burn_10_90_std_deg",
        shown: shown(
            BURN,
            "10–90 duration std over cycles",
            "deg",
            1.0,
            3,
            Basis::None,
        ),
        get: |s| burn(s, |c| c.burn_10_90_std_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "dp_dphi_max_std_bar_deg",
        shown: shown(
            BURN,
            "max dp/dφ std over cycles",
            "bar/deg",
            1.0,
            3,
            Basis::None,
        ),
        get: |s| burn(s, |c| c.dp_dphi_max_std_bar_deg),
        columns: COMBUSTION,
    },
    Key {
        key: "imep_lnv",
        shown: shown(
            BURN,
            "IMEP LNV (lowest cycle / mean)",
            "",
            1.0,
            4,
            Basis::None,
        ),
        get: |s| burn(s, |c| c.imep_lnv),
        columns: COMBUSTION,
    },
    Key {
        key: "heat_released_gross_j",
        shown: shown(
            BURN,
            "gross heat released per cylinder (with wall heat)",
            "J",
            1.0,
            1,
            Basis::None,
        ),
        get: |s| burn_opt(s, |c| c.heat_released_gross_j),
        columns: APPENDED_3,
    },
    Key {
        key: "wall_heat_j",
        shown: shown(
            BURN,
            "heat lost to the walls, SOC to EOC",
            "J",
            1.0,
            1,
            Basis::None,
        ),
        get: |s| burn_opt(s, |c| c.wall_heat_j),
        columns: APPENDED_3,
    },
    Key {
        key: "mapo_mean_bar",
        shown: shown(
            BURN,
            "knock: MAPO, mean over cycles",
            "bar",
            1.0,
            3,
            Basis::None,
        ),
        get: |s| burn(s, |c| c.mapo_mean_bar),
        columns: APPENDED_3,
    },
    Key {
        key: "mapo_max_bar",
        shown: shown(BURN, "knock: MAPO, largest", "bar", 1.0, 3, Basis::None),
        get: |s| burn(s, |c| c.mapo_max_bar),
        columns: APPENDED_3,
    },
    Key {
        key: "knock_share",
        shown: shown(
            BURN,
            "knock: share of cycles over the threshold",
            "",
            1.0,
            3,
            Basis::None,
        ),
        get: |s| burn(s, |c| c.knock_share),
        columns: APPENDED_3,
    },
    Key {
        key: "p_max_bar",
        shown: shown(
            WORK,
            "peak pressure (mean trace)",
            "bar",
            1.0,
            2,
            Basis::None,
        ),
        get: |s| s.p_max_bar.map(|x| Value::Num(Some(x))),
        columns: APPENDED_3,
    },
    Key {
        key: "p_max_angle_deg",
        shown: shown(
            WORK,
            "peak pressure angle (from firing TDC)",
            "deg",
            1.0,
            1,
            Basis::None,
        ),
        get: |s| s.p_max_angle_deg.map(|x| Value::Num(Some(x))),
        columns: APPENDED_3,
    },
    Key {
        key: "fmep_bar",
        shown: shown(WORK, "FMEP (Chen–Flynn)", "bar", 1.0, 3, Basis::None),
        get: |s| brake(s, |b| Some(b.fmep_bar)),
        columns: APPENDED_4,
    },
    Key {
        key: "bmep_bar",
        shown: shown(WORK, "BMEP (IMEP − FMEP)", "bar", 1.0, 3, Basis::None),
        get: |s| brake(s, |b| Some(b.bmep_bar)),
        columns: APPENDED_4,
    },
    Key {
        key: "brake_torque_nm",
        shown: shown(WORK, "brake torque", "N m", 1.0, 1, Basis::None),
        get: |s| brake(s, |b| Some(b.brake_torque_nm)),
        columns: APPENDED_4,
    },
    Key {
        key: "brake_power_kw",
        shown: shown(WORK, "brake power", "kW", 1.0, 2, Basis::None),
        get: |s| brake(s, |b| Some(b.brake_power_kw)),
        columns: APPENDED_4,
    },
    Key {
        key: "mechanical_efficiency",
        shown: shown(
            WORK,
            "mechanical efficiency (BMEP/IMEP)",
            "",
            1.0,
            3,
            Basis::None,
        ),
        get: |s| brake(s, |b| b.mechanical_efficiency),
        columns: APPENDED_4,
    },
    Key {
        key: "design",
        shown: None,
        get: |s| object(s, DESIGN),
        columns: Columns::Object(DESIGN),
    },
];
