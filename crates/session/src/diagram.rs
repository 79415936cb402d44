//! Reading diagrams: reader options onto ingest's, files opened safely,
//! one diagram streamed onto the grid or read whole, per-cylinder files
//! merged, the grid step checked.

use crate::engine::{Bundled, Loaded};
use crate::error::{Error, Result};
use crate::hashing::Hashing;
use crate::options::Reader;
use enginedyn_engine::Engine;
use enginedyn_ingest::{GridOptions, ParseOptions, Peg, Resampled};
use std::path::{Path, PathBuf};

/// A synthesised diagram: its text (`crank_deg,pressure_bar` with `#`
/// lines giving every parameter), how messages name it, and what it gives.
#[derive(Debug, Clone)]
pub struct Synthesised {
    /// How messages name it: `synthesised from FILE [combustion]`.
    pub name: String,
    /// The diagram as `enginedyn synth` writes it.
    pub text: String,
    /// The speed written in its `# rpm` line, when one was known.
    pub rpm: Option<f64>,
    /// The step of its rows (deg).
    pub step_deg: f64,
    /// The IMEP asked for (bar), when the load is an IMEP.
    pub imep_target_bar: Option<f64>,
    /// The net IMEP of the cycle (bar).
    pub imep_bar: f64,
    /// The heat released per cylinder and cycle (J): given, or solved for.
    pub heat_released_j: f64,
    /// The intake pressure of the cycle (bar): the file's at this speed,
    /// or what a spark-ignition engine's throttle gives for the load.
    pub intake_pressure_bar: f64,
    /// The air ratio, when the file says how the engine makes its load.
    pub lambda: Option<f64>,
    /// How the engine makes its load (`charge`), when the file says.
    pub charge: Option<enginedyn_combustion::charge::ChargeKind>,
    /// The note a command says when it runs on it.
    pub note: String,
    /// Its rows as columns (crank_deg, pressure_bar), when it is kept as
    /// samples instead of text (`text` empty; [`crate::synth::synthesise_samples`]).
    pub samples: (Vec<f64>, Vec<f64>),
    /// What may make its figures wrong (a throttle below a running
    /// engine's idle): warnings a command says beside the note.
    pub warnings: Vec<String>,
    /// The γ model it was made with (the analysis reads it back with the
    /// same, PHYSICS "Combustion").
    pub gamma: enginedyn_combustion::GammaModel,
    /// The burn window that holds its whole burn (deg): the default
    /// −90…120°, widened to the law's 0.1 % and 99.9 % points ± 15°,
    /// within IVC … EVO.
    pub burn_window_deg: (f64, f64),
}

