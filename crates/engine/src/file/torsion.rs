//! `[torsion]` of the engine file (INTERFACE.md, "Torsion"): keys in the
//! file's units, each checked here against its hard bounds
//! ([`crate::torsion::BOUNDS`]); the chain is built from them in
//! `enginedyn_pipeline::torsion`, which notes implausible values
//! ([`TorsionSpec::plausibility_notes`]).

use super::{EngineError, Raw, bad};
use crate::torsion::{DamperSpec, Key, PerItem, TorsionSpec};
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
    let text = super::read_text(path)?;
    parse_torsion(&text)
}

/// [`read_torsion`] on the file's text.
pub fn parse_torsion(text: &str) -> Result<Option<TorsionSpec>, EngineError> {
    let raw: Raw = toml::from_str(text).map_err(|e| EngineError::Toml(e.to_string()))?;
    raw.torsion.map(spec).transpose()
}

fn per_item(key: Key, v: Option<RawPerItem>) -> Result<Option<PerItem>, EngineError> {
    Ok(match v {
        None => None,
        Some(RawPerItem::One(x)) => Some(PerItem::One(key.check(None, x)?)),
        Some(RawPerItem::Each(list)) => {
            if list.is_empty() {
                return Err(bad(key.name(), "[]", "one value, or one per item"));
            }
            let checked: Result<Vec<f64>, _> = list
                .iter()
                .enumerate()
                .map(|(i, &x)| key.check(Some(i), x))
                .collect();
            Some(PerItem::Each(checked?))
        }
    })
}

/// Every number against its bounds ([`crate::torsion::BOUNDS`], the one
/// table): a value outside is refused naming the key, with a list's
/// 1-based index.
fn spec(raw: RawTorsion) -> Result<TorsionSpec, EngineError> {
    let opt = |key: Key, v: Option<f64>| v.map(|x| key.check(None, x)).transpose();
    let damper = match raw.damper {
        None => None,
        Some(d) => Some(DamperSpec {
            inertia: Key::DamperInertia.check(
                None,
                d.inertia_kg_m2.ok_or(EngineError::Missing {
                    key: "torsion.damper.inertia_kg_m2",
                    why: "the damper ring's inertia",
                })?,
            )?,
            stiffness: Key::DamperStiffness.check(
                None,
                d.stiffness_nm_rad.ok_or(EngineError::Missing {
                    key: "torsion.damper.stiffness_nm_rad",
                    why: "the spring between damper ring and hub",
                })?,
            )?,
            damping: Key::DamperDamping.check(None, d.damping_nm_s_rad.unwrap_or(0.0))?,
        }),
    };
    Ok(TorsionSpec {
        throw_inertia: per_item(Key::ThrowInertia, raw.throw_inertia_kg_m2)?,
        journal_stiffness: per_item(Key::JournalStiffness, raw.journal_stiffness_nm_rad)?,
        journal_diameter: per_item(Key::JournalDiameter, raw.journal_diameter_mm)?,
        journal_length: per_item(Key::JournalLength, raw.journal_length_mm)?,
        front_inertia: Key::FrontInertia.check(None, raw.front_inertia_kg_m2.unwrap_or(0.0))?,
        front_stiffness: opt(Key::FrontStiffness, raw.front_stiffness_nm_rad)?,
        flywheel_inertia: opt(Key::FlywheelInertia, raw.flywheel_inertia_kg_m2)?,
        flywheel_stiffness: opt(Key::FlywheelStiffness, raw.flywheel_stiffness_nm_rad)?,
        load_inertia: opt(Key::LoadInertia, raw.load_inertia_kg_m2)?,
        load_stiffness: opt(Key::LoadStiffness, raw.load_stiffness_nm_rad)?,
        damping_ratio: Key::DampingRatio.check(None, raw.damping_ratio.unwrap_or(0.02))?,
        damper,
        shaft_diameter: per_item(Key::ShaftDiameter, raw.shaft_diameter_mm)?,
    })
}
