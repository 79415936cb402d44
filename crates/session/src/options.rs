//! Reader and method options: plain structs, their bounds checked in one
//! place. The CLI's flag parsers and the Python package's keyword
//! arguments both come here, so a bound, a default or its message is
//! written once.

use crate::error::{Error, Result};
use enginedyn_numerics::format::{human, quote};

/// A number from `lo` to `hi` (both included), read by the one number rule
/// of cells, banners and comment lines, or why not.
pub fn number_in(s: &str, lo: f64, hi: f64, unit: &str) -> std::result::Result<f64, String> {
    let v = enginedyn_ingest::read_number(s, false).map_err(|e| format!("`{}` {e}", quote(s)))?;
    within(v, lo, hi, unit).map_err(|_| {
        format!(
            "{} is outside {} to {}{unit}",
            quote(s.trim()),
            human(lo),
            human(hi)
        )
    })
}

fn within(v: f64, lo: f64, hi: f64, unit: &str) -> std::result::Result<f64, String> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(format!(
            "{} is outside {} to {}{unit}",
            human(v),
            human(lo),
            human(hi)
        ))
    }
}

/// One option's bound: its range, its unit, and whether its low end is
/// excluded (with the message when it is reached).
#[derive(Debug, Clone, Copy)]
pub struct Bound {
    /// The lowest value.
    pub lo: f64,
    /// The highest value.
    pub hi: f64,
    /// The unit as a message writes it after a number (`°`, ` bar`).
    pub unit: &'static str,
    /// `Some(why)`: the low end itself is refused, saying why.
    pub above_lo: Option<&'static str>,
}

impl Bound {
    const fn closed(lo: f64, hi: f64, unit: &'static str) -> Self {
        Self {
            lo,
            hi,
            unit,
            above_lo: None,
        }
    }
    /// A value as the user wrote it (a flag): read, then checked.
    pub fn read(&self, s: &str) -> std::result::Result<f64, String> {
        let v = number_in(s, self.lo, self.hi, self.unit)?;
        self.check_low(v)
    }
    /// A value already a number (a keyword argument), checked.
    pub fn check(&self, v: f64) -> std::result::Result<f64, String> {
        let v = within(v, self.lo, self.hi, self.unit)?;
        self.check_low(v)
    }
    fn check_low(&self, v: f64) -> std::result::Result<f64, String> {
        match self.above_lo {
            Some(why) if v <= self.lo => Err(why.to_string()),
            _ => Ok(v),
        }
    }
}

/// The grid step (deg), INTERFACE.md's "Limits".
pub const STEP: Bound = Bound::closed(0.001, 10.0, "°");
/// The grid step when none is given (deg).
pub const DEFAULT_STEP_DEG: f64 = 0.1;
/// `tdc_deg`: any finite offset a file's angles can carry.
pub const TDC_DEG: Bound = Bound::closed(-1e5, 1e5, "°");
/// `peg_bar`: an absolute pressure above 0 up to 10 kbar.
pub const PEG_BAR: Bound = Bound {
    lo: 0.0,
    hi: 1e4,
    unit: " bar",
    above_lo: Some("an absolute pressure above 0 bar is needed"),
};
/// `max_gap_deg`: 0 to 360°.
pub const MAX_GAP: Bound = Bound::closed(0.0, enginedyn_ingest::MAX_GAP_BOUND_DEG, "°");
/// `tdc_time`: any finite time within ±1e9 s.
pub const TDC_TIME: Bound = Bound::closed(-1e9, 1e9, "");
/// `gain_bar_per_v`: above 0 up to 1e6 bar per volt.
pub const GAIN: Bound = Bound {
    lo: 0.0,
    hi: 1e6,
    unit: " bar/V",
    above_lo: Some("a gain above 0 bar/V is needed"),
};
/// `wheel_tdc_deg`: within a revolution either way.
pub const WHEEL_TDC_DEG: Bound = Bound::closed(
    -enginedyn_ingest::MAX_WHEEL_TDC_DEG,
    enginedyn_ingest::MAX_WHEEL_TDC_DEG,
    "°",
);
/// `angle_step`: the crank angle between rows of a record sampled on the
/// crank angle (deg): an encoder's step, from 0.001° to 10°.
pub const ANGLE_STEP: Bound = Bound::closed(0.001, 10.0, "°");
/// `encoder_ppr`: pulses a revolution, 1 to this.
pub const MAX_ENCODER_PPR: u32 = enginedyn_ingest::MAX_ENCODER_PPR;
/// `group`: an MDF4 channel group, 1 to this.
pub const MAX_GROUP: u32 = 1_000_000;
/// `tolerance`: a relative error from 1e-6 to 0.5.
pub const TOLERANCE: Bound = Bound::closed(1e-6, 0.5, "");
/// `skip_lines`: up to a million.
pub const MAX_SKIP_LINES: u32 = 1_000_000;
/// The most worker threads of a batch (INTERFACE.md, "Limits").
pub const MAX_JOBS: usize = 256;
/// The most Monte Carlo samples (INTERFACE.md, "Limits").
pub const MAX_SAMPLES: u64 = 10_000_000;
/// The default polytropic exponent of `peg = polytropic`.
pub const POLYTROPIC_N: f64 = 1.32;

