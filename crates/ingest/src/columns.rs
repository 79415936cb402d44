//! The column resolver: header names as other tools write them, or
//! `--columns`, into the roles the layouts read (INTERFACE.md, "Indicator
//! diagram").
//!
//! A name is read case-insensitively as words and a unit: the unit in
//! brackets or parentheses (`Pressure [bar]`, `CA (deg)`), or a unit word
//! (`pressure_bar`, `time ms`); a number after `cyl` names a cylinder
//! (`Pressure[bar]_Cyl01`, `P_cyl1 (MPa)`), any other number a cycle
//! (`pressure_bar_2`). The canonical names of INTERFACE.md are read first.

use crate::Quantity;
use crate::error::{IngestError, at};

/// One standard atmosphere (Pa): what `--gauge` adds.
pub(crate) const ATM: f64 = 101_325.0;

/// Pa per unit of a canonical pressure column (`pressure_bar`, …,
/// `pressure_kgf_cm2`), from the one table of pressure units.
pub fn pressure_unit(name: &str) -> Option<f64> {
    let unit = name.strip_prefix("pressure_")?;
    match pressure_scale(&unit.replace('_', "")) {
        Some(Ok(pa)) => Some(pa),
        _ => None,
    }
}

/// What a column name (with its unit, as a tool writes it: `P_cyl1 [MPa]`,
/// `Crank angle (rad)`) reads as: the canonical column and the factor from
/// the name's unit to that column's (`("pressure_bar", 10.0)`), by the same
/// resolver as a file's header; `None` when the name is not one.
pub fn canonical(name: &str) -> Option<(&'static str, f64)> {
    Some(match recognise(name).ok()? {
        Role::Angle(s) => ("crank_deg", s),
        Role::Time(s) => ("time_s", s),
        Role::Volume(s) => ("volume_m3", s),
        Role::Pressure { scale, .. } => ("pressure_bar", scale / 1e5),
        Role::Volts { scale, .. } => ("pressure_v", scale),
        Role::Torque(Quantity::CylinderTorque) => ("torque_cylinder_nm", 1.0),
        Role::Torque(_) => ("torque_engine_nm", 1.0),
        Role::Cycle => ("cycle", 1.0),
        Role::Cylinder => ("cylinder", 1.0),
        Role::Tdc => ("tdc", 1.0),
        Role::Encoder => ("encoder", 1.0),
        Role::Wheel => ("wheel", 1.0),
        Role::Cam => ("cam", 1.0),
        Role::Skip => return None,
    })
}

/// Pa per psi, from exact definitions (0.45359237 kg × 9.80665 m/s² / (0.0254 m)²).
const PSI: f64 = 0.453_592_37 * 9.806_65 / (0.0254 * 0.0254);
const KGF_CM2: f64 = 98_066.5;

/// The canonical names (INTERFACE.md), for messages.
pub(crate) const KNOWN: &[&str] = &[
    "crank_deg",
    "volume_cm3",
    "volume_m3",
    "volume_l",
    "time_s",
    "time_ms",
    "pressure_bar",
    "pressure_mpa",
    "pressure_kpa",
    "pressure_pa",
    "pressure_psi",
    "pressure_kgf_cm2",
    "pressure_v",
    "torque_cylinder_nm",
    "torque_engine_nm",
    "cycle",
    "cylinder",
    "tdc",
    "encoder",
    "wheel",
    "cam",
];

/// What one column holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Role {
    /// Crank angle; degrees per file unit.
    Angle(f64),
    /// Cylinder volume; m³ per file unit.
    Volume(f64),
    /// Time; seconds per file unit.
    Time(f64),
    /// Pressure; Pa per file unit. `cylinder` from a `cyl` number in the
    /// name, `index` from any other number.
    Pressure {
        scale: f64,
        cylinder: Option<u32>,
        index: Option<u32>,
    },
    /// A charge amplifier's voltage (relative pressure); volts per unit.
    Volts {
        scale: f64,
        cylinder: Option<u32>,
        index: Option<u32>,
    },
    /// Torque (N m) of one cylinder or of the engine.
    Torque(Quantity),
    Cycle,
    Cylinder,
    /// A TDC pulse per revolution.
    Tdc,
    /// A crank encoder's pulses (`--encoder-ppr` a revolution).
    Encoder,
    /// A tooth wheel with missing teeth (`--wheel`).
    Wheel,
    /// A cam signal: one pulse a cycle.
    Cam,
    /// `_`, or an empty name: nothing.
    Skip,
}

impl Role {
    fn describe(self) -> String {
        match self {
            Role::Angle(s) => format!("crank angle ({})", unit_name(ANGLE_UNITS, s)),
            Role::Volume(s) => format!("volume ({})", unit_name(VOLUME_UNITS, s)),
            Role::Time(s) => format!("time ({})", unit_name(TIME_UNITS, s)),
            Role::Pressure {
                scale, cylinder, ..
            } => format!(
                "pressure ({}){}",
                unit_name(PRESSURE_UNITS, scale),
                cylinder
                    .map(|c| format!(", cylinder {c}"))
                    .unwrap_or_default()
            ),
            Role::Volts { cylinder, .. } => format!(
                "pressure (V, relative){}",
                cylinder
                    .map(|c| format!(", cylinder {c}"))
                    .unwrap_or_default()
            ),
            Role::Torque(Quantity::EngineTorque) => "engine torque (N m)".into(),
            Role::Torque(_) => "cylinder torque (N m)".into(),
            Role::Cycle => "cycle number".into(),
            Role::Cylinder => "cylinder number".into(),
            Role::Tdc => "TDC pulse".into(),
            Role::Encoder => "crank encoder".into(),
            Role::Wheel => "tooth wheel".into(),
            Role::Cam => "cam pulse".into(),
            Role::Skip => "skipped".into(),
        }
    }
}

