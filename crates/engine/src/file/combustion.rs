//! `[combustion]` of the engine file (INTERFACE.md "Combustion"): the burn
//! law (CA50 + 10–90 duration + m, or Wiebe start + duration + a + m; a
//! second burn in `[combustion.second]`), the load, the intake state, the
//! γ model and the valve events, each checked against its bounds here
//! (exit 2 naming the key).

use super::EngineError;
use crate::Stroke;
use crate::combustion::*;
use enginedyn_combustion::{CombustionError, DEFAULT_A};
use enginedyn_numerics::format::human;
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum RawGamma {
    Value(f64),
    Name(String),
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCombustion {
    ca50_deg: Option<f64>,
    duration_10_90_deg: Option<f64>,
    start_deg: Option<f64>,
    duration_deg: Option<f64>,
    wiebe_a: Option<f64>,
    wiebe_m: Option<f64>,
    imep_bar: Option<f64>,
    heat_released_j: Option<f64>,
    intake_pressure_bar: Option<f64>,
    intake_temp_k: Option<f64>,
    gamma: Option<RawGamma>,
    ivc_deg: Option<f64>,
    evo_deg: Option<f64>,
    second: Option<RawSecond>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSecond {
    fraction: Option<f64>,
    ca50_deg: Option<f64>,
    duration_10_90_deg: Option<f64>,
    start_deg: Option<f64>,
    duration_deg: Option<f64>,
    wiebe_a: Option<f64>,
    wiebe_m: Option<f64>,
}

/// One burn's keys, as either section gives them.
struct BurnKeys {
    ca50_deg: Option<f64>,
    duration_10_90_deg: Option<f64>,
    start_deg: Option<f64>,
    duration_deg: Option<f64>,
    wiebe_a: Option<f64>,
    wiebe_m: Option<f64>,
}

fn invalid(key: String, value: impl ToString, expected: impl Into<String>) -> EngineError {
    EngineError::InvalidItem {
        key,
        value: value.to_string(),
        expected: expected.into(),
    }
}

fn missing(key: &'static str, why: &'static str) -> EngineError {
    EngineError::Missing { key, why }
}

/// A number within `lo..=hi` or an error naming `section.key`.
fn within(
    section: &str,
    key: &str,
    v: f64,
    lo: f64,
    hi: f64,
    unit: &str,
) -> Result<f64, EngineError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(invalid(
            format!("{section}.{key}"),
            v,
            format!("{lo} to {hi}{unit}"),
        ))
    }
}

/// The combustion crate's range error as the engine file's, naming the key
/// in `section`; `derived` says the start was worked out from CA50.
fn from_law(section: &str, e: CombustionError, derived: bool) -> EngineError {
    match e {
        CombustionError::Range {
            name,
            value,
            lo,
            hi,
        } => {
            let how = if derived && matches!(name, "start_deg" | "duration_deg") {
                " (the Wiebe law that ca50_deg, duration_10_90_deg and wiebe_m give)"
            } else {
                ""
            };
            invalid(
                format!("{section}.{name}"),
                value,
                format!("{lo} to {hi}{how}"),
            )
        }
        CombustionError::Input(m) => EngineError::Toml(format!("[{section}]: {m}")),
    }
}

/// One Wiebe from `section`'s keys: CA50 + 10–90 + m (a = 6.908 unless
/// given), or start + duration + a + m; exactly one of the two forms.
fn wiebe(section: &'static str, k: &BurnKeys, second: bool) -> Result<Wiebe, EngineError> {
    let key = |name: &str| format!("{section}.{name}");
    match (k.ca50_deg, k.start_deg) {
        (Some(_), Some(_)) => Err(invalid(
            key("start_deg"),
            "given with ca50_deg",
            "one form of the burn law: ca50_deg + duration_10_90_deg + wiebe_m, or start_deg + duration_deg + wiebe_a + wiebe_m",
        )),
        (Some(ca50), None) => {
            if k.duration_deg.is_some() {
                return Err(invalid(
                    key("duration_deg"),
                    "given with ca50_deg",
                    "duration_10_90_deg with ca50_deg (duration_deg goes with start_deg)",
                ));
            }
            let d = k.duration_10_90_deg.ok_or_else(|| {
                missing(
                    if second {
                        "combustion.second.duration_10_90_deg"
                    } else {
                        "combustion.duration_10_90_deg"
                    },
                    "the 10–90 % burn duration, with ca50_deg",
                )
            })?;
            let m = need_m(k, second)?;
            Wiebe::from_ca50(ca50, d, m, k.wiebe_a.unwrap_or(DEFAULT_A))
                .map_err(|e| from_law(section, e, true))
        }
        (None, Some(start)) => {
            if k.duration_10_90_deg.is_some() {
                return Err(invalid(
                    key("duration_10_90_deg"),
                    "given with start_deg",
                    "duration_deg with start_deg (duration_10_90_deg goes with ca50_deg)",
                ));
            }
            let (dur_key, a_key) = if second {
                (
                    "combustion.second.duration_deg",
                    "combustion.second.wiebe_a",
                )
            } else {
                ("combustion.duration_deg", "combustion.wiebe_a")
            };
            let dur = k
                .duration_deg
                .ok_or_else(|| missing(dur_key, "the Wiebe duration, with start_deg"))?;
            let a = k
                .wiebe_a
                .ok_or_else(|| missing(a_key, "the Wiebe efficiency a, with start_deg"))?;
            let m = need_m(k, second)?;
            Wiebe::new(start, dur, a, m).map_err(|e| from_law(section, e, false))
        }
        (None, None) => Err(missing(
            if second {
                "combustion.second.ca50_deg"
            } else {
                "combustion.ca50_deg"
            },
            "the burn law: ca50_deg + duration_10_90_deg + wiebe_m, or start_deg + duration_deg + wiebe_a + wiebe_m",
        )),
    }
}

