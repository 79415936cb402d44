//! The combustion analysis' options (INTERFACE.md "Combustion"): the burn
//! levels, the window, the γ model, the smoothing and the IVC state, as
//! both front ends give them (`--burn-points 5,10,50,90`, `--burn-window
//! -90:120`, `--gamma 1.32|brunt`, `--smooth SG:2|off`, `--intake-temp-k`,
//! `--ivc-deg`; Python's keywords of the same names). Parsed and checked
//! here once, defaults from `enginedyn_combustion`.

use crate::error::{Error, Result};
use enginedyn_combustion::{
    DEFAULT_INTAKE_TEMP_K, DEFAULT_IVC_DEG, DEFAULT_LEVELS, DEFAULT_WINDOW, GammaModel, Options,
};
use enginedyn_ingest::read_number;

pub use enginedyn_combustion::Smoothing;

/// Most burn levels one run reports.
pub const MAX_LEVELS: usize = 16;

/// The γ asked for: a constant, or Brunt's γ(T).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gamma {
    /// One γ throughout.
    Constant(f64),
    /// Brunt's γ(T) from the IVC state.
    Brunt,
}

/// The wall-heat model asked for (`--wall-heat`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallSetting {
    /// No wall heat: the net figures (the default).
    Off,
    /// Woschni's or Hohenberg's correlation: the gross figures.
    Model(enginedyn_combustion::WallModel),
}

/// Burn levels (percent), rising, at most [`MAX_LEVELS`]: a fixed array so
/// the method options stay `Copy`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Levels {
    pct: [f64; MAX_LEVELS],
    len: usize,
}

impl Levels {
    /// The levels as a slice.
    pub fn as_slice(&self) -> &[f64] {
        &self.pct[..self.len]
    }

    /// Levels from a list (sorted, duplicates dropped), each 1–99 %.
    pub fn new(v: &[f64]) -> std::result::Result<Self, String> {
        let mut v: Vec<f64> = v.to_vec();
        v.sort_by(f64::total_cmp);
        v.dedup();
        if v.is_empty() || v.len() > MAX_LEVELS {
            return Err(format!("{} levels: give 1 to {MAX_LEVELS}", v.len()));
        }
        if let Some(bad) = v.iter().find(|l| !(1.0..=99.0).contains(*l)) {
            return Err(format!("{bad} is outside 1 to 99 (percent burnt)"));
        }
        if let Some(bad) = v.iter().find(|l| l.fract() != 0.0) {
            return Err(format!(
                "{bad}: give whole percentages (the key is caK_deg)"
            ));
        }
        let mut pct = [0.0; MAX_LEVELS];
        pct[..v.len()].copy_from_slice(&v);
        Ok(Self { pct, len: v.len() })
    }

    /// `5,10,50,90` (commas or spaces between levels).
    pub fn parse(s: &str) -> std::result::Result<Self, String> {
        let v: std::result::Result<Vec<f64>, String> = s
            .split([',', ' ', ';'])
            .filter(|t| !t.trim().is_empty())
            .map(|t| read_number(t.trim(), false).map_err(|e| format!("`{t}` {e}")))
            .collect();
        Self::new(&v?)
    }
}

/// The combustion analysis' options as given (`None`: the default).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BurnMethod {
    /// `--burn-points`.
    pub levels: Option<Levels>,
    /// `--burn-window A:B` (deg).
    pub window_deg: Option<(f64, f64)>,
    /// `--gamma`.
    pub gamma: Option<Gamma>,
    /// `--smooth`.
    pub smooth: Option<Smoothing>,
    /// `--intake-temp-k` (γ(T) only).
    pub intake_temp_k: Option<f64>,
    /// `--ivc-deg` (γ(T) or the wall heat).
    pub ivc_deg: Option<f64>,
    /// `--wall-heat`.
    pub wall_heat: Option<WallSetting>,
    /// `--wall-temp-k`.
    pub wall_temp_k: Option<f64>,
    /// `--knock`: measure knock (also when any `--knock-…` value is
    /// given); off by default, as it costs an FFT of every cycle.
    pub knock: bool,
    /// `--knock-band LO:HI` (Hz).
    pub knock_band_hz: Option<(f64, f64)>,
    /// `--knock-window A:B` (deg).
    pub knock_window_deg: Option<(f64, f64)>,
    /// `--knock-threshold` (Pa).
    pub knock_threshold_pa: Option<f64>,
    /// No analysis at all (the hidden `--no-burn` of the benches, which
    /// measure what the analysis costs).
    pub off: bool,
}

