//! The engine file (TOML) of INTERFACE.md: keys carry their unit in the name;
//! an unknown key is an error that names the nearest known one.

use crate::model::*;
use enginedyn_kinematics::{CrankSlider, Mechanism, ScotchYoke};
use serde::Deserialize;
use std::path::{Path, PathBuf};

mod combustion;
mod torsion;
pub use torsion::{parse_torsion, read_torsion};

/// The tolerance keys of INTERFACE.md's `[tolerances]` section.
pub const TOLERANCE_KEYS: &[&str] = &[
    "stroke_mm",
    "rod_length_mm",
    "pin_offset_mm",
    "bore_mm",
    "piston_group_kg",
    "rod_kg",
    "throw_angle_deg",
    "tdc_deg",
    "yoke_slot_squareness_deg",
];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    name: Option<String>,
    cycle: Option<String>,
    mechanism: Option<String>,
    cylinders: Option<i64>,
    layout: Option<String>,
    bank_angle_deg: Option<f64>,
    firing_order: Option<Vec<i64>>,
    firing_angles_deg: Option<Vec<f64>>,
    crank_angles_deg: Option<Vec<f64>>,
    bore_mm: Option<f64>,
    stroke_mm: Option<f64>,
    rod_length_mm: Option<f64>,
    lambda: Option<f64>,
    pin_offset_mm: Option<f64>,
    cylinder_spacing_mm: Option<f64>,
    compression_ratio: Option<f64>,
    rod_model: Option<String>,
    diagram: Option<String>,
    #[serde(default)]
    masses: RawMasses,
    #[serde(default)]
    operating: RawOperating,
    flywheel: Option<RawFlywheel>,
    #[serde(default)]
    tolerances: toml::Table,
    torsion: Option<torsion::RawTorsion>,
    combustion: Option<combustion::RawCombustion>,
    friction: Option<combustion::RawFriction>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawMasses {
    piston_group_kg: Option<f64>,
    rod_kg: Option<f64>,
    rod_cg_from_small_end_mm: Option<f64>,
    rod_inertia_kg_m2: Option<f64>,
    crank_unbalanced_kg: Option<f64>,
    yoke_kg: Option<f64>,
    slider_block_kg: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawOperating {
    rpm: Option<f64>,
    crankcase_pressure_bar: Option<f64>,
    mechanical_efficiency: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawFlywheel {
    speed_fluctuation: Option<f64>,
    other_rotating_inertia_kg_m2: Option<f64>,
    include_crank_train: Option<bool>,
    max_rim_speed_m_s: Option<f64>,
    outer_diameter_mm: Option<f64>,
    density_kg_m3: Option<f64>,
    shape: Option<String>,
    rim_inner_ratio: Option<f64>,
    idle_rpm: Option<f64>,
    idle_speed_fluctuation: Option<f64>,
}

/// The largest engine file read (bytes), and the most text checked.
pub const MAX_ENGINE_FILE: usize = 1 << 20;

/// An engine file's text: a regular file of at most [`MAX_ENGINE_FILE`]
/// bytes. A FIFO, a device (`/dev/zero`), a folder or a larger file is an
/// error, never read until memory runs out; the metadata is looked at before
/// the file is opened, as opening a FIFO waits for a writer.
pub fn read_text(path: &Path) -> Result<String, EngineError> {
    use std::io::Read as _;
    let cannot = |e: std::io::Error| EngineError::Toml(format!("cannot read the engine file: {e}"));
    let regular = |m: &std::fs::Metadata| -> Result<(), EngineError> {
        if !m.is_file() {
            return Err(EngineError::Toml(format!(
                "the engine file is not a regular file ({}): an engine file is TOML text",
                if m.is_dir() {
                    "a folder"
                } else {
                    "a FIFO, a device or a socket"
                }
            )));
        }
        if m.len() > MAX_ENGINE_FILE as u64 {
            return Err(too_long(m.len()));
        }
        Ok(())
    };
    regular(&std::fs::metadata(path).map_err(cannot)?)?;
    let file = std::fs::File::open(path).map_err(cannot)?;
    regular(&file.metadata().map_err(cannot)?)?;
    let mut bytes = Vec::new();
    file.take(MAX_ENGINE_FILE as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() > MAX_ENGINE_FILE {
        return Err(too_long(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| {
        EngineError::Toml(format!(
            "cannot read the engine file: not UTF-8 text (byte {} is not); save it as UTF-8",
            e.utf8_error().valid_up_to() + 1
        ))
    })
}

/// Engine-file text of at most [`MAX_ENGINE_FILE`] bytes (Python's
/// `Engine.from_str` takes no more than a file holds).
pub fn check_len(text: &str) -> Result<(), EngineError> {
    if text.len() > MAX_ENGINE_FILE {
        return Err(too_long(text.len() as u64));
    }
    Ok(())
}

fn too_long(len: u64) -> EngineError {
    EngineError::Toml(format!(
        "the engine file holds {len} bytes, more than the {} MiB bound on one (an engine file is a page of TOML)",
        MAX_ENGINE_FILE >> 20
    ))
}

/// Reads and checks an engine file; `diagram` is resolved against its folder.
pub fn read(path: &Path) -> Result<Engine, EngineError> {
    read_with(path, EngineBuilder::build)
}

/// [`read`] for `enginedyn firing-orders --all-cranks`: `firing_order` may
/// be left out (see [`EngineBuilder::build_for_crank_search`]).
pub fn read_for_crank_search(path: &Path) -> Result<Engine, EngineError> {
    read_with(path, EngineBuilder::build_for_crank_search)
}

fn read_with(
    path: &Path,
    build: fn(EngineBuilder) -> Result<Engine, EngineError>,
) -> Result<Engine, EngineError> {
    let text = read_text(path)?;
    parse_with(&text, path, build)
}

/// Checks engine-file `text` read from `path` (its stem the default name,
/// `diagram` resolved against its folder): [`read`] without reading.
pub fn parse_file(text: &str, path: &Path) -> Result<Engine, EngineError> {
    parse_with(text, path, EngineBuilder::build)
}

fn parse_with(
    text: &str,
    path: &Path,
    build: fn(EngineBuilder) -> Result<Engine, EngineError>,
) -> Result<Engine, EngineError> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "engine".into());
    let (builder, defaults, burn) = raw_builder(text, &stem)?;
    let mut engine = build(builder)?;
    engine.defaults_taken = defaults;
    (engine.combustion, engine.friction) = burn;
    if let Some(d) = &engine.diagram
        && d.is_relative()
    {
        let base = path.parent().unwrap_or(Path::new("."));
        engine.diagram = Some(base.join(d));
    }
    Ok(engine)
}

/// The longest engine `name` (characters).
pub const MAX_NAME: usize = 200;

/// Parses engine-file text; `stem` is the default name.
pub fn parse(text: &str, stem: &str) -> Result<Engine, EngineError> {
    let (builder, defaults, burn) = raw_builder(text, stem)?;
    let mut engine = builder.build()?;
    engine.defaults_taken = defaults;
    (engine.combustion, engine.friction) = burn;
    Ok(engine)
}

/// [`parse`] for a search of every crank: `firing_order` may be left out
/// (see [`EngineBuilder::build_for_crank_search`]).
pub fn parse_for_crank_search(text: &str, stem: &str) -> Result<Engine, EngineError> {
    let (builder, defaults, burn) = raw_builder(text, stem)?;
    let mut engine = builder.build_for_crank_search()?;
    engine.defaults_taken = defaults;
    (engine.combustion, engine.friction) = burn;
    Ok(engine)
}

/// The checked `[combustion]` and `[friction]` sections, when the file
/// has them.
type Burn = (
    Option<crate::combustion::CombustionSpec>,
    Option<enginedyn_combustion::friction::ChenFlynn>,
);

/// The keys of an engine file as an unchecked builder (known keys, types,
/// units and per-key bounds checked; the rest is `build`'s), the
/// defaults it leaves to enginedyn that shape the results, and its
/// `[combustion]` section checked.
fn raw_builder(
    text: &str,
    stem: &str,
) -> Result<(EngineBuilder, Vec<TakenDefault>, Burn), EngineError> {
    let table: toml::Table = toml::from_str(text).map_err(|e| EngineError::Toml(e.to_string()))?;
    check_keys(&table, text)?;
    let mut raw: Raw = toml::from_str(text).map_err(|e| EngineError::Toml(e.to_string()))?;
    let defaults = taken_defaults(&raw);
    let burn = raw.combustion.take();
    let friction = raw.friction.take();
    let b = builder(raw, stem)?;
    let burn = burn
        .map(|c| combustion::spec(c, b.stroke, bdc_volume(&b)))
        .transpose()?;
    let kind = burn.as_ref().and_then(|c| c.charge).map(|c| c.kind);
    let friction = friction
        .map(|f| combustion::friction(f, kind))
        .transpose()?;
    if let Some(c) = &burn
        && c.full_load.as_ref().is_some_and(|f| f.brake)
        && friction.is_none()
    {
        return Err(EngineError::Missing {
            key: "friction",
            why: "[combustion.full_load] gives bmep_bar: the FMEP of [friction] turns it into the IMEP a cycle is made for (or give imep_bar)",
        });
    }
    Ok((b, defaults, (burn, friction)))
}

/// The cylinder's whole volume at BDC (m³: swept plus clearance), from
/// the keys as given (`None` when they cannot give one: `build` refuses
/// the geometry then).
fn bdc_volume(b: &EngineBuilder) -> Option<f64> {
    let swept = std::f64::consts::FRAC_PI_4 * b.bore * b.bore * b.mechanism.stroke();
    let r = b.compression_ratio;
    let v = swept * r / (r - 1.0);
    (r > 1.0 && v.is_finite() && v > 0.0).then_some(v)
}

/// The keys left out whose defaults shape the results (issue 30, item 11):
/// η_m, δ, the rim speed (unless the diameter is given) and the crank's
/// unbalanced mass.
fn taken_defaults(raw: &Raw) -> Vec<TakenDefault> {
    let fw = raw.flywheel.as_ref();
    let mut taken = Vec::new();
    // With [friction] the brake figures come from it, not from η_m.
    if raw.operating.mechanical_efficiency.is_none() && raw.friction.is_none() {
        taken.push(TakenDefault::MechanicalEfficiency);
    }
    if fw.and_then(|f| f.speed_fluctuation).is_none() {
        taken.push(TakenDefault::SpeedFluctuation);
    }
    if fw.and_then(|f| f.max_rim_speed_m_s).is_none()
        && fw.and_then(|f| f.outer_diameter_mm).is_none()
    {
        taken.push(TakenDefault::RimSpeed);
    }
    if raw.masses.crank_unbalanced_kg.is_none() {
        taken.push(TakenDefault::CrankUnbalance);
    }
    taken
}

/// The tolerances section as (key, value) pairs, each checked as a number >= 0.
pub fn tolerances(text: &str) -> Result<Vec<(String, f64)>, EngineError> {
    let raw: Raw = toml::from_str(text).map_err(|e| EngineError::Toml(e.to_string()))?;
    raw.tolerances
        .into_iter()
        .map(|(k, v)| {
            let x = v
                .as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .filter(|x| x.is_finite() && *x >= 0.0);
            match x {
                Some(x) => Ok((k, x)),
                None => Err(EngineError::Toml(format!(
                    "tolerances.{k} = {v}: expected a deviation of 0 or more"
                ))),
            }
        })
        .collect()
}

/// Every key against [`crate::keys::KEYS`], the one table of known keys:
/// the top of the file, each section, and `[torsion]`'s `damper`.
fn check_keys(table: &toml::Table, text: &str) -> Result<(), EngineError> {
    let root = section_keys("");
    for (key, value) in table {
        if !root.contains(&key.as_str()) {
            return Err(unknown(key, "root", &root, text));
        }
        if crate::keys::SECTIONS.contains(&key.as_str()) {
            let section = key.as_str();
            let Some(sub) = value.as_table() else {
                return Err(EngineError::Toml(format!(
                    "`{section}` must be a table: [{section}]"
                )));
            };
            let keys = section_keys(section);
            for (k, v) in sub {
                if !keys.contains(&k.as_str()) {
                    return Err(unknown(k, section, &keys, text));
                }
                // The inner tables: `[torsion]`'s damper, `[combustion.second]`.
                let inner = match (section, k.as_str()) {
                    ("torsion", "damper") => Some("torsion.damper"),
                    ("combustion", "second") => Some("combustion.second"),
                    ("combustion", "full_load") => Some("combustion.full_load"),
                    _ => None,
                };
                if let Some(name) = inner
                    && let Some(table) = v.as_table()
                {
                    let known = section_keys(name);
                    for d in table.keys() {
                        if !known.contains(&d.as_str()) {
                            return Err(unknown(d, name, &known, text));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

fn section_keys(section: &str) -> Vec<&'static str> {
    crate::keys::section_keys(section)
}

fn unknown(key: &str, section: &str, known: &[&str], text: &str) -> EngineError {
    let lower = key.to_ascii_lowercase();
    let best = known
        .iter()
        .map(|k| {
            let prefix = k.starts_with(&lower) || lower.starts_with(*k);
            let score = strsim::jaro_winkler(&lower, k) + if prefix { 0.2 } else { 0.0 };
            (score, *k)
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    // Only a close name is suggested: similar as a whole (at most about
    // half the letters changed), or a known key the key begins (`cyl`,
    // `bore` for `bore_mm`), not any name that shares a first letter.
    let close = |k: &str| enginedyn_numerics::format::close_name(&lower, k);
    let mut suggestion = best
        .filter(|(s, k)| *s > 0.8 && close(k))
        .map(|(_, k)| k.to_string());
    if suggestion.is_none() {
        // The key may belong to another section: `rpm` at the root.
        for s in crate::keys::SECTIONS {
            if *s != section && section_keys(s).contains(&key) {
                suggestion = Some(format!("{key}` in [{s}]; or `{s}.{key}"));
            }
        }
        if section != "root" && section_keys("").contains(&key) {
            suggestion = Some(format!(
                "{key}` at the top of the file, before any [section]; or `{key}"
            ));
        }
    }
    // With nothing close, the section's keys: the user need not guess.
    let valid = if suggestion.is_none() {
        known
            .iter()
            .filter(|k| !crate::keys::SECTIONS.contains(k) || section != "root")
            .map(|k| k.to_string())
            .collect()
    } else {
        Vec::new()
    };
    EngineError::UnknownKey {
        key: key.to_string(),
        section: section.to_string(),
        suggestion,
        valid,
        line: find_line(text, section, key),
    }
}

/// 1-based line where `key` is set in `section` (`root` = before any header).
/// A key of an inline table (`damper = { … }` in `[torsion]`) is found
/// on its parent's line when the file has no `[torsion.damper]` header.
fn find_line(text: &str, section: &str, key: &str) -> Option<usize> {
    scan_line(text, section, key).or_else(|| {
        let (parent, child) = section.rsplit_once('.')?;
        scan_line(text, parent, child)
    })
}

fn scan_line(text: &str, section: &str, key: &str) -> Option<usize> {
    let mut current = "root".to_string();
    for (n, line) in text.lines().enumerate() {
        let t = line.trim();
        if let Some(h) = t.strip_prefix('[') {
            current = h.trim_end_matches(']').trim().to_string();
            continue;
        }
        let k = t.split('=').next().unwrap_or("").trim().trim_matches('"');
        if current == section && k == key {
            return Some(n + 1);
        }
    }
    None
}

fn need<T>(v: Option<T>, key: &'static str, why: &'static str) -> Result<T, EngineError> {
    v.ok_or(EngineError::Missing { key, why })
}

fn bad(key: &'static str, value: impl ToString, expected: &str) -> EngineError {
    EngineError::Invalid {
        key,
        value: value.to_string(),
        expected: expected.to_string(),
    }
}

fn builder(raw: Raw, stem: &str) -> Result<EngineBuilder, EngineError> {
    let stroke = match need(
        raw.cycle.as_deref(),
        "cycle",
        "\"four-stroke\" or \"two-stroke\"",
    )? {
        "four-stroke" => Stroke::Four,
        "two-stroke" => Stroke::Two,
        other => {
            return Err(bad(
                "cycle",
                format!("\"{other}\""),
                "\"four-stroke\" or \"two-stroke\"",
            ));
        }
    };
    let cylinders = need(
        raw.cylinders,
        "cylinders",
        "the number of cylinders, 1 to 24",
    )?;
    if !(1..=24).contains(&cylinders) {
        return Err(bad("cylinders", cylinders, "1 to 24"));
    }
    let layout = read_layout(&raw)?;
    let bore = need(raw.bore_mm, "bore_mm", "the cylinder bore")? * 1e-3;
    let r = need(raw.stroke_mm, "stroke_mm", "twice the crank radius")? * 0.5e-3;
    let compression_ratio = need(
        raw.compression_ratio,
        "compression_ratio",
        "the geometric compression ratio",
    )?;
    let m = &raw.masses;
    let (mechanism, yoke) = read_mechanism(&raw, r)?;
    let rod_model = match raw.rod_model.as_deref() {
        None => RodModel::TwoMass,
        Some(s) => RodModel::from_name(s).ok_or_else(|| {
            bad(
                "rod_model",
                format!("\"{s}\""),
                "\"two-mass\", \"three-mass\" or \"rigid\"",
            )
        })?,
    };
    let masses = read_masses(m, yoke)?;
    let op = &raw.operating;
    let operating = Operating {
        rpm: op.rpm,
        crankcase_pressure: op.crankcase_pressure_bar.unwrap_or(1.01325) * 1e5,
        mechanical_efficiency: op.mechanical_efficiency.unwrap_or(1.0),
    };
    let flywheel = read_flywheel(raw.flywheel.unwrap_or_default())?;
    let firing_order = read_firing_order(raw.firing_order, cylinders)?;
    // A name is a label: bounded, so that it cannot blow up every output.
    if let Some(n) = &raw.name
        && n.chars().count() > MAX_NAME
    {
        return Err(EngineError::Invalid {
            key: "name",
            value: enginedyn_numerics::format::quote(n),
            expected: format!("at most {MAX_NAME} characters"),
        });
    }
    // A vee's `crank_angles_deg` with one angle per cylinder (z/2 throws)
    // gives each rod its own pin.
    let split_pins = matches!(layout, Layout::Vee { .. })
        && raw
            .crank_angles_deg
            .as_ref()
            .is_some_and(|c| c.len() == cylinders as usize);
    Ok(EngineBuilder {
        rod_cg_from_small_end: m.rod_cg_from_small_end_mm.map(|v| v * 1e-3),
        name: raw.name.unwrap_or_else(|| stem.to_string()),
        stroke,
        layout,
        cylinders: cylinders as usize,
        firing_order,
        firing_angles: raw
            .firing_angles_deg
            .map(|v| v.into_iter().map(f64::to_radians).collect()),
        crank_angles: raw
            .crank_angles_deg
            .map(|v| v.into_iter().map(f64::to_radians).collect()),
        split_pins,
        mechanism,
        bore,
        compression_ratio,
        cylinder_spacing: raw.cylinder_spacing_mm.map(|v| v * 1e-3),
        rod_model,
        diagram: raw.diagram.map(PathBuf::from),
        masses,
        operating,
        flywheel,
    })
}

/// The cylinders' `layout` (inline when not given), and `bank_angle_deg`
/// for a vee only.
fn read_layout(raw: &Raw) -> Result<Layout, EngineError> {
    let layout = match raw.layout.as_deref().unwrap_or("inline") {
        "inline" => Layout::Inline,
        "vee" => Layout::Vee {
            bank_angle: need(raw.bank_angle_deg, "bank_angle_deg", "required for a vee")?
                .to_radians(),
        },
        "boxer" => Layout::Boxer,
        other => {
            return Err(bad(
                "layout",
                format!("\"{other}\""),
                "\"inline\", \"vee\" or \"boxer\"",
            ));
        }
    };
    if raw.bank_angle_deg.is_some() && !matches!(layout, Layout::Vee { .. }) {
        return Err(bad(
            "bank_angle_deg",
            raw.bank_angle_deg.unwrap_or_default(),
            "only with layout = \"vee\"",
        ));
    }
    Ok(layout)
}

/// The `mechanism` of crank radius `r` (m), and whether it is a Scotch
/// yoke: a yoke takes none of the rod's keys, a crank-slider none of the
/// yoke's masses.
fn read_mechanism(raw: &Raw, r: f64) -> Result<(Mechanism, bool), EngineError> {
    let m = &raw.masses;
    let yoke = match raw.mechanism.as_deref().unwrap_or("crank-slider") {
        "crank-slider" => false,
        "scotch-yoke" => true,
        other => {
            return Err(bad(
                "mechanism",
                format!("\"{other}\""),
                "\"crank-slider\" or \"scotch-yoke\"",
            ));
        }
    };
    if !yoke {
        return Ok((read_crank_slider(raw, r)?, false));
    }
    let rod_keys = [
        ("rod_length_mm", raw.rod_length_mm.is_some()),
        ("lambda", raw.lambda.is_some()),
        ("pin_offset_mm", raw.pin_offset_mm.is_some()),
        ("masses.rod_kg", m.rod_kg.is_some()),
        (
            "masses.rod_cg_from_small_end_mm",
            m.rod_cg_from_small_end_mm.is_some(),
        ),
        ("masses.rod_inertia_kg_m2", m.rod_inertia_kg_m2.is_some()),
    ];
    if let Some((k, _)) = rod_keys.iter().find(|(_, set)| *set) {
        return Err(EngineError::Invalid {
            key: k,
            value: "given".into(),
            expected: "nothing: a Scotch yoke has no connecting rod or pin offset".into(),
        });
    }
    let yoke = ScotchYoke::new(r, 0.0).map_err(|source| EngineError::Mechanism {
        keys: "stroke_mm",
        source,
    })?;
    Ok((Mechanism::ScotchYoke(yoke), true))
}

/// A crank-slider of crank radius `r` (m): the rod from `rod_length_mm`
/// or `lambda` (exactly one), the pin offset from `pin_offset_mm`.
fn read_crank_slider(raw: &Raw, r: f64) -> Result<Mechanism, EngineError> {
    let m = &raw.masses;
    if m.yoke_kg.is_some() || m.slider_block_kg.is_some() {
        return Err(bad(
            "masses.yoke_kg",
            "given",
            "only with mechanism = \"scotch-yoke\"",
        ));
    }
    let l = match (raw.rod_length_mm, raw.lambda) {
        (Some(l), None) => l * 1e-3,
        (None, Some(lambda)) => {
            if !(lambda > 0.0 && lambda < 1.0) {
                return Err(bad("lambda", lambda, "R/L between 0 and 1"));
            }
            r / lambda
        }
        (Some(_), Some(_)) => {
            return Err(bad(
                "lambda",
                "given with rod_length_mm",
                "exactly one of `rod_length_mm` and `lambda`",
            ));
        }
        (None, None) => {
            return Err(EngineError::Missing {
                key: "rod_length_mm",
                why: "give `rod_length_mm` or `lambda` (exactly one)",
            });
        }
    };
    let e = raw.pin_offset_mm.unwrap_or(0.0) * 1e-3;
    Ok(Mechanism::CrankSlider(CrankSlider::new(r, l, e).map_err(
        |source| EngineError::Mechanism {
            keys: "stroke_mm, rod_length_mm (or lambda), pin_offset_mm",
            source,
        },
    )?))
}

/// The `[masses]` (kg): a yoke's mass with the piston group's, a slider
/// block's with the crank's unbalanced mass; a rod for a crank-slider only.
fn read_masses(m: &RawMasses, yoke: bool) -> Result<Masses, EngineError> {
    Ok(Masses {
        piston_group: need(
            m.piston_group_kg,
            "masses.piston_group_kg",
            "piston, rings and pin",
        )? + m.yoke_kg.unwrap_or(0.0),
        rod: if yoke {
            0.0
        } else {
            need(m.rod_kg, "masses.rod_kg", "required for a crank-slider")?
        },
        rod_cg_from_small_end: 0.0,
        rod_inertia: m.rod_inertia_kg_m2,
        crank_unbalanced: m.crank_unbalanced_kg.unwrap_or(0.0) + m.slider_block_kg.unwrap_or(0.0),
    })
}

/// The `[flywheel]` in SI units, each key not given at its default.
fn read_flywheel(fw: RawFlywheel) -> Result<FlywheelSpec, EngineError> {
    let d = FlywheelSpec::default();
    Ok(FlywheelSpec {
        speed_fluctuation: fw.speed_fluctuation.unwrap_or(d.speed_fluctuation),
        other_rotating_inertia: fw
            .other_rotating_inertia_kg_m2
            .unwrap_or(d.other_rotating_inertia),
        include_crank_train: fw.include_crank_train.unwrap_or(d.include_crank_train),
        max_rim_speed: fw.max_rim_speed_m_s.unwrap_or(d.max_rim_speed),
        outer_diameter: fw.outer_diameter_mm.map(|v| v * 1e-3),
        density: fw.density_kg_m3.unwrap_or(d.density),
        shape: match fw.shape.as_deref() {
            None | Some("rim") => FlywheelShape::Rim,
            Some("disc") => FlywheelShape::Disc,
            Some(other) => {
                return Err(bad(
                    "flywheel.shape",
                    format!("\"{other}\""),
                    "\"rim\" or \"disc\"",
                ));
            }
        },
        rim_inner_ratio: fw.rim_inner_ratio.unwrap_or(d.rim_inner_ratio),
        idle: match (fw.idle_rpm, fw.idle_speed_fluctuation) {
            (Some(rpm), delta) => Some((
                rpm,
                delta.unwrap_or(fw.speed_fluctuation.unwrap_or(d.speed_fluctuation)),
            )),
            (None, Some(_)) => {
                return Err(bad(
                    "flywheel.idle_speed_fluctuation",
                    "given without idle_rpm".to_string(),
                    "idle_rpm with it: the idle speed the δ is allowed at",
                ));
            }
            (None, None) => None,
        },
    })
}

/// The `firing_order` as 1-based cylinder numbers. Cylinder numbers as
/// written: a negative or huge one is refused here, quoting the list as
/// the file gives it.
fn read_firing_order(
    order: Option<Vec<i64>>,
    cylinders: i64,
) -> Result<Option<Vec<usize>>, EngineError> {
    let Some(v) = order else {
        return Ok(None);
    };
    let z = cylinders.max(1);
    if v.iter().any(|&c| !(1..=z).contains(&c)) {
        let list: Vec<String> = v.iter().map(i64::to_string).collect();
        return Err(EngineError::Invalid {
            key: "firing_order",
            value: enginedyn_numerics::format::quote(&format!("[{}]", list.join(", "))),
            expected: format!("each cylinder 1..{z} exactly once"),
        });
    }
    Ok(Some(v.into_iter().map(|c| c as usize).collect()))
}

#[cfg(test)]
mod tests {
    //! The keys serde accepts are the keys of [`crate::keys::KEYS`]: a
    //! field of a `Raw*` struct is read from each struct's own field list
    //! (what `#[derive(Deserialize)]` hands `deserialize_struct`), so a key
    //! added to the reader without its documentation, or the other way
    //! round, fails here.
    use super::torsion::{RawDamper, RawTorsion};
    use super::*;
    use serde::de::{self, Visitor};

    #[derive(Debug)]
    struct Fields(Vec<&'static str>);

    impl std::fmt::Display for Fields {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "{:?}", self.0)
        }
    }

    impl std::error::Error for Fields {}

    impl de::Error for Fields {
        fn custom<T: std::fmt::Display>(_: T) -> Self {
            Fields(Vec::new())
        }
    }

    /// A deserializer that answers a struct with its field names.
    struct Catch;

    impl<'de> de::Deserializer<'de> for Catch {
        type Error = Fields;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Fields> {
            Err(Fields(Vec::new()))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Fields> {
            Err(Fields(fields.to_vec()))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
            bytes byte_buf option unit unit_struct newtype_struct seq tuple
            tuple_struct map enum identifier ignored_any
        }
    }

    fn fields<T: for<'de> Deserialize<'de>>() -> Vec<&'static str> {
        let Err(Fields(mut f)) = T::deserialize(Catch) else {
            panic!("a struct reads from nothing")
        };
        f.sort_unstable();
        f
    }

    fn documented(section: &str) -> Vec<&'static str> {
        let mut k = crate::keys::section_keys(section);
        k.sort_unstable();
        k
    }

    #[test]
    fn serde_fields_are_the_documented_keys() {
        assert_eq!(fields::<Raw>(), documented(""));
        assert_eq!(fields::<RawMasses>(), documented("masses"));
        assert_eq!(fields::<RawOperating>(), documented("operating"));
        assert_eq!(fields::<RawFlywheel>(), documented("flywheel"));
        assert_eq!(fields::<RawTorsion>(), documented("torsion"));
        assert_eq!(fields::<RawDamper>(), documented("torsion.damper"));
        assert_eq!(
            fields::<combustion::RawCombustion>(),
            documented("combustion")
        );
        assert_eq!(
            fields::<combustion::RawSecond>(),
            documented("combustion.second")
        );
        assert_eq!(
            fields::<combustion::RawFullLoad>(),
            documented("combustion.full_load")
        );
        assert_eq!(fields::<combustion::RawFriction>(), documented("friction"));
        let mut tol = TOLERANCE_KEYS.to_vec();
        tol.sort_unstable();
        assert_eq!(tol, documented("tolerances"));
        // Every documented key has a unit, a default and a meaning.
        for k in crate::keys::KEYS {
            assert!(
                !k.default.is_empty() && !k.meaning.is_empty() && !k.example.is_empty(),
                "{}",
                k.path()
            );
            assert!(!k.bounds_text().is_empty(), "{} has no bounds", k.path());
        }
    }
}
