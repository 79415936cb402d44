//! `enginedyn report`: the engine design report (INTERFACE "The design
//! report"). With the engine file's `[combustion]` it runs the studies a
//! design review asks for: the speed × load map in percent of the
//! full-load line (`[combustion.full_load]`, else the file's own load),
//! the full analysis at rated power and at peak torque, torsional vibration
//! over the map's speeds at full load, the firing orders and free forces,
//! the tolerances; with `--diagram` (or the file's `diagram` and no
//! `[combustion]`), the same studies at that one operating point. The
//! page is laid out by `enginedyn_report::design`.

use crate::diagram::Input;
use crate::engine::Loaded;
use crate::error::{Error, Result};
use crate::map::{Loads, SweepMap};
use crate::options::{Method, Reader};
use crate::session::Session;
use enginedyn_numerics::format::{fixed, human};
use enginedyn_pipeline::{Analysis, Scope};
use enginedyn_report::{DesignPage, Headline, MapView, Section, shown};
use std::path::Path;

/// What `enginedyn report` was asked for.
#[derive(Debug, Clone, Default)]
pub struct Request<'a> {
    /// `--diagram`: a report at that one operating point.
    pub diagram: Option<&'a Path>,
    /// `--rpm A:B:S`: the map's speeds.
    pub rpm: Option<&'a str>,
    /// `--load P:Q:R`: the map's loads (percent of the full-load line).
    pub load: Option<&'a str>,
    /// `--parquet`: the map also as `tables/map.parquet`.
    pub parquet: bool,
}

/// The report's files.
#[derive(Debug)]
pub struct Report {
    /// `report.html` and every chart, for DIR.
    pub files: Vec<(String, Vec<u8>)>,
    /// The tables, for `DIR/tables` (`README.txt` among them).
    pub tables: Vec<(String, Vec<u8>)>,
    /// The one-screen summary as text (what the command prints).
    pub text: String,
    /// Notes to say once (the studies' own are in the page).
    pub notes: Vec<String>,
}

/// The loads a report's map runs at when `--load` is not given (percent).
pub const DEFAULT_LOADS: &str = "10:100:10";
/// How many speeds a report's map runs at when `--rpm` is not given
/// (about: the step is a round number).
const DEFAULT_SPEED_COUNT: f64 = 16.0;
/// Speeds of the torsion study over the map's span (its resonances are
/// narrower than the map's speed step).
const TORSION_SPEEDS: usize = 200;
/// Firing orders listed in the page (the CSV has every one).
const FIRING_ROWS: usize = 8;

/// The design report of `loaded` (see the module's documentation).
pub fn report(loaded: Loaded, reader: Reader, method: Method, req: &Request<'_>) -> Result<Report> {
    let design = loaded.engine.combustion().is_some() && req.diagram.is_none();
    if design {
        design_report(loaded, reader, method, req)
    } else {
        if req.rpm.is_some() || req.load.is_some() {
            return Err(Error::usage(format!(
                "--rpm and --load set the map of a design report, which needs [combustion] in the engine file and no --diagram; {} is reported at its one operating point",
                req.diagram
                    .map_or("the engine file's diagram".to_string(), |d| d
                        .display()
                        .to_string())
            )));
        }
        point_report(loaded, reader, method, req.diagram)
    }
}

/// The speeds of a design report: `--rpm`, else the full-load line's span
/// (or from idle, else a fifth of the operating speed, up to the
/// operating speed) in about [`DEFAULT_SPEED_COUNT`] round steps; with how
/// they are named.
fn speeds(loaded: &Loaded, given: Option<&str>) -> Result<(Vec<f64>, String)> {
    if let Some(g) = given {
        return Ok((crate::speed::speeds(g)?, g.to_string()));
    }
    let engine = &loaded.engine;
    let line = engine
        .combustion()
        .and_then(|c| c.full_load.as_ref())
        .map(|f| (f.curve.rpm[0], f.curve.rpm[f.curve.rpm.len() - 1]));
    let (lo, hi) = match line {
        Some((a, b)) if b > a => (a, b),
        _ => {
            let rpm = engine.operating().rpm.unwrap_or(3000.0);
            let idle = engine.flywheel().idle.map(|(r, _)| r);
            (idle.unwrap_or(rpm / 5.0).min(rpm / 2.0), rpm)
        }
    };
    let raw = (hi - lo) / DEFAULT_SPEED_COUNT;
    let step = [10.0, 20.0, 25.0, 50.0, 100.0, 200.0, 250.0, 500.0, 1000.0]
        .into_iter()
        .find(|s| *s >= raw)
        .unwrap_or(1000.0);
    let first = (lo / step).ceil() * step;
    let shown = format!("{}:{}:{}", human(first), human(hi), human(step));
    let mut rpms = crate::speed::speeds(&shown)?;
    if rpms.last().is_some_and(|&r| r < hi) {
        rpms.push(hi);
    }
    Ok((rpms, shown))
}