/// The analysis' own bound on one part of its options (the others at
/// their defaults), as a flag parser's message.
fn bounded(o: Options) -> std::result::Result<(), String> {
    o.check().map_err(|e| e.to_string())
}

/// `A:B` in degrees, within −180…180° and at least 10° long.
pub fn parse_window(s: &str) -> std::result::Result<(f64, f64), String> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| format!("`{s}`: give the window as A:B in degrees, e.g. -90:120"))?;
    let a = read_number(a.trim(), false).map_err(|e| format!("`{a}` {e}"))?;
    let b = read_number(b.trim(), false).map_err(|e| format!("`{b}` {e}"))?;
    bounded(Options {
        window_deg: (a, b),
        ..Options::default()
    })?;
    Ok((a, b))
}

/// `1.32` (within 1.01–1.67) or `brunt`.
pub fn parse_gamma(s: &str) -> std::result::Result<Gamma, String> {
    if s.trim().eq_ignore_ascii_case("brunt") {
        return Ok(Gamma::Brunt);
    }
    let g = read_number(s.trim(), false)
        .map_err(|e| format!("`{s}` {e}: give a number such as 1.32, or brunt"))?;
    GammaModel::Constant(g).check().map_err(|e| e.to_string())?;
    Ok(Gamma::Constant(g))
}

/// `SG:DEG` (Savitzky–Golay over DEG degrees, 0.1–20) or `off`.
pub fn parse_smooth(s: &str) -> std::result::Result<Smoothing, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("off") {
        return Ok(Smoothing::Off);
    }
    let w = t
        .strip_prefix("SG:")
        .or_else(|| t.strip_prefix("sg:"))
        .ok_or_else(|| format!("`{s}`: give SG:DEG (e.g. SG:2) or off"))?;
    let smooth = read_number(w.trim(), false)
        .map(|width_deg| Smoothing::SavitzkyGolay { width_deg })
        .map_err(|e| format!("`{w}` {e}"))?;
    smooth.check().map_err(|e| e.to_string())?;
    Ok(smooth)
}

/// The charge temperature at IVC (K), within Brunt's model's bound.
pub fn parse_intake_temp_k(s: &str) -> std::result::Result<f64, String> {
    let t = read_number(s.trim(), false).map_err(|e| format!("`{s}` {e}"))?;
    GammaModel::Brunt {
        ivc_deg: DEFAULT_IVC_DEG,
        intake_temp_k: t,
    }
    .check()
    .map_err(|e| e.to_string())?;
    Ok(t)
}

/// `woschni`, `hohenberg` or `off`.
pub fn parse_wall_heat(s: &str) -> std::result::Result<WallSetting, String> {
    use enginedyn_combustion::WallModel;
    match s.trim().to_ascii_lowercase().as_str() {
        "off" => Ok(WallSetting::Off),
        "woschni" => Ok(WallSetting::Model(WallModel::Woschni)),
        "hohenberg" => Ok(WallSetting::Model(WallModel::Hohenberg)),
        _ => Err(format!("`{s}`: give woschni, hohenberg or off")),
    }
}

/// The mean wall temperature (K), 250–1000.
pub fn parse_wall_temp_k(s: &str) -> std::result::Result<f64, String> {
    let t = read_number(s.trim(), false).map_err(|e| format!("`{s}` {e}"))?;
    let (lo, hi) = enginedyn_combustion::wall::WALL_TEMP_RANGE_K;
    if !(lo..=hi).contains(&t) {
        return Err(format!("{t} K: expected {lo} to {hi}"));
    }
    Ok(t)
}