/// Equal to within rounding: the unit factors are the same constants.
pub(crate) fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs()
}

/// A unit: its spellings (lower case, letters and digits only), its
/// factor to SI, and how notes write it.
type Unit = (&'static [&'static str], f64, &'static str);

/// Pressure units, Pa per unit: the one table for names and factors.
const PRESSURE_UNITS: &[Unit] = &[
    (&["bar", "bara", "barabs"], 1e5, "bar"),
    (&["mbar", "hpa"], 1e2, "mbar"),
    (&["mpa"], 1e6, "MPa"),
    (&["kpa"], 1e3, "kPa"),
    (&["pa"], 1.0, "Pa"),
    (&["psi", "psia"], PSI, "psi"),
    (&["kgfcm2", "kgcm2", "at", "kgf"], KGF_CM2, "kgf/cm²"),
    (&["atm"], ATM, "atm"),
    (&["torr"], ATM / 760.0, "Torr"),
];

/// A charge amplifier's output, volts per unit.
const VOLT_UNITS: &[Unit] = &[(&["v", "volt", "volts"], 1.0, "V"), (&["mv"], 1e-3, "mV")];

/// Volume units, m³ per unit.
const VOLUME_UNITS: &[Unit] = &[
    (&["cm3", "ccm", "ml", "cc"], 1e-6, "cm³"),
    (&["m3"], 1.0, "m³"),
    (&["l", "dm3", "litre", "liter"], 1e-3, "l"),
    (&["mm3"], 1e-9, "mm³"),
];

/// Time units, s per unit.
const TIME_UNITS: &[Unit] = &[
    (&["s", "sec", "secs"], 1.0, "s"),
    (&["ms", "msec"], 1e-3, "ms"),
    (&["us", "usec"], 1e-6, "µs"),
    (&["min"], 60.0, "min"),
];

/// Angle units, degrees per unit (`grad` is the German degree, `gon` the
/// 400th of a turn).
const ANGLE_UNITS: &[Unit] = &[
    (
        &[
            "", "deg", "degca", "degkw", "degcrank", "grad", "ca", "kw", "cad", "degree", "degrees",
        ],
        1.0,
        "deg",
    ),
    (&["rad"], 180.0 / std::f64::consts::PI, "rad"),
    (&["gon"], 0.9, "gon"),
    (&["rev", "revs", "turn", "turns"], 360.0, "rev"),
];

/// The factor of spelling `u` in `table`.
fn factor(table: &[Unit], u: &str) -> Option<f64> {
    table
        .iter()
        .find(|(names, ..)| names.contains(&u))
        .map(|(_, f, _)| *f)
}

/// How notes write the unit of `factor` in `table`.
fn unit_name(table: &[Unit], factor: f64) -> &'static str {
    table
        .iter()
        .find(|(_, f, _)| same(*f, factor))
        .map_or("?", |(.., n)| n)
}

/// Why a name cannot be read.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Unread {
    /// No word that names a quantity.
    Unknown,
    /// A quantity with no unit where one is needed (`Pressure`).
    NoUnit(&'static str, &'static str),
    /// A unit that does not fit the quantity.
    BadUnit(&'static str, String),
}

/// Splits a name into lower-case words and numbers, and the unit in
/// brackets or parentheses (normalised: `°` as `deg`, `³` as `3`).
fn words(name: &str) -> (Vec<String>, Option<String>) {
    let mut unit = None;
    let mut rest = String::new();
    let mut depth: Option<(char, String)> = None;
    for c in name.chars() {
        match (&mut depth, c) {
            (None, '[' | '(' | '{') => depth = Some((c, String::new())),
            (Some((o, u)), ']' | ')' | '}')
                if matches!((*o, c), ('[', ']') | ('(', ')') | ('{', '}')) =>
            {
                if unit.is_none() {
                    unit = Some(normal_unit(u));
                }
                depth = None;
                rest.push(' ');
            }
            (Some((_, u)), _) => u.push(c),
            (None, _) => rest.push(c),
        }
    }
    if let Some((_, u)) = depth {
        // An unclosed bracket: its text is part of the name.
        rest.push(' ');
        rest.push_str(&u);
    }
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    let mut digits = false;
    let flush = |cur: &mut String, out: &mut Vec<String>| {
        if !cur.is_empty() {
            out.push(std::mem::take(cur));
        }
    };
    for c in rest.chars().flat_map(char::to_lowercase) {
        let c = match c {
            '³' => '3',
            '²' => '2',
            'µ' | 'μ' => 'u',
            c => c,
        };
        if c == '°' {
            flush(&mut cur, &mut out);
            out.push("deg".into());
        } else if c.is_alphanumeric() {
            let d = c.is_ascii_digit();
            if !cur.is_empty() && d != digits {
                flush(&mut cur, &mut out);
            }
            digits = d;
            cur.push(c);
        } else {
            flush(&mut cur, &mut out);
        }
    }
    flush(&mut cur, &mut out);
    (out, unit)
}

