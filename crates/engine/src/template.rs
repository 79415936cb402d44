//! `enginedyn template`: a commented engine file that runs as it is with
//! the bundled diagram (`data/vaz2108.csv`). Every key of [`crate::keys::KEYS`]
//! is written with its unit, its default and what it is for; the keys a
//! file needs come first and are set, the rest are commented out. The
//! numbers are the bundled example's cylinder (a 1.3 l petrol four), the
//! firing order and crank the layout's usual ones ([`Plan`]); the text is
//! parsed before it is returned, so a template always passes the crank
//! checks.

use crate::keys::{KEYS, KeyDoc};
use crate::{Engine, EngineError, Layout};

/// The layouts `enginedyn template --layout` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TemplateLayout {
    /// One bank.
    Inline,
    /// Two banks.
    Vee,
    /// Opposed banks.
    Boxer,
}

impl TemplateLayout {
    /// As the engine file writes it.
    pub fn name(self) -> &'static str {
        match self {
            TemplateLayout::Inline => "inline",
            TemplateLayout::Vee => "vee",
            TemplateLayout::Boxer => "boxer",
        }
    }
}

/// What `enginedyn template` is asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TemplateOptions {
    /// Number of cylinders, 1 to 24 (even for a vee or a boxer).
    pub cylinders: usize,
    /// Layout.
    pub layout: TemplateLayout,
    /// Add the `[torsion]` section.
    pub torsion: bool,
    /// Add a `[combustion]` section (a burn law for a synthesised diagram).
    pub combustion: Option<CombustionKind>,
}

impl Default for TemplateOptions {
    fn default() -> Self {
        Self {
            cylinders: 4,
            layout: TemplateLayout::Inline,
            torsion: false,
            combustion: None,
        }
    }
}

/// The burn law `enginedyn template --combustion` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CombustionKind {
    /// A spark-ignition engine at full load: one Wiebe.
    Petrol,
    /// A turbocharged direct-injection diesel: a premixed and a diffusion
    /// burn.
    Diesel,
}

impl CombustionKind {
    /// As the flag writes it.
    pub fn name(self) -> &'static str {
        match self {
            CombustionKind::Petrol => "petrol",
            CombustionKind::Diesel => "diesel",
        }
    }
}

/// Why no template can be written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TemplateError {
    /// A cylinder count the layout cannot have.
    #[error("--cylinders {cylinders}: {expected}")]
    Cylinders {
        /// The count asked for.
        cylinders: usize,
        /// What the layout takes.
        expected: &'static str,
    },
    /// The text written does not read back as an engine (a bug).
    #[error("the template does not read back: {0}")]
    Internal(#[from] EngineError),
}

/// The firing order and crank a template writes.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The bank angle (deg), for a vee.
    pub bank_angle_deg: Option<f64>,
    /// The firing order (1-based), each cylinder once.
    pub firing_order: Vec<usize>,
    /// Throw lags to write (deg): a vee's split pins (one per cylinder), or
    /// a crank the firing order alone would not give.
    pub crank_angles_deg: Option<Vec<f64>>,
    /// Why this firing and crank, for the file's comment.
    pub why: String,
}

/// A firing order for an inline engine of `z` cylinders: the usual one for
/// 1 to 6 and 8 cylinders; for other even counts the mirror-image crank
/// (each cylinder's mirror fires 360° after it), for other odd counts every
/// second cylinder.
pub fn inline_order(z: usize) -> Vec<usize> {
    match z {
        0 | 1 => vec![1],
        2 => vec![1, 2],
        3 => vec![1, 3, 2],
        4 => vec![1, 3, 4, 2],
        5 => vec![1, 2, 4, 5, 3],
        6 => vec![1, 5, 3, 6, 2, 4],
        8 => vec![1, 6, 2, 5, 8, 3, 7, 4],
        z if z.is_multiple_of(2) => {
            let half = inline_order(z / 2);
            let mirror = half.iter().map(|&c| z + 1 - c);
            half.iter().copied().chain(mirror).collect()
        }
        z => (1..=z).step_by(2).chain((2..=z).step_by(2)).collect(),
    }
}