/// The loads of a design report: percent of the full-load line; without
/// `[combustion.full_load]`, percent of the engine file's own load (its
/// `imep_bar`, else the IMEP its cycle gives at the operating speed) at
/// every speed. With how they are named and what 100 % is.
fn loads(session: &Session, given: Option<&str>) -> Result<(Loads, String, String)> {
    let shown = given.unwrap_or(DEFAULT_LOADS).to_string();
    let pct = crate::options::load_range(&shown)?;
    let spec = crate::synth::spec(&session.loaded)?;
    if spec.full_load.is_some() {
        return Ok((
            Loads::Percent(pct),
            shown,
            "[combustion.full_load] at each speed".to_string(),
        ));
    }
    let base = match spec.load {
        Some(enginedyn_engine::combustion::CombustionLoad::Imep(pa)) => pa / 1e5,
        _ => {
            let d = crate::synth::synthesise(&session.loaded, None, None, session.method.step())?;
            let o = session.analyse(&[d.input()])?;
            o.analysis.summary.imep_bar.ok_or_else(|| {
                Error::usage(
                    "the engine file's cycle gives no IMEP to take as full load".to_string(),
                )
            })?
        }
    };
    let imeps = pct.iter().map(|p| p / 100.0 * base).collect();
    Ok((
        Loads::Imep(imeps),
        shown,
        format!(
            "IMEP {} bar, the engine file's load, at every speed (no [combustion.full_load])",
            human((base * 1e3).round() / 1e3)
        ),
    ))
}

/// The full analysis at a full-load point of `map` (`rpm`): its cycle made
/// again at that speed and load, with every curve.
fn full_load_point(session: &Session, map: &SweepMap, rpm: f64) -> Result<Analysis> {
    let last = map.loads.values().len() - 1;
    let p = map
        .points
        .iter()
        .find(|p| p.load == last && p.point.summary.rpm.to_bits() == rpm.to_bits())
        .ok_or_else(|| Error::usage(format!("no full-load point at {} rpm", human(rpm))))?;
    let d = crate::synth::synthesise_samples(
        &session.loaded,
        Some(rpm),
        Some(p.imep_target_bar),
        session.method.step(),
    )?;
    session.analyse_synthesised(&d, rpm)
}

/// The map as the report's layout reads it.
fn view(map: &SweepMap, brake: bool) -> MapView<'_> {
    MapView {
        rpms: &map.rpms,
        load_names: map
            .loads
            .values()
            .iter()
            .map(|v| match map.loads {
                Loads::Percent(_) => format!("{} %", human(*v)),
                Loads::Imep(_) => format!("IMEP {} bar", human((v * 1e3).round() / 1e3)),
            })
            .collect(),
        cells: map.points.iter().map(|p| &p.point.summary).collect(),
        imep_targets: map.points.iter().map(|p| p.imep_target_bar).collect(),
        rated: map.rated_power,
        peak: map.peak_torque,
        brake,
    }
}

/// The method's settings as every section names them.
fn method_settings(s: &enginedyn_pipeline::Summary) -> (String, String) {
    (
        "method".to_string(),
        format!(
            "{} kinematics, {} rod, {}° grid, {} rule",
            s.kinematics, s.rod_model, s.grid_step_deg, s.integration
        ),
    )
}

fn design_report(
    loaded: Loaded,
    reader: Reader,
    method: Method,
    req: &Request<'_>,
) -> Result<Report> {
    let map_session = Session::new(loaded.clone(), reader.clone(), method, Scope::Summary)?;
    let (rpms, rpm_shown) = speeds(&loaded, req.rpm)?;
    let (loads, load_shown, full_basis) = loads(&map_session, req.load)?;
    let map = map_session.sweep_map(&rpms, &loads, &rpm_shown, &load_shown)?;
    let session = Session::new(loaded, reader, method, Scope::Full)?;
    let engine = session.engine();
    let brake = engine.friction().is_some();
    let v = view(&map, brake);
    let (Some((rated_rpm, _)), Some((peak_rpm, _))) = (map.rated_power, map.peak_torque) else {
        return Err(Error::data(
            "the map's full-load row delivers no work: no rated power or peak torque to report"
                .to_string(),
        ));
    };
    let rated = full_load_point(&session, &map, rated_rpm)?;
    let peak = if peak_rpm.to_bits() == rated_rpm.to_bits() {
        None
    } else {
        Some(full_load_point(&session, &map, peak_rpm)?)
    };
    let mut page = DesignPage {
        title: format!("{} — engine design report", engine.name()),
        lead: format!(
            "{} speeds ({} rpm) × {} loads ({} % of {}); computed by enginedyn {} from {}",
            rpms.len(),
            rpm_shown,
            loads.values().len(),
            load_shown,
            full_basis,
            env!("CARGO_PKG_VERSION"),
            session.loaded.shown()
        ),
        ..DesignPage::default()
    };
    let mut tables = Vec::new();
    if req.parquet {
        tables.push(("map.parquet".to_string(), map.parquet(&map_session)?));
    }
    let method = method_settings(&rated.summary);
    page.sections.push(engine_section(&session, &rated)?);
    page.sections
        .push(full_load_section(engine.name(), &v, &method, &mut tables)?);
    page.sections
        .push(map_section(engine.name(), &v, &map, &method, &mut tables)?);
    page.sections
        .push(flywheel_section(engine.name(), &v, &map)?);
    for (what, a) in [
        ("rated power", Some(&rated)),
        ("peak torque", peak.as_ref()),
    ] {
        if let Some(a) = a {
            page.sections.push(crank_train_section(engine, a, what)?);
        }
    }
    // Resonances are narrow: the map's span on a finer grid of speeds.
    let (lo, hi) = (rpms[0], rpms[rpms.len() - 1]);
    let torsion_rpms: Vec<f64> = (0..TORSION_SPEEDS)
        .map(|k| lo + (hi - lo) * k as f64 / (TORSION_SPEEDS - 1) as f64)
        .collect();
    let torsion = torsion_section(&session, &rated, &torsion_rpms)?;
    page.sections.push(torsion.0);
    let firing = firing_section(&session, &rated, &mut tables)?;
    page.sections.push(firing.0);
    page.sections.push(tolerance_section(&session, &rated)?);
    page.headlines = headlines(
        engine,
        &v,
        &map,
        &rated,
        peak.as_ref(),
        torsion.1.as_ref(),
        &firing.1,
    );
    finish(page, tables, map.notes)
}