fn need_m(k: &BurnKeys, second: bool) -> Result<f64, EngineError> {
    k.wiebe_m.ok_or_else(|| {
        missing(
            if second {
                "combustion.second.wiebe_m"
            } else {
                "combustion.wiebe_m"
            },
            "the Wiebe shape m (about 2 for a spark-ignition burn, 0.5–1 for a diesel's diffusion burn)",
        )
    })
}

/// The load (`imep_bar`, `heat_released_j`: one of them): an IMEP up to
/// [`MAX_IMEP_BAR`], a heat up to what the cylinder's trapped air can
/// burn ([`max_heat_released_j`] of its whole volume `bdc_volume_m3` at
/// the intake state; when the geometry is not known, the geometry's own
/// check refuses the file).
fn load(
    given: (Option<f64>, Option<f64>),
    bdc_volume_m3: Option<f64>,
    intake_pressure_pa: f64,
    intake_temp_k: f64,
) -> Result<Option<CombustionLoad>, EngineError> {
    Ok(match given {
        (Some(_), Some(_)) => {
            return Err(invalid(
                "combustion.heat_released_j".into(),
                "given with imep_bar",
                "one load: imep_bar or heat_released_j",
            ));
        }
        (Some(i), None) => {
            if !(i.is_finite() && i > 0.0 && i <= MAX_IMEP_BAR) {
                return Err(invalid(
                    "combustion.imep_bar".into(),
                    i,
                    format!(
                        "above 0, up to {MAX_IMEP_BAR} bar (a high-boost engine at full load reaches 30–35 bar: is the unit bar?)"
                    ),
                ));
            }
            Some(CombustionLoad::Imep(i * 1e5))
        }
        (None, Some(q)) => {
            let volume = bdc_volume_m3.filter(|v| v.is_finite() && *v > 0.0);
            let (hi, why) = match volume {
                Some(v) => (
                    max_heat_released_j(v, intake_pressure_pa, intake_temp_k),
                    format!(
                        " J per cylinder and cycle, what its trapped air can burn ({} MJ per kg of air; the whole cylinder, {} cm³, full of air at intake_pressure_bar and intake_temp_k)",
                        MAX_HEAT_PER_KG_AIR / 1e6,
                        human((v * 1e7).round() / 10.0)
                    ),
                ),
                None => (f64::MAX, " J".to_string()),
            };
            if !(q.is_finite() && (0.0..=hi).contains(&q)) {
                return Err(invalid(
                    "combustion.heat_released_j".into(),
                    q,
                    format!("0 to {}{why}", human(hi.floor())),
                ));
            }
            Some(CombustionLoad::Heat(q))
        }
        (None, None) => None,
    })
}

