//! Synthesis for design (INTERFACE.md "Combustion"): the diagram of an
//! engine file's `[combustion]` section (`enginedyn synth`), and the
//! diagram a command takes when it is given none and the engine file has
//! no `diagram` but a `[combustion]` section. The cycle is
//! `enginedyn_synth`'s design cycle ([`enginedyn_synth::design`]); the
//! text it is written as is a diagram like any other, read back by the
//! same reader.

use crate::diagram::Input;
use crate::engine::Loaded;
use crate::error::{Error, Result};
use enginedyn_engine::Engine;
use enginedyn_engine::combustion::{CombustionLoad, CombustionSpec, MAX_PRESSURE_RISE_BAR_DEG};
use enginedyn_numerics::format::human;
use enginedyn_synth::{Design, DesignModel, GammaModel, Load, SynthError};
use std::path::{Path, PathBuf};

/// How the notes that say a diagram was synthesised begin (a decision,
/// `pipeline::notes::DECIDED`).
pub const NOTE_PREFIX: &str = "diagram synthesised from [combustion]";

/// The first line of every diagram `enginedyn synth` writes: the mark by
/// which it knows a file of its own, the only kind `synth --out` replaces,
/// and by which the reader knows a synthetic diagram
/// ([`enginedyn_ingest::SYNTHETIC_MARK`] is its start: a test holds it).
pub const MARKER: &str =
    "# synthetic indicator diagram, not measured: enginedyn synth, the design cycle";

pub use crate::diagram::Synthesised;

impl Synthesised {
    /// How the cycle met its load, as `summary.json`'s `design` gives it.
    pub fn design_summary(&self) -> enginedyn_pipeline::DesignSummary {
        enginedyn_pipeline::DesignSummary {
            charge: self.charge.map(|c| c.name()),
            intake_pressure_bar: self.intake_pressure_bar,
            lambda: self.lambda,
        }
    }

    /// The diagram as a command's input.
    pub fn input(&self) -> Input<'_> {
        Input::Synthesised(self)
    }

    /// The analysis options for this diagram: where `opts` has the
    /// defaults (no `--gamma`, no `--burn-window`), the diagram's own γ
    /// model and a window that holds its burn.
    pub fn analysis_options(
        &self,
        opts: &enginedyn_combustion::Options,
    ) -> enginedyn_combustion::Options {
        let mut o = opts.clone();
        if o.gamma == GammaModel::default() {
            o.gamma = self.gamma;
        }
        if o.window_deg == enginedyn_combustion::DEFAULT_WINDOW {
            o.window_deg = self.burn_window_deg;
        }
        o
    }
}

/// The burn window of a design cycle: the default, widened to hold the
/// law from its 0.1 % to its 99.9 % point with 15° to spare, within IVC …
/// EVO (5° inside each) and the analysis' bounds.
fn burn_window(m: &DesignModel) -> (f64, f64) {
    let (d0, d1) = enginedyn_combustion::DEFAULT_WINDOW;
    let a = d0.min(m.burn.angle_of(0.001) - 15.0).max(m.ivc_deg + 5.0);
    let b = d1.max(m.burn.angle_of(0.999) + 15.0).min(m.evo_deg - 5.0);
    (a.max(-180.0).floor(), b.min(180.0).ceil())
}

/// The `[combustion]` section of `loaded`, or a usage error naming the file.
pub fn spec(loaded: &Loaded) -> Result<CombustionSpec> {
    loaded.engine.combustion().cloned().ok_or_else(|| {
        Error::usage(format!(
            "{}: no [combustion] section: give the burn law (`enginedyn template --combustion petrol` writes one)",
            loaded.shown()
        ))
    })
}