/// A vee's firing order: bank 1 (cylinders 1..z/2) fires as an inline
/// engine of z/2 cylinders, at every second firing, and each cylinder's
/// partner on bank 2 (the cylinder on its throw) `k` firings later. With
/// `k` odd the two banks take turns, so every firing interval is 720°/z.
fn vee_positions(z: usize, k: usize) -> Vec<usize> {
    let h = z / 2;
    let mut pos = vec![0; z];
    for (m, &c) in inline_order(h).iter().enumerate() {
        pos[c - 1] = 2 * m;
        pos[c - 1 + h] = (2 * m + k) % z;
    }
    pos
}

fn order_of(pos: &[usize]) -> Vec<usize> {
    let mut order: Vec<usize> = (1..=pos.len()).collect();
    order.sort_by_key(|&c| pos[c - 1]);
    order
}

/// The firing and crank for `z` cylinders in `layout` (four-stroke):
///
/// - inline and boxer: [`inline_order`], the crank derived from it;
/// - a vee of 8: the cross-plane crank (`data/v8_crossplane.toml`);
/// - a vee whose banks can take turns on shared crank pins at 60°, 72°
///   or 90° (10, 12 and 24 cylinders): that bank angle;
/// - any other vee (2, 4, 6, 14 … cylinders): 90° with split crank pins
///   (each rod on a pin of its own, as in 90° V6s; for 6 cylinders
///   `data/v6_90.toml`), which fires evenly.
pub fn plan(z: usize, layout: TemplateLayout) -> Plan {
    let interval = 720.0 / z as f64;
    match layout {
        TemplateLayout::Inline | TemplateLayout::Boxer => Plan {
            bank_angle_deg: None,
            firing_order: inline_order(z),
            crank_angles_deg: None,
            why: format!(
                "even firing, every {}°; the crank follows from the order",
                crate::model::plain(interval, 3)
            ),
        },
        TemplateLayout::Vee if z == 8 => Plan {
            bank_angle_deg: Some(90.0),
            firing_order: vec![1, 5, 4, 8, 7, 2, 6, 3],
            crank_angles_deg: Some(vec![0.0, 90.0, 270.0, 180.0]),
            why: "a 90° cross-plane V8: even firing every 90°".to_string(),
        },
        TemplateLayout::Vee => {
            let shared = (1..z).step_by(2).find(|&k| {
                let a = k as f64 * interval;
                [60.0, 72.0, 90.0].iter().any(|&b| (a - b).abs() < 1e-9)
            });
            match shared {
                Some(k) => Plan {
                    bank_angle_deg: Some(k as f64 * interval),
                    firing_order: order_of(&vee_positions(z, k)),
                    crank_angles_deg: None,
                    why: format!(
                        "the banks take turns on shared crank pins: even firing every {}°",
                        crate::model::plain(interval, 3)
                    ),
                },
                None => {
                    let pos = vee_positions(z, 1);
                    let h = z / 2;
                    let crank = (0..z)
                        .map(|i| {
                            let gamma = if i < h { 0.0 } else { 90.0 };
                            let a = (pos[i] as f64 * interval - gamma).rem_euclid(360.0);
                            (a * 1e9).round() / 1e9
                        })
                        .collect();
                    Plan {
                        bank_angle_deg: Some(90.0),
                        firing_order: order_of(&pos),
                        crank_angles_deg: Some(crank),
                        why: format!(
                            "a 90° vee on split crank pins (each rod on a pin of its own, one lag per cylinder): even firing every {}°; shared pins could not fire evenly",
                            crate::model::plain(interval, 3)
                        ),
                    }
                }
            }
        }
    }
}

/// A number list as TOML: `[0.0, 90.0]`, integers as `[1, 3]`.
fn list<T: std::fmt::Display>(v: &[T]) -> String {
    let s: Vec<String> = v.iter().map(|x| x.to_string()).collect();
    format!("[{}]", s.join(", "))
}

fn deg_list(v: &[f64]) -> String {
    let s: Vec<String> = v
        .iter()
        .map(|a| {
            let r = (a * 1e9).round() / 1e9;
            if r.fract().abs() < 1e-12 {
                format!("{r:.1}")
            } else {
                format!("{r}")
            }
        })
        .collect();
    format!("[{}]", s.join(", "))
}