/// `A:B` as two numbers.
fn pair(s: &str, example: &str) -> std::result::Result<(f64, f64), String> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| format!("`{s}`: give A:B, e.g. {example}"))?;
    let a = read_number(a.trim(), false).map_err(|e| format!("`{a}` {e}"))?;
    let b = read_number(b.trim(), false).map_err(|e| format!("`{b}` {e}"))?;
    Ok((a, b))
}

/// The knock band `LO:HI` in kHz (as given) to Hz, within the bounds of
/// [`enginedyn_combustion::Knock::check`].
pub fn parse_knock_band(s: &str) -> std::result::Result<(f64, f64), String> {
    let (a, b) = pair(s, "4:20 (kHz)")?;
    let band_hz = (a * 1e3, b * 1e3);
    enginedyn_combustion::Knock {
        band_hz,
        ..Default::default()
    }
    .check()
    .map_err(|e| e.to_string())?;
    Ok(band_hz)
}

/// The knock window `A:B` (deg from firing TDC).
pub fn parse_knock_window(s: &str) -> std::result::Result<(f64, f64), String> {
    let window_deg = pair(s, "-10:70")?;
    enginedyn_combustion::Knock {
        window_deg,
        ..Default::default()
    }
    .check()
    .map_err(|e| e.to_string())?;
    Ok(window_deg)
}

/// The knock threshold in bar (as given) to Pa.
pub fn parse_knock_threshold(s: &str) -> std::result::Result<f64, String> {
    let t = read_number(s.trim(), false).map_err(|e| format!("`{s}` {e}"))?;
    let threshold_pa = t * 1e5;
    enginedyn_combustion::Knock {
        threshold_pa,
        ..Default::default()
    }
    .check()
    .map_err(|_| format!("{t} bar: expected 0.01 to 100"))?;
    Ok(threshold_pa)
}

/// Intake valve closing (deg from firing TDC), within Brunt's model's bound.
pub fn parse_ivc_deg(s: &str) -> std::result::Result<f64, String> {
    let a = read_number(s.trim(), false).map_err(|e| format!("`{s}` {e}"))?;
    GammaModel::Brunt {
        ivc_deg: a,
        intake_temp_k: DEFAULT_INTAKE_TEMP_K,
    }
    .check()
    .map_err(|e| e.to_string())?;
    Ok(a)
}

impl BurnMethod {
    /// The analysis' options, defaults where none is given.
    pub fn options(&self) -> Options {
        let gamma = match self.gamma {
            Some(Gamma::Constant(g)) => GammaModel::Constant(g),
            Some(Gamma::Brunt) => GammaModel::Brunt {
                ivc_deg: self.ivc_deg.unwrap_or(DEFAULT_IVC_DEG),
                intake_temp_k: self.intake_temp_k.unwrap_or(DEFAULT_INTAKE_TEMP_K),
            },
            None => GammaModel::default(),
        };
        Options {
            gamma,
            smoothing: self.smooth.unwrap_or_default(),
            window_deg: self.window_deg.unwrap_or(DEFAULT_WINDOW),
            levels_pct: self
                .levels
                .map_or(DEFAULT_LEVELS.to_vec(), |l| l.as_slice().to_vec()),
            wall_heat: None,
            knock: self.knock_on().then(|| enginedyn_combustion::Knock {
                band_hz: self
                    .knock_band_hz
                    .unwrap_or(enginedyn_combustion::knock::DEFAULT_BAND_HZ),
                window_deg: self
                    .knock_window_deg
                    .unwrap_or(enginedyn_combustion::knock::DEFAULT_WINDOW_DEG),
                threshold_pa: self
                    .knock_threshold_pa
                    .unwrap_or(enginedyn_combustion::knock::DEFAULT_THRESHOLD_PA),
            }),
            rpm: None,
        }
    }

    /// Knock is measured: `--knock`, or a `--knock-…` value given.
    pub fn knock_on(&self) -> bool {
        self.knock
            || self.knock_band_hz.is_some()
            || self.knock_window_deg.is_some()
            || self.knock_threshold_pa.is_some()
    }