/// The report at one operating point: the diagram given, else the engine
/// file's.
fn point_report(
    loaded: Loaded,
    reader: Reader,
    method: Method,
    diagram: Option<&Path>,
) -> Result<Report> {
    let session = Session::new(loaded, reader, method, Scope::Full)?;
    let path = match crate::diagram::diagram_path(diagram, &session.loaded) {
        Ok(p) => Some(p),
        // A template as written: its cylinder is the bundled example's,
        // whose diagram was measured on it.
        Err(_) if example_cylinder(&session.loaded)? => None,
        Err(e) => {
            return Err(Error::usage(format!(
                "{e}; or add a [combustion] section for a design report over the speed × load map (`enginedyn template --combustion petrol` writes one)"
            )));
        }
    };
    let input = path
        .as_deref()
        .map_or(Input::Bundled(crate::EXAMPLE), Input::File);
    let mut a = session.analyse(&[input])?.analysis;
    if path.is_none() {
        a.summary.notes.insert(
            0,
            format!(
                "no diagram and no [combustion]: the report reads the bundled example's diagram ({}), measured on this engine's cylinder (bore, stroke, rod and compression ratio are the example's); give --diagram for your own",
                crate::EXAMPLE.diagram_name()
            ),
        );
    }
    let engine = session.engine();
    let mut page = DesignPage {
        title: format!("{} — engine design report", engine.name()),
        lead: format!(
            "one operating point: {} at {} rpm; computed by enginedyn {} from {}",
            input.shown(),
            human(a.summary.rpm),
            env!("CARGO_PKG_VERSION"),
            session.loaded.shown()
        ),
        ..DesignPage::default()
    };
    let mut tables = Vec::new();
    page.sections.push(engine_section(&session, &a)?);
    page.sections.push(Section {
        id: "map",
        heading: "Full-load line and map".into(),
        body: "<p>A measured diagram is one operating point: there is no full-load line or map. \
               An engine file with <code>[combustion]</code> and <code>[combustion.full_load]</code> \
               (<code>enginedyn template --combustion petrol</code> writes one) gives both.</p>\n"
            .into(),
        ..Section::default()
    });
    page.sections.push(point_flywheel_section(&a));
    page.sections
        .push(crank_train_section(engine, &a, "the operating point")?);
    let rpms = crate::torsion::default_speeds(a.summary.rpm);
    let torsion = torsion_section(&session, &a, &rpms)?;
    page.sections.push(torsion.0);
    let firing = firing_section(&session, &a, &mut tables)?;
    page.sections.push(firing.0);
    page.sections.push(tolerance_section(&session, &a)?);
    page.headlines = point_headlines(engine, &a, torsion.1.as_ref(), &firing.1);
    finish(page, tables, a.summary.notes.clone())
}

/// Whether `loaded`'s engine has the bundled example's cylinder (its
/// diagram then fits it: a template as written) and cycle.
fn example_cylinder(loaded: &Loaded) -> Result<bool> {
    let example = Loaded::bundled(crate::EXAMPLE)?;
    let (a, b) = (&loaded.engine, &example.engine);
    // The same volume law to 0.5 % at every 30° (a rod length given as
    // λ in one file and in mm in the other differs in its last digits).
    let same_law = (0..12).all(|k| {
        let phi = (k as f64 * 30.0).to_radians();
        let (va, vb) = (a.cylinder().volume(phi), b.cylinder().volume(phi));
        (va - vb).abs() <= 5e-3 * vb
    });
    Ok(same_law && a.stroke_kind() == b.stroke_kind())
}