/// The design cycle of `engine`'s `[combustion]` section at `rpm` (its
/// curves over speed taken there), its load the file's unless `imep_bar`
/// is given (`--imep`). `file` names the engine file in errors.
pub fn design_model(
    file: &str,
    engine: &Engine,
    spec: &CombustionSpec,
    imep_bar: Option<f64>,
    rpm: Option<f64>,
) -> Result<DesignModel> {
    let load = match (imep_bar, spec.load) {
        (Some(i), _) => Load::Imep { pa: i * 1e5 },
        (None, Some(CombustionLoad::Imep(pa))) => Load::Imep { pa },
        (None, Some(CombustionLoad::Heat(j))) => Load::Heat { j },
        (None, None) => {
            return Err(Error::usage(format!(
                "{file}: [combustion] gives no load: set `imep_bar` or `heat_released_j` there, or give --imep"
            )));
        }
    };
    let two = engine.stroke_kind() == enginedyn_engine::Stroke::Two;
    let burn = spec
        .burn_at(rpm)
        .map_err(|e| Error::engine(format!("{file}: [combustion]: {e}")))?;
    let mut m = DesignModel::new(burn, load, spec.gamma, two);
    let intake = spec.intake_at(rpm);
    m.intake_pressure_pa = intake;
    m.exhaust_pressure_pa = enginedyn_synth::exhaust_pressure_for(intake);
    m.air = spec.charge.map(|charge| enginedyn_synth::Air {
        charge,
        intake_temp_k: spec.intake_temp_k,
    });
    m.ivc_deg = spec.ivc_deg;
    m.evo_deg = spec.evo_deg;
    m.fit_blowdown();
    Ok(m)
}

/// A synthesis error as the session's: an IMEP from `--imep` that no heat
/// gives is the command line's; the rest the engine file's.
fn failure(file: &str, from_flag: bool, e: SynthError) -> Error {
    match e {
        SynthError::Load(m) if from_flag => Error::usage(format!("--imep: {m}")),
        e => Error::engine(format!("{file}: [combustion]: {e}")),
    }
}

/// The diagram of `loaded`'s `[combustion]` at `step_deg`: the load the
/// file's, or `imep_bar` (`--imep`); `rpm` written in its `# rpm` line
/// (`None`: the engine file's `operating.rpm`, when it has one).
pub fn synthesise(
    loaded: &Loaded,
    rpm: Option<f64>,
    imep_bar: Option<f64>,
    step_deg: f64,
) -> Result<Synthesised> {
    synthesise_as(loaded, rpm, imep_bar, step_deg, true)
}

/// [`synthesise`], the diagram kept as its samples instead of its text
/// (`text` empty, [`Synthesised::samples`] the rows as the text would give
/// them, rounded as it writes them): a map's points, which never write
/// it, skip formatting 7,200 rows and reading them back.
pub fn synthesise_samples(
    loaded: &Loaded,
    rpm: Option<f64>,
    imep_bar: Option<f64>,
    step_deg: f64,
) -> Result<Synthesised> {
    synthesise_as(loaded, rpm, imep_bar, step_deg, false)
}

fn synthesise_as(
    loaded: &Loaded,
    rpm: Option<f64>,
    imep_bar: Option<f64>,
    step_deg: f64,
    as_text: bool,
) -> Result<Synthesised> {
    let file = loaded.shown();
    let spec = spec(loaded)?;
    let engine = &loaded.engine;
    crate::diagram::check_step(engine, step_deg)?;
    let rpm = rpm.or(engine.operating().rpm);
    let model = design_model(&file, engine, &spec, imep_bar, rpm)?;
    let cyl = engine.cylinder();
    let design =
        enginedyn_synth::design(cyl, &model).map_err(|e| failure(&file, imep_bar.is_some(), e))?;
    plausible(&file, imep_bar.is_some(), engine, &spec, &model, &design)?;
    let n = (model.cycle_deg() / step_deg).round() as usize;
    let trace = design.sample(n, step_deg);
    let (text, samples) = if as_text {
        let lines = header(&file, engine, &model, &design, step_deg, &trace);
        let refs: Vec<&str> = lines.iter().map(String::as_str).collect();
        let mut buf = Vec::new();
        enginedyn_synth::write_csv(&mut buf, &trace, rpm, &refs)
            .map_err(|e| Error::io(e.to_string()))?;
        let text = String::from_utf8(buf).map_err(|e| Error::io(e.to_string()))?;
        (text, (Vec::new(), Vec::new()))
    } else {
        (String::new(), enginedyn_synth::csv_values(&trace))
    };
    let imep_target_bar = match model.load {
        Load::Imep { pa } => Some(pa / 1e5),
        Load::Heat { .. } => None,
    };
    let law = describe_burn(&model);
    let charge = describe_charge(&model, &design);
    let load = match imep_target_bar {
        Some(i) => format!(
            "IMEP {} bar (heat released {} J per cylinder)",
            human(i),
            human(design.heat_released_j)
        ),
        None => format!(
            "heat released {} J per cylinder (IMEP {} bar)",
            human(design.heat_released_j),
            human(design.imep_pa / 1e5)
        ),
    };
    let mut warnings = Vec::new();
    if spec.charge.is_some()
        && design.intake_pressure_pa < enginedyn_engine::combustion::MIN_INTAKE_BAR * 1e5
    {
        warnings.push(format!(
            "the design cycle meets IMEP {} bar with the throttle at {} bar intake, below the {} bar of a running engine at idle: the lossless cycle (no wall heat, no residual gas) needs less air than an engine, so its pumping loss here is an upper bound",
            human((design.imep_pa / 1e4).round() / 10.0),
            human((design.intake_pressure_pa / 1e3).round() / 100.0),
            enginedyn_engine::combustion::MIN_INTAKE_BAR
        ));
    }
    Ok(Synthesised {
        samples,
        warnings,
        name: format!("synthesised from {file} [combustion]"),
        note: format!(
            "{NOTE_PREFIX} of {file}: no diagram given and no `diagram` in the engine file, so the design cycle at {load}, {law}, γ {}{charge}; {}",
            model.gamma.describe(),
            if spec.varies_with_speed() {
                format!(
                    "its curves over speed taken at {}",
                    rpm.map_or("their first speed".to_string(), |r| format!(
                        "{} rpm",
                        human(r)
                    ))
                )
            } else {
                "the lossless cycle is the same at every speed".to_string()
            }
        ),
        text,
        rpm,
        step_deg,
        imep_target_bar,
        imep_bar: design.imep_pa / 1e5,
        heat_released_j: design.heat_released_j,
        intake_pressure_bar: design.intake_pressure_pa / 1e5,
        lambda: design.lambda,
        charge: spec.charge.map(|c| c.kind),
        gamma: model.gamma,
        burn_window_deg: burn_window(&model),
    })
}