/// True when a row is a units row, which belongs to the names row above
/// it (INTERFACE.md, "Units are not angles"): every cell that is not empty
/// or skipped is a unit alone, and at least half of them are units the
/// reader knows (`deg`, `bar`, `[V]`, `-`). The others may be any unit of
/// a column the reader does not know (`J/°CA`, `kg/h`, `mm`): a unit's
/// shape, one short token that is no number.
pub(crate) fn units_row(cells: &[String]) -> bool {
    const OTHER: &[&str] = &[
        "deg", "degca", "degkw", "ca", "kw", "rad", "grad", "n", "nm", "rpm", "1min", "umin",
        "min1", "hz", "khz", "degc", "c", "k", "a", "ma", "w", "kw", "percent", "",
    ];
    let (mut known, mut other) = (0usize, 0usize);
    for c in cells {
        let t = c.trim();
        if t.is_empty() || t == "_" || t == "-" || t == "%" {
            continue;
        }
        let u = normal_unit(t.trim_matches(['[', ']', '(', ')']));
        let is_known = [PRESSURE_UNITS, VOLT_UNITS, VOLUME_UNITS, TIME_UNITS]
            .iter()
            .any(|table| factor(table, &u).is_some())
            || OTHER.contains(&u.as_str());
        if is_known {
            known += 1;
        } else if unit_shaped(t) {
            other += 1;
        } else {
            return false;
        }
    }
    known > 0 && known >= other
}

/// A cell shaped like a unit: one token of at most 12 characters, no
/// number, either short (`mm`, `kJ`) or written with a unit's signs
/// (`J/°CA`, `kg/h`, `m³`, `1/min`).
fn unit_shaped(t: &str) -> bool {
    let t = t.trim_matches(['[', ']', '(', ')']);
    let n = t.chars().count();
    let signs = t.contains(['/', '°', '³', '²', '^', '·', '*', 'µ', 'μ']);
    n > 0
        && n <= 12
        && !t.contains(char::is_whitespace)
        && crate::read_number(t, false).is_err()
        && crate::read_number(t, true).is_err()
        && t.chars().any(|c| c.is_alphabetic() || c == '°')
        && (signs || n <= 4)
}

fn normal_unit(u: &str) -> String {
    u.chars()
        .flat_map(char::to_lowercase)
        .filter_map(|c| match c {
            '°' => Some("deg".to_string()),
            '³' => Some("3".into()),
            '²' => Some("2".into()),
            'µ' | 'μ' => Some("u".into()),
            c if c.is_alphanumeric() => Some(c.to_string()),
            _ => None,
        })
        .collect()
}

const ANGLE_WORDS: &[&str] = &[
    "crank",
    "angle",
    "crankangle",
    "ca",
    "cad",
    "theta",
    "θ",
    "phi",
    "φ",
    "kw",
    "kurbelwinkel",
    "winkel",
    "alpha",
];
const PRESSURE_WORDS: &[&str] = &[
    "pressure",
    "p",
    "pcyl",
    "pzyl",
    "druck",
    "zylinderdruck",
    "cylinderpressure",
    "pc",
    "pi",
    "press",
];
const TIME_WORDS: &[&str] = &["time", "t", "zeit", "timestamp"];
const VOLUME_WORDS: &[&str] = &["volume", "vol", "v", "hubraum"];
const TDC_WORDS: &[&str] = &["tdc", "ot", "trigger", "pulse", "marker"];
/// The crank's own signals (INTERFACE.md): read before the angle words, so
/// `Crank encoder` and `Crank wheel` are no angle.
const ENCODER_WORDS: &[&str] = &["encoder", "enc", "drehgeber", "inkrementalgeber"];
const WHEEL_WORDS: &[&str] = &["wheel", "ckp", "geberrad", "zahnrad", "toothwheel"];
const CAM_WORDS: &[&str] = &["cam", "cmp", "camshaft", "nocken", "nockenwelle"];
const CYCLE_WORDS: &[&str] = &["cycle", "cyc", "zyklus", "arbeitsspiel", "cycles"];
/// True when `name` holds the unit `kW` as written (lower-case k, upper-case
/// W, not after `°`): power, not the crank angle `KW`.
fn is_kilowatt(name: &str) -> bool {
    let b = name.as_bytes();
    name.match_indices("kW").any(|(i, _)| {
        let before = name[..i].chars().next_back();
        let after = b.get(i + 2).copied();
        !before.is_some_and(|c| c.is_alphanumeric() || c == '°')
            && !after.is_some_and(|c| c.is_ascii_alphanumeric())
    })
}

/// Words that name a torque column (`Torque [Nm]`, `Drehmoment [N m]`).
const TORQUE_WORDS: &[&str] = &["torque", "drehmoment", "moment", "trq", "tq"];

const CYLINDER_WORDS: &[&str] = &["cylinder", "cyl", "zylinder", "zyl"];

fn angle_unit(u: &str) -> Option<f64> {
    factor(ANGLE_UNITS, u)
}

/// Ok: Pa per unit; Err: volts per unit (a charge amplifier's output).
fn pressure_scale(u: &str) -> Option<Result<f64, f64>> {
    factor(PRESSURE_UNITS, u)
        .map(Ok)
        .or_else(|| factor(VOLT_UNITS, u).map(Err))
}

fn time_unit(u: &str) -> Option<f64> {
    factor(TIME_UNITS, u)
}

fn volume_unit(u: &str) -> Option<f64> {
    factor(VOLUME_UNITS, u)
}

fn is_unit_word(w: &str) -> bool {
    // Units only in brackets or after the quantity (`pressure_atm`): in a
    // name, `min` is a minimum (`p_min`) and `atm` the ambient (`p_atm`).
    if matches!(w, "min" | "atm") {
        return false;
    }
    pressure_scale(w).is_some()
        || time_unit(w).is_some()
        || volume_unit(w).is_some()
        || matches!(w, "deg" | "rad" | "degca" | "grad")
}