/// The page and the tables as files; the headlines as text.
fn finish(
    page: DesignPage,
    mut tables: Vec<(String, Vec<u8>)>,
    notes: Vec<String>,
) -> Result<Report> {
    let mut files = vec![(
        "report.html".to_string(),
        enginedyn_report::design_html(&page).into_bytes(),
    )];
    for s in &page.sections {
        for (name, svg) in &s.charts {
            files.push((name.clone(), svg.clone().into_bytes()));
        }
    }
    let listed: Vec<(&str, &str)> = tables
        .iter()
        .map(|(n, _)| (n.as_str(), table_purpose(n)))
        .collect();
    let readme = enginedyn_report::tables_readme(&listed);
    tables.push((
        enginedyn_report::TABLES_MARKER.to_string(),
        readme.into_bytes(),
    ));
    let mut text = format!("{}\n", page.title);
    for h in &page.headlines {
        text.push_str(&format!(
            "  {}: {} {} ({})\n",
            h.label, h.value, h.unit, h.at
        ));
    }
    Ok(Report {
        files,
        tables,
        text,
        notes,
    })
}

/// What a table of the report holds (its README line).
fn table_purpose(name: &str) -> &'static str {
    match name {
        "map.csv" => {
            "every point of the map: the summary's columns (as sweep.csv) with imep_target_bar, load_pct and the flywheel's sizing point"
        }
        "map.parquet" => {
            "the map as a Parquet table (map/1: the summary's columns, then imep_target_bar, load_pct, flywheel_sized_at_rpm, flywheel_sized_at_imep_bar)"
        }
        "full_load.csv" => "the full-load line: a row a speed, indicated and brake figures",
        "firing_orders.csv" => {
            "every firing order of the engine's crank, ranked, with its criteria (as firing-orders --out)"
        }
        _ => "a table of the report",
    }
}

fn engine_section(session: &Session, a: &Analysis) -> Result<Section> {
    let engine = session.engine();
    let s = &a.summary;
    let rows: Vec<Vec<String>> = enginedyn_report::engine_rows(engine, s)
        .into_iter()
        .filter(|(k, _)| *k != "speed")
        .map(|(k, v)| vec![k.to_string(), v])
        .collect();
    let z = engine.cylinders() as f64;
    let displacement = z * engine.cylinder().swept_volume();
    let mut body = enginedyn_report::text_table(&["", ""], &rows, &[false, false]);
    body.push_str(&format!(
        "<p>Displacement {} l ({} × {} cm³).</p>\n",
        fixed(displacement * 1e3, 3),
        engine.cylinders(),
        fixed(engine.cylinder().swept_volume() * 1e6, 1)
    ));
    let inputs = crate::inputs::of(&session.loaded, &[])?;
    body.push_str(&enginedyn_report::text_table(
        &["provenance", ""],
        &[
            vec![
                "engine file".into(),
                format!("{} (BLAKE3 {})", inputs.engine_file, inputs.engine_blake3),
            ],
            vec![
                "computed by".into(),
                format!("enginedyn {}", inputs.enginedyn_version),
            ],
        ],
        &[false, false],
    ));
    Ok(Section {
        id: "engine",
        heading: "The engine".into(),
        settings: vec![method_settings(s)],
        body,
        notes: engine.notes().to_vec(),
        ..Section::default()
    })
}

fn full_load_section(
    name: &str,
    v: &MapView<'_>,
    method: &(String, String),
    tables: &mut Vec<(String, Vec<u8>)>,
) -> Result<Section> {
    let (html, csv) = enginedyn_report::full_load_table(v);
    tables.push(("full_load.csv".into(), csv.into_bytes()));
    let fig = enginedyn_report::full_load_figure(name, v);
    let svg = fig.render().map_err(|e| Error::data(e.to_string()))?;
    let mut body = String::new();
    if let (Some((rr, p)), Some((tr, t))) = (v.rated, v.peak) {
        body.push_str(&format!(
            "<p><b>Rated power {} kW at {} rpm; peak torque {} N m at {} rpm</b> ({} figures).</p>\n",
            fixed(p, 1),
            human(rr),
            fixed(t, 1),
            human(tr),
            v.basis()
        ));
    }
    body.push_str(&html);
    Ok(Section {
        id: "full-load",
        heading: "The full-load line".into(),
        settings: vec![
            (
                "load".into(),
                v.load_names.last().cloned().unwrap_or_default(),
            ),
            ("friction".into(), friction_basis(v.brake)),
            method.clone(),
        ],
        body,
        charts: vec![(fig.file, svg)],
        ..Section::default()
    })
}

/// How the effective figures are made, as settings name it.
fn friction_basis(brake: bool) -> String {
    if brake {
        "Chen–Flynn, [friction]: FMEP on each point's own peak pressure and piston speed".into()
    } else {
        "none: effective = indicated × operating.mechanical_efficiency".into()
    }
}