/// `text` as `#` comment lines of at most 78 characters, each after
/// `indent`.
fn comment(out: &mut String, indent: &str, text: &str) {
    // Words, a `code span` kept whole.
    let mut words: Vec<String> = Vec::new();
    let mut open = false;
    for w in text.split_whitespace() {
        match words.last_mut() {
            Some(last) if open => {
                last.push(' ');
                last.push_str(w);
            }
            _ => words.push(w.to_string()),
        }
        if w.matches('`').count() % 2 == 1 {
            open = !open;
        }
    }
    let mut line = format!("{indent}#");
    for word in &words {
        if line.chars().count() + 1 + word.chars().count() > 78 && line.len() > indent.len() + 1 {
            out.push_str(&line);
            out.push('\n');
            line = format!("{indent}#");
        }
        line.push(' ');
        line.push_str(word);
    }
    out.push_str(&line);
    out.push('\n');
}

/// "required", "required for a vee", "none", or "default 0.01".
fn default_text(k: &KeyDoc) -> String {
    if k.default.starts_with("required") || k.default.starts_with("none") {
        k.default.to_string()
    } else {
        format!("default {}", k.default)
    }
}

/// One key: its comment, then `key = value` (commented out unless `set`).
fn entry(out: &mut String, k: &KeyDoc, value: &str, set: bool) {
    let unit = if k.unit.is_empty() {
        String::new()
    } else {
        format!(" [{}]", k.unit)
    };
    let bounds = k.bounds_text();
    let bounds = if bounds.is_empty() {
        String::new()
    } else {
        format!(" Bounds: {bounds}.")
    };
    let default = default_text(k);
    comment(
        out,
        "",
        &format!("{}{unit}, {default}: {}.{bounds}", k.key, k.meaning),
    );
    if set {
        out.push_str(&format!("{} = {value}\n", k.key));
    } else {
        out.push_str(&format!("# {} = {value}\n", k.key));
    }
}

/// The value `key` gets in this template and whether it is set.
fn value(k: &KeyDoc, o: &TemplateOptions, p: &Plan, engine: Option<&Engine>) -> (String, bool) {
    let z = o.cylinders;
    let vee = o.layout == TemplateLayout::Vee;
    match (k.section, k.key) {
        ("", "cylinders") => (z.to_string(), true),
        ("", "layout") => (
            format!("\"{}\"", o.layout.name()),
            o.layout != TemplateLayout::Inline,
        ),
        ("", "bank_angle_deg") => match p.bank_angle_deg {
            Some(b) => (deg_list(&[b]).trim_matches(['[', ']']).to_string(), true),
            None => (k.example.to_string(), false),
        },
        ("", "firing_order") => (list(&p.firing_order), z > 1),
        ("", "firing_angles_deg") => match engine {
            Some(e) => (
                deg_list(
                    &e.firing_angles()
                        .iter()
                        .map(|a| a.to_degrees())
                        .collect::<Vec<_>>(),
                ),
                false,
            ),
            None => (k.example.to_string(), false),
        },
        ("", "crank_angles_deg") => match (&p.crank_angles_deg, engine) {
            (Some(c), _) => (deg_list(c), true),
            (None, Some(e)) => (
                deg_list(
                    &e.crank_angles()
                        .iter()
                        .map(|a| a.to_degrees())
                        .collect::<Vec<_>>(),
                ),
                false,
            ),
            (None, None) => (k.example.to_string(), false),
        },
        ("", "name") => (
            format!(
                "\"{}-cylinder {}{}\"",
                z,
                o.layout.name(),
                if vee { "" } else { " engine" }
            ),
            false,
        ),
        ("masses", "crank_unbalanced_kg") => ("0.0".to_string(), false),
        (section, key) if o.combustion == Some(CombustionKind::Diesel) => {
            match diesel_value(section, key) {
                Some((v, set)) => (v.to_string(), set),
                None => (k.example.to_string(), k.required),
            }
        }
        _ => (k.example.to_string(), k.required),
    }
}

/// The cylinder of the diesel template: a heavy-duty truck engine's
/// (bore 130 mm, stroke 160 mm: 2.12 l a cylinder, 12.7 l as a six; CR
/// 17; rated at 1,900 rpm), the masses of the bundled inline-6 diesel.
fn diesel_value(section: &str, key: &str) -> Option<(&'static str, bool)> {
    Some(match (section, key) {
        ("", "bore_mm") => ("130.0", true),
        ("", "stroke_mm") => ("160.0", true),
        ("", "rod_length_mm") => ("265.0", true),
        ("", "cylinder_spacing_mm") => ("160.0", false),
        ("", "compression_ratio") => ("17.0", true),
        ("masses", "piston_group_kg") => ("3.9", true),
        ("masses", "rod_kg") => ("4.2", true),
        ("masses", "rod_inertia_kg_m2") => ("0.047", false),
        ("operating", "rpm") => ("1900.0", true),
        _ => return None,
    })
}