/// A design cycle no engine runs is refused (INTERFACE "The design
/// model"): a heat released beyond what the cylinder's air can burn (for
/// a file without `charge`; with one, the design model bounds the fuel),
/// a pressure rise over [`MAX_PRESSURE_RISE_BAR_DEG`].
fn plausible(
    file: &str,
    from_flag: bool,
    engine: &Engine,
    spec: &CombustionSpec,
    m: &DesignModel,
    d: &Design,
) -> Result<()> {
    let load_key = match (from_flag, m.load) {
        (true, _) => "--imep",
        (false, Load::Imep { .. }) => "imep_bar",
        (false, Load::Heat { .. }) => "heat_released_j",
    };
    let refuse = |m: String| {
        if from_flag {
            Error::usage(m)
        } else {
            Error::engine(format!("{file}: [combustion]: {m}"))
        }
    };
    let cyl = engine.cylinder();
    let bdc = cyl.swept_volume() + cyl.clearance_volume();
    let most = enginedyn_engine::combustion::max_heat_released_j(
        bdc,
        d.intake_pressure_pa,
        spec.intake_temp_k,
    );
    if spec.charge.is_none() && d.heat_released_j > most {
        return Err(refuse(format!(
            "{load_key}: the cycle needs {} J of heat per cylinder, more than its trapped air can burn ({} J: the whole cylinder full of air at {} bar and {} K, {} MJ per kg of air); lower the load, raise intake_pressure_bar, or set charge = \"si\" or \"ci\" for the design model's own bound",
            human(d.heat_released_j.round()),
            human(most.floor()),
            human(d.intake_pressure_pa / 1e5),
            human(spec.intake_temp_k),
            enginedyn_engine::combustion::MAX_HEAT_PER_KG_AIR / 1e6
        )));
    }
    let (rise, at) = d.solution.max_rise();
    if rise > MAX_PRESSURE_RISE_BAR_DEG * 1e5 {
        return Err(refuse(format!(
            "{load_key}: the burn law gives a pressure rise of {} bar/° at {}°, over the {MAX_PRESSURE_RISE_BAR_DEG} bar/° of a running engine (a knocking one's); lengthen combustion.duration_10_90_deg, split the burn ([combustion.second]) or lower the load",
            human((rise / 1e5 * 100.0).round() / 100.0),
            human((at * 10.0).round() / 10.0)
        )));
    }
    Ok(())
}