fn map_section(
    name: &str,
    v: &MapView<'_>,
    map: &SweepMap,
    method: &(String, String),
    tables: &mut Vec<(String, Vec<u8>)>,
) -> Result<Section> {
    tables.push(("map.csv".into(), map.csv().into_bytes()));
    let mut charts = Vec::new();
    for c in enginedyn_report::map_contours(name, v) {
        if matches!(c.file.as_str(), "map_delta.svg" | "map_inertia.svg") {
            continue;
        }
        let svg = c.render().map_err(|e| Error::data(e.to_string()))?;
        charts.push((c.file, svg));
    }
    let body = format!(
        "<p>Each point's cycle is synthesised at its own speed and load from <code>[combustion]</code> \
         (spark ignition: the intake pressure meets the load; compression ignition: the fuel) and analysed \
         at that speed. The vertical axis is the {} (the torque is it × displacement / 4π, / 2π for a \
         two-stroke). The full-load line is drawn over each chart. Every point is in \
         <code>tables/map.csv</code>.</p>\n",
        v.mep_label()
    );
    Ok(Section {
        id: "map",
        heading: "The map".into(),
        settings: vec![
            (
                "speeds".into(),
                format!(
                    "{} speeds, {} to {} rpm",
                    v.rpms.len(),
                    human(v.rpms.first().copied().unwrap_or_default()),
                    human(v.rpms.last().copied().unwrap_or_default())
                ),
            ),
            ("loads".into(), v.load_names.join(", ")),
            method.clone(),
        ],
        body,
        charts,
        ..Section::default()
    })
}

fn flywheel_section(name: &str, v: &MapView<'_>, map: &SweepMap) -> Result<Section> {
    let part = v.cells.iter().find(|s| s.flywheel_inertia_kg_m2.is_some());
    let mut body = String::new();
    match (map.sized_at, part) {
        (Some((rpm, imep)), Some(s)) => {
            let top = v.rpms.iter().copied().fold(0.0, f64::max);
            let rim = s
                .flywheel_outer_diameter_m
                .map(|d| d * std::f64::consts::PI * top / 60.0);
            let mut rows = vec![vec![
                "sized at".into(),
                format!("{} rpm, IMEP {} bar", human(rpm), fixed(imep, 2)),
                String::new(),
            ]];
            rows.extend(part_rows(s));
            rows.push(vec![
                "rim speed at the highest speed".into(),
                shown(rim, 1),
                "m/s".into(),
            ]);
            body.push_str(&enginedyn_report::text_table(
                &["flywheel", "value", "unit"],
                &rows,
                &[false, true, false],
            ));
            body.push_str(&delta_table(v));
        }
        _ => body.push_str("<p>No point of the map delivers work: no flywheel is sized.</p>\n"),
    }
    let mut charts = Vec::new();
    for c in enginedyn_report::map_contours(name, v) {
        if matches!(c.file.as_str(), "map_delta.svg" | "map_inertia.svg") {
            let svg = c.render().map_err(|e| Error::data(e.to_string()))?;
            charts.push((c.file, svg));
        }
    }
    Ok(Section {
        id: "flywheel",
        heading: "The flywheel".into(),
        settings: vec![(
            "criterion".into(),
            "the worst of the map's points and idle (flywheel.idle_rpm)".into(),
        )],
        body,
        charts,
        notes: map
            .notes
            .iter()
            .filter(|n| n.contains("flywheel") || n.contains("idle"))
            .cloned()
            .collect(),
    })
}

/// The speed fluctuation the one flywheel gives at every point (‰), a row
/// a load.
fn delta_table(v: &MapView<'_>) -> String {
    let n = v.rpms.len();
    let mut head = vec!["δ (‰) at load \\ speed (rpm)".to_string()];
    head.extend(v.rpms.iter().map(|r| human(*r)));
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let rows: Vec<Vec<String>> = v
        .cells
        .chunks(n.max(1))
        .zip(&v.load_names)
        .rev()
        .map(|(row, name)| {
            let mut r = vec![name.clone()];
            r.extend(
                row.iter()
                    .map(|s| shown(s.speed_fluctuation_achieved.map(|d| d * 1e3), 2)),
            );
            r
        })
        .collect();
    let mut numeric = vec![false];
    numeric.extend(std::iter::repeat_n(true, n));
    format!(
        "<h3>Speed fluctuation δ with this flywheel at every point</h3>\n{}",
        enginedyn_report::text_table(&head, &rows, &numeric)
    )
}

fn point_flywheel_section(a: &Analysis) -> Section {
    let s = &a.summary;
    let mut rows = vec![vec![
        "inertia needed".into(),
        shown(s.required_inertia_kg_m2, 4),
        "kg m²".into(),
    ]];
    rows.extend(part_rows(s));
    rows.push(vec![
        "speed fluctuation δ achieved".into(),
        shown(s.speed_fluctuation_achieved, 4),
        String::new(),
    ]);
    Section {
        id: "flywheel",
        heading: "The flywheel".into(),
        settings: vec![("criterion".into(), "the operating point".into())],
        body: enginedyn_report::text_table(
            &["flywheel", "value", "unit"],
            &rows,
            &[false, true, false],
        ),
        ..Section::default()
    }
}