/// A pressure column in `unit` (Pa per unit, or volts per unit: a
/// charge amplifier's relative output).
fn pressure_role(unit: Result<f64, f64>, cylinder: Option<u32>, index: Option<u32>) -> Role {
    match unit {
        Ok(scale) => Role::Pressure {
            scale,
            cylinder,
            index,
        },
        Err(scale) => Role::Volts {
            scale,
            cylinder,
            index,
        },
    }
}

/// What a column name holds.
pub(crate) fn recognise(raw: &str) -> Result<Role, Unread> {
    let s = raw.trim().trim_matches('"').trim();
    let lower = s.to_lowercase();
    match lower.as_str() {
        "" | "_" => return Ok(Role::Skip),
        "crank_deg" => return Ok(Role::Angle(1.0)),
        "torque_cylinder_nm" => return Ok(Role::Torque(Quantity::CylinderTorque)),
        "torque_engine_nm" => return Ok(Role::Torque(Quantity::EngineTorque)),
        "cycle" => return Ok(Role::Cycle),
        "cylinder" => return Ok(Role::Cylinder),
        "tdc" => return Ok(Role::Tdc),
        "encoder" => return Ok(Role::Encoder),
        "wheel" => return Ok(Role::Wheel),
        "cam" => return Ok(Role::Cam),
        n => {
            // `volume_cm3`, `time_ms`, `pressure_kgf_cm2`, `pressure_v`: the
            // unit after the quantity, read from the unit tables.
            let (quantity, unit) = n.split_once('_').unwrap_or((n, ""));
            let unit = unit.replace('_', "");
            let role = match quantity {
                "volume" => volume_unit(&unit).map(Role::Volume),
                "time" => time_unit(&unit).map(Role::Time),
                "pressure" => pressure_scale(&unit).map(|s| pressure_role(s, None, None)),
                _ => None,
            };
            if let Some(r) = role {
                return Ok(r);
            }
        }
    }
    let (mut w, bracket) = words(s);
    // The unit: in brackets, else the last unit word (`pressure_bar_1`).
    let unit = match bracket {
        Some(u) => u,
        None => match w.iter().rposition(|x| is_unit_word(x)) {
            // A lone unit word is the name itself (`deg`, `bar`).
            Some(i) if w.len() > 1 => w.remove(i),
            _ => String::new(),
        },
    };
    let mut cylinder = None;
    let mut index = None;
    let mut names: Vec<&str> = Vec::new();
    let mut after_cyl = false;
    for x in &w {
        if x.bytes().all(|b| b.is_ascii_digit()) {
            let n: Option<u32> = x.parse().ok();
            if after_cyl {
                cylinder = n;
            } else {
                index = n;
            }
            after_cyl = false;
            continue;
        }
        // `PCYL1`, `PZYL1`: the pressure word that names a cylinder.
        after_cyl =
            CYLINDER_WORDS.contains(&x.as_str()) || matches!(x.as_str(), "c" | "pcyl" | "pzyl");
        names.push(x);
    }
    let has = |set: &[&str]| names.iter().any(|n| set.contains(n));
    let unit = unit.as_str();
    // Torque, as dynamometers write it: `Torque [Nm]`, `Drehmoment [N m]`,
    // `M [Nm]`; the engine's unless the name says a cylinder's.
    let torque_unit = if unit.is_empty() && names.contains(&"nm") {
        "nm"
    } else {
        unit
    };
    if has(TORQUE_WORDS) || (matches!(names.as_slice(), ["m"] | ["md"]) && torque_unit == "nm") {
        let q = if has(CYLINDER_WORDS) || cylinder.is_some() {
            Quantity::CylinderTorque
        } else {
            Quantity::EngineTorque
        };
        return match torque_unit {
            "nm" => Ok(Role::Torque(q)),
            "" => Err(Unread::NoUnit("torque", "Torque [Nm]")),
            u => Err(Unread::BadUnit("a torque unit: N m", u.to_string())),
        };
    }
    if has(PRESSURE_WORDS)
        || (names.is_empty() || names == ["deg"]) && pressure_scale(unit).is_some()
        || names.len() == 1 && pressure_scale(names[0]).is_some()
    {
        let u = if unit.is_empty() && names.len() == 1 && pressure_scale(names[0]).is_some() {
            names[0]
        } else {
            unit
        };
        return match pressure_scale(u) {
            Some(unit) => Ok(pressure_role(unit, cylinder, index)),
            None if u.is_empty() => Err(Unread::NoUnit("pressure", "Pressure [bar]")),
            None => Err(Unread::BadUnit(
                "a pressure unit: bar, mbar, MPa, kPa, Pa, psi, kgf/cm2 or V",
                u.to_string(),
            )),
        };
    }
    if has(ENCODER_WORDS) {
        return Ok(Role::Encoder);
    }
    if has(WHEEL_WORDS) {
        return Ok(Role::Wheel);
    }
    if has(CAM_WORDS) {
        return Ok(Role::Cam);
    }
    // `kW` is a dynamometer's power, never the German crank angle `KW`
    // (`°KW`, `KW [°]`, `Kurbelwinkel`): the case tells them apart.
    if is_kilowatt(s) {
        return Err(Unread::Unknown);
    }
    if has(ANGLE_WORDS) || names == ["deg"] || names.is_empty() && angle_unit(unit).is_some() {
        return match angle_unit(unit) {
            Some(s) => Ok(Role::Angle(s)),
            None => Err(Unread::BadUnit("an angle unit: deg or rad", unit.into())),
        };
    }
    if has(TIME_WORDS) || names.is_empty() && time_unit(unit).is_some() {
        return match time_unit(unit) {
            Some(s) => Ok(Role::Time(s)),
            None if unit.is_empty() => Err(Unread::NoUnit("time", "Time [s]")),
            None => Err(Unread::BadUnit("a time unit: s, ms or us", unit.into())),
        };
    }
    if has(TDC_WORDS) {
        return Ok(Role::Tdc);
    }
    if has(VOLUME_WORDS) {
        return match volume_unit(unit) {
            Some(s) => Ok(Role::Volume(s)),
            None if unit.is_empty() => Err(Unread::NoUnit("volume", "Volume [cm3]")),
            None => Err(Unread::BadUnit(
                "a volume unit: cm3, m3, l or mm3",
                unit.into(),
            )),
        };
    }
    if has(CYCLE_WORDS) {
        return Ok(Role::Cycle);
    }
    if has(CYLINDER_WORDS) {
        return Ok(Role::Cylinder);
    }
    Err(Unread::Unknown)
}