/// The charge in a few words (empty without `charge`): `, spark ignition
/// throttled to 0.43 bar intake at λ 1`.
fn describe_charge(m: &DesignModel, d: &Design) -> String {
    use enginedyn_combustion::charge::ChargeKind;
    let (Some(air), Some(lambda)) = (m.air, d.lambda) else {
        return String::new();
    };
    let p = human((d.intake_pressure_pa / 1e5 * 1e4).round() / 1e4);
    let l = human((lambda * 1e3).round() / 1e3);
    match air.charge.kind {
        ChargeKind::Si if d.intake_pressure_pa < m.intake_pressure_pa * (1.0 - 1e-9) => {
            format!(", spark ignition throttled to {p} bar intake at λ {l}")
        }
        ChargeKind::Si => format!(", spark ignition at full load ({p} bar intake, λ {l})"),
        ChargeKind::Ci => format!(", compression ignition at {p} bar intake, λ {l}"),
    }
}

/// The burn law in a few words: `Wiebe CA10 −1.6°, CA50 8°, CA90 18.4°`.
fn describe_burn(m: &DesignModel) -> String {
    let b = &m.burn;
    format!(
        "{} CA10 {}°, CA50 {}°, CA90 {}°",
        if b.second().is_some() {
            "double Wiebe"
        } else {
            "Wiebe"
        },
        human((b.angle_of(0.1) * 1e3).round() / 1e3),
        human((b.angle_of(0.5) * 1e3).round() / 1e3),
        human((b.angle_of(0.9) * 1e3).round() / 1e3)
    )
}

/// The `#` lines of a synthesised diagram: that it is synthetic, the
/// engine, every parameter of the cycle, and what it gives.
fn header(
    file: &str,
    engine: &Engine,
    m: &DesignModel,
    d: &Design,
    step_deg: f64,
    trace: &[(f64, f64)],
) -> Vec<String> {
    let cyl = engine.cylinder();
    let mech = cyl.mechanism();
    let geometry = match mech {
        enginedyn_kinematics::Mechanism::CrankSlider(cs) => format!(
            "crank-slider, rod {} mm, pin offset {} mm",
            human(cs.l() * 1e3),
            human(cs.e() * 1e3)
        ),
        enginedyn_kinematics::Mechanism::ScotchYoke(_) => "Scotch yoke".to_string(),
    };
    let wiebe = |w: &enginedyn_synth::Wiebe| {
        format!(
            "start_deg = {}, duration_deg = {}, wiebe_a = {}, wiebe_m = {}",
            w.start_deg(),
            w.duration_deg(),
            w.a(),
            w.m()
        )
    };
    let mut lines = vec![
        format!(
            "{} of the engine file's [combustion] (single-zone first law from IVC to EVO with a Wiebe heat release, no wall heat; docs/combustion.md, Synthesis for design)",
            &MARKER[2..]
        ),
        format!(
            "engine: {file} ({}): bore {} mm, stroke {} mm, {geometry}, compression ratio {}, {}",
            engine.name(),
            human(cyl.bore() * 1e3),
            human(mech.stroke() * 1e3),
            human(cyl.compression_ratio()),
            if m.two_stroke {
                "two-stroke"
            } else {
                "four-stroke"
            }
        ),
        format!("burn: {}", wiebe(m.burn.first())),
    ];
    if let Some((w, f)) = m.burn.second() {
        lines.push(format!("burn: second Wiebe, fraction = {f}: {}", wiebe(w)));
    }
    lines.push(format!("burn points of the law: {}", describe_burn(m)));
    lines.push(match m.load {
        Load::Imep { pa } => format!(
            "load: imep_bar = {} (target), heat_released_j = {} (solved, {} cycles)",
            pa / 1e5,
            d.heat_released_j,
            d.evaluations
        ),
        Load::Heat { j } => format!("load: heat_released_j = {j}"),
    });
    lines.push(format!(
        "gas: gamma = {}, intake_pressure_bar = {}, intake_temp_k = {}, exhaust_pressure_bar = {}, ivc_deg = {}, evo_deg = {}, blowdown_deg = {}",
        match m.gamma {
            GammaModel::Constant(g) => format!("{g}"),
            GammaModel::Brunt { .. } => "brunt".to_string(),
        },
        d.intake_pressure_pa / 1e5,
        match m.gamma {
            GammaModel::Brunt { intake_temp_k, .. } => intake_temp_k,
            GammaModel::Constant(_) => engine
                .combustion()
                .map_or(enginedyn_synth::DEFAULT_INTAKE_TEMP_K, |c| c.intake_temp_k),
        },
        enginedyn_synth::exhaust_pressure_for(d.intake_pressure_pa) / 1e5,
        m.ivc_deg,
        m.evo_deg,
        m.blowdown_deg
    ));
    if let (Some(air), Some(lambda)) = (m.air, d.lambda) {
        let c = air.charge;
        lines.push(format!(
            "charge: {} (full-load intake_pressure_bar = {}), lambda = {lambda}, lambda_min = {}, fuel_lhv_mj_kg = {}, afr_stoich = {}, combustion_efficiency = {}",
            c.kind.name(),
            m.intake_pressure_pa / 1e5,
            c.lambda_min,
            c.lhv_j_kg / 1e6,
            c.afr_stoich,
            c.combustion_efficiency
        ));
    }
    let (peak_deg, peak) = enginedyn_synth::peak_pressure(trace).unwrap_or((0.0, 0.0));
    lines.push(format!(
        "result: step_deg = {step_deg}, IMEP {:.4} bar net, peak {:.2} bar at {peak_deg:.1} deg after firing TDC",
        d.imep_pa / 1e5,
        peak / 1e5
    ));
    lines
}

