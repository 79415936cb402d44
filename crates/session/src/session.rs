//! A session: an engine with its tables built once, reader and method
//! options checked once, and "analyse one operating point" in every form a
//! front end asks for (a file, one file per cylinder, a turning moment,
//! within a tolerance).

use crate::diagram::{
    Input, check_step, diagram_options, load_diagram, load_diagram_hashed, merge_per_cylinder,
    parse_diagram,
};
use crate::engine::Loaded;
use crate::error::{Error, Result};
use crate::options::{Method, Reader};
use crate::speed::resolve_rpm;
use enginedyn_engine::Engine;
use enginedyn_ingest::{Cancel, GridOptions, ParseOptions, Quantity, Resampled};
use enginedyn_pipeline::{Analysis, Options, Scope};

/// An engine, how its diagrams are read and how they are computed.
#[derive(Debug)]
pub struct Session {
    /// The engine.
    pub loaded: Loaded,
    /// Reader options as given.
    pub reader: Reader,
    /// Method options as given.
    pub method: Method,
    /// Ingest's options, built from `reader` for this engine.
    pub parse: ParseOptions,
    /// The grid (step, interpolant, pegging, the shared volume law).
    pub grid: GridOptions,
    /// The pipeline's options.
    pub opts: Options,
    /// A batch keeps each file's diagram on the grid for the cycles and
    /// traces tables (a campaign); otherwise it is freed after its analysis.
    pub keep_grid: bool,
    /// The motion and volume law on the grid, built once for every file
    /// when the first file needs them (`None` when the model does not
    /// apply: the analysis then says why). A batch that only parses
    /// (`--parse-only`) never builds them.
    tables: std::sync::OnceLock<Option<enginedyn_pipeline::Tables>>,
    /// The grid's points a cycle, for the tables.
    points: usize,
}

/// One operating point analysed: the analysis and the options it used
/// (with a tolerance: the setting chosen).
#[derive(Debug)]
pub struct Outcome {
    /// The analysis, its summary's notes complete.
    pub analysis: Analysis,
    /// The options used.
    pub opts: Options,
    /// The diagram on the grid with its per-cycle figures (the cycles
    /// table), when the run read one grid.
    pub resampled: Option<Resampled>,
    /// Each diagram file's BLAKE3, hashed as it was read (`None` where it
    /// was not: text in memory, or a command that reads it otherwise).
    pub diagram_blake3: Vec<Option<String>>,
}

impl Session {
    /// A session for `loaded` with these options; `scope` says whether the
    /// report curves are wanted. The step and every bound are checked here.
    pub fn new(loaded: Loaded, reader: Reader, method: Method, scope: Scope) -> Result<Self> {
        // The front end's parser bounded each flag alone; their
        // combinations are checked here, for every command alike.
        method.check(crate::options::flag)?;
        let step = method.step();
        check_step(&loaded.engine, step)?;
        method.burn.check_engine(&loaded.engine, step, reader.rpm)?;
        let opts = Options {
            scope,
            ..method.options()
        };
        let (parse, mut grid) = diagram_options(&loaded.engine, &reader, step, opts.interp)?;
        grid.combustion = (!method.burn.off)
            .then(|| std::sync::Arc::new(method.burn.options_for(&loaded.engine, reader.rpm)));
        let points = (loaded.engine.cycle().to_degrees() / step).round() as usize;
        Ok(Self {
            loaded,
            reader,
            method,
            parse,
            grid,
            opts,
            keep_grid: false,
            tables: std::sync::OnceLock::new(),
            points,
        })
    }

    /// The engine.
    pub fn engine(&self) -> &Engine {
        &self.loaded.engine
    }

    /// The grid tables shared by every file, built by the first call.
    pub fn tables(&self) -> Option<&enginedyn_pipeline::Tables> {
        self.tables
            .get_or_init(|| {
                enginedyn_pipeline::Tables::new(&self.loaded.engine, self.points, &self.opts).ok()
            })
            .as_ref()
    }