/// The first canonical name close to `n`, for a "did you mean".
fn close_known(n: &str) -> Option<&'static str> {
    KNOWN
        .iter()
        .max_by(|a, b| {
            enginedyn_numerics::format::name_similarity(n, a)
                .total_cmp(&enginedyn_numerics::format::name_similarity(n, b))
        })
        .copied()
        .filter(|k| enginedyn_numerics::format::close_name(n, k))
}

/// Why `name` cannot be read, as a message.
fn unread_message(name: &str, why: &Unread) -> String {
    let q = enginedyn_numerics::format::quote(name);
    // A near miss of a canonical name (`pressure_bars`): did you mean it?
    // A plain word without its unit (`Pressure`) is told what it lacks.
    let lower = name.trim().to_lowercase();
    if let Some(k) = close_known(&lower)
        && (*why == Unread::Unknown || lower.contains('_'))
    {
        return format!("unknown column `{q}`; did you mean `{k}`?");
    }
    match why {
        Unread::Unknown => format!("unknown column `{q}`"),
        Unread::NoUnit(what, example) => {
            format!("`{q}` is a {what} without a unit: write it as `{example}`")
        }
        Unread::BadUnit(expected, unit) => format!(
            "`{q}`: unit `{}` is not {expected}",
            enginedyn_numerics::format::quote(unit)
        ),
    }
}

/// The x column: what the traces run over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Axis {
    /// Crank angle (deg per unit).
    Angle(f64),
    /// Volume (m³ per unit): p–V data.
    Volume(f64),
    /// Time (s per unit): a time record.
    Time(f64),
}

/// One value column (pressure, volts or torque).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ValueCol {
    /// 0-based column.
    pub col: usize,
    /// Value unit per file unit (Pa, V or N m).
    pub scale: f64,
    /// The cylinder its name gives (0: none).
    pub cylinder: i64,
}

/// Where the columns are and what they hold.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Roles {
    pub x: usize,
    pub axis: Axis,
    /// One column (long layout, time record) or several (one cycle, or one
    /// cylinder, per column).
    pub values: Vec<ValueCol>,
    /// Each value column as messages name it: "column 2 `P [bar]` (in bar)".
    pub labels: Vec<String>,
    pub quantity: Quantity,
    /// The values are a charge amplifier's volts.
    pub volts: bool,
    /// Several value columns are cylinders (their names say so), not cycles.
    pub per_cylinder: bool,
    pub cycle: Option<usize>,
    pub cylinder: Option<usize>,
    pub tdc: Option<usize>,
    /// The crank's own signals of a time record: an encoder, a tooth wheel,
    /// a cam pulse (each `None` unless the axis is time).
    pub encoder: Option<usize>,
    pub wheel: Option<usize>,
    pub cam: Option<usize>,
    /// Columns the names cover.
    pub ncols: usize,
    /// How the columns were read, when that is worth saying.
    pub note: Option<String>,
}

/// Expands a trailing `...` (`pressure_bar...`) over `cells` columns.
pub(crate) fn expand(names: &[String], cells: usize) -> Vec<String> {
    match names.last() {
        Some(l) if l.ends_with("...") => {
            let base = l.trim_end_matches("...").trim().to_string();
            let mut out: Vec<String> = names[..names.len() - 1].to_vec();
            while out.len() < cells.max(names.len()) {
                out.push(base.clone());
            }
            out
        }
        _ => names.to_vec(),
    }
}

/// The x column of a record sampled on the crank angle without one
/// (`--angle-step`): no column of the file; row k lies at k times the step.
pub(crate) const STEPPED_X: usize = usize::MAX;

/// A value column as resolved: its role and what it is read as.
type Values = (Vec<(usize, Role)>, Quantity, bool);

/// The names of a header being resolved, phase by phase: each name read
/// ([`Names::read`]), the axis chosen ([`Names::axis`]), the signal and
/// numbering columns ([`Names::one`]), the value columns
/// ([`Names::values`]), the layout's checks ([`Names::layout`]) and the
/// note on how they were read ([`Names::note`]).
struct Names<'a> {
    names: &'a [String],
    explicit: bool,
    line: usize,
    want_torque: bool,
    /// Each name read, and its role.
    read: Vec<(usize, Role)>,
    /// Each name that cannot be read, and why (a header's only).
    unread: Vec<(usize, Unread)>,
    /// What is left out, as the note says it.
    left_out: Vec<String>,
}