/// `[friction]` (Chen–Flynn) for a template with `[combustion]`: the
/// defaults of its kind, set, so a design run gives its brake figures.
fn friction_section(out: &mut String, kind: Option<CombustionKind>) {
    let Some(kind) = kind else {
        out.push('\n');
        comment(
            out,
            "",
            "[friction]: Chen–Flynn friction, FMEP = a + b p_max + c c_m + d c_m², for the brake figures (FMEP, BMEP, brake torque and power) in place of operating.mechanical_efficiency; `enginedyn template --combustion petrol|diesel` writes its keys.",
        );
        return;
    };
    let f = match kind {
        CombustionKind::Petrol => enginedyn_combustion::friction::ChenFlynn::PETROL,
        CombustionKind::Diesel => enginedyn_combustion::friction::ChenFlynn::DIESEL,
    };
    section_header(
        out,
        "friction",
        "Chen–Flynn friction: FMEP = a + b p_max + c c_m + d c_m² (bar; p_max the peak cylinder pressure in bar, c_m the mean piston speed in m/s). With it every run gives FMEP, BMEP = IMEP − FMEP, brake torque and power and the mechanical efficiency, in place of operating.mechanical_efficiency. The values are enginedyn's defaults for this kind of engine (docs/design.md).",
    );
    for k in KEYS.iter().filter(|k| k.section == "friction") {
        let v = match k.key {
            "a_bar" => f.a_pa / 1e5,
            "b" => f.b,
            "c_bar_s_m" => f.c_pa_s_m / 1e5,
            _ => f.d_pa_s2_m2 / 1e5,
        };
        out.push('\n');
        entry(out, k, &format!("{v:?}"), true);
    }
}

fn section_header(out: &mut String, title: &str, about: &str) {
    out.push('\n');
    out.push_str(&format!("[{title}]\n"));
    comment(out, "", about);
}

fn write_keys(
    out: &mut String,
    section: &str,
    o: &TemplateOptions,
    p: &Plan,
    engine: Option<&Engine>,
    commented: bool,
) {
    let keys: Vec<&KeyDoc> = KEYS.iter().filter(|k| k.section == section).collect();
    let values: Vec<(String, bool)> = keys.iter().map(|k| value(k, o, p, engine)).collect();
    // The keys set first, then the rest.
    for want in [true, false] {
        let mut first = true;
        for (k, (v, set)) in keys.iter().zip(&values) {
            if *set != want {
                continue;
            }
            if first && !want && section.is_empty() {
                out.push_str("\n# ---- optional: delete the `#` to set one ----\n");
            }
            first = false;
            out.push('\n');
            entry(out, k, v, *set && !commented);
            if k.key == "damper" {
                for d in KEYS.iter().filter(|d| d.section == "torsion.damper") {
                    let unit = if d.unit.is_empty() {
                        String::new()
                    } else {
                        format!(" [{}]", d.unit)
                    };
                    comment(
                        out,
                        "",
                        &format!(
                            "  damper's {}{unit}, {}: {}. Bounds: {}.",
                            d.key,
                            default_text(d),
                            d.meaning,
                            d.bounds_text()
                        ),
                    );
                }
            }
        }
    }
}

