//! `report.html`: one self-contained page (no external files, no scripts)
//! with the engine, the operating point, the summary, the data and method
//! (input files with their BLAKE3, the version, the models), the notes
//! and every chart inlined as SVG.

use enginedyn_engine::Engine;
use enginedyn_pipeline::Analysis;
use std::fmt::Write as _;

/// `s` escaped for HTML text and attribute values: the one escaping
/// every page of the project uses.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A relative link's path percent-encoded (RFC 3986): every byte but the
/// unreserved ones and `/` is written `%XX`, so `run#1` and `a?b` stay path.
pub fn percent_encode(path: &str) -> String {
    let mut o = String::with_capacity(path.len());
    for b in path.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'.' | b'_' | b'~' | b'/') {
            o.push(b as char);
        } else {
            o.push_str(&format!("%{b:02X}"));
        }
    }
    o
}

/// An HTML table: `head` cells, then `rows` of cells already in HTML;
/// `numeric` columns are right-aligned. Text is escaped by the caller with
/// [`esc`].
pub fn table(head: &[&str], rows: &[Vec<String>], numeric: &[bool]) -> String {
    let mut o = String::from("<table><tr>");
    for h in head {
        let _ = write!(o, "<th>{}</th>", esc(h));
    }
    o.push_str("</tr>\n");
    for r in rows {
        o.push_str("<tr>");
        for (k, c) in r.iter().enumerate() {
            if numeric.get(k).copied().unwrap_or(false) {
                let _ = write!(o, "<td class=\"v\">{c}</td>");
            } else if k == 0 {
                let _ = write!(o, "<th>{c}</th>");
            } else {
                let _ = write!(o, "<td>{c}</td>");
            }
        }
        o.push_str("</tr>\n");
    }
    o.push_str("</table>\n");
    o
}

/// The engine table's row for what takes the indicated figures to the
/// effective ones: `[friction]`'s Chen–Flynn constants, else η_m.
fn effective_basis(engine: &Engine) -> (&'static str, String) {
    let h = |x: f64| crate::human(x);
    match engine.friction() {
        Some(f) => (
            "friction (Chen–Flynn, [friction])",
            format!(
                "FMEP = {} bar + {} p_max + {} bar s/m c_m + {} bar s²/m² c_m²",
                h(f.a_pa / 1e5),
                h(f.b),
                h(f.c_pa_s_m / 1e5),
                h(f.d_pa_s2_m2 / 1e5)
            ),
        ),
        None => (
            "mechanical efficiency η_m",
            h(engine.operating().mechanical_efficiency),
        ),
    }
}