impl<'a> Names<'a> {
    /// Phase 1: every name read. From a header, names that cannot be read
    /// are kept for the note; from `--columns` they are errors.
    fn read(
        names: &'a [String],
        explicit: bool,
        line: usize,
        want_torque: bool,
    ) -> Result<Self, IngestError> {
        let mut read = Vec::new();
        let mut unread = Vec::new();
        for (i, n) in names.iter().enumerate() {
            match recognise(n) {
                Ok(Role::Skip) => {}
                Ok(r) => read.push((i, r)),
                Err(why) if explicit => {
                    return Err(at(
                        line,
                        Some(i + 1),
                        format!(
                            "--columns: {} (known: {}; `_` skips a column; a trailing `...` repeats the last name)",
                            unread_message(n, &why),
                            KNOWN.join(", ")
                        ),
                    ));
                }
                Err(why) => unread.push((i, why)),
            }
        }
        Ok(Self {
            names,
            explicit,
            line,
            want_torque,
            read,
            unread,
            left_out: Vec::new(),
        })
    }

    /// The error for a column the header lacks: what was read, what not.
    fn missing(&self, what: &str) -> IngestError {
        let names = self.names;
        let mut m = format!("no {what} column");
        if !self.unread.is_empty() {
            let list: Vec<String> = self
                .unread
                .iter()
                .map(|(i, why)| format!("{} (column {})", unread_message(&names[*i], why), i + 1))
                .collect();
            m.push_str(&format!(": {}", list.join("; ")));
        }
        let readable: Vec<String> = self
            .read
            .iter()
            .map(|(i, r)| {
                format!(
                    "`{}` as {}",
                    enginedyn_numerics::format::quote(&names[*i]),
                    r.describe()
                )
            })
            .collect();
        if !readable.is_empty() {
            m.push_str(&format!("; read: {}", readable.join(", ")));
        }
        m.push_str(&format!(
            "; known names: {} and spellings such as `Crank Angle [deg]` or {}; --columns names the columns",
            KNOWN.join(", "),
            if self.want_torque {
                "`Torque [Nm]` (the engine's; `Torque Cyl [Nm]` one cylinder's)"
            } else {
                "`Pressure [bar]`"
            }
        ));
        if what.starts_with("crank angle") && !self.want_torque {
            m.push_str(
                "; a pressure-only record sampled on the crank angle (a DAQ clocked by the encoder) reads with --angle-step DEG",
            );
        }
        at(self.line, None, m)
    }

    /// The columns whose role `f` accepts, in file order.
    fn all(&self, f: fn(&Role) -> bool) -> Vec<(usize, Role)> {
        self.read
            .iter()
            .filter(|(_, r)| f(r))
            .map(|(i, r)| (*i, *r))
            .collect()
    }

    /// Phase 2: the x column: the angle, else the volume, else the time;
    /// the others left out. `stepped` (`--angle-step`): there is none, and
    /// a file that has one is an error.
    fn axis(&mut self, stepped: bool) -> Result<(usize, Axis), IngestError> {
        let angles = self.all(|r| matches!(r, Role::Angle(_)));
        let volumes = self.all(|r| matches!(r, Role::Volume(_)));
        let times = self.all(|r| matches!(r, Role::Time(_)));
        if stepped {
            if let Some(&(i, _)) = angles.first().or(volumes.first()).or(times.first()) {
                return Err(at(
                    self.line,
                    Some(i + 1),
                    format!(
                        "--angle-step gives the angle of a record without an angle, volume or time column; this one has `{}`: leave --angle-step out",
                        enginedyn_numerics::format::quote(&self.names[i])
                    ),
                ));
            }
            return Ok((STEPPED_X, Axis::Angle(1.0)));
        }
        let (x, axis) = match (angles.first(), volumes.first(), times.first()) {
            (Some(&(i, Role::Angle(s))), _, _) => (i, Axis::Angle(s)),
            (None, Some(&(i, Role::Volume(s))), _) => (i, Axis::Volume(s)),
            (None, None, Some(&(i, Role::Time(s)))) => (i, Axis::Time(s)),
            _ => return Err(self.missing("crank angle (or volume, or time)")),
        };
        for (i, _) in angles.iter().chain(&volumes).chain(&times) {
            if *i != x {
                self.left_out.push(format!(
                    "`{}` (the {} is used)",
                    enginedyn_numerics::format::quote(&self.names[*i]),
                    match axis {
                        Axis::Angle(_) => "angle",
                        Axis::Volume(_) => "volume",
                        Axis::Time(_) => "time",
                    }
                ));
            }
        }
        Ok((x, axis))
    }

    /// Phase 3: the one column of a role (cycle, cylinder, a signal), if
    /// any; two are an error.
    fn one(&self, f: fn(&Role) -> bool, what: &str) -> Result<Option<usize>, IngestError> {
        let v = self.all(f);
        if v.len() > 1 {
            return Err(at(
                self.line,
                Some(v[1].0 + 1),
                format!(
                    "two {what} columns (columns {} and {}): skip one with `_` in --columns",
                    v[0].0 + 1,
                    v[1].0 + 1
                ),
            ));
        }
        Ok(v.first().map(|(i, _)| *i))
    }