/// The checked section for an engine of `stroke` whose cylinder holds
/// `bdc_volume_m3` at BDC (swept plus clearance; `None` when the geometry
/// is not known).
pub(super) fn spec(
    raw: RawCombustion,
    stroke: Stroke,
    bdc_volume_m3: Option<f64>,
) -> Result<CombustionSpec, EngineError> {
    const S: &str = "combustion";
    let two = stroke == Stroke::Two;
    let first = wiebe(
        S,
        &BurnKeys {
            ca50_deg: raw.ca50_deg,
            duration_10_90_deg: raw.duration_10_90_deg,
            start_deg: raw.start_deg,
            duration_deg: raw.duration_deg,
            wiebe_a: raw.wiebe_a,
            wiebe_m: raw.wiebe_m,
        },
        false,
    )?;
    let burn = match raw.second {
        None => BurnLaw::single(first),
        Some(s) => {
            let fraction = s.fraction.ok_or_else(|| {
                missing(
                    "combustion.second.fraction",
                    "the second burn's share of the heat, 0 to 1",
                )
            })?;
            let fraction = within("combustion.second", "fraction", fraction, 0.0, 1.0, "")?;
            let w = wiebe(
                "combustion.second",
                &BurnKeys {
                    ca50_deg: s.ca50_deg,
                    duration_10_90_deg: s.duration_10_90_deg,
                    start_deg: s.start_deg,
                    duration_deg: s.duration_deg,
                    wiebe_a: s.wiebe_a,
                    wiebe_m: s.wiebe_m,
                },
                true,
            )?;
            BurnLaw::double(first, w, fraction)
                .map_err(|e| from_law("combustion.second", e, false))?
        }
    };
    let intake_pressure_pa = within(
        S,
        "intake_pressure_bar",
        raw.intake_pressure_bar.unwrap_or(DEFAULT_INTAKE_PA / 1e5),
        MIN_INTAKE_BAR,
        MAX_INTAKE_BAR,
        " bar absolute (a throttled engine at idle to a two-stage charged one)",
    )? * 1e5;
    let intake_temp_k = within(
        S,
        "intake_temp_k",
        raw.intake_temp_k
            .unwrap_or(enginedyn_combustion::DEFAULT_INTAKE_TEMP_K),
        200.0,
        1000.0,
        " K",
    )?;
    let load = load(
        (raw.imep_bar, raw.heat_released_j),
        bdc_volume_m3,
        intake_pressure_pa,
        intake_temp_k,
    )?;
    let (ivc_deg, evo_deg) = valves(raw.ivc_deg, raw.evo_deg, two)?;
    check_start(&burn, raw.ca50_deg.is_some(), ivc_deg, evo_deg)?;
    let gamma = match raw.gamma {
        None => GammaModel::Constant(enginedyn_combustion::DEFAULT_GAMMA),
        Some(RawGamma::Value(g)) => GammaModel::Constant(within(S, "gamma", g, 1.01, 1.67, "")?),
        Some(RawGamma::Name(n)) if n == "brunt" => GammaModel::Brunt {
            ivc_deg,
            intake_temp_k,
        },
        Some(RawGamma::Name(n)) => {
            return Err(invalid(
                "combustion.gamma".into(),
                format!("\"{}\"", enginedyn_numerics::format::quote(&n)),
                "a number from 1.01 to 1.67, or \"brunt\"",
            ));
        }
    };
    Ok(CombustionSpec {
        burn,
        load,
        intake_pressure_pa,
        intake_temp_k,
        gamma,
        ivc_deg,
        evo_deg,
    })
}

/// `ivc_deg` and `evo_deg` (their defaults for the cycle), within the
/// cycle model's range.
fn valves(ivc: Option<f64>, evo: Option<f64>, two: bool) -> Result<(f64, f64), EngineError> {
    let evo_hi = if two { 164.0 } else { 344.0 };
    let ivc_deg = ivc.unwrap_or(if two {
        DEFAULT_IVC_DEG_TWO_STROKE
    } else {
        DEFAULT_IVC_DEG
    });
    check_ivc(ivc_deg, two).map_err(|why| invalid("combustion.ivc_deg".into(), ivc_deg, why))?;
    let evo_deg = evo.unwrap_or(if two {
        DEFAULT_EVO_DEG_TWO_STROKE
    } else {
        DEFAULT_EVO_DEG
    });
    if !(evo_deg.is_finite() && evo_deg > 0.0 && evo_deg <= evo_hi) {
        return Err(invalid(
            "combustion.evo_deg".into(),
            evo_deg,
            format!(
                "above 0, up to {evo_hi}° for a {}",
                if two { "two-stroke" } else { "four-stroke" }
            ),
        ));
    }
    Ok((ivc_deg, evo_deg))
}

/// Each burn starts inside the closed part (after IVC, before EVO) and
/// reaches 90 % before EVO.
fn check_start(burn: &BurnLaw, ca50_form: bool, ivc: f64, evo: f64) -> Result<(), EngineError> {
    let mut each = vec![("combustion", *burn.first(), ca50_form)];
    if let Some((w, _)) = burn.second() {
        each.push(("combustion.second", *w, false));
    }
    for (section, w, ca50) in each {
        let start = w.start_deg();
        if !(start > ivc && start < evo) {
            let key = if ca50 { "ca50_deg" } else { "start_deg" };
            return Err(invalid(
                format!("{section}.{key}"),
                if ca50 { w.angle_of(0.5) } else { start },
                format!(
                    "a burn starting after ivc_deg ({ivc}°) and before evo_deg ({evo}°); it starts at {}°",
                    enginedyn_numerics::format::human(start)
                ),
            ));
        }
    }
    let ca90 = burn.angle_of(0.9);
    if ca90 >= evo {
        return Err(invalid(
            "combustion.evo_deg".into(),
            evo,
            format!(
                "after the burn's 90 % point ({}°): the exhaust opens once the charge has burnt",
                enginedyn_numerics::format::human(ca90)
            ),
        ));
    }
    Ok(())
}
