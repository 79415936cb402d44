//! The combustion figures of one operating point: the mean trace's burn
//! points, heat released and pressure rise, the gross IMEP and PMEP, and
//! their spread over the measured cycles (INTERFACE.md "Combustion"). The
//! laws are `enginedyn_combustion`'s; each cycle was analysed as it was
//! read (`enginedyn_ingest::CycleCombustion`), the mean trace is analysed
//! here.

use enginedyn_combustion::{Curves, CycleGrid, Options};
use enginedyn_ingest::{CycleCombustion, Resampled, mean_std};
use enginedyn_numerics::format::sig;

/// The burn levels that have keys of their own in [`crate::KEYS`].
pub const FIXED_LEVELS: [f64; 4] = [5.0, 10.0, 50.0, 90.0];

/// The summary key of a burn level beyond [`FIXED_LEVELS`] (`ca25_deg`):
/// levels are whole percentages 1–99, each name made once.
pub fn level_key(pct: f64) -> &'static str {
    static NAMES: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
    let names = NAMES.get_or_init(|| {
        (0..100)
            .map(|k| &*Box::leak(format!("ca{k}_deg").into_boxed_str()))
            .collect()
    });
    names[(pct.round() as usize).min(99)]
}

/// The burn levels of `s` asked for beyond [`FIXED_LEVELS`], as
/// `(caK_deg, angle)`: the keys `summary.json`, `summary.csv` and the
/// tables add for them.
pub fn extra_levels(s: &crate::Summary) -> impl Iterator<Item = (&'static str, Option<f64>)> + '_ {
    s.combustion
        .iter()
        .flat_map(|c| c.levels.iter())
        .filter(|(pct, _)| !FIXED_LEVELS.contains(pct))
        .map(|(pct, deg)| (level_key(*pct), *deg))
}

/// The combustion keys of `summary.json` (SI inside: bar and degrees only
/// where the key says so).
#[derive(Debug, Clone, PartialEq, Default)]
#[allow(missing_docs)] // each field is the summary.json key of the same name (INTERFACE.md)
pub struct CombustionSummary {
    /// `(level %, its angle)` for every level asked for.
    pub levels: Vec<(f64, Option<f64>)>,
    pub burn_10_90_deg: Option<f64>,
    pub soc_deg: Option<f64>,
    pub eoc_deg: Option<f64>,
    pub heat_released_j: Option<f64>,
    pub dp_dphi_max_bar_deg: Option<f64>,
    pub dp_dphi_max_angle_deg: Option<f64>,
    pub imep_gross_bar: Option<f64>,
    pub pmep_bar: Option<f64>,
    pub ca50_std_deg: Option<f64>,
    pub burn_10_90_std_deg: Option<f64>,
    pub dp_dphi_max_std_bar_deg: Option<f64>,
    pub imep_lnv: Option<f64>,
    /// With a wall-heat model: the mean trace's gross heat released (J);
    /// `None` without a model.
    pub heat_released_gross_j: Option<Option<f64>>,
    /// With a wall-heat model: its heat lost to the walls, SOC to EOC (J).
    pub wall_heat_j: Option<Option<f64>>,
    /// Knock: MAPO over the cycles, mean and largest (bar), and the share
    /// of cycles over the threshold; `None` where not resolved.
    pub mapo_mean_bar: Option<f64>,
    #[allow(missing_docs)]
    pub mapo_max_bar: Option<f64>,
    #[allow(missing_docs)]
    pub knock_share: Option<f64>,
    /// `models.wall_heat`: `woschni (T_w 450 K)` or `off`.
    pub wall_heat: String,
    /// `models.gamma`.
    pub gamma: String,
    /// `models.smoothing`.
    pub smoothing: String,
    /// `models.burn_window`.
    pub burn_window: String,
    /// The burn window as numbers (deg), for the charts.
    pub window_deg: (f64, f64),
}

impl CombustionSummary {
    /// The angle of level `pct`, when asked for and found.
    pub fn level(&self, pct: f64) -> Option<f64> {
        self.levels
            .iter()
            .find(|(l, _)| (l - pct).abs() < 1e-9)
            .and_then(|(_, a)| *a)
    }
}

/// The 10–90 duration of a cycle's burn points, when both levels were
/// asked for.
pub fn duration_10_90(opts: &Options, b: &enginedyn_combustion::BurnPoints) -> Option<f64> {
    Some(b.level(opts, 90.0)? - b.level(opts, 10.0)?)
}

/// [`duration_10_90`] in the argument order of the cycles table's getters.
pub(crate) fn duration_10_90_of(
    b: &enginedyn_combustion::BurnPoints,
    opts: &Options,
) -> Option<f64> {
    duration_10_90(opts, b)
}

/// The mean trace's analysis with its curves, the summary, and the notes.
pub(crate) struct Found {
    pub summary: CombustionSummary,
    /// The mean trace's curves, when they are shown ([`crate::Scope::Full`]).
    pub curves: Option<Curves>,
    pub notes: Vec<String>,
    /// `(cylinder, cycle, IMEP bar, CA50 deg)` of each used cycle that burns.
    pub scatter: Vec<(i64, i64, f64, f64)>,
}

/// Analyses the mean trace `traces[0]` (cylinder 1's) and gathers the
/// cycles' figures. `traces` are every cylinder's means (the gross IMEP is
/// their mean, as `imep_bar` is), `imep_pa` the run's net IMEP; the curves
/// are made only when `with_curves` (they are a sixth of the analysis'
/// cost in a batch, which shows none).
pub(crate) fn analyse(
    pressure: &Resampled,
    traces: &[&[f64]],
    (volume, dvolume): (&[f64], &[f64]),
    swept: f64,
    (imep_pa, rpm): (Option<f64>, f64),
    with_curves: bool,
) -> Option<Found> {
    let opts = pressure.combustion.as_deref()?;
    let grid = |p| CycleGrid {
        pressure: p,
        volume,
        dvolume,
        step_deg: pressure.step_deg,
        rpm: Some(rpm),
        sample_step_deg: Some(pressure.sample_step_deg),
    };
    // Knock is each cycle's: the mean trace's (its oscillations averaged
    // away) is wanted only where no cycle was analysed for it.
    let cycles_knock = pressure
        .stats
        .iter()
        .any(|c| c.combustion.as_ref().is_some_and(|b| b.knock.is_some()));
    let mean_opts = if cycles_knock && opts.knock.is_some() {
        std::borrow::Cow::Owned(Options {
            knock: None,
            ..opts.clone()
        })
    } else {
        std::borrow::Cow::Borrowed(opts)
    };
    let mean = enginedyn_combustion::analyse(&grid(traces[0]), &mean_opts).ok()?;
    let curves = if with_curves {
        Some(enginedyn_combustion::curves(&grid(traces[0]), opts, &mean).ok()?)
    } else {
        None
    };
    let gross = traces
        .iter()
        .map(|p| enginedyn_combustion::gross_work(&grid(p)))
        .sum::<f64>()
        / traces.len() as f64
        / swept;
    let mut notes = Vec::new();
    let b = mean.burn.as_ref();
    if mean.unresolved {
        notes.push(noise_note(
            "the mean trace",
            mean.noise_pa,
            mean.ca50_uncertainty_deg,
        ));
    } else if b.is_none() {
        notes.push(format!(
            "no combustion in the mean trace: heat released {} J, under the bound of {} J (5 % of p_max V/(γ−1)): the burn keys are null",
            sig(mean.heat_released_j, 3),
            sig(mean.bound_j, 3)
        ));
    }
    if let Some(b) = b {
        notes.extend(edge_notes(b, opts, "the mean trace"));
    }
    notes.extend(cycle_note(pressure));
    notes.extend(cycle_noise_note(pressure));
    let step = pressure.step_deg;
    let mut s = CombustionSummary {
        levels: opts
            .levels_pct
            .iter()
            .enumerate()
            .map(|(i, l)| (*l, b.map(|b| b.levels_deg[i])))
            .collect(),
        burn_10_90_deg: b.and_then(|b| duration_10_90(opts, b)),
        soc_deg: b.map(|b| b.soc_deg),
        eoc_deg: b.map(|b| b.eoc_deg),
        heat_released_j: b.map(|_| mean.heat_released_j),
        dp_dphi_max_bar_deg: b.map(|b| b.dp_max_pa_deg / 1e5),
        dp_dphi_max_angle_deg: b.map(|b| b.dp_max_angle_deg),
        imep_gross_bar: Some(gross / 1e5),
        pmep_bar: imep_pa.map(|i| (i - gross) / 1e5),
        heat_released_gross_j: opts.wall_heat.map(|_| b.and(mean.heat_released_gross_j)),
        wall_heat_j: opts.wall_heat.map(|_| b.and(mean.wall_heat_j)),
        wall_heat: opts
            .wall_heat
            .map_or_else(|| "off".to_string(), |w| w.describe()),
        gamma: opts.gamma.describe(),
        smoothing: opts.smoothing.describe(step),
        burn_window: format!("{}:{}", opts.window_deg.0, opts.window_deg.1),
        window_deg: opts.window_deg,
        ..CombustionSummary::default()
    };
    spread(pressure, opts, &mut s);
    notes.extend(knock(pressure, &mean, opts, &mut s));
    let scatter = pressure
        .stats
        .iter()
        .filter_map(|c| {
            let b = c.combustion.as_ref()?.burn.as_ref()?;
            Some((c.cylinder, c.cycle, c.imep_pa? / 1e5, b.level(opts, 50.0)?))
        })
        .collect();
    Some(Found {
        summary: s,
        curves,
        notes,
        scatter,
    })
}

/// The spread over the used cycles that burn: CA50, the 10–90 duration and
/// the pressure rise (standard deviations), and the IMEP's LNV.
fn spread(pressure: &Resampled, opts: &Options, s: &mut CombustionSummary) {
    let burns: Vec<&enginedyn_combustion::BurnPoints> = pressure
        .stats
        .iter()
        .filter_map(|c| c.combustion.as_ref()?.burn.as_ref())
        .collect();
    if burns.len() >= 2 {
        let std = |v: Vec<f64>| (v.len() >= 2).then(|| mean_std(v.iter().copied()).1);
        s.ca50_std_deg = std(burns.iter().filter_map(|b| b.level(opts, 50.0)).collect());
        s.burn_10_90_std_deg = std(burns
            .iter()
            .filter_map(|b| duration_10_90(opts, b))
            .collect());
        s.dp_dphi_max_std_bar_deg = std(burns.iter().map(|b| b.dp_max_pa_deg / 1e5).collect());
    }
    let imeps: Vec<f64> = pressure.stats.iter().filter_map(|c| c.imep_pa).collect();
    if imeps.len() >= 2 {
        let mean = imeps.iter().sum::<f64>() / imeps.len() as f64;
        let low = imeps.iter().copied().fold(f64::INFINITY, f64::min);
        if mean > 0.0 {
            s.imep_lnv = Some(low / mean);
        }
    }
}

/// Knock over the measured cycles (the mean trace's for one cycle): MAPO
/// mean and largest, the share over the threshold; a note when the data
/// do not resolve the band, a warning when cycles knock.
fn knock(
    pressure: &Resampled,
    mean: &enginedyn_combustion::CycleBurn,
    opts: &Options,
    s: &mut CombustionSummary,
) -> Option<String> {
    let k = opts.knock.as_ref()?;
    let mut per: Vec<&Result<_, _>> = pressure
        .stats
        .iter()
        .filter_map(|c| c.combustion.as_ref()?.knock.as_ref())
        .collect();
    if per.is_empty() {
        per.extend(mean.knock.as_ref());
    }
    let figures: Vec<f64> = per
        .iter()
        .filter_map(|r| r.as_ref().ok().map(|f| f.mapo_pa))
        .collect();
    if figures.is_empty() {
        let why = per.iter().find_map(|r| r.as_ref().err())?;
        return Some(format!(
            "knock not measured: the samples resolve up to {} kHz at this speed (2.5 a period), under the band's {} kHz (--knock-band): mapo_mean_bar and mapo_max_bar are null",
            sig(why.highest_hz / 1e3, 3),
            sig(k.band_hz.1 / 1e3, 3)
        ));
    }
    let n = figures.len() as f64;
    let max = figures.iter().copied().fold(0.0, f64::max);
    let over = figures.iter().filter(|m| **m > k.threshold_pa).count();
    s.mapo_mean_bar = Some(figures.iter().sum::<f64>() / n / 1e5);
    s.mapo_max_bar = Some(max / 1e5);
    s.knock_share = Some(over as f64 / n);
    (over > 0).then(|| {
        format!(
            "knock in {over} of {} cycles: MAPO up to {} bar, over the threshold of {} bar (--knock-threshold; band {}–{} kHz)",
            figures.len(),
            sig(max / 1e5, 3),
            sig(k.threshold_pa / 1e5, 3),
            sig(k.band_hz.0 / 1e3, 3),
            sig(k.band_hz.1 / 1e3, 3)
        )
    })
}

/// The warning for a trace whose noise hides its burn (PHYSICS "Burn
/// points need data that resolve them").
fn noise_note(what: &str, noise_pa: f64, uncertainty: Option<f64>) -> String {
    let by = match uncertainty {
        Some(u) if u <= enginedyn_combustion::burn::MAX_CA50_UNCERTAINTY_DEG => {
            "its heat released is under 10 σ of the cumulative's noise".to_string()
        }
        Some(u) if u < 1e3 => format!("CA50 is uncertain by ±{}°", sig(u, 2)),
        _ => "CA50 cannot be told from the noise".to_string(),
    };
    format!(
        "the noise of {what} ({} bar RMS, from the smoothing fit's residual) hides its burn: {by}; the burn points are null (a wider --smooth, or the mean of more cycles, resolves them)",
        sig(noise_pa / 1e5, 2)
    )
}

/// Warnings for a burn that runs past the burn window's edges.
fn edge_notes(b: &enginedyn_combustion::BurnPoints, opts: &Options, what: &str) -> Vec<String> {
    let (w0, w1) = opts.window_deg;
    let mut out = Vec::new();
    if b.cut_at_end {
        out.push(format!(
            "the burn of {what} runs past the burn window's end ({w1}°): EOC lies on its edge, and the heat released and the late burn points are cut short; widen --burn-window"
        ));
    }
    if b.cut_at_start {
        out.push(format!(
            "the burn of {what} starts before the burn window ({w0}°): SOC lies on its edge, and the early burn points are cut short; widen --burn-window"
        ));
    }
    out
}

/// One warning on the measured cycles whose noise hides their burn.
fn cycle_noise_note(pressure: &Resampled) -> Option<String> {
    let hidden: Vec<(i64, f64)> = pressure
        .stats
        .iter()
        .filter_map(|c| {
            let b = c.combustion.as_ref()?;
            b.unresolved.then_some((c.cycle, b.noise_pa))
        })
        .collect();
    if hidden.is_empty() || pressure.stats.len() < 2 {
        return None;
    }
    let worst = hidden.iter().map(|h| h.1).fold(0.0, f64::max);
    let listed: Vec<String> = hidden.iter().take(8).map(|h| h.0.to_string()).collect();
    Some(format!(
        "the noise hides the burn in {} of {} cycles ({}{}): up to {} bar RMS; their burn points are null",
        hidden.len(),
        pressure.stats.len(),
        listed.join(", "),
        if hidden.len() > 8 { ", …" } else { "" },
        sig(worst / 1e5, 2)
    ))
}

/// One note on the measured cycles without combustion, naming them (up to
/// eight) with the largest heat released among them.
fn cycle_note(pressure: &Resampled) -> Option<String> {
    let none: Vec<(i64, i64, &CycleCombustion)> = pressure
        .stats
        .iter()
        .filter_map(|c| {
            let b = c.combustion.as_ref()?;
            (b.burn.is_none() && !b.unresolved).then_some((c.cylinder, c.cycle, b))
        })
        .collect();
    if none.is_empty() || pressure.stats.len() < 2 {
        return None;
    }
    let name = |(cyl, cycle, _): &(i64, i64, &CycleCombustion)| {
        if *cyl > 0 {
            format!("{cycle} of cylinder {cyl}")
        } else {
            cycle.to_string()
        }
    };
    let (most, bound) = none.iter().fold((f64::NEG_INFINITY, 0.0), |(m, b), c| {
        if c.2.heat_released_j > m {
            (c.2.heat_released_j, c.2.bound_j)
        } else {
            (m, b)
        }
    });
    let listed: Vec<String> = none.iter().take(8).map(name).collect();
    Some(if none.len() == 1 {
        format!(
            "no combustion in cycle {}: heat released {} J, under the bound of {} J; its burn points are null",
            listed[0],
            sig(most, 3),
            sig(bound, 3)
        )
    } else {
        format!(
            "no combustion in {} of {} cycles ({}{}): heat released {} J at most, under the bound of {} J; their burn points are null",
            none.len(),
            pressure.stats.len(),
            listed.join(", "),
            if none.len() > 8 { ", …" } else { "" },
            sig(most, 3),
            sig(bound, 3)
        )
    })
}