/// The flywheel part of `s` as table rows: its inertia, outer diameter,
/// width and mass with their units.
fn part_rows(s: &enginedyn_pipeline::Summary) -> Vec<Vec<String>> {
    vec![
        vec![
            "flywheel inertia".into(),
            shown(s.flywheel_inertia_kg_m2, 4),
            "kg m²".into(),
        ],
        vec![
            "outer diameter".into(),
            shown(s.flywheel_outer_diameter_m.map(|d| d * 1e3), 0),
            "mm".into(),
        ],
        vec![
            "rim width".into(),
            shown(s.flywheel_width_m.map(|d| d * 1e3), 1),
            "mm".into(),
        ],
        vec!["mass".into(), shown(s.flywheel_mass_kg, 2), "kg".into()],
    ]
}

fn crank_train_section(
    engine: &enginedyn_engine::Engine,
    a: &Analysis,
    what: &str,
) -> Result<Section> {
    let prefix = match what {
        "rated power" => "rated",
        "peak torque" => "peak_torque",
        _ => "point",
    };
    let (body, charts) =
        enginedyn_report::crank_train(engine, a, prefix).map_err(|e| Error::data(e.to_string()))?;
    let s = &a.summary;
    Ok(Section {
        id: match prefix {
            "rated" => "loads-rated",
            "peak_torque" => "loads-peak-torque",
            _ => "loads",
        },
        heading: format!("Crank-train loads at {what}"),
        settings: vec![
            ("speed".into(), format!("{} rpm", human(s.rpm))),
            ("IMEP".into(), format!("{} bar", shown(s.imep_bar, 2))),
            method_settings(s),
        ],
        body,
        charts,
        // What the analysis noted there, but the engine's own notes (the
        // engine section has them).
        notes: s
            .notes
            .iter()
            .filter(|n| !engine.notes().contains(n))
            .cloned()
            .collect(),
    })
}

/// A study's own `report.html` sections as parts of one of the report's:
/// each under its heading, but one that repeats the section's.
fn sub_sections(parts: &[(String, String)], heading: &str) -> String {
    let mut body = String::new();
    for (h, b) in parts {
        if !h.eq_ignore_ascii_case(heading) {
            body.push_str(&format!("<h3>{}</h3>\n", enginedyn_report::esc(h)));
        }
        body.push_str(b);
    }
    body
}

fn torsion_section(
    session: &Session,
    a: &Analysis,
    rpms: &[f64],
) -> Result<(Section, Option<enginedyn_pipeline::torsion::Study>)> {
    let engine = session.engine();
    let found =
        crate::torsion::report_extra_over(engine, &session.loaded.text, a, session.opts, rpms)?;
    let Some((extra, study)) = found else {
        return Ok((
            Section {
                id: "torsion",
                heading: "Torsional vibration".into(),
                body: "<p>Not studied: the engine file has no <code>[torsion]</code> section \
                       (<code>enginedyn template --torsion</code> writes one).</p>\n"
                    .into(),
                ..Section::default()
            },
            None,
        ));
    };
    let body = sub_sections(&extra.sections, "Torsional vibration");
    Ok((
        Section {
            id: "torsion",
            heading: "Torsional vibration".into(),
            settings: vec![
                (
                    "speeds".into(),
                    format!(
                        "{} to {} rpm, {} speeds",
                        human(rpms[0]),
                        human(rpms[rpms.len() - 1]),
                        rpms.len()
                    ),
                ),
                (
                    "excitation".into(),
                    format!(
                        "the cycle at {} rpm and IMEP {} bar (gas torque harmonics held over the speeds, inertia torque at each speed)",
                        human(a.summary.rpm),
                        shown(a.summary.imep_bar, 2)
                    ),
                ),
            ],
            body,
            charts: extra.charts,
            ..Section::default()
        },
        Some(study),
    ))
}