/// The page, with `charts` as (file name, SVG text) inlined in order and
/// `sections` as (heading, HTML body) before the charts; `inputs` under
/// "Data and method".
pub fn report_html(
    engine: &Engine,
    a: &Analysis,
    inputs: &crate::Inputs,
    sections: &[(String, String)],
    charts: &[(String, String)],
) -> String {
    let s = &a.summary;
    let mut o = String::with_capacity(600_000);
    let title = format!("{} — {:.0} rpm", engine.name(), s.rpm);
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\n<style>\
body{{font-family:sans-serif;margin:24px auto;max-width:1280px;color:#222}}\
h1{{font-size:22px}}h2{{font-size:17px;margin-top:28px;border-bottom:1px solid #ddd}}\
table{{border-collapse:collapse;font-size:14px}}td,th{{padding:3px 10px;border-bottom:1px solid #eee;text-align:left}}\
td.v{{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}}.grid{{display:flex;gap:40px;flex-wrap:wrap}}\
figure{{margin:12px 0}}figure svg{{max-width:100%;height:auto}}figcaption{{font-size:13px;color:#555}}\
code{{font-size:12px;word-break:break-all}}\
</style></head><body>\n<h1>{}</h1>\n",
        esc(&title),
        esc(&title)
    );
    let _ = writeln!(o, "<div class=\"grid\"><div><h2>Engine</h2><table>");
    for (k, v) in engine_rows(engine, s) {
        let _ = writeln!(o, "<tr><th>{}</th><td>{}</td></tr>", esc(k), esc(&v));
    }
    let _ = writeln!(o, "</table></div><div><h2>Summary</h2><table>");
    for row in crate::summary_rows(&a.summary) {
        let (label, unit, v) = (&row.label, row.unit, row.shown());
        let _ = writeln!(
            o,
            "<tr><th>{}</th><td class=\"v\">{v}</td><td>{}</td></tr>",
            esc(label),
            esc(unit)
        );
    }
    let _ = writeln!(o, "</table></div></div>");
    data_and_method(&mut o, a, inputs);
    let _ = writeln!(o, "<h2>Notes</h2>");
    if s.notes.is_empty() {
        let _ = writeln!(o, "<p>None.</p>");
    } else {
        let _ = writeln!(o, "<ul>");
        for n in &s.notes {
            let _ = writeln!(o, "<li>{}</li>", esc(n));
        }
        let _ = writeln!(o, "</ul>");
    }
    for (heading, body) in sections {
        let _ = writeln!(o, "<h2>{}</h2>\n{body}", esc(heading));
    }
    let _ = writeln!(o, "<h2>Charts</h2>");
    for (name, svg) in charts {
        let body = svg.find("<svg").map_or(svg.as_str(), |i| &svg[i..]);
        let _ = writeln!(
            o,
            "<figure id=\"{}\">{body}<figcaption>{}</figcaption></figure>",
            esc(name.trim_end_matches(".svg")),
            esc(name)
        );
    }
    let _ = writeln!(o, "</body></html>");
    o
}

/// "Data and method": what the results came from (`summary.json`'s
/// `inputs`: the files as given with their BLAKE3, the version) and the
/// models and method options that computed them.
fn data_and_method(o: &mut String, a: &Analysis, inputs: &crate::Inputs) {
    let s = &a.summary;
    let _ = writeln!(o, "<h2>Data and method</h2><table>");
    // `inputs` writes "bundled" for the bundled example's files.
    let shown = |f: &str| {
        if f == "bundled" {
            "the bundled example".to_string()
        } else {
            esc(f)
        }
    };
    let _ = writeln!(
        o,
        "<tr><th>engine file</th><td>{}</td><td>BLAKE3 <code>{}</code></td></tr>",
        shown(&inputs.engine_file),
        esc(&inputs.engine_blake3)
    );
    let several = inputs.diagram_files.len() > 1;
    for (k, (file, hash)) in inputs
        .diagram_files
        .iter()
        .zip(&inputs.diagram_blake3)
        .enumerate()
    {
        let label = if several {
            format!("diagram file {}", k + 1)
        } else {
            "diagram file".to_string()
        };
        let _ = writeln!(
            o,
            "<tr><th>{label}</th><td>{}</td><td>BLAKE3 <code>{}</code></td></tr>",
            shown(file),
            esc(hash)
        );
    }
    let _ = writeln!(
        o,
        "<tr><th>computed by</th><td colspan=\"2\">enginedyn {}</td></tr>",
        esc(inputs.enginedyn_version)
    );
    for (k, v) in [
        ("kinematics", s.kinematics.to_string()),
        ("rod model", s.rod_model.to_string()),
        ("interpolation", s.interpolation.to_string()),
        ("grid step", format!("{}°", s.grid_step_deg)),
        ("integration", s.integration.to_string()),
    ] {
        let _ = writeln!(o, "<tr><th>{k}</th><td colspan=\"2\">{}</td></tr>", esc(&v));
    }
    let _ = writeln!(o, "</table>");
}

/// The engine as a page's table shows it: the geometry, the firing order,
/// the speed of `s`, and everything else its results depend on (masses,
/// rod model, friction or η_m, flywheel): (label, value with its unit).
pub fn engine_rows(
    engine: &Engine,
    s: &enginedyn_pipeline::Summary,
) -> Vec<(&'static str, String)> {
    let geometry = [
        ("cycle", engine.stroke_kind().name().to_string()),
        (
            "layout",
            format!("{} {}", engine.layout().name(), engine.cylinders()),
        ),
        (
            "firing order",
            engine
                .firing_order()
                .iter()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join("-"),
        ),
        ("bore", format!("{:.2} mm", engine.cylinder().bore() * 1e3)),
        ("stroke", format!("{:.3} mm", s.stroke_m * 1e3)),
        ("λ = R/L", format!("{:.4}", s.lambda)),
        (
            "compression ratio",
            format!("{}", engine.cylinder().compression_ratio()),
        ),
        (
            "speed",
            format!("{:.0} rpm (ω = {:.3} rad/s)", s.rpm, s.omega_rad_s),
        ),
    ];
    // Everything else the results depend on.
    let h = |x: f64| enginedyn_numerics::format::sig(x, 4);
    let m = engine.masses();
    let rod_model =
        enginedyn_engine::RodModel::from_name(s.rod_model).unwrap_or(engine.rod_model());
    let mut depends: Vec<(&str, String)> = Vec::new();
    match engine.mechanism() {
        enginedyn_kinematics::Mechanism::CrankSlider(cs) => {
            depends.push(("rod length", format!("{} mm", h(cs.l() * 1e3))));
            depends.push(("pin offset", format!("{} mm", h(cs.e() * 1e3))));
            depends.push(("rod mass", format!("{} kg", h(m.rod))));
            depends.push((
                "rod centre of mass from the small end",
                format!("{} mm", h(m.rod_cg_from_small_end * 1e3)),
            ));
            depends.push((
                "rod inertia about its centre of mass",
                m.rod_inertia
                    .map_or("not given".to_string(), |i| format!("{} kg m²", h(i))),
            ));
        }
        enginedyn_kinematics::Mechanism::ScotchYoke(_) => {
            depends.push(("mechanism", "Scotch yoke".to_string()));
        }
    }
    depends.extend([
        ("rod model", s.rod_model.to_string()),
        ("piston group mass", format!("{} kg", h(m.piston_group))),
        (
            "reciprocating mass m_j",
            format!("{} kg", h(engine.reciprocating_mass(rod_model))),
        ),
        (
            "rotating mass m_r (throw 1)",
            format!("{} kg", h(engine.rotating_mass(0, rod_model))),
        ),
        (
            "crank unbalanced mass",
            format!("{} kg", h(m.crank_unbalanced)),
        ),
        effective_basis(engine),
        (
            "speed fluctuation δ",
            h(engine.flywheel().speed_fluctuation),
        ),
        (
            "flywheel",
            match engine.flywheel().outer_diameter {
                Some(d) => format!("outer diameter {} mm (given)", h(d * 1e3)),
                None => format!(
                    "rim speed {} m/s at most",
                    h(engine.flywheel().max_rim_speed)
                ),
            },
        ),
    ]);
    geometry.into_iter().chain(depends).collect()
}