    /// [`Self::options`] for `engine`: the wall heat's chamber and the
    /// trapped state (IVC from `--ivc-deg`, else −140°, −100° for a
    /// two-stroke; T_ivc from `--intake-temp-k`, else 320 K), and the
    /// speed of a cycle whose file gives none (`rpm`, else the engine
    /// file's).
    pub fn options_for(&self, engine: &enginedyn_engine::Engine, rpm: Option<f64>) -> Options {
        let mut o = self.options();
        o.rpm = rpm.or(engine.operating().rpm);
        if let Some(WallSetting::Model(model)) = self.wall_heat {
            let cyl = engine.cylinder();
            let two = engine.stroke_kind() == enginedyn_engine::Stroke::Two;
            let (ivc_deg, intake_temp_k) = match o.gamma {
                GammaModel::Brunt {
                    ivc_deg,
                    intake_temp_k,
                } => (ivc_deg, intake_temp_k),
                GammaModel::Constant(_) => (
                    self.ivc_deg
                        .unwrap_or(if two { -100.0 } else { DEFAULT_IVC_DEG }),
                    self.intake_temp_k.unwrap_or(DEFAULT_INTAKE_TEMP_K),
                ),
            };
            o.wall_heat = Some(enginedyn_combustion::WallHeat {
                model,
                wall_temp_k: self
                    .wall_temp_k
                    .unwrap_or(enginedyn_combustion::DEFAULT_WALL_TEMP_K),
                intake_temp_k,
                ivc_deg,
                bore_m: cyl.bore(),
                stroke_m: cyl.mechanism().stroke(),
                swept_m3: cyl.swept_volume(),
            });
        }
        o
    }

    /// Every bound checked; `name` gives an option's name as the front end
    /// says it (`--gamma` or `gamma=`).
    pub fn check(&self, name: impl Fn(&str) -> String) -> Result<()> {
        let wall = matches!(self.wall_heat, Some(WallSetting::Model(_)));
        if (self.intake_temp_k.is_some() || self.ivc_deg.is_some())
            && self.gamma != Some(Gamma::Brunt)
            && !wall
        {
            return Err(Error::usage(format!(
                "{} and {} set the state at intake valve closing for γ(T) and the wall heat: give them with {} brunt or {}",
                name("intake_temp_k"),
                name("ivc_deg"),
                name("gamma"),
                name("wall_heat")
            )));
        }
        if self.wall_temp_k.is_some() && !wall {
            return Err(Error::usage(format!(
                "{} is the wall heat's: give it with {} woschni or hohenberg",
                name("wall_temp_k"),
                name("wall_heat")
            )));
        }
        self.options().check().map_err(|e| {
            let key = match &e {
                enginedyn_combustion::CombustionError::Range { name: n, .. } => match *n {
                    "gamma" => "gamma",
                    "ivc_deg" => "ivc_deg",
                    "intake_temp_k" => "intake_temp_k",
                    "smooth" => "smooth",
                    "burn window start" | "burn window end" => "burn_window",
                    _ => "burn_points",
                },
                _ => "burn_points",
            };
            Error::usage(format!("{}: {e}", name(key)))
        })
    }

    /// The bounds that depend on the engine and the grid, checked before
    /// any work (the front end's own [`BurnMethod::check`] has run):
    /// `--ivc-deg` within the engine's cycle's range (the engine file's
    /// `ivc_deg` bound, [`enginedyn_engine::combustion::check_ivc`]), and
    /// the burn window holding enough points of the grid at `step_deg`
    /// (the analysis' own rule, asked of it on a flat cycle). Messages
    /// name the command line's flags; the Python package rewrites them as
    /// its keywords.
    pub fn check_engine(
        &self,
        engine: &enginedyn_engine::Engine,
        step_deg: f64,
        rpm: Option<f64>,
    ) -> Result<()> {
        if self.off {
            return Ok(());
        }
        let two = engine.stroke_kind() == enginedyn_engine::Stroke::Two;
        if let Some(a) = self.ivc_deg {
            enginedyn_engine::combustion::check_ivc(a, two).map_err(|why| {
                Error::usage(format!(
                    "--ivc-deg {}: expected {why} (as the engine file's ivc_deg)",
                    enginedyn_numerics::format::human(a)
                ))
            })?;
        }
        let o = self.options_for(engine, rpm);
        o.check_filter(step_deg)
            .map_err(|e| Error::usage(e.to_string()))?;
        o.check_window(step_deg, engine.cycle().to_degrees())
            .map_err(|why| {
                let (a, b) = o.window_deg;
                Error::usage(format!(
                    "--burn-window {a}:{b} with --step {step_deg}: {why}; give a longer window or a finer step"
                ))
            })
    }