    /// One operating point from one diagram, or one diagram per cylinder in
    /// order 1..z (as `enginedyn run` reads them); with a tolerance, the
    /// cheapest setting within it.
    pub fn analyse(&self, inputs: &[Input<'_>]) -> Result<Outcome> {
        self.analyse_cancellable(inputs, &Cancel::default())
    }

    /// [`Session::analyse`], stopped by `cancel` (an error) at its reader's
    /// next block once it is set.
    pub fn analyse_cancellable(&self, inputs: &[Input<'_>], cancel: &Cancel) -> Result<Outcome> {
        if let Some(t) = self.method.tolerance {
            return self.analyse_within(inputs, t);
        }
        let several = inputs.len() > 1;
        let mut hashes = Vec::with_capacity(inputs.len());
        let loaded = inputs
            .iter()
            .enumerate()
            .map(|(k, input)| {
                let parse = ParseOptions {
                    cancel: cancel.clone(),
                    ..self.cylinder_parse(several, k)
                };
                let (r, hash) = load_diagram_hashed(*input, &parse, &self.grid)?;
                hashes.push(hash);
                Ok((input.shown(), r))
            })
            .collect::<Result<Vec<_>>>()?;
        let resampled = merge_per_cylinder(loaded)?;
        let mut out = self.analyse_resampled(&resampled, &shown_of(inputs))?;
        out.resampled = Some(resampled);
        out.diagram_blake3 = hashes;
        Ok(out)
    }

    /// One operating point from a diagram already on the grid.
    pub fn analyse_resampled(&self, resampled: &Resampled, shown: &str) -> Result<Outcome> {
        if resampled.quantity != Quantity::Pressure {
            return Err(Error::data(format!(
                "{shown}: a turning-moment (torque) file: give it with --torque"
            )));
        }
        let engine = self.engine();
        let speed = resolve_rpm(self.reader.rpm, resampled.rpm, engine)?;
        let mut analysis = enginedyn_pipeline::analyse(engine, resampled, speed.rpm, &self.opts)?;
        analysis.summary.notes.extend(speed.note);
        Ok(Outcome {
            analysis,
            opts: self.opts,
            resampled: None,
            diagram_blake3: Vec::new(),
        })
    }

    /// One operating point from a turning-moment file (`run --torque`).
    pub fn analyse_torque(&self, input: Input<'_>) -> Result<Outcome> {
        let shown = input.shown();
        let grid = GridOptions {
            peg: None,
            ..self.grid.clone()
        };
        let parse = ParseOptions {
            torque: true,
            ..self.parse.clone()
        };
        let resampled = load_diagram(input, &parse, &grid)?;
        if resampled.quantity == Quantity::Pressure {
            return Err(Error::data(format!(
                "{shown}: a pressure diagram; --torque reads `crank_deg` with `torque_cylinder_nm` or `torque_engine_nm` (use --diagram for pressure)"
            )));
        }
        let engine = self.engine();
        let speed = resolve_rpm(self.reader.rpm, resampled.rpm, engine)?;
        let mut analysis = enginedyn_pipeline::analyse_torque(
            engine,
            &resampled,
            resampled.quantity,
            speed.rpm,
            &self.opts,
        )?;
        analysis.summary.notes.extend(speed.note);
        Ok(Outcome {
            analysis,
            opts: self.opts,
            resampled: None,
            diagram_blake3: Vec::new(),
        })
    }

    /// One operating point from named columns in memory (`crank_deg`,
    /// `pressure_bar`, `cycle`, `cylinder`, or a time record's `time_s`,
    /// `tdc`, …): the reader's every rule, as for a file with that header
    /// and those rows. `rpm` stands for the reader's speed when given;
    /// `cancel` stops the read (an error) once set.
    pub fn analyse_columns(
        &self,
        names: &[String],
        columns: &[&[f64]],
        rpm: Option<f64>,
        cancel: &Cancel,
    ) -> Result<Outcome> {
        let rpm = rpm.or(self.reader.rpm);
        if let Some(r) = rpm {
            crate::options::check_rpm(r).map_err(|w| Error::usage(format!("rpm: {w}")))?;
        }
        let parse = ParseOptions {
            rpm,
            cancel: cancel.clone(),
            ..self.parse.clone()
        };
        let resampled = enginedyn_ingest::load_columns(names, columns, &parse, &self.grid)
            .map_err(|e| Error::from(e).in_file("arrays"))?;
        if resampled.quantity != Quantity::Pressure {
            return Err(Error::data("arrays: a turning moment, not a pressure"));
        }
        let engine = self.engine();
        let speed = resolve_rpm(rpm, resampled.rpm, engine)?;
        let mut analysis = enginedyn_pipeline::analyse(engine, &resampled, speed.rpm, &self.opts)?;
        analysis.summary.notes.extend(speed.note);
        Ok(Outcome {
            analysis,
            opts: self.opts,
            resampled: Some(resampled),
            diagram_blake3: Vec::new(),
        })
    }

    /// One operating point from named columns with one pressure column per
    /// cylinder (`pressures[k]`, cylinder k + 1, under the name `pressure`
    /// beside `names`): read as a file whose header names the cylinders
    /// (`P_Cyl1 [bar]` …), so every cylinder lies on the one crank angle
    /// the shared columns give (a time record's time, pulse, encoder: the
    /// reference cylinder 1's) and the peaks say whether each trace is on
    /// that axis or its own. One pressure column is
    /// [`Session::analyse_columns`].
    #[allow(clippy::too_many_arguments)]
    pub fn analyse_cylinder_columns(
        &self,
        names: &[String],
        columns: &[&[f64]],
        pressure: &str,
        pressures: &[&[f64]],
        rpm: Option<f64>,
        cancel: &Cancel,
    ) -> Result<Outcome> {
        let unit = match pressure.strip_prefix("pressure_") {
            Some("v") => "V",
            Some(u) => u,
            None => pressure,
        };
        let mut n = names.to_vec();
        let mut c = columns.to_vec();
        if let [one] = pressures {
            n.push(pressure.to_string());
            c.push(one);
        } else {
            n.extend((1..=pressures.len()).map(|k| format!("P_Cyl{k} [{unit}]")));
            c.extend(pressures.iter().copied());
        }
        self.analyse_columns(&n, &c, rpm, cancel)
    }

    /// Ingest's options for the `k`-th of several per-cylinder files
    /// (cylinder k + 1's, its axis judged so), or for one file.
    fn cylinder_parse(&self, several: bool, k: usize) -> ParseOptions {
        ParseOptions {
            as_cylinder: if several { k + 1 } else { 0 },
            ..self.parse.clone()
        }
    }

    /// The diagrams read once, the cheapest method setting within the
    /// tolerance chosen on their cycle average, then the run with it.
    fn analyse_within(&self, inputs: &[Input<'_>], tolerance: f64) -> Result<Outcome> {
        let several = inputs.len() > 1;
        let diagrams = inputs
            .iter()
            .enumerate()
            .map(|(k, input)| {
                let d = parse_diagram(*input, &self.cylinder_parse(several, k))?;
                let name = input.shown();
                if d.quantity != Quantity::Pressure {
                    return Err(Error::data(format!(
                        "{name}: a turning-moment (torque) file: give it with --torque"
                    )));
                }
                Ok((name, d))
            })
            .collect::<Result<Vec<_>>>()?;
        self.within_diagrams(&diagrams, self.reader.rpm, tolerance)
    }

    /// [`within`] on diagrams already read, the speed resolved from `rpm`
    /// or the first diagram's.
    pub fn within_diagrams(
        &self,
        diagrams: &[(String, enginedyn_ingest::Diagram)],
        rpm: Option<f64>,
        tolerance: f64,
    ) -> Result<Outcome> {
        let engine = self.engine();
        let first = diagrams.first().ok_or_else(|| Error::usage("no diagram"))?;
        let speed = resolve_rpm(rpm, first.1.rpm, engine)?;
        let (mut analysis, choice) = within(
            engine,
            diagrams,
            &self.grid,
            speed.rpm,
            tolerance,
            &self.method.kept(),
        )?;
        analysis.summary.estimated_relative_error = Some(choice.estimated);
        analysis.summary.notes.extend(choice.notes);
        analysis.summary.notes.extend(speed.note);
        Ok(Outcome {
            analysis,
            opts: Options {
                scope: self.opts.scope,
                ..choice.options
            },
            resampled: None,
            diagram_blake3: Vec::new(),
        })
    }
}

/// How a run names its diagrams: the one file, or "N files, one per cylinder".
pub fn shown_of(inputs: &[Input<'_>]) -> String {
    match inputs {
        [one] => one.shown(),
        many => format!("{} files, one per cylinder", many.len()),
    }
}

/// The cheapest setting within `tolerance` for these diagrams (one, or one
/// per cylinder) and the analysis with it (with the report curves).
pub fn within(
    engine: &Engine,
    diagrams: &[(String, enginedyn_ingest::Diagram)],
    grid: &GridOptions,
    rpm: f64,
    tolerance: f64,
    kept: &enginedyn_accuracy::Kept,
) -> Result<(Analysis, enginedyn_accuracy::Choice)> {
    let resample = |ds: &[(String, &enginedyn_ingest::Diagram)], g: &GridOptions| {
        let each = ds
            .iter()
            .map(|(n, d)| {
                enginedyn_ingest::resample_with(d, g)
                    .map(|r| (n.clone(), r))
                    .map_err(|e| Error::from(e).in_file(n))
            })
            .collect::<Result<Vec<_>>>()?;
        merge_per_cylinder(each)
    };
    // The choice on the cycle average (cheap); the run on every cycle.
    let averaged: Vec<(String, enginedyn_ingest::Diagram)> = diagrams
        .iter()
        .map(|(n, d)| (n.clone(), d.averaged().unwrap_or_else(|| d.clone())))
        .collect();
    let avg_refs: Vec<(String, &enginedyn_ingest::Diagram)> =
        averaged.iter().map(|(n, d)| (n.clone(), d)).collect();
    let full_refs: Vec<(String, &enginedyn_ingest::Diagram)> =
        diagrams.iter().map(|(n, d)| (n.clone(), d)).collect();
    let on = |step: f64, interp| GridOptions {
        step_deg: step,
        interp,
        ..grid.clone()
    };
    let choice = enginedyn_accuracy::choose(engine, rpm, tolerance, kept, &|step, interp| {
        resample(&avg_refs, &on(step, interp))
            .map_err(|f| enginedyn_accuracy::AccuracyError::Synth(f.message))
    })?;
    let opts = Options {
        scope: Scope::Full,
        ..choice.options
    };
    let resampled = resample(&full_refs, &on(opts.step_deg, opts.interp))?;
    let analysis = enginedyn_pipeline::analyse(engine, &resampled, rpm, &opts)?;
    Ok((analysis, choice))
}