/// The diagram a command reads when given none: the engine file's
/// `diagram`, else (an engine file with `[combustion]`) the synthesised
/// one at `step_deg` with `rpm` in its `# rpm` line, else a usage error
/// that says so. A bundled engine keeps its bundled diagram (the caller's
/// to give).
#[derive(Debug)]
pub enum DefaultDiagram {
    /// The engine file's `diagram`.
    File(PathBuf),
    /// The synthesised diagram.
    Synthesised(Box<Synthesised>),
}

impl DefaultDiagram {
    /// As a command's input.
    pub fn input(&self) -> Input<'_> {
        match self {
            DefaultDiagram::File(p) => Input::File(p),
            DefaultDiagram::Synthesised(s) => s.input(),
        }
    }
    /// A synthesised diagram's `design` figures.
    pub fn design_summary(&self) -> Option<enginedyn_pipeline::DesignSummary> {
        match self {
            DefaultDiagram::File(_) => None,
            DefaultDiagram::Synthesised(s) => Some(s.design_summary()),
        }
    }

    /// The warnings to say beside the note (a synthesised diagram's).
    pub fn warnings(&self) -> &[String] {
        match self {
            DefaultDiagram::File(_) => &[],
            DefaultDiagram::Synthesised(s) => &s.warnings,
        }
    }

    /// The note to say (a synthesised diagram's).
    pub fn note(&self) -> Option<&str> {
        match self {
            DefaultDiagram::File(_) => None,
            DefaultDiagram::Synthesised(s) => Some(&s.note),
        }
    }
}

/// See [`DefaultDiagram`].
pub fn default_diagram(loaded: &Loaded, rpm: Option<f64>, step_deg: f64) -> Result<DefaultDiagram> {
    if let Some(p) = loaded.engine.diagram() {
        return Ok(DefaultDiagram::File(p.to_path_buf()));
    }
    if loaded.engine.combustion().is_some() {
        return Ok(DefaultDiagram::Synthesised(Box::new(synthesise(
            loaded, rpm, None, step_deg,
        )?)));
    }
    crate::diagram::diagram_path(None, loaded).map(DefaultDiagram::File)
}

/// `--out P.csv` as the folder and the file name written.
fn out_parts(out: &Path) -> Result<(&Path, &str)> {
    let dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = out
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| Error::usage(format!("--out {}: not a file name", out.display())))?;
    Ok((dir, name))
}

/// Before any work: whether `out` may be written, absent or a diagram
/// `enginedyn synth` wrote (it begins with [`MARKER`]); a measured file
/// or anything else there is refused (exit 2), never replaced.
pub fn check_out(out: &Path) -> Result<()> {
    let (dir, name) = out_parts(out)?;
    enginedyn_report::check_marked(dir, name, MARKER)?;
    Ok(())
}

/// Writes a synthesised diagram to `out` (its folder made when missing,
/// the file whole or not at all, replacing only a diagram `enginedyn
/// synth` wrote: [`check_out`]; `-`: standard output is the caller's).
pub fn write(s: &Synthesised, out: &Path) -> Result<()> {
    let (dir, name) = out_parts(out)?;
    enginedyn_report::replace_marked_file(dir, name, s.text.as_bytes(), MARKER)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    /// The reader's mark of a synthetic diagram is the start of the line
    /// `synth` writes first.
    #[test]
    fn the_reader_knows_the_marker() {
        let line = super::MARKER.strip_prefix("# ").unwrap();
        assert!(line.starts_with(enginedyn_ingest::SYNTHETIC_MARK), "{line}");
    }
}