/// A diagram to read: a file, or a bundled example's.
#[derive(Debug, Clone, Copy)]
pub enum Input<'a> {
    /// A file.
    File(&'a Path),
    /// A bundled example's diagram.
    Bundled(&'static Bundled),
    /// A diagram synthesised from the engine file's `[combustion]`.
    Synthesised(&'a Synthesised),
}

impl Input<'_> {
    /// How messages name it.
    pub fn shown(&self) -> String {
        match self {
            Input::File(p) => p.display().to_string(),
            Input::Bundled(b) => b.diagram_name(),
            Input::Synthesised(s) => s.name.clone(),
        }
    }
}

/// How to read and grid a diagram for `engine`, from the reader options,
/// the grid step and the interpolant.
pub fn diagram_options(
    engine: &Engine,
    d: &Reader,
    step: f64,
    interp: enginedyn_ingest::Interp,
) -> Result<(ParseOptions, GridOptions)> {
    let peg = match (d.peg_bar, d.peg_polytropic) {
        (Some(p), _) if p.is_finite() && p > 0.0 => Some(Peg::Bar(p * 1e5)),
        (Some(p), _) => {
            return Err(Error::usage(format!(
                "--peg-bar {p}: an absolute pressure in bar above 0 is needed"
            )));
        }
        (None, Some(n)) => Some(Peg::Polytropic(n)),
        (None, None) => None,
    };
    let cylinder = Some(*engine.cylinder());
    let parse = ParseOptions {
        cycle_deg: engine.cycle().to_degrees(),
        tdc_deg: d.tdc_deg.unwrap_or(0.0),
        tdc_given: d.tdc_deg.is_some(),
        relative: peg.is_some(),
        skip_lines: d.skip_lines.map_or(0, |n| n as usize),
        sheet: d.sheet.as_ref().map(|s| match s.trim().parse::<usize>() {
            Ok(n) => enginedyn_ingest::Sheet::Index(n),
            Err(_) => enginedyn_ingest::Sheet::Name(s.clone()),
        }),
        max_gap_deg: d.max_gap_deg.unwrap_or(enginedyn_ingest::MAX_GAP_DEG),
        tdc_time: d.tdc_time,
        gain_bar_per_v: d.gain_bar_per_v,
        rpm: d.rpm,
        gauge: d.gauge,
        columns: d
            .columns
            .as_ref()
            .map(|c| c.iter().map(|s| s.trim().to_ascii_lowercase()).collect()),
        cylinder,
        pv_start_bdc: d.pv_start_bdc,
        max_cylinder: engine.cylinders(),
        firing_deg: engine
            .firing_angles()
            .iter()
            .map(|t| t.to_degrees())
            .collect(),
        cylinder_axis: d.cylinder_axis,
        as_cylinder: 0,
        torque: false,
        group: d.group.map(|n| n as usize),
        encoder_ppr: d.encoder_ppr,
        wheel: d.wheel,
        wheel_tdc_deg: d.wheel_tdc_deg,
        compression_check: !d.no_compression_check,
        synthetic: false,
        despike: d.despike,
        angle_step_deg: d.angle_step_deg,
        cancel: enginedyn_ingest::Cancel::default(),
        operating_rpm: engine.operating().rpm,
    };
    let mut grid = GridOptions {
        step_deg: step,
        interp,
        peg,
        cylinder,
        volume_law: None,
        combustion: None,
    };
    // Built once here for every file the command reads.
    grid.share_volume_law(parse.cycle_deg);
    Ok((parse, grid))
}

/// Opens a diagram (or torque) file for reading: a regular file only. A
/// FIFO or a device is refused before anything is read (opening a FIFO
/// would block a batch forever; a device may never end), and so is a
/// folder.
pub fn open_diagram(p: &Path) -> Result<std::fs::File> {
    let shown = p.display();
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Open never blocks (a FIFO without a writer); reads of a regular
        // file are unaffected by the flag.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options
        .open(p)
        .map_err(|e| Error::io_from(format!("cannot open: {e}"), &e).in_file(&shown))?;
    let meta = file
        .metadata()
        .map_err(|e| Error::io(format!("cannot open: {e}")).in_file(&shown))?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a folder"
        } else {
            "not a regular file (a FIFO, socket or device)"
        };
        return Err(
            Error::io(format!("{what}: a diagram is read from a regular file")).in_file(shown),
        );
    }
    Ok(file)
}

/// Reads one diagram straight onto the grid.
pub fn load_diagram(
    input: Input<'_>,
    parse: &ParseOptions,
    grid: &GridOptions,
) -> Result<Resampled> {
    let mut unused = std::time::Duration::ZERO;
    load_diagram_timed(input, parse, grid, &mut unused)
}