    /// Phase 4: the value columns, one kind: torque, pressure or volts.
    fn values(&self) -> Result<Values, IngestError> {
        let torque = self.all(|r| matches!(r, Role::Torque(_)));
        let pressures = self.all(|r| matches!(r, Role::Pressure { .. }));
        let volts = self.all(|r| matches!(r, Role::Volts { .. }));
        match (torque.is_empty(), pressures.is_empty(), volts.is_empty()) {
            (false, true, true) => {
                let q = match torque[0].1 {
                    Role::Torque(q) => q,
                    _ => Quantity::CylinderTorque,
                };
                if torque.len() > 1 {
                    return Err(at(
                        self.line,
                        Some(torque[1].0 + 1),
                        "two torque columns: a turning-moment file has one",
                    ));
                }
                Ok((torque, q, false))
            }
            (true, false, true) => Ok((pressures, Quantity::Pressure, false)),
            (true, true, false) => Ok((volts, Quantity::Pressure, true)),
            // A turning-moment file (`--torque`) is told about torque.
            (true, true, true) if self.want_torque => Err(self.missing("torque")),
            (true, true, true) => Err(self.missing("pressure")),
            _ => Err(at(
                self.line,
                None,
                "pressure, voltage and torque columns mixed: a diagram holds one kind (skip the others with `_` in --columns)",
            )),
        }
    }

    /// Phase 5: what several value columns allow (one cycle or one
    /// cylinder per column is read against crank angle, without a cycle or
    /// cylinder column; a time record takes one column per cylinder).
    fn layout(
        &self,
        values: &[ValueCol],
        (axis, per_cylinder): (Axis, bool),
        x: usize,
        numbered: Option<usize>,
    ) -> Result<(), IngestError> {
        if values.len() <= 1 {
            return Ok(());
        }
        let time = matches!(axis, Axis::Time(_));
        if let Some(c) = numbered {
            return Err(at(
                self.line,
                Some(c + 1),
                "several pressure columns and a cycle or cylinder column: give one pressure column per row (long layout), or one cycle per column without cycle and cylinder columns",
            ));
        }
        if time && per_cylinder {
            return Ok(());
        }
        if time || matches!(axis, Axis::Volume(_)) || x == STEPPED_X {
            return Err(at(
                self.line,
                Some(values[1].col + 1),
                if x == STEPPED_X {
                    "several pressure columns: --angle-step reads one pressure column, a row a step; skip the others with `_` in --columns"
                } else {
                    "several pressure columns: one cycle per column is read against crank angle, not time or volume; skip the others with `_` in --columns"
                },
            ));
        }
        Ok(())
    }

    /// Phase 6: the note on how the names were read, when any is not
    /// canonical or a column is left out (never for `--columns`).
    fn note(&self, used: &[usize], values: &[ValueCol]) -> Option<String> {
        let names = self.names;
        let canonical = self
            .read
            .iter()
            .all(|(i, _)| KNOWN.contains(&names[*i].trim().to_lowercase().as_str()));
        if self.explicit || (canonical && self.left_out.is_empty()) {
            return None;
        }
        let mut shown: Vec<String> = Vec::new();
        let many = values.len() > 3;
        for (i, r) in &self.read {
            if !used.contains(i) {
                continue;
            }
            if many && values.iter().skip(1).any(|v| v.col == *i) {
                continue;
            }
            shown.push(format!(
                "`{}` as {}",
                enginedyn_numerics::format::quote(&names[*i]),
                r.describe()
            ));
        }
        if many {
            shown.push(format!(
                "and {} more pressure columns like it",
                values.len() - 1
            ));
        }
        let mut n = format!("columns read: {}", shown.join(", "));
        if !self.left_out.is_empty() {
            n.push_str(&format!("; left out: {}", self.left_out.join("; ")));
        }
        Some(n)
    }
}

impl Roles {
    /// Resolves `names` (header cells, or `--columns` when `explicit`).
    /// From a header, names that cannot be read are left out with a note;
    /// from `--columns` they are errors. `line` is where the names are.
    pub(crate) fn resolve(
        names: &[String],
        explicit: bool,
        line: usize,
        want_torque: bool,
    ) -> Result<Roles, IngestError> {
        Self::resolve_with(names, explicit, line, want_torque, false)
    }