fn render(o: &TemplateOptions, p: &Plan, engine: Option<&Engine>) -> String {
    let mut out = String::new();
    let flags = format!(
        "--cylinders {} --layout {}{}{}",
        o.cylinders,
        o.layout.name(),
        if o.torsion { " --torsion" } else { "" },
        o.combustion
            .map(|c| format!(" --combustion {}", c.name()))
            .unwrap_or_default()
    );
    comment(
        &mut out,
        "",
        &format!(
            "enginedyn engine file (TOML) for a four-stroke engine, {} cylinders {}, written by `enginedyn template {flags}`.",
            o.cylinders,
            match o.layout {
                TemplateLayout::Inline => "in line",
                TemplateLayout::Vee => "in a vee",
                TemplateLayout::Boxer => "opposed (boxer)",
            }
        ),
    );
    comment(
        &mut out,
        "",
        "Every key the file takes is below with its unit, its default and what it is for: first the keys a file needs, set; then the optional ones, commented out (with their default, or an example where the default is not a number). Units are in the names: _mm, _kg, _deg, _bar, _m_s (m/s), _kg_m2 (kg m²), _nm_rad (N m/rad). docs/engine-file.md lists the keys too.",
    );
    comment(
        &mut out,
        "",
        if o.combustion == Some(CombustionKind::Diesel) {
            "The numbers are a heavy-duty diesel's cylinder (bore 130 mm, stroke 160 mm, 2.12 l, compression ratio 17, rated at 1900 rpm; the masses of the bundled inline-6 diesel), and [combustion] makes its diagram, so the file runs as it is:"
        } else if o.combustion.is_some() {
            "The numbers are one cylinder of the bundled example (VAZ-2108 type, 1.3 l petrol, 4900 rpm), and [combustion] makes its diagram, so the file runs as it is:"
        } else {
            "The numbers are one cylinder of the bundled example (VAZ-2108 type, 1.3 l petrol, 4900 rpm), so the file runs as it is:"
        },
    );
    out.push_str(if o.combustion.is_some() {
        "#     enginedyn run --engine THIS_FILE.toml\n"
    } else {
        "#     enginedyn run --engine THIS_FILE.toml --diagram data/vaz2108.csv\n"
    });
    comment(
        &mut out,
        "",
        &format!(
            "Put in your engine's numbers. Firing: {}. `enginedyn firing-orders --all-cranks --engine THIS_FILE.toml` ranks the others.",
            p.why
        ),
    );
    out.push_str("\n# ---- needed ----\n");
    write_keys(&mut out, "", o, p, engine, false);
    section_header(
        &mut out,
        "masses",
        "One cylinder's crank train: piston group, rod, crank.",
    );
    write_keys(&mut out, "masses", o, p, engine, false);
    section_header(&mut out, "operating", "The operating point.");
    write_keys(&mut out, "operating", o, p, engine, false);
    section_header(
        &mut out,
        "flywheel",
        "Flywheel sizing; the section is optional as a whole.",
    );
    write_keys(&mut out, "flywheel", o, p, engine, false);
    out.push('\n');
    out.push_str("# [tolerances]\n");
    comment(
        &mut out,
        "",
        "± manufacturing and measurement tolerances for `enginedyn tolerance`; optional. Delete the `#` before [tolerances] and the keys you use.",
    );
    write_keys(&mut out, "tolerances", o, p, engine, true);
    if o.torsion {
        section_header(
            &mut out,
            "torsion",
            "The crankshaft as a chain of inertias on torsional springs, from the free end: front mass, one mass per throw, flywheel, driven load (`enginedyn torsion`). A list gives one value per item from the free end.",
        );
        write_keys(&mut out, "torsion", o, p, engine, false);
    } else {
        out.push('\n');
        comment(
            &mut out,
            "",
            "[torsion]: the crankshaft's torsional vibration (`enginedyn torsion`); `enginedyn template --torsion` writes its keys.",
        );
    }
    match o.combustion {
        Some(kind) => {
            combustion_section(&mut out, kind);
            friction_section(&mut out, Some(kind));
        }
        None => {
            out.push('\n');
            comment(
                &mut out,
                "",
                "[combustion]: a burn law that makes the diagram for an engine that has none yet (`enginedyn synth`); `enginedyn template --combustion petrol|diesel` writes its keys.",
            );
            friction_section(&mut out, None);
        }
    }
    out
}

/// The value of each `[combustion]` (and `[combustion.second]`) key in
/// the template of `kind`, and whether it is set (the rest commented out).
fn combustion_value(
    kind: CombustionKind,
    section: &str,
    key: &str,
) -> Option<(&'static str, bool)> {
    let diesel = kind == CombustionKind::Diesel;
    Some(match (section, key) {
        ("combustion", "ca50_deg") => (if diesel { "2.0" } else { "8.0" }, true),
        ("combustion", "duration_10_90_deg") => (if diesel { "6.0" } else { "20.0" }, true),
        ("combustion", "wiebe_m") => ("2.0", true),
        ("combustion", "imep_bar") => (if diesel { "18.0" } else { "10.0" }, true),
        ("combustion", "intake_pressure_bar") => (if diesel { "2.2" } else { "1.0" }, diesel),
        ("combustion", "ivc_deg") => (if diesel { "-145.0" } else { "-140.0" }, diesel),
        ("combustion", "evo_deg") => (if diesel { "125.0" } else { "130.0" }, diesel),
        ("combustion", "charge") => (if diesel { "\"ci\"" } else { "\"si\"" }, true),
        ("combustion", "full_load") => (
            if diesel {
                "{ rpm = [800.0, 1000.0, 1200.0, 1400.0, 1600.0, 1900.0, 2100.0], imep_bar = [15.0, 20.0, 23.0, 23.0, 22.0, 20.0, 17.0] }"
            } else {
                "{ rpm = [1000.0, 2000.0, 3000.0, 3400.0, 4000.0, 5000.0, 5600.0, 6000.0], imep_bar = [9.6, 10.3, 10.8, 10.9, 10.8, 10.3, 9.9, 9.5] }"
            },
            true,
        ),
        ("combustion", "second") => return None,
        ("combustion.second", "fraction") => ("0.8", diesel),
        ("combustion.second", "ca50_deg") => ("18.0", diesel),
        ("combustion.second", "duration_10_90_deg") => ("40.0", diesel),
        ("combustion.second", "wiebe_m") => ("0.8", diesel),
        _ => ("", false),
    })
}