    /// The options given, by their names (a campaign's `options`).
    pub fn json(&self, o: &mut serde_json::Map<String, serde_json::Value>) {
        if let Some(l) = self.levels {
            o.insert("burn_points".into(), l.as_slice().to_vec().into());
        }
        if let Some((a, b)) = self.window_deg {
            o.insert("burn_window".into(), vec![a, b].into());
        }
        match self.gamma {
            Some(Gamma::Constant(g)) => {
                o.insert("gamma".into(), g.into());
            }
            Some(Gamma::Brunt) => {
                o.insert("gamma".into(), "brunt".into());
            }
            None => {}
        }
        match self.smooth {
            Some(Smoothing::Off) => {
                o.insert("smooth".into(), "off".into());
            }
            Some(Smoothing::SavitzkyGolay { width_deg }) => {
                o.insert("smooth".into(), format!("SG:{width_deg}").into());
            }
            None => {}
        }
        if let Some(t) = self.intake_temp_k {
            o.insert("intake_temp_k".into(), t.into());
        }
        if let Some(a) = self.ivc_deg {
            o.insert("ivc_deg".into(), a.into());
        }
        match self.wall_heat {
            Some(WallSetting::Model(m)) => {
                o.insert("wall_heat".into(), m.name().into());
            }
            Some(WallSetting::Off) => {
                o.insert("wall_heat".into(), "off".into());
            }
            None => {}
        }
        if let Some(t) = self.wall_temp_k {
            o.insert("wall_temp_k".into(), t.into());
        }
        if self.knock {
            o.insert("knock".into(), true.into());
        }
        if let Some((a, b)) = self.knock_band_hz {
            o.insert("knock_band".into(), vec![a / 1e3, b / 1e3].into());
        }
        if let Some((a, b)) = self.knock_window_deg {
            o.insert("knock_window".into(), vec![a, b].into());
        }
        if let Some(t) = self.knock_threshold_pa {
            o.insert("knock_threshold".into(), (t / 1e5).into());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_read() {
        assert_eq!(
            Levels::parse("90, 5,50,10,50").unwrap().as_slice(),
            &[5.0, 10.0, 50.0, 90.0]
        );
        assert!(Levels::parse("0,50").is_err());
        assert!(parse_window("-90:120").unwrap() == (-90.0, 120.0));
        assert!(parse_window("-90").is_err());
        assert_eq!(parse_gamma("Brunt").unwrap(), Gamma::Brunt);
        assert_eq!(parse_gamma("1.3").unwrap(), Gamma::Constant(1.3));
        assert_eq!(parse_smooth("off").unwrap(), Smoothing::Off);
        assert_eq!(
            parse_smooth("SG:3").unwrap(),
            Smoothing::SavitzkyGolay { width_deg: 3.0 }
        );
    }

    #[test]
    fn bounds_name_the_option() {
        let m = BurnMethod {
            gamma: Some(Gamma::Constant(2.5)),
            ..BurnMethod::default()
        };
        let e = m
            .check(|k| format!("--{}", k.replace('_', "-")))
            .unwrap_err();
        assert!(e.to_string().contains("--gamma"), "{e}");
        let m = BurnMethod {
            ivc_deg: Some(-150.0),
            ..BurnMethod::default()
        };
        assert!(m.check(|k| k.to_string()).is_err());
    }
}
