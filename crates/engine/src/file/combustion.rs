//! `[combustion]` of the engine file (INTERFACE.md "Combustion"): the burn
//! law (CA50 + 10–90 duration + m, or Wiebe start + duration + a + m; a
//! second burn in `[combustion.second]`), the load, the intake state, the
//! γ model and the valve events, each checked against its bounds here
//! (exit 2 naming the key).

use super::EngineError;
use crate::Stroke;
use crate::combustion::*;
use enginedyn_combustion::charge::{Charge, ChargeKind};
use enginedyn_combustion::friction::ChenFlynn;
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
    duration_10_90_deg: Option<toml::Value>,
    start_deg: Option<f64>,
    duration_deg: Option<f64>,
    wiebe_a: Option<f64>,
    wiebe_m: Option<f64>,
    imep_bar: Option<f64>,
    heat_released_j: Option<f64>,
    intake_pressure_bar: Option<toml::Value>,
    intake_temp_k: Option<f64>,
    gamma: Option<RawGamma>,
    ivc_deg: Option<f64>,
    evo_deg: Option<f64>,
    charge: Option<String>,
    lambda: Option<f64>,
    lambda_min: Option<f64>,
    fuel_lhv_mj_kg: Option<f64>,
    afr_stoich: Option<f64>,
    combustion_efficiency: Option<f64>,
    full_load: Option<RawFullLoad>,
    second: Option<RawSecond>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFullLoad {
    rpm: Option<Vec<f64>>,
    imep_bar: Option<Vec<f64>>,
    bmep_bar: Option<Vec<f64>>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFriction {
    a_bar: Option<f64>,
    b: Option<f64>,
    c_bar_s_m: Option<f64>,
    d_bar_s2_m2: Option<f64>,
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

/// The most points of a curve over speed.
pub const MAX_CURVE_POINTS: usize = 1000;

/// A number of a TOML value (an integer too).
fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// A list of numbers, or an error naming `key`.
fn numbers(key: &str, v: &toml::Value) -> Result<Vec<f64>, EngineError> {
    let list = v
        .as_array()
        .ok_or_else(|| invalid(key.into(), v, "a list of numbers"))?;
    if list.is_empty() || list.len() > MAX_CURVE_POINTS {
        return Err(invalid(
            key.into(),
            format!("{} values", list.len()),
            format!("1 to {MAX_CURVE_POINTS} values"),
        ));
    }
    list.iter()
        .map(|x| number(x).ok_or_else(|| invalid(key.into(), x, "a number")))
        .collect()
}

/// A curve's speeds: rising, 1 to 100,000 rpm.
fn speeds(key: &str, rpm: &[f64]) -> Result<(), EngineError> {
    for (k, &r) in rpm.iter().enumerate() {
        if !(r.is_finite() && (1.0..=1e5).contains(&r)) {
            return Err(invalid(key.into(), r, "speeds of 1 to 100,000 rpm"));
        }
        if k > 0 && r <= rpm[k - 1] {
            return Err(invalid(
                key.into(),
                format!("{} after {}", human(r), human(rpm[k - 1])),
                "rising speeds, each once",
            ));
        }
    }
    Ok(())
}

/// A curve `{ rpm = [...], <field> = [...] }` of `key`, each value within
/// `lo..=hi` (`unit`), times `scale` into SI.
fn curve(
    key: &str,
    t: &toml::Table,
    field: &str,
    bounds: (f64, f64, &str),
    scale: f64,
) -> Result<Curve, EngineError> {
    for k in t.keys() {
        if k != "rpm" && k != field {
            return Err(invalid(
                format!("{key}.{k}"),
                "an unknown key",
                format!("a curve over speed: {{ rpm = [...], {field} = [...] }}"),
            ));
        }
    }
    let get = |name: &str| {
        t.get(name).ok_or_else(|| {
            invalid(
                key.into(),
                format!("a table without `{name}`"),
                format!("a curve over speed: {{ rpm = [...], {field} = [...] }}"),
            )
        })
    };
    let rpm = numbers(&format!("{key}.rpm"), get("rpm")?)?;
    let values = numbers(&format!("{key}.{field}"), get(field)?)?;
    curve_of(key, rpm, values, field, bounds, scale)
}

/// A curve of `key` from its speeds and values (`field` names them), each
/// value within `lo..=hi` (`unit`), times `scale` into SI.
fn curve_of(
    key: &str,
    rpm: Vec<f64>,
    values: Vec<f64>,
    field: &str,
    (lo, hi, unit): (f64, f64, &str),
    scale: f64,
) -> Result<Curve, EngineError> {
    if rpm.is_empty() || rpm.len() > MAX_CURVE_POINTS {
        return Err(invalid(
            format!("{key}.rpm"),
            format!("{} speeds", rpm.len()),
            format!("1 to {MAX_CURVE_POINTS} speeds"),
        ));
    }
    speeds(&format!("{key}.rpm"), &rpm)?;
    if values.len() != rpm.len() {
        return Err(invalid(
            format!("{key}.{field}"),
            format!("{} values for {} speeds", values.len(), rpm.len()),
            "one value for each speed of rpm",
        ));
    }
    for &v in &values {
        if !(v.is_finite() && (lo..=hi).contains(&v)) {
            return Err(invalid(
                format!("{key}.{field}"),
                v,
                format!("{lo} to {hi}{unit} each"),
            ));
        }
    }
    Ok(Curve {
        rpm,
        values: values.iter().map(|v| v * scale).collect(),
    })
}

/// One value or a curve over speed, as [`curve`] takes it.
fn over_speed(
    key: &str,
    v: &toml::Value,
    field: &str,
    bounds: (f64, f64, &str),
    scale: f64,
) -> Result<OverSpeed, EngineError> {
    match (number(v), v.as_table()) {
        (Some(x), _) => {
            let (lo, hi, unit) = bounds;
            if x.is_finite() && (lo..=hi).contains(&x) {
                Ok(OverSpeed::Fixed(x * scale))
            } else {
                Err(invalid(key.into(), x, format!("{lo} to {hi}{unit}")))
            }
        }
        (None, Some(t)) => Ok(OverSpeed::Curve(curve(key, t, field, bounds, scale)?)),
        (None, None) => Err(invalid(
            key.into(),
            v,
            format!("a number, or a curve over speed {{ rpm = [...], {field} = [...] }}"),
        )),
    }
}

/// The air and fuel keys: `None` without `charge` (the other keys then
/// refused, as they would do nothing).
fn charge(raw: &RawCombustion) -> Result<Option<Charge>, EngineError> {
    const S: &str = "combustion";
    let kind = match raw.charge.as_deref() {
        None => {
            let given = [
                ("lambda", raw.lambda),
                ("lambda_min", raw.lambda_min),
                ("fuel_lhv_mj_kg", raw.fuel_lhv_mj_kg),
                ("afr_stoich", raw.afr_stoich),
                ("combustion_efficiency", raw.combustion_efficiency),
            ];
            if let Some((k, _)) = given.iter().find(|(_, v)| v.is_some()) {
                return Err(invalid(
                    format!("combustion.{k}"),
                    "given without charge",
                    "charge = \"si\" or \"ci\" with it: the design model it belongs to",
                ));
            }
            return Ok(None);
        }
        Some("si") => ChargeKind::Si,
        Some("ci") => ChargeKind::Ci,
        Some(other) => {
            return Err(invalid(
                "combustion.charge".into(),
                format!("\"{}\"", enginedyn_numerics::format::quote(other)),
                "\"si\" (spark ignition) or \"ci\" (compression ignition)",
            ));
        }
    };
    let mut c = Charge::default_for(kind);
    if let Some(l) = raw.lambda {
        c.lambda = within(S, "lambda", l, 0.6, 2.0, "")?;
    }
    if let Some(l) = raw.lambda_min {
        c.lambda_min = within(S, "lambda_min", l, 1.0, 3.0, "")?;
    }
    if let Some(q) = raw.fuel_lhv_mj_kg {
        c.lhv_j_kg = within(S, "fuel_lhv_mj_kg", q, 10.0, 130.0, " MJ/kg")? * 1e6;
    }
    if let Some(a) = raw.afr_stoich {
        c.afr_stoich = within(S, "afr_stoich", a, 1.0, 40.0, "")?;
    }
    if let Some(e) = raw.combustion_efficiency {
        c.combustion_efficiency = within(S, "combustion_efficiency", e, 0.5, 1.0, "")?;
    }
    Ok(Some(c))
}

/// `[combustion.full_load]`: speeds and IMEP (or BMEP) at each.
fn full_load(raw: RawFullLoad) -> Result<FullLoad, EngineError> {
    const K: &str = "combustion.full_load";
    let rpm = raw.rpm.ok_or_else(|| {
        missing(
            "combustion.full_load.rpm",
            "the speeds of the full-load line",
        )
    })?;
    let (values, brake, key) = match (raw.imep_bar, raw.bmep_bar) {
        (Some(i), None) => (i, false, "imep_bar"),
        (None, Some(b)) => (b, true, "bmep_bar"),
        (Some(_), Some(_)) => {
            return Err(invalid(
                format!("{K}.bmep_bar"),
                "given with imep_bar",
                "one of imep_bar or bmep_bar",
            ));
        }
        (None, None) => {
            return Err(missing(
                "combustion.full_load.imep_bar",
                "the full load at each speed: imep_bar (or bmep_bar)",
            ));
        }
    };
    let bounds = (f64::MIN_POSITIVE, MAX_IMEP_BAR, " bar (above 0)");
    Ok(FullLoad {
        curve: curve_of(K, rpm, values, key, bounds, 1e5)?,
        brake,
    })
}

/// `[friction]`: the Chen–Flynn constants, each left out taking the
/// default of the engine's kind (`charge`; spark ignition without one).
pub(super) fn friction(
    raw: RawFriction,
    kind: Option<ChargeKind>,
) -> Result<ChenFlynn, EngineError> {
    const S: &str = "friction";
    let d = match kind {
        Some(ChargeKind::Ci) => ChenFlynn::DIESEL,
        _ => ChenFlynn::PETROL,
    };
    let get = |v: Option<f64>, key: &str, hi: f64, unit: &str, default: f64, scale: f64| {
        v.map_or(Ok(default), |x| {
            within(S, key, x, 0.0, hi, unit).map(|x| x * scale)
        })
    };
    Ok(ChenFlynn {
        a_pa: get(raw.a_bar, "a_bar", 5.0, " bar", d.a_pa, 1e5)?,
        b: get(raw.b, "b", 0.05, "", d.b, 1.0)?,
        c_pa_s_m: get(raw.c_bar_s_m, "c_bar_s_m", 1.0, " bar s/m", d.c_pa_s_m, 1e5)?,
        d_pa_s2_m2: get(
            raw.d_bar_s2_m2,
            "d_bar_s2_m2",
            0.1,
            " bar s²/m²",
            d.d_pa_s2_m2,
            1e5,
        )?,
    })
}

/// The 10–90 duration: one value, or a curve (each speed's law checked).
fn duration(raw: &RawCombustion) -> Result<(Option<f64>, Option<Curve>), EngineError> {
    let Some(v) = &raw.duration_10_90_deg else {
        return Ok((None, None));
    };
    match over_speed(
        "combustion.duration_10_90_deg",
        v,
        "deg",
        (0.5, 240.0, "°"),
        1.0,
    )? {
        OverSpeed::Fixed(d) => Ok((Some(d), None)),
        OverSpeed::Curve(c) => {
            if raw.start_deg.is_some() {
                return Err(invalid(
                    "combustion.duration_10_90_deg".into(),
                    "given with start_deg",
                    "duration_deg with start_deg (duration_10_90_deg goes with ca50_deg)",
                ));
            }
            Ok((Some(c.values[0]), Some(c)))
        }
    }
}

/// The checked section for an engine of `stroke` whose cylinder holds
/// `bdc_volume_m3` at BDC (swept plus clearance; `None` when the geometry
/// is not known).
pub(super) fn spec(
    mut raw: RawCombustion,
    stroke: Stroke,
    bdc_volume_m3: Option<f64>,
) -> Result<CombustionSpec, EngineError> {
    const S: &str = "combustion";
    let two = stroke == Stroke::Two;
    let (duration_10_90_deg, duration_curve) = duration(&raw)?;
    let first = wiebe(
        S,
        &BurnKeys {
            ca50_deg: raw.ca50_deg,
            duration_10_90_deg,
            start_deg: raw.start_deg,
            duration_deg: raw.duration_deg,
            wiebe_a: raw.wiebe_a,
            wiebe_m: raw.wiebe_m,
        },
        false,
    )?;
    let burn = match raw.second.take() {
        None => BurnLaw::single(first),
        Some(s) => second(s, first)?,
    };
    check_ca50(&burn, raw.ca50_deg.is_some())?;
    let intake = over_speed(
        "combustion.intake_pressure_bar",
        raw.intake_pressure_bar
            .as_ref()
            .unwrap_or(&toml::Value::Float(DEFAULT_INTAKE_PA / 1e5)),
        "bar",
        (
            MIN_INTAKE_BAR,
            MAX_INTAKE_BAR,
            " bar absolute (a throttled engine at idle to a two-stage charged one)",
        ),
        1e5,
    )?;
    let intake_pressure_pa = intake.at(None);
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
        intake.max(),
        intake_temp_k,
    )?;
    let (ivc_deg, evo_deg) = valves(raw.ivc_deg, raw.evo_deg, two)?;
    check_start(&burn, raw.ca50_deg.is_some(), ivc_deg, evo_deg)?;
    let duration_curve = match duration_curve {
        None => None,
        Some(c) => Some(speed_laws(
            &burn,
            raw.ca50_deg,
            raw.wiebe_m,
            raw.wiebe_a,
            c,
            ivc_deg,
            evo_deg,
        )?),
    };
    let gamma = match raw.gamma.take() {
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
    let charge = charge(&raw)?;
    let full_load = raw.full_load.take().map(full_load).transpose()?;
    Ok(CombustionSpec {
        burn,
        duration_curve,
        charge,
        intake,
        full_load,
        load,
        intake_pressure_pa,
        intake_temp_k,
        gamma,
        ivc_deg,
        evo_deg,
    })
}

/// The law's CA50 within [`CA50_RANGE_DEG`], or an error naming the key
/// that sets it.
fn check_ca50(burn: &BurnLaw, ca50_form: bool) -> Result<(), EngineError> {
    let ca50 = burn.angle_of(0.5);
    let (lo, hi) = CA50_RANGE_DEG;
    if (lo..=hi).contains(&ca50) {
        return Ok(());
    }
    let key = if ca50_form { "ca50_deg" } else { "start_deg" };
    Err(invalid(
        format!("combustion.{key}"),
        human((ca50 * 1e3).round() / 1e3),
        format!(
            "a burn law whose CA50 lies {lo} to {hi}° after firing TDC{}: earlier, the charge burns against the rising piston; later, most of it burns in the exhaust",
            if ca50_form {
                ""
            } else {
                " (this law's CA50, from start_deg and duration_deg)"
            }
        ),
    ))
}

/// `[combustion.second]` beside the first burn.
fn second(s: RawSecond, first: Wiebe) -> Result<BurnLaw, EngineError> {
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
    BurnLaw::double(first, w, fraction).map_err(|e| from_law("combustion.second", e, false))
}

/// The duration curve's law at each of its speeds, each checked as the
/// file's law is (inside IVC … EVO).
fn speed_laws(
    burn: &BurnLaw,
    ca50: Option<f64>,
    m: Option<f64>,
    a: Option<f64>,
    c: Curve,
    ivc: f64,
    evo: f64,
) -> Result<DurationCurve, EngineError> {
    let d = DurationCurve {
        ca50_deg: ca50.unwrap_or_default(),
        duration_deg: c,
        m: m.unwrap_or_default(),
        a: a.unwrap_or(DEFAULT_A),
    };
    for (&rpm, &dur) in d.duration_deg.rpm.iter().zip(&d.duration_deg.values) {
        let w = Wiebe::from_ca50(d.ca50_deg, dur, d.m, d.a).map_err(|e| {
            let at = from_law("combustion", e, true);
            EngineError::Toml(format!(
                "combustion.duration_10_90_deg at {} rpm: {at}",
                human(rpm)
            ))
        })?;
        let law = match burn.second() {
            Some(&(s, f)) => {
                BurnLaw::double(w, s, f).map_err(|e| from_law("combustion.second", e, false))?
            }
            None => BurnLaw::single(w),
        };
        check_start(&law, true, ivc, evo).map_err(|e| {
            EngineError::Toml(format!(
                "combustion.duration_10_90_deg at {} rpm: {e}",
                human(rpm)
            ))
        })?;
    }
    Ok(d)
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