/// An engine speed as the user wrote it: read by the one speed reader of
/// the diagram's `# rpm` line and banners (`4.9e3`, `4,900`; held to the
/// speed bound).
pub fn read_rpm(s: &str) -> std::result::Result<f64, String> {
    enginedyn_ingest::read_rpm(s).map_err(|e| match e {
        enginedyn_ingest::SpeedError::Number(n) => {
            format!("`{s}` {n}: the engine speed must be a number of rpm from 0.001 to 100000 rpm")
        }
        e => format!(
            "{} rpm {e}",
            human(enginedyn_ingest::read_number(s, false).unwrap_or(f64::NAN))
        ),
    })
}

/// An engine speed given as a number, held to the speed bound.
pub fn check_rpm(v: f64) -> std::result::Result<f64, String> {
    enginedyn_ingest::check_rpm(v).map_err(|e| format!("{} rpm {e}", human(v)))
}

/// Reads `polytropic` or `polytropic=N` (1 < N < 2): the exponent.
pub fn read_peg(s: &str) -> std::result::Result<f64, String> {
    let t = s.trim();
    let rest = t
        .strip_prefix("polytropic")
        .ok_or_else(|| format!("expected polytropic or polytropic=N, not `{t}`"))?;
    if rest.is_empty() {
        return Ok(POLYTROPIC_N);
    }
    rest.strip_prefix('=')
        .and_then(|v| enginedyn_ingest::read_number(v, false).ok())
        .filter(|n| check_polytropic(*n).is_ok())
        .ok_or_else(|| format!("expected polytropic=N with 1 < N < 2, not `{t}`"))
}

/// A polytropic exponent for pegging: 1 < N < 2.
pub fn check_polytropic(n: f64) -> std::result::Result<f64, String> {
    if n.is_finite() && n > 1.0 && n < 2.0 {
        Ok(n)
    } else {
        Err(format!(
            "polytropic exponent {}: 1 < N < 2 is needed",
            human(n)
        ))
    }
}

/// Per-cylinder traces: over cylinder 1's crank angle, or each over its own.
pub use enginedyn_ingest::CylinderAxis;

