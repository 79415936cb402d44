//! `[torsion]` of the engine file (INTERFACE.md, "Torsion"): keys in the
//! file's units, each checked here; the chain is built from them in
//! `enginedyn_pipeline::torsion`.

use super::{EngineError, Raw, bad};
use crate::torsion::{DamperSpec, PerItem, TorsionSpec};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum RawPerItem {
    One(f64),
    Each(Vec<f64>),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDamper {
    inertia_kg_m2: Option<f64>,
    stiffness_nm_rad: Option<f64>,
    damping_nm_s_rad: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTorsion {
    throw_inertia_kg_m2: Option<RawPerItem>,
    journal_stiffness_nm_rad: Option<RawPerItem>,
    journal_diameter_mm: Option<RawPerItem>,
    journal_length_mm: Option<RawPerItem>,
    front_inertia_kg_m2: Option<f64>,
    front_stiffness_nm_rad: Option<f64>,
    flywheel_inertia_kg_m2: Option<f64>,
    flywheel_stiffness_nm_rad: Option<f64>,
    load_inertia_kg_m2: Option<f64>,
    load_stiffness_nm_rad: Option<f64>,
    damping_ratio: Option<f64>,
    damper: Option<RawDamper>,
    shaft_diameter_mm: Option<RawPerItem>,
}

/// Reads the `[torsion]` section of an engine file: `None` when it has none.
/// Unknown keys are [`super::read`]'s to report; read the engine first.
pub fn read_torsion(path: &Path) -> Result<Option<TorsionSpec>, EngineError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| EngineError::Toml(format!("cannot read the engine file: {e}")))?;
    parse_torsion(&text)
}

/// [`read_torsion`] on the file's text.
pub fn parse_torsion(text: &str) -> Result<Option<TorsionSpec>, EngineError> {
    let raw: Raw = toml::from_str(text).map_err(|e| EngineError::Toml(e.to_string()))?;
    raw.torsion.map(spec).transpose()
}

/// A value above 0 (or, with `zero_ok`, 0 or more), finite.
fn positive(key: &'static str, v: f64, zero_ok: bool) -> Result<f64, EngineError> {
    let ok = v.is_finite() && (v > 0.0 || (zero_ok && v >= 0.0));
    if ok {
        Ok(v)
    } else {
        Err(bad(key, v, if zero_ok { "0 or more" } else { "above 0" }))
    }
}

fn per_item(
    key: &'static str,
    v: Option<RawPerItem>,
    scale: f64,
) -> Result<Option<PerItem>, EngineError> {
    Ok(match v {
        None => None,
        Some(RawPerItem::One(x)) => Some(PerItem::One(positive(key, x, false)? * scale)),
        Some(RawPerItem::Each(list)) => {
            if list.is_empty() {
                return Err(bad(key, "[]", "one value, or one per item"));
            }
            let checked: Result<Vec<f64>, _> = list
                .iter()
                .map(|&x| positive(key, x, false).map(|x| x * scale))
                .collect();
            Some(PerItem::Each(checked?))
        }
    })
}

fn spec(raw: RawTorsion) -> Result<TorsionSpec, EngineError> {
    let opt = |key, v: Option<f64>| v.map(|x| positive(key, x, false)).transpose();
    let damping_ratio = raw.damping_ratio.unwrap_or(0.02);
    if !(damping_ratio.is_finite() && (0.0..1.0).contains(&damping_ratio)) {
        return Err(bad(
            "torsion.damping_ratio",
            damping_ratio,
            "a modal damping ratio from 0 to below 1 (0.02 is typical of a crankshaft)",
        ));
    }
    let damper = match raw.damper {
        None => None,
        Some(d) => Some(DamperSpec {
            inertia: positive(
                "torsion.damper.inertia_kg_m2",
                d.inertia_kg_m2.ok_or(EngineError::Missing {
                    key: "torsion.damper.inertia_kg_m2",
                    why: "the damper ring's inertia",
                })?,
                false,
            )?,
            stiffness: positive(
                "torsion.damper.stiffness_nm_rad",
                d.stiffness_nm_rad.ok_or(EngineError::Missing {
                    key: "torsion.damper.stiffness_nm_rad",
                    why: "the spring between damper ring and hub",
                })?,
                false,
            )?,
            damping: positive(
                "torsion.damper.damping_nm_s_rad",
                d.damping_nm_s_rad.unwrap_or(0.0),
                true,
            )?,
        }),
    };
    Ok(TorsionSpec {
        throw_inertia: per_item("torsion.throw_inertia_kg_m2", raw.throw_inertia_kg_m2, 1.0)?,
        journal_stiffness: per_item(
            "torsion.journal_stiffness_nm_rad",
            raw.journal_stiffness_nm_rad,
            1.0,
        )?,
        journal_diameter: per_item("torsion.journal_diameter_mm", raw.journal_diameter_mm, 1e-3)?,
        journal_length: per_item("torsion.journal_length_mm", raw.journal_length_mm, 1e-3)?,
        front_inertia: positive(
            "torsion.front_inertia_kg_m2",
            raw.front_inertia_kg_m2.unwrap_or(0.0),
            true,
        )?,
        front_stiffness: opt("torsion.front_stiffness_nm_rad", raw.front_stiffness_nm_rad)?,
        flywheel_inertia: opt("torsion.flywheel_inertia_kg_m2", raw.flywheel_inertia_kg_m2)?,
        flywheel_stiffness: opt(
            "torsion.flywheel_stiffness_nm_rad",
            raw.flywheel_stiffness_nm_rad,
        )?,
        load_inertia: opt("torsion.load_inertia_kg_m2", raw.load_inertia_kg_m2)?,
        load_stiffness: opt("torsion.load_stiffness_nm_rad", raw.load_stiffness_nm_rad)?,
        damping_ratio,
        damper,
        shaft_diameter: per_item("torsion.shaft_diameter_mm", raw.shaft_diameter_mm, 1e-3)?,
    })
}