/// [`load_diagram`], adding the time spent after parsing (putting the
/// traces on the grid) to `on_grid`.
pub fn load_diagram_timed(
    input: Input<'_>,
    parse: &ParseOptions,
    grid: &GridOptions,
    on_grid: &mut std::time::Duration,
) -> Result<Resampled> {
    match input {
        Input::File(p) => {
            let file = open_diagram(p)?;
            enginedyn_ingest::load_timed(
                // The reader keeps its own 64 KiB blocks: a small BufReader
                // passes those reads straight through instead of copying.
                enginedyn_ingest::Cancellable::new(
                    std::io::BufReader::with_capacity(1 << 12, file),
                    parse.cancel.clone(),
                ),
                parse,
                grid,
                on_grid,
            )
            .map_err(|e| Error::from(e).in_file(p.display()))
        }
        Input::Bundled(b) => {
            enginedyn_ingest::load_timed(b.diagram.as_bytes(), parse, grid, on_grid)
                .map_err(|e| Error::from(e).in_file(b.diagram_name()))
        }
        Input::Synthesised(s) => {
            // Read back with its own γ model and a window that holds its
            // burn (unless the command line says otherwise).
            let own = GridOptions {
                combustion: grid
                    .combustion
                    .as_deref()
                    .map(|o| std::sync::Arc::new(s.analysis_options(o))),
                ..grid.clone()
            };
            if s.text.is_empty() {
                // Kept as samples: the same rows, handed over as arrays.
                let parse = ParseOptions {
                    synthetic: true,
                    rpm: s.rpm.or(parse.rpm),
                    ..parse.clone()
                };
                let names = ["crank_deg".to_string(), "pressure_bar".to_string()];
                return enginedyn_ingest::load_columns(
                    &names,
                    &[&s.samples.0, &s.samples.1],
                    &parse,
                    &own,
                )
                .map_err(|e| Error::from(e).in_file(&s.name));
            }
            enginedyn_ingest::load_timed(s.text.as_bytes(), parse, &own, on_grid)
                .map_err(|e| Error::from(e).in_file(&s.name))
        }
    }
}

/// [`load_diagram_timed`] of a file, which also gives the BLAKE3 of the
/// file's bytes, hashed as they are read.
pub fn load_file_hashed(
    p: &Path,
    parse: &ParseOptions,
    grid: &GridOptions,
    on_grid: &mut std::time::Duration,
) -> Result<(Resampled, String)> {
    let mut reader = hashing_reader(p, parse)?;
    let r = enginedyn_ingest::load_timed(&mut reader, parse, grid, on_grid)
        .map_err(|e| Error::from(e).in_file(p.display()))?;
    Ok((r, finish_hash(reader, p)?))
}

/// [`load_diagram`], with a file's BLAKE3 hashed in the same read (`None`
/// for text in memory: `inputs` hashes it there).
pub fn load_diagram_hashed(
    input: Input<'_>,
    parse: &ParseOptions,
    grid: &GridOptions,
) -> Result<(Resampled, Option<String>)> {
    match input {
        Input::File(p) => {
            let mut unused = std::time::Duration::ZERO;
            let (r, hash) = load_file_hashed(p, parse, grid, &mut unused)?;
            Ok((r, Some(hash)))
        }
        other => Ok((load_diagram(other, parse, grid)?, None)),
    }
}

/// [`parse_diagram`] of a file, with the BLAKE3 of its bytes.
pub fn parse_file_hashed(
    p: &Path,
    parse: &ParseOptions,
) -> Result<(enginedyn_ingest::Diagram, String)> {
    let mut reader = hashing_reader(p, parse)?;
    let d = enginedyn_ingest::parse(&mut reader, parse)
        .map_err(|e| Error::from(e).in_file(p.display()))?;
    Ok((d, finish_hash(reader, p)?))
}

/// A file read through the hash, stopped by `parse.cancel`.
type HashingReader = std::io::BufReader<enginedyn_ingest::Cancellable<Hashing<std::fs::File>>>;

fn hashing_reader(p: &Path, parse: &ParseOptions) -> Result<HashingReader> {
    Ok(std::io::BufReader::with_capacity(
        1 << 12,
        enginedyn_ingest::Cancellable::new(Hashing::beside(open_diagram(p)?), parse.cancel.clone()),
    ))
}

fn finish_hash(reader: HashingReader, p: &Path) -> Result<String> {
    // What the BufReader holds unread was hashed when it was read.
    reader
        .into_inner()
        .into_inner()
        .finish()
        .map_err(|e| Error::io(format!("cannot read: {e}")).in_file(p.display()))
}

/// Reads a whole diagram into memory (every trace), for the commands that
/// put it on several grids.
pub fn parse_diagram(input: Input<'_>, parse: &ParseOptions) -> Result<enginedyn_ingest::Diagram> {
    match input {
        Input::File(path) => {
            let file = open_diagram(path)?;
            enginedyn_ingest::parse(std::io::BufReader::with_capacity(1 << 12, file), parse)
                .map_err(|e| Error::from(e).in_file(path.display()))
        }
        Input::Bundled(b) => enginedyn_ingest::parse(b.diagram.as_bytes(), parse)
            .map_err(|e| Error::from(e).in_file(b.diagram_name())),
        Input::Synthesised(s) => enginedyn_ingest::parse(s.text.as_bytes(), parse)
            .map_err(|e| Error::from(e).in_file(&s.name)),
    }
}