/// How a diagram is read (INTERFACE.md, "Indicator diagram"): the reader
/// flags of `run`, `batch`, `sweep` and the studies.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Reader {
    /// Per-cylinder traces over cylinder 1's angle or each over its own
    /// (`None`: from where the peaks lie).
    pub cylinder_axis: Option<CylinderAxis>,
    /// The file's angle value that is firing TDC (deg).
    pub tdc_deg: Option<f64>,
    /// Pressures are gauge (relative to 1.01325 bar).
    pub gauge: bool,
    /// Column names for a file without a header (or replacing it).
    pub columns: Option<Vec<String>>,
    /// Peg each cycle at this absolute pressure (bar) around intake BDC.
    pub peg_bar: Option<f64>,
    /// Peg each cycle so p V^N is constant on compression: N.
    pub peg_polytropic: Option<f64>,
    /// p–V data starts at the BDC before firing TDC (else at firing TDC).
    pub pv_start_bdc: bool,
    /// Lines skipped at the top of the file.
    pub skip_lines: Option<u32>,
    /// A workbook's sheet: its name or its number from 1.
    pub sheet: Option<String>,
    /// The widest gap bridged in a single digitised cycle (deg).
    pub max_gap_deg: Option<f64>,
    /// A time record's firing TDC time (s).
    pub tdc_time: Option<f64>,
    /// A charge amplifier's gain (bar per volt).
    pub gain_bar_per_v: Option<f64>,
    /// The engine speed (rpm): overrides the diagram's and the engine file's.
    pub rpm: Option<f64>,
    /// An MDF4 file's channel group, from 1 (default: the first that holds
    /// a pressure).
    pub group: Option<u32>,
    /// A time record's `encoder` column: pulses a revolution.
    pub encoder_ppr: Option<u32>,
    /// A time record's `wheel` column: the tooth wheel (60-2, 36-1, …).
    pub wheel: Option<enginedyn_ingest::Wheel>,
    /// The angle (deg) from the wheel's first tooth after the gap to
    /// cylinder 1's TDC.
    pub wheel_tdc_deg: Option<f64>,
    /// `--no-compression-check`: the trace is read as the cylinder's
    /// pressure without the checks that assume a compressing engine (the
    /// compression bound, the peak-angle rule).
    pub no_compression_check: bool,
    /// `--despike`: each glitch (a lone sample off the cubic through its
    /// neighbours by more than 10 bar and 20 % of the cycle's peak) is
    /// replaced by that cubic.
    pub despike: bool,
    /// A pressure-only record sampled on the crank angle: row k is at the
    /// angle k times this (deg).
    pub angle_step_deg: Option<f64>,
}