fn firing_section(
    session: &Session,
    a: &Analysis,
    tables: &mut Vec<(String, Vec<u8>)>,
) -> Result<(Section, Option<enginedyn_balance::Study>)> {
    let engine = session.engine();
    let study = match crate::firing::ranked(
        engine,
        session.opts.rod_model.unwrap_or(engine.rod_model()),
        a.summary.rpm,
        Some(a),
        enginedyn_balance::Weights::default(),
        false,
    ) {
        Ok(s) => s,
        Err(e) => {
            return Ok((
                Section {
                    id: "firing",
                    heading: "Free forces and moments, firing orders".into(),
                    body: format!(
                        "<p>Not studied: {}.</p>\n",
                        enginedyn_report::esc(&e.to_string())
                    ),
                    ..Section::default()
                },
                None,
            ));
        }
    };
    tables.push((
        "firing_orders.csv".into(),
        enginedyn_report::firing_csv(&study).into_bytes(),
    ));
    let svg = enginedyn_report::crank_end_view(engine, &study)
        .render()
        .map_err(|e| Error::data(e.to_string()))?;
    Ok((
        Section {
            id: "firing",
            heading: "Free forces and moments, firing orders".into(),
            settings: vec![
                (
                    "journal torques".into(),
                    format!("the cycle at {} rpm", human(a.summary.rpm)),
                ),
                (
                    "weights".into(),
                    "the default score weights (firing-orders --weights)".into(),
                ),
            ],
            body: enginedyn_report::firing_ranking(&study, FIRING_ROWS),
            charts: vec![("crank_end_view.svg".into(), svg)],
            notes: study.notes.clone(),
        },
        Some(study),
    ))
}

fn tolerance_section(session: &Session, a: &Analysis) -> Result<Section> {
    let engine = session.engine();
    let Some(extra) =
        crate::tolerance::report_extra(engine, &session.loaded.text, a, session.opts)?
    else {
        return Ok(Section {
            id: "tolerances",
            heading: "Tolerances".into(),
            body: "<p>Not studied: the engine file has no <code>[tolerances]</code> section.</p>\n"
                .into(),
            ..Section::default()
        });
    };
    let body = sub_sections(&extra.sections, "Tolerances");
    Ok(Section {
        id: "tolerances",
        heading: "Tolerances".into(),
        settings: vec![
            (
                "point".into(),
                format!(
                    "{} rpm, IMEP {} bar",
                    human(a.summary.rpm),
                    shown(a.summary.imep_bar, 2)
                ),
            ),
            (
                "model".into(),
                "linear sensitivities on a 0.5° grid (enginedyn tolerance adds Monte Carlo)".into(),
            ),
        ],
        body,
        charts: extra.charts,
        ..Section::default()
    })
}

/// A headline.
fn headline(label: &str, value: String, unit: &str, at: String, section: &'static str) -> Headline {
    Headline {
        label: label.into(),
        value,
        unit: unit.into(),
        at,
        section,
    }
}