/// Reads every cell and builds every trace of a diagram, then drops them:
/// the parse floor of the benchmark.
pub fn parse_only(f: &Path, parse: &ParseOptions) -> Result<()> {
    let file = open_diagram(f)?;
    enginedyn_ingest::parse_stream(
        std::io::BufReader::with_capacity(1 << 12, file),
        parse,
        |_| Ok(()),
    )
    .map_err(|e| Error::from(e).in_file(f.display()))?;
    Ok(())
}

/// The diagram a command needs: the one given, else the engine file's
/// `diagram` key, else a usage error that says so.
pub fn diagram_path(given: Option<&Path>, loaded: &Loaded) -> Result<PathBuf> {
    match given {
        Some(p) => Ok(p.to_path_buf()),
        None => loaded
            .engine
            .diagram()
            .map(Path::to_path_buf)
            .ok_or_else(|| {
                Error::usage(format!(
                    "no indicator diagram: give --diagram or `diagram =` in {}",
                    loaded
                        .path
                        .as_deref()
                        .map(|p| p.display().to_string())
                        .unwrap_or_else(|| "the engine file".into())
                ))
            }),
    }
}

/// One trace per file and cylinder, in cylinder order 1..z, as one diagram.
pub fn merge_per_cylinder(files: Vec<(String, Resampled)>) -> Result<Resampled> {
    let mut it = files.into_iter();
    let Some((_, mut first)) = it.next() else {
        return Err(Error::usage("no diagram"));
    };
    let Some((name, second)) = it.next() else {
        // One file: all cylinders, or its own `cylinder` column.
        return Ok(first);
    };
    if !first.cylinders.is_empty() {
        return Err(Error::usage(
            "several --diagram files are one trace per cylinder: a file with a `cylinder` column must come alone",
        ));
    }
    let mut cylinders = vec![std::mem::take(&mut first.pressure)];
    // Each file's cycles are its cylinder's (k + 1), in the cycles table.
    for s in &mut first.stats {
        s.cylinder = 1;
    }
    for s in &mut first.skipped {
        s.cylinder = 1;
    }
    for (k, (name, mut r)) in std::iter::once((name, second)).chain(it).enumerate() {
        if !r.cylinders.is_empty() {
            return Err(Error::usage(format!(
                "{name}: has a `cylinder` column; with several --diagram files each file is one cylinder"
            )));
        }
        let cylinder = k as i64 + 2;
        first.cycles = first.cycles.min(r.cycles);
        for s in &mut r.stats {
            s.cylinder = cylinder;
        }
        for s in &mut r.skipped {
            s.cylinder = cylinder;
        }
        first.stats.extend(r.stats);
        first.skipped.extend(r.skipped);
        first.cycles_skipped += r.cycles_skipped;
        for n in r.notes {
            // One axis note for the files (each file's says the same kind).
            let same_kind = n.starts_with("cylinder traces ")
                && first
                    .notes
                    .iter()
                    .any(|m| m.starts_with("cylinder traces "));
            if !first.notes.contains(&n) && !same_kind {
                first.notes.push(n);
            }
        }
        cylinders.push(r.pressure);
    }
    first.pressure = cylinders[0].clone();
    first.cylinders = cylinders;
    Ok(first)
}

/// The grid step must be positive and divide the cycle.
pub fn check_step(engine: &Engine, step: f64) -> Result<()> {
    let cycle_deg = engine.cycle().to_degrees();
    let n = (cycle_deg / step).round();
    if !(step.is_finite() && step > 0.0)
        || (n * step - cycle_deg).abs() > 1e-9 * cycle_deg
        || n < 8.0
    {
        return Err(Error::usage(format!(
            "--step {step}: the step must divide the {cycle_deg}° cycle (0.1, 0.2, 0.25, 0.5, 1, …)"
        )));
    }
    Ok(())
}