/// `[combustion]` for `kind`: the burn law as CA50, the 10–90 duration and
/// m, set; the other form and the optional keys commented out.
fn combustion_section(out: &mut String, kind: CombustionKind) {
    let diesel = kind == CombustionKind::Diesel;
    section_header(
        out,
        "combustion",
        &if diesel {
            "The burn law of a synthesised diagram (`enginedyn synth`; `run`, `torsion`, `tolerance` and `sweep` use it when no diagram is given): a turbocharged direct-injection diesel at full load, a short premixed burn (this section, a fifth of the heat) and a long diffusion burn ([combustion.second]). The burn law is given either as ca50_deg + duration_10_90_deg + wiebe_m, or as start_deg + duration_deg + wiebe_a + wiebe_m. docs/combustion.md, \"Synthesis for design\", says how the diagram is made.".to_string()
        } else {
            "The burn law of a synthesised diagram (`enginedyn synth`; `run`, `torsion`, `tolerance` and `sweep` use it when no diagram is given): a spark-ignition engine at full load, CA50 8° after TDC at best-torque timing, 10–90 in 20°. The burn law is given either as ca50_deg + duration_10_90_deg + wiebe_m, or as start_deg + duration_deg + wiebe_a + wiebe_m. docs/combustion.md, \"Synthesis for design\", says how the diagram is made.".to_string()
        },
    );
    for section in ["combustion", "combustion.second"] {
        if section == "combustion.second" {
            out.push('\n');
            if diesel {
                out.push_str("[combustion.second]\n");
            } else {
                out.push_str("# [combustion.second]\n");
            }
            comment(
                out,
                "",
                "A second Wiebe burn, its share of the heat `fraction` (a diesel's diffusion burn); optional.",
            );
        }
        let keys: Vec<&KeyDoc> = KEYS.iter().filter(|k| k.section == section).collect();
        for want in [true, false] {
            for k in &keys {
                let Some((v, set)) = combustion_value(kind, section, k.key) else {
                    continue;
                };
                if set != want {
                    continue;
                }
                let v = if v.is_empty() { k.example } else { v };
                out.push('\n');
                entry(out, k, v, set);
            }
        }
    }
}

/// The commented engine file `enginedyn template` prints. It is read back
/// ([`crate::file::parse`]) before it is returned: the firing and crank
/// written pass the engine's checks.
pub fn template(o: &TemplateOptions) -> Result<String, TemplateError> {
    let z = o.cylinders;
    if !(1..=24).contains(&z) {
        return Err(TemplateError::Cylinders {
            cylinders: z,
            expected: "1 to 24",
        });
    }
    if o.layout != TemplateLayout::Inline && !z.is_multiple_of(2) {
        return Err(TemplateError::Cylinders {
            cylinders: z,
            expected: match o.layout {
                TemplateLayout::Vee => "a vee has an even number of cylinders, 2 to 24",
                _ => "a boxer has an even number of cylinders, 2 to 24",
            },
        });
    }
    let p = plan(z, o.layout);
    let first = render(o, &p, None);
    let engine = crate::file::parse(&first, "template")?;
    debug_assert!(matches!(
        (engine.layout(), o.layout),
        (Layout::Inline, TemplateLayout::Inline)
            | (Layout::Vee { .. }, TemplateLayout::Vee)
            | (Layout::Boxer, TemplateLayout::Boxer)
    ));
    let text = render(o, &p, Some(&engine));
    crate::file::parse(&text, "template")?;
    Ok(text)
}