fn headlines(
    engine: &enginedyn_engine::Engine,
    v: &MapView<'_>,
    map: &SweepMap,
    rated: &Analysis,
    peak: Option<&Analysis>,
    torsion: Option<&enginedyn_pipeline::torsion::Study>,
    firing: &Option<enginedyn_balance::Study>,
) -> Vec<Headline> {
    let mut h = vec![engine_headline(engine)];
    if let (Some((rr, p)), Some((tr, t))) = (v.rated, v.peak) {
        h.push(headline(
            &format!("rated power ({})", v.basis()),
            fixed(p, 1),
            "kW",
            format!("at {} rpm", human(rr)),
            "full-load",
        ));
        h.push(headline(
            &format!("peak torque ({})", v.basis()),
            fixed(t, 1),
            "N m",
            format!("at {} rpm", human(tr)),
            "full-load",
        ));
    }
    let best_mep = v
        .full_load()
        .iter()
        .filter_map(|s| s.effective_mep_bar().map(|m| (s.rpm, m)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((rpm, m)) = best_mep {
        let label = if v.brake {
            "highest BMEP"
        } else {
            "highest IMEP × η_m"
        };
        h.push(headline(
            label,
            fixed(m, 2),
            "bar",
            format!("at {} rpm, full load", human(rpm)),
            "full-load",
        ));
    }
    let pmax = map
        .points
        .iter()
        .filter_map(|p| p.point.summary.p_max_bar.map(|x| (p, x)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((p, x)) = pmax {
        h.push(headline(
            "highest peak pressure",
            fixed(x, 1),
            "bar",
            format!("at {} rpm, {}", human(p.point.summary.rpm), p.load_name()),
            "map",
        ));
    }
    if let (Some((rpm, imep)), Some(s)) = (map.sized_at, v.cells.first()) {
        h.push(headline(
            "flywheel inertia",
            shown(s.flywheel_inertia_kg_m2, 3),
            "kg m²",
            format!(
                "sized at {} rpm, IMEP {} bar; {} mm, {} kg",
                human(rpm),
                fixed(imep, 2),
                shown(s.flywheel_outer_diameter_m.map(|d| d * 1e3), 0),
                shown(s.flywheel_mass_kg, 1)
            ),
            "flywheel",
        ));
    }
    let points: Vec<&Analysis> = std::iter::once(rated).chain(peak).collect();
    crank_headlines(&mut h, &points);
    h.extend(torsion_headline(torsion));
    h.extend(firing_headline(engine, firing));
    h
}

fn point_headlines(
    engine: &enginedyn_engine::Engine,
    a: &Analysis,
    torsion: Option<&enginedyn_pipeline::torsion::Study>,
    firing: &Option<enginedyn_balance::Study>,
) -> Vec<Headline> {
    let s = &a.summary;
    let at = format!("at {} rpm", human(s.rpm));
    let mut h = vec![engine_headline(engine)];
    h.push(headline(
        "power",
        shown(s.power_kw, 1),
        "kW",
        at.clone(),
        "loads",
    ));
    h.push(headline(
        "mean torque",
        shown(s.mean_torque_nm, 1),
        "N m",
        at.clone(),
        "loads",
    ));
    h.push(headline(
        "peak pressure",
        shown(s.p_max_bar, 1),
        "bar",
        at.clone(),
        "loads",
    ));
    h.push(headline(
        "inertia needed",
        shown(s.required_inertia_kg_m2, 3),
        "kg m²",
        at,
        "flywheel",
    ));
    crank_headlines(&mut h, &[a]);
    h.extend(torsion_headline(torsion));
    h.extend(firing_headline(engine, firing));
    h
}

fn engine_headline(engine: &enginedyn_engine::Engine) -> Headline {
    let z = engine.cylinders();
    let c = engine.cylinder();
    headline(
        "displacement",
        fixed(z as f64 * c.swept_volume() * 1e3, 3),
        "l",
        format!(
            "{} {z}, bore {} mm, CR {}",
            engine.layout().name(),
            human((c.bore() * 1e4).round() / 10.0),
            human(c.compression_ratio())
        ),
        "engine",
    )
}

/// The largest crank-pin load, main-bearing load and journal torque over
/// the analyses `points` (rated power, peak torque), each with where.
fn crank_headlines(h: &mut Vec<Headline>, points: &[&Analysis]) {
    let at = |a: &Analysis| format!("at {} rpm", human(a.summary.rpm));
    let section = |k: usize| {
        if k == 0 {
            "loads-rated"
        } else {
            "loads-peak-torque"
        }
    };
    let most = |f: &dyn Fn(&Analysis) -> Option<(f64, String)>| {
        points
            .iter()
            .enumerate()
            .filter_map(|(k, a)| f(a).map(|(v, w)| (k, v, w)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
    };
    let single = points.len() == 1;
    let place = |k: usize| if single { "loads" } else { section(k) };
    if let Some((k, v, w)) = most(&|a| a.summary.crankpin_load_max_n.map(|x| (x, at(a)))) {
        h.push(headline(
            "largest crank-pin load",
            fixed(v / 1e3, 2),
            "kN",
            w,
            place(k),
        ));
    }
    let bearing = |a: &Analysis| {
        a.bearings
            .iter()
            .enumerate()
            .map(|(j, b)| {
                (
                    b.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                    format!("bearing {} {}", j + 1, at(a)),
                )
            })
            .max_by(|x, y| x.0.total_cmp(&y.0))
    };
    if let Some((k, v, w)) = most(&bearing) {
        h.push(headline(
            "largest main-bearing load",
            fixed(v / 1e3, 2),
            "kN",
            w,
            place(k),
        ));
    }
    let journal = |a: &Analysis| {
        Some((
            a.summary.journal_torque_max_nm,
            format!("journal {} {}", a.summary.journal_most_loaded, at(a)),
        ))
    };
    if let Some((k, v, w)) = most(&journal) {
        h.push(headline(
            "largest journal torque",
            fixed(v, 0),
            "N m",
            w,
            place(k),
        ));
    }
}

fn torsion_headline(t: Option<&enginedyn_pipeline::torsion::Study>) -> Option<Headline> {
    let t = t?;
    Some(match t.resonances.first() {
        Some(r) => headline(
            "worst torsional resonance",
            fixed(r.amplitude_deg, 3),
            "°",
            format!(
                "order {} of mode {} at {} rpm",
                human(r.order),
                r.mode,
                human(r.rpm.round())
            ),
            "torsion",
        ),
        None => headline(
            "torsional resonances",
            "none".into(),
            "",
            "in the speed range".into(),
            "torsion",
        ),
    })
}

fn firing_headline(
    engine: &enginedyn_engine::Engine,
    s: &Option<enginedyn_balance::Study>,
) -> Option<Headline> {
    let s = s.as_ref()?;
    let c = s
        .cranks
        .iter()
        .find(|c| c.engine_crank)
        .or(s.cranks.first())?;
    let ours = engine.firing_order();
    // Its rank: one more than the orders that score better (ties share).
    let rank = c.orders.iter().find(|o| o.order.order == ours).map(|me| {
        c.orders
            .iter()
            .filter(|o| o.score < me.score - 1e-12)
            .count()
    });
    let f = &c.free;
    Some(headline(
        "firing order",
        ours.iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join("-"),
        "",
        format!(
            "{}; free moments 1st {} N m, 2nd {} N m",
            rank.map_or("not among the crank's orders".to_string(), |r| format!(
                "rank {} of {}",
                r + 1,
                c.orders.len()
            )),
            human((f.free_moment_1_nm * 10.0).round() / 10.0),
            human((f.free_moment_2_nm * 10.0).round() / 10.0)
        ),
        "firing",
    ))
}