    /// [`Self::resolve`]; `stepped` (`--angle-step`): the record has no x
    /// column, its rows lie a step apart on the crank angle ([`STEPPED_X`]).
    pub(crate) fn resolve_with(
        names: &[String],
        explicit: bool,
        line: usize,
        want_torque: bool,
        stepped: bool,
    ) -> Result<Roles, IngestError> {
        let mut n = Names::read(names, explicit, line, want_torque)?;
        let (x, axis) = n.axis(stepped)?;
        let cycle = n.one(|r| matches!(r, Role::Cycle), "cycle")?;
        let cylinder = n.one(|r| matches!(r, Role::Cylinder), "cylinder")?;
        let tdc = n.one(|r| matches!(r, Role::Tdc), "TDC pulse")?;
        let encoder = n.one(|r| matches!(r, Role::Encoder), "encoder")?;
        let wheel = n.one(|r| matches!(r, Role::Wheel), "tooth wheel")?;
        let cam = n.one(|r| matches!(r, Role::Cam), "cam")?;
        if x == STEPPED_X
            && let Some(c) = cycle
        {
            return Err(at(
                line,
                Some(c + 1),
                "--angle-step and a cycle column: a record sampled on the crank angle is one run of rows, cut at each firing TDC",
            ));
        }
        let (values, quantity, is_volts) = n.values()?;
        let labels: Vec<String> = values
            .iter()
            .map(|&(col, r)| {
                let unit = match r {
                    Role::Pressure { scale, .. } => unit_name(PRESSURE_UNITS, scale),
                    Role::Volts { .. } => "V",
                    _ => "N m",
                };
                format!(
                    "column {} `{}` (in {unit})",
                    col + 1,
                    enginedyn_numerics::format::quote(&names[col])
                )
            })
            .collect();
        let values: Vec<ValueCol> = values
            .iter()
            .map(|&(col, r)| {
                let (scale, cyl) = match r {
                    Role::Pressure {
                        scale, cylinder, ..
                    }
                    | Role::Volts {
                        scale, cylinder, ..
                    } => (scale, cylinder),
                    _ => (1.0, None),
                };
                ValueCol {
                    col,
                    scale,
                    cylinder: cyl.map_or(0, i64::from),
                }
            })
            .collect();
        // Several columns naming distinct cylinders are one trace per
        // cylinder; otherwise one cycle per column.
        let per_cylinder = values.len() > 1 && {
            let mut c: Vec<i64> = values.iter().map(|v| v.cylinder).collect();
            c.sort_unstable();
            c[0] > 0 && c.windows(2).all(|w| w[0] != w[1])
        };
        n.layout(&values, (axis, per_cylinder), x, cycle.or(cylinder))?;
        for (i, why) in &n.unread {
            n.left_out.push(match why {
                Unread::Unknown => format!(
                    "`{}` (not a name enginedyn reads)",
                    enginedyn_numerics::format::quote(&names[*i])
                ),
                _ => unread_message(&names[*i], why),
            });
        }
        let time = matches!(axis, Axis::Time(_));
        for (col, what) in [
            (tdc, "a TDC pulse"),
            (encoder, "an encoder"),
            (wheel, "a tooth wheel"),
            (cam, "a cam pulse"),
        ] {
            if let Some(i) = col.filter(|_| !time) {
                n.left_out.push(format!(
                    "`{}` ({what} is used with a time column only)",
                    enginedyn_numerics::format::quote(&names[i])
                ));
            }
        }
        let used: Vec<usize> = std::iter::once(x)
            .chain(values.iter().map(|v| v.col))
            .chain(cycle)
            .chain(cylinder)
            .chain(
                [tdc, encoder, wheel, cam]
                    .into_iter()
                    .flatten()
                    .filter(|_| time),
            )
            .collect();
        let note = n.note(&used, &values);
        Ok(Roles {
            x,
            axis,
            values,
            labels,
            quantity,
            volts: is_volts,
            per_cylinder,
            cycle,
            cylinder,
            tdc: tdc.filter(|_| time),
            encoder: encoder.filter(|_| time),
            wheel: wheel.filter(|_| time),
            cam: cam.filter(|_| time),
            ncols: names.len(),
            note,
        })
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn kilowatts_are_no_angle() {
        for power in ["P [kW]", "Leistung (kW)", "Power_kW", "kW"] {
            assert!(!matches!(recognise(power), Ok(Role::Angle(_))), "{power}");
        }
        for angle in [
            "Kurbelwinkel [°KW]",
            "KW [°]",
            "°CA",
            "Kurbelwinkel",
            "CA [deg]",
        ] {
            assert!(matches!(recognise(angle), Ok(Role::Angle(_))), "{angle}");
        }
    }

    use super::*;

    fn p(scale: f64, cylinder: Option<u32>, index: Option<u32>) -> Role {
        Role::Pressure {
            scale,
            cylinder,
            index,
        }
    }

    /// The spellings INTERFACE.md lists, and a few more tools write.
    #[test]
    fn names_as_tools_write_them() {
        let cases: &[(&str, Role)] = &[
            ("Crank Angle [deg]", Role::Angle(1.0)),
            ("CA (deg)", Role::Angle(1.0)),
            ("Crank_angle[deg.]", Role::Angle(1.0)),
            ("theta", Role::Angle(1.0)),
            ("Kurbelwinkel [°KW]", Role::Angle(1.0)),
            ("Pressure [bar]", p(1e5, None, None)),
            ("P_cyl1 (MPa)", p(1e6, Some(1), None)),
            ("Pressure[bar]_Cyl01", p(1e5, Some(1), None)),
            ("Zylinderdruck [bar]", p(1e5, None, None)),
            ("pressure_bar_2", p(1e5, None, Some(2))),
            ("Pressure [bar] 2", p(1e5, None, Some(2))),
            ("Time_[s]", Role::Time(1.0)),
            ("time (ms)", Role::Time(1e-3)),
            ("Volume [cm³]", Role::Volume(1e-6)),
            ("TDC", Role::Tdc),
            ("Cycle No.", Role::Cycle),
            ("Zylinder", Role::Cylinder),
            ("p [psi]", p(PSI, None, None)),
        ];
        for (name, want) in cases {
            assert_eq!(recognise(name).as_ref(), Ok(want), "{name}");
        }
        assert_eq!(
            recognise("Pressure"),
            Err(Unread::NoUnit("pressure", "Pressure [bar]"))
        );
        assert_eq!(recognise("Comment"), Err(Unread::Unknown));
        assert!(matches!(
            recognise("Pressure [furlong]"),
            Err(Unread::BadUnit(..))
        ));
    }

    #[test]
    fn several_pressure_columns() {
        let names: Vec<String> = ["CA [deg]", "p_1 [bar]", "p_2 [bar]"]
            .map(String::from)
            .to_vec();
        let r = Roles::resolve(&names, false, 1, false).unwrap();
        assert_eq!(r.values.len(), 2);
        assert!(!r.per_cylinder);
        let names: Vec<String> = ["CA [deg]", "Pressure[bar]_Cyl01", "Pressure[bar]_Cyl02"]
            .map(String::from)
            .to_vec();
        assert!(
            Roles::resolve(&names, false, 1, false)
                .unwrap()
                .per_cylinder
        );
        assert_eq!(
            expand(&["crank_deg".into(), "pressure_bar...".into()], 4).len(),
            4
        );
    }
}