/// The name `table` gives `value`.
fn name_of<T: PartialEq>(table: &[(&'static str, T)], value: &T) -> &'static str {
    table
        .iter()
        .find(|(_, v)| v == value)
        .map_or("", |(n, _)| n)
}

impl Reader {
    /// The options given, by their names (the `options` a campaign's parts
    /// record).
    pub fn json(&self) -> serde_json::Value {
        let mut o = serde_json::Map::new();
        let mut put = |k: &str, v: serde_json::Value| {
            if !v.is_null() {
                o.insert(k.to_string(), v);
            }
        };
        put(
            "cylinder_axis",
            self.cylinder_axis
                .map(|a| name_of(CYLINDER_AXES, &a))
                .into(),
        );
        put("tdc_deg", self.tdc_deg.into());
        if self.gauge {
            put("gauge", true.into());
        }
        put("columns", self.columns.clone().into());
        put("peg_bar", self.peg_bar.into());
        put(
            "peg",
            self.peg_polytropic
                .map(|n| format!("polytropic={n}"))
                .into(),
        );
        if self.pv_start_bdc {
            put("pv_start", "bdc".into());
        }
        put("skip_lines", self.skip_lines.into());
        put("sheet", self.sheet.clone().into());
        put("group", self.group.into());
        put("max_gap_deg", self.max_gap_deg.into());
        put("tdc_time", self.tdc_time.into());
        put("gain_bar_per_v", self.gain_bar_per_v.into());
        put("rpm", self.rpm.into());
        put("encoder_ppr", self.encoder_ppr.into());
        put("wheel", self.wheel.map(|w| w.to_string()).into());
        put("wheel_tdc_deg", self.wheel_tdc_deg.into());
        if self.no_compression_check {
            put("compression_check", false.into());
        }
        if self.despike {
            put("despike", true.into());
        }
        put("angle_step", self.angle_step_deg.into());
        serde_json::Value::Object(o)
    }

    /// Every bound checked; the error names the option as `name` gives it
    /// (the CLI's flags are checked by their parsers before this).
    pub fn check(&self, name: impl Fn(&str) -> String) -> Result<()> {
        let bad = |field: &str, why: String| Error::usage(format!("{}: {why}", name(field)));
        let each: [(&str, Option<f64>, &Bound); 7] = [
            ("angle_step", self.angle_step_deg, &ANGLE_STEP),
            ("tdc_deg", self.tdc_deg, &TDC_DEG),
            ("wheel_tdc_deg", self.wheel_tdc_deg, &WHEEL_TDC_DEG),
            ("peg_bar", self.peg_bar, &PEG_BAR),
            ("max_gap_deg", self.max_gap_deg, &MAX_GAP),
            ("tdc_time", self.tdc_time, &TDC_TIME),
            ("gain_bar_per_v", self.gain_bar_per_v, &GAIN),
        ];
        for (field, v, b) in each {
            if let Some(v) = v {
                b.check(v).map_err(|w| bad(field, w))?;
            }
        }
        if self.peg_bar.is_some() && self.peg_polytropic.is_some() {
            return Err(bad(
                "peg",
                format!("cannot be used with {}", name("peg_bar")),
            ));
        }
        if let Some(n) = self.peg_polytropic {
            check_polytropic(n).map_err(|w| bad("peg", w))?;
        }
        if let Some(n) = self.skip_lines
            && n > MAX_SKIP_LINES
        {
            return Err(bad(
                "skip_lines",
                format!("{n} is outside 0 to {MAX_SKIP_LINES}"),
            ));
        }
        if let Some(r) = self.rpm {
            check_rpm(r).map_err(|w| bad("rpm", w))?;
        }
        if let Some(n) = self.group
            && !(1..=MAX_GROUP).contains(&n)
        {
            return Err(bad("group", format!("{n} is outside 1 to {MAX_GROUP}")));
        }
        if let Some(n) = self.encoder_ppr
            && !(1..=MAX_ENCODER_PPR).contains(&n)
        {
            return Err(bad(
                "encoder_ppr",
                format!("{n} is outside 1 to {MAX_ENCODER_PPR}"),
            ));
        }
        Ok(())
    }
}

/// How the computation is done (INTERFACE.md's method options). Each is
/// `None` unless given, so that a tolerance can keep the ones given.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Method {
    /// Grid step (deg) [default: 0.1].
    pub step_deg: Option<f64>,
    /// Piston kinematics [default: exact].
    pub kinematics: Option<enginedyn_kinematics::Model>,
    /// Connecting-rod mass model [default: the engine file's].
    pub rod_model: Option<enginedyn_engine::RodModel>,
    /// Interpolation onto the grid [default: auto].
    pub interp: Option<enginedyn_ingest::Interp>,
    /// Integration rule [default: trapezoid].
    pub integration: Option<enginedyn_numerics::integrate::Rule>,
    /// The cheapest setting whose estimated relative error is below this.
    pub tolerance: Option<f64>,
    /// The combustion analysis' options.
    pub burn: crate::burn::BurnMethod,
}

impl Method {
    /// The options given, by their names (the `options` a campaign's parts
    /// record).
    pub fn json(&self) -> serde_json::Value {
        let mut o = serde_json::Map::new();
        let mut put = |k: &str, v: serde_json::Value| {
            if !v.is_null() {
                o.insert(k.to_string(), v);
            }
        };
        put("step_deg", self.step_deg.into());
        put(
            "kinematics",
            self.kinematics.map(|m| name_of(KINEMATICS, &m)).into(),
        );
        put(
            "rod_model",
            self.rod_model.map(|m| name_of(ROD_MODELS, &m)).into(),
        );
        put(
            "interp",
            self.interp.map(|m| name_of(INTERPOLANTS, &m)).into(),
        );
        put(
            "integration",
            self.integration.map(|m| name_of(INTEGRATIONS, &m)).into(),
        );
        put("tolerance", self.tolerance.into());
        self.burn.json(&mut o);
        serde_json::Value::Object(o)
    }

    /// The options as they are used, defaults filled in (the rod model the
    /// engine file's when none is given): what a campaign's parts record
    /// and `merge` compares, so that `--step 0.1` is no flag at all.
    pub fn resolved_json(&self, engine_rod_model: enginedyn_engine::RodModel) -> serde_json::Value {
        let d = self.options();
        Method {
            step_deg: Some(self.step()),
            kinematics: Some(d.kinematics),
            rod_model: Some(self.rod_model.unwrap_or(engine_rod_model)),
            interp: Some(d.interp),
            integration: Some(d.integration),
            ..*self
        }
        .json()
    }

    /// The grid step (deg): given or the default.
    pub fn step(&self) -> f64 {
        self.step_deg.unwrap_or(DEFAULT_STEP_DEG)
    }

    /// The pipeline options, defaults where none is given.
    pub fn options(&self) -> enginedyn_pipeline::Options {
        let d = enginedyn_pipeline::Options::default();
        enginedyn_pipeline::Options {
            step_deg: self.step(),
            kinematics: self.kinematics.unwrap_or(d.kinematics),
            rod_model: self.rod_model,
            interp: self.interp.unwrap_or(d.interp),
            integration: self.integration.unwrap_or(d.integration),
            scope: enginedyn_pipeline::Scope::Full,
        }
    }

    /// The options given explicitly, which a tolerance keeps.
    pub fn kept(&self) -> enginedyn_accuracy::Kept {
        enginedyn_accuracy::Kept {
            step_deg: self.step_deg,
            kinematics: self.kinematics,
            rod_model: self.rod_model,
            interp: self.interp,
            integration: self.integration,
        }
    }

    /// Every bound checked; the error names the option as `name` gives it.
    pub fn check(&self, name: impl Fn(&str) -> String) -> Result<()> {
        if let Some(s) = self.step_deg {
            STEP.check(s)
                .map_err(|w| Error::usage(format!("{}: {w}", name("step_deg"))))?;
        }
        if let Some(t) = self.tolerance {
            check_tolerance(t, &name("tolerance"))?;
        }
        self.burn.check(&name)
    }
}

/// A tolerance (relative error) within its bound; `shown` names it.
pub fn check_tolerance(t: f64, shown: &str) -> Result<f64> {
    if (TOLERANCE.lo..=TOLERANCE.hi).contains(&t) {
        Ok(t)
    } else {
        Err(Error::usage(format!(
            "{shown} {t}: a relative error between 1e-6 and 0.5 is needed"
        )))
    }
}

/// The reader options by the names both front ends give them (the CLI's
/// flags without `--`, `-` as `_`; INTERFACE.md, "Python package").
pub const READER_KEYS: &[&str] = &[
    "cylinder_axis",
    "tdc_deg",
    "gauge",
    "columns",
    "peg_bar",
    "peg",
    "pv_start",
    "skip_lines",
    "sheet",
    "group",
    "max_gap_deg",
    "tdc_time",
    "gain_bar_per_v",
    "rpm",
    "encoder_ppr",
    "wheel",
    "wheel_tdc_deg",
    "compression_check",
    "despike",
    "angle_step",
];

/// The method options by name.
pub const METHOD_KEYS: &[&str] = &[
    "step_deg",
    "kinematics",
    "rod_model",
    "interp",
    "integration",
    "tolerance",
    "burn_points",
    "burn_window",
    "gamma",
    "smooth",
    "intake_temp_k",
    "ivc_deg",
    "wall_heat",
    "wall_temp_k",
    "knock",
    "knock_band",
    "knock_window",
    "knock_threshold",
];

/// `kinematics` by name.
pub const KINEMATICS: &[(&str, enginedyn_kinematics::Model)] = &[
    ("exact", enginedyn_kinematics::Model::Exact),
    ("series2", enginedyn_kinematics::Model::Series2),
    ("series4", enginedyn_kinematics::Model::Series4),
    ("series6", enginedyn_kinematics::Model::Series6),
];

/// `rod_model` by name.
pub const ROD_MODELS: &[(&str, enginedyn_engine::RodModel)] = &[
    ("two-mass", enginedyn_engine::RodModel::TwoMass),
    ("three-mass", enginedyn_engine::RodModel::ThreeMass),
    ("rigid", enginedyn_engine::RodModel::Rigid),
];

/// `interp` by name.
pub const INTERPOLANTS: &[(&str, enginedyn_ingest::Interp)] = &[
    ("auto", enginedyn_ingest::Interp::Auto),
    ("linear", enginedyn_ingest::Interp::Linear),
    ("spline", enginedyn_ingest::Interp::Spline),
    ("pchip", enginedyn_ingest::Interp::Pchip),
];

/// `integration` by name.
pub const INTEGRATIONS: &[(&str, enginedyn_numerics::integrate::Rule)] = &[
    ("trapezoid", enginedyn_numerics::integrate::Rule::Trapezoid),
    ("simpson", enginedyn_numerics::integrate::Rule::Simpson),
];

/// `cylinder_axis` by name.
pub const CYLINDER_AXES: &[(&str, CylinderAxis)] =
    &[("shared", CylinderAxis::Shared), ("own", CylinderAxis::Own)];

/// `pv_start` by name: `true` for the BDC before firing TDC.
pub const PV_STARTS: &[(&str, bool)] = &[("tdc", false), ("bdc", true)];

// ---- synthesis for design (issue 35, section 3): `synth`, `sweep --imep` ----

/// `--imep`: a net IMEP target (bar), above 0 up to 40 bar (the engine
/// file's `[combustion].imep_bar` bound, [`enginedyn_engine::combustion::MAX_IMEP_BAR`]).
pub const IMEP_BAR: Bound = Bound {
    lo: 0.0,
    hi: enginedyn_engine::combustion::MAX_IMEP_BAR,
    unit: " bar",
    above_lo: Some("an IMEP above 0 bar is needed"),
};

/// The row step of `enginedyn synth` without `--step` (deg): the analysis'
/// default grid, so that a run on it interpolates nothing.
pub const DEFAULT_SYNTH_STEP_DEG: f64 = DEFAULT_STEP_DEG;

/// The most loads of one `sweep --imep` map.
pub const MAX_LOADS: usize = 1_000;

/// The most points (speeds × loads) of one `sweep --rpm … --imep …` map,
/// as of one speed-only sweep ([`crate::speed::MAX_SPEEDS`]): each point
/// keeps only its summary (a few kB), so a map at the cap stays within
/// about 100 MB.
pub const MAX_MAP_POINTS: usize = 10_000;

/// A map of `speeds` × `loads` points within [`MAX_MAP_POINTS`]; past it a
/// usage error naming both flags (`rpm`, and the loads' flag and value as
/// given) and the cap.
pub fn check_map_size(
    speeds: usize,
    loads: usize,
    rpm: &str,
    (flag, imep): (&str, &str),
) -> Result<()> {
    let points = speeds.saturating_mul(loads);
    if points > MAX_MAP_POINTS {
        return Err(Error::usage(format!(
            "--rpm {} × {flag} {}: {speeds} speeds × {loads} loads = {points} points; a map computes at most {MAX_MAP_POINTS} (fewer speeds or loads, or a coarser step of either)",
            quote(rpm),
            quote(imep)
        )));
    }
    Ok(())
}

/// `--imep FROM:TO:STEP` (bar): FROM, FROM + STEP, … up to TO (included
/// when it falls on the step), each within [`IMEP_BAR`], at most
/// [`MAX_LOADS`].
pub fn imep_range(spec: &str) -> Result<Vec<f64>> {
    loads_range("--imep", spec, "in bar", |v| IMEP_BAR.check(v).map(|_| ()))
}

/// `--load FROM:TO:STEP` (percent of the full-load line): FROM, FROM +
/// STEP, … up to TO (included when it falls on the step), each above 0
/// and at most 100, at most [`MAX_LOADS`].
pub fn load_range(spec: &str) -> Result<Vec<f64>> {
    loads_range("--load", spec, "in percent of the full-load line", |v| {
        if v > 0.0 && v <= 100.0 {
            Ok(())
        } else {
            Err(format!("{} %: expected above 0, up to 100 %", human(v)))
        }
    })
}

/// The loads of `flag` `spec` (`FROM:TO:STEP`, `unit` as the message
/// says it), each end held to `check`, at most [`MAX_LOADS`].
fn loads_range(
    flag: &str,
    spec: &str,
    unit: &str,
    check: impl Fn(f64) -> std::result::Result<(), String>,
) -> Result<Vec<f64>> {
    let bad = |why: String| Error::usage(format!("{flag} {}: {why}", quote(spec)));
    let parts: Vec<f64> = spec
        .split(':')
        .map(|x| enginedyn_ingest::read_number(x, false))
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad(format!("expected FROM:TO:STEP {unit}")))?;
    let [from, to, step] = parts[..] else {
        return Err(bad(format!("expected FROM:TO:STEP {unit}")));
    };
    for v in [from, to] {
        check(v).map_err(bad)?;
    }
    if !(to >= from && step > 0.0 && step.is_finite()) {
        return Err(bad("expected FROM <= TO and STEP > 0".into()));
    }
    let n = ((to - from) / step + 1e-9).floor();
    if n + 1.0 > MAX_LOADS as f64 {
        return Err(bad(format!(
            "{} loads; a map takes at most {MAX_LOADS}",
            n + 1.0
        )));
    }
    Ok((0..=n as usize).map(|k| from + k as f64 * step).collect())
}
// ---- end synthesis for design ----

/// The command line's flags as the Python package's keywords
/// (INTERFACE.md, "Python package": messages raised in Python name the
/// keyword, not the flag). One table for every message: a front end that
/// takes keywords rewrites the shared message with [`in_keywords`].
pub const FLAG_KEYWORDS: &[(&str, &str)] = &[
    ("--step", "step_deg="),
    ("--diagram", "diagram="),
    ("--parts", "parts="),
    ("--shard", "part=/parts="),
    ("--jobs", "jobs="),
    ("--tdc-deg", "tdc_deg="),
    ("--columns", "columns="),
    ("--tdc-time", "tdc_time="),
    ("--rpm", "rpm="),
    ("--max-gap", "max_gap_deg="),
    ("--wheel-tdc-deg", "wheel_tdc_deg="),
    ("--sheet", "sheet="),
    ("--group", "group="),
    ("--wheel", "wheel="),
    ("--gain", "gain_bar_per_v="),
    ("--encoder-ppr", "encoder_ppr="),
    ("--angle-step", "angle_step="),
    ("--cylinder-axis", "cylinder_axis="),
    ("--tolerance", "tolerance="),
    ("--torque", "analyse_torque()"),
    ("--peg-bar", "peg_bar="),
    ("--peg", "peg="),
    ("--gauge", "gauge=True"),
    ("--no-compression-check", "compression_check=False"),
    ("--despike", "despike=True"),
    ("--gamma", "gamma="),
    ("--smooth", "smooth="),
    ("--skip-lines", "skip_lines="),
    ("--kinematics", "kinematics="),
    ("--rod-model", "rod_model="),
    ("--interp", "interp="),
    ("--integration", "integration="),
    ("--ivc-deg", "ivc_deg="),
    ("--intake-temp-k", "intake_temp_k="),
    ("--burn-window", "burn_window="),
    ("--burn-points", "burn_points="),
    ("--wall-heat", "wall_heat="),
    ("--wall-temp-k", "wall_temp_k="),
    ("--knock-band", "knock_band="),
    ("--knock-window", "knock_window="),
    ("--knock-threshold", "knock_threshold="),
    // After the `--knock-…` flags, of which it is the start.
    ("--knock", "knock=True"),
    ("--pv-start", "pv_start="),
];

/// The command line's flag of an option named as the library names it
/// (`step_deg` → `--step`, `ivc_deg` → `--ivc-deg`): the reverse of
/// [`FLAG_KEYWORDS`], for the checks the command line shares with the
/// Python package (`Method::check`).
pub fn flag(key: &str) -> String {
    let kw = format!("{key}=");
    FLAG_KEYWORDS.iter().find(|(_, k)| *k == kw).map_or_else(
        || format!("--{}", key.replace('_', "-")),
        |(f, _)| f.to_string(),
    )
}

/// `message` with each flag of [`FLAG_KEYWORDS`] as its keyword: `--step
/// 0.1: …` reads `step_deg=0.1: …`, `give --diagram` reads `give
/// diagram=`. Other flags stay as they are.
pub fn in_keywords(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find("--") {
        let (before, from) = rest.split_at(at);
        out.push_str(before);
        let name_len = from[2..]
            .find(|c: char| !(c.is_ascii_lowercase() || c == '-'))
            .map_or(from.len(), |n| n + 2);
        let flag = &from[..name_len];
        let boundary = before.is_empty() || !before.ends_with(|c: char| c.is_alphanumeric());
        match FLAG_KEYWORDS.iter().find(|(f, _)| *f == flag) {
            Some((_, kw)) if boundary => {
                out.push_str(kw);
                rest = &from[name_len..];
                // `--step 0.1` → `step_deg=0.1`: a value right after joins
                // (a number, or a placeholder such as `P`).
                if kw.ends_with('=')
                    && let Some(v) = rest.strip_prefix(' ')
                    && joins(v)
                {
                    rest = v;
                }
            }
            _ => {
                out.push_str(flag);
                rest = &from[name_len..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// Whether the text after a flag is its value: a number, or a placeholder
/// in capitals (`P`, `N`).
fn joins(v: &str) -> bool {
    let word = v.split([' ', ',', ';', ':', ')']).next().unwrap_or("");
    (!word.is_empty() && word.chars().all(|c| c.is_ascii_uppercase()))
        || v.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '.')
}

#[cfg(test)]
mod keyword_tests {
    use super::*;

    #[test]
    fn flags_read_as_keywords_in_one_mapping() {
        assert_eq!(
            in_keywords("--step 20: a grid step from 0.001 to 10° is needed"),
            "step_deg=20: a grid step from 0.001 to 10° is needed"
        );
        assert_eq!(
            in_keywords("no indicator diagram: give --diagram or `diagram =` in e.toml"),
            "no indicator diagram: give diagram= or `diagram =` in e.toml"
        );
        assert_eq!(
            in_keywords("--parts 3 but 4 parts found; --peg-bar or --peg, --out stays"),
            "parts=3 but 4 parts found; peg_bar= or peg=, --out stays"
        );
        assert_eq!(
            in_keywords("pass --no-compression-check or --gauge"),
            "pass compression_check=False or gauge=True"
        );
        assert_eq!(in_keywords("a--step b -- c"), "a--step b -- c");
        assert_eq!(
            in_keywords("a relative (piezo) trace: --peg-bar P or --peg polytropic"),
            "a relative (piezo) trace: peg_bar=P or peg= polytropic"
        );
    }
}
