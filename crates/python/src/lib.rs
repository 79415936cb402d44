//! `enginedyn._native`: the Python package's binding to `enginedyn-session`,
//! the same application layer the `enginedyn` command line calls. Nothing
//! here decides a rule, a bound, a default or a note: options go to
//! `enginedyn_session::{Reader, Method}` (checked there), analyses to
//! `Session`, outputs to `enginedyn_report` (the same functions that write
//! `summary.json`, `curves.csv` and the charts). The GIL is released while
//! reading and computing. The Python API around it lives in
//! `python/enginedyn/`.

use enginedyn_session::{Class, Error, Input, Loaded, Method, Reader, Session, Work};
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyOSError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::Arc;

create_exception!(
    enginedyn,
    EnginedynError,
    PyException,
    "Base of every error enginedyn raises (but OSError)."
);
create_exception!(
    enginedyn,
    DiagramError,
    EnginedynError,
    "A diagram that cannot be used (the CLI exits 1): `path`, `line`, `column`."
);
create_exception!(
    enginedyn,
    EngineFileError,
    EnginedynError,
    "A bad engine file (the CLI exits 2): `path`, `key`."
);
create_exception!(
    enginedyn,
    UsageError,
    EnginedynError,
    "A bad option (the CLI exits 2), naming the argument."
);

/// The library's error as its Python exception, with its attributes; the
/// message speaks of keywords (`step_deg=`), not the CLI's flags, by the
/// session's one table. A missing file is `FileNotFoundError` with its
/// path; work stopped by Ctrl-C is `KeyboardInterrupt`.
fn py_err(e: Error) -> PyErr {
    Python::attach(|py| {
        if e.is_cancelled() {
            return pyo3::exceptions::PyKeyboardInterrupt::new_err(());
        }
        let message = enginedyn_session::options::in_keywords(&e.to_string());
        let err = match e.class {
            Class::Diagram => DiagramError::new_err(message),
            Class::EngineFile => EngineFileError::new_err(message),
            Class::Usage => UsageError::new_err(message),
            Class::Io if e.io_kind == Some(std::io::ErrorKind::NotFound) => {
                let why = enginedyn_session::options::in_keywords(&e.message);
                pyo3::exceptions::PyFileNotFoundError::new_err((2, why, e.file.clone()))
            }
            Class::Io => PyOSError::new_err(message),
        };
        let value = err.value(py);
        if e.class != Class::Io {
            let _ = value.setattr("path", e.file.clone());
        }
        match e.class {
            Class::Diagram => {
                let _ = value.setattr("line", e.line);
                let _ = value.setattr("column", e.column);
            }
            Class::EngineFile => {
                let _ = value.setattr("key", e.key.clone());
            }
            _ => {}
        }
        err
    })
}

/// How many times [`interrupt_all`] was called: a call computing in any
/// thread stops once it has changed since the call began.
static INTERRUPTS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Runs `work` on its own thread with the GIL released, polling Python's
/// signal handlers every 20 ms: Ctrl-C sets `cancel` (the session's loops
/// stop at their next check), waits for the work to stop, and raises
/// `KeyboardInterrupt`. Python runs its signal handlers in the main thread
/// only: a call in another thread is stopped by [`interrupt_all`] (the
/// package's SIGINT handler), seen here at the same poll.
fn interruptible<T: Send>(
    py: Python<'_>,
    cancel: &enginedyn_ingest::Cancel,
    work: impl FnOnce() -> Result<T, Error> + Send,
) -> PyResult<T> {
    use std::sync::atomic::Ordering;
    let began = INTERRUPTS.load(Ordering::SeqCst);
    std::thread::scope(|scope| {
        let handle = scope.spawn(work);
        loop {
            if INTERRUPTS.load(Ordering::SeqCst) != began {
                cancel.cancel();
                let _ = py.detach(|| handle.join());
                return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(()));
            }
            py.detach(|| {
                for _ in 0..4 {
                    if handle.is_finished() {
                        break;
                    }
                    std::thread::sleep(std::time::Duration::from_millis(5));
                }
            });
            if handle.is_finished() {
                break;
            }
            if let Err(interrupt) = py.check_signals() {
                cancel.cancel();
                let _ = py.detach(|| handle.join());
                return Err(interrupt);
            }
        }
        match handle.join() {
            Ok(r) => r.py(),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

trait OrPy<T> {
    fn py(self) -> PyResult<T>;
}

impl<T> OrPy<T> for Result<T, Error> {
    fn py(self) -> PyResult<T> {
        self.map_err(py_err)
    }
}

/// A checked engine.
#[pyclass(module = "enginedyn._native", frozen)]
struct Engine {
    loaded: Arc<Loaded>,
}

#[pymethods]
impl Engine {
    /// Reads and checks an engine file (TOML).
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        // A missing file is Python's FileNotFoundError; anything else goes
        // through the session's one rule (a regular file of at most 1 MiB).
        std::fs::metadata(&path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => pyo3::exceptions::PyFileNotFoundError::new_err((
                2,
                "No such file or directory",
                path.display().to_string(),
            )),
            _ => e.into(),
        })?;
        let loaded = py.detach(|| Loaded::from_file(&path)).py()?;
        Ok(Self {
            loaded: Arc::new(loaded),
        })
    }

    /// Checks engine-file text; `path`, when given, is where it was read
    /// from (its name, and the folder `diagram` is relative to).
    #[staticmethod]
    #[pyo3(signature = (text, path=None))]
    fn from_str(py: Python<'_>, text: String, path: Option<PathBuf>) -> PyResult<Self> {
        let loaded = py
            .detach(|| Loaded::from_text(text, path.as_deref()))
            .py()?;
        Ok(Self {
            loaded: Arc::new(loaded),
        })
    }

    /// A bundled example by name (`vaz2108`, `single`, …).
    #[staticmethod]
    fn bundled(name: &str) -> PyResult<Self> {
        let b = enginedyn_session::Bundled::find(name).py()?;
        Ok(Self {
            loaded: Arc::new(Loaded::bundled(b).py()?),
        })
    }

    /// The names of the bundled examples.
    #[staticmethod]
    fn bundled_names() -> Vec<&'static str> {
        enginedyn_session::BUNDLED.iter().map(|b| b.name).collect()
    }

    /// The engine's name.
    #[getter]
    fn name(&self) -> String {
        self.loaded.engine.name().to_string()
    }

    /// The number of cylinders.
    #[getter]
    fn cylinders(&self) -> usize {
        self.loaded.engine.cylinders()
    }

    /// The engine file's text.
    #[getter]
    fn text(&self) -> String {
        self.loaded.text.clone()
    }

    /// The engine file's path, if it came from one.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.loaded.path.clone()
    }

    /// The bundled example's name, if it is one.
    #[getter]
    fn bundled_name(&self) -> Option<&'static str> {
        self.loaded.bundled.map(|b| b.name)
    }

    /// The engine file's `diagram`, resolved against its folder.
    #[getter]
    fn diagram(&self) -> Option<PathBuf> {
        self.loaded.engine.diagram().map(PathBuf::from)
    }
}

/// A value of an options dict, or `None`.
fn get<'py, T>(d: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<T>>
where
    T: for<'a> FromPyObject<'a, 'py>,
    for<'a> <T as FromPyObject<'a, 'py>>::Error: Into<PyErr>,
{
    match d.get_item(key)? {
        Some(v) if !v.is_none() => Ok(Some(v.extract::<T>().map_err(|e| {
            let e: PyErr = e.into();
            UsageError::new_err(format!("{key}: {e}"))
        })?)),
        _ => Ok(None),
    }
}

/// A name of an options dict mapped by `table`, or a usage error listing them.
fn named<'py, T: Copy>(
    d: &Bound<'py, PyDict>,
    key: &str,
    table: &[(&str, T)],
) -> PyResult<Option<T>> {
    let Some(name) = get::<String>(d, key)? else {
        return Ok(None);
    };
    table
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name.trim()))
        .map(|(_, v)| Some(*v))
        .ok_or_else(|| {
            UsageError::new_err(format!(
                "{key}: `{name}` is not one of {}",
                table.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
            ))
        })
}

/// The keyword argument names as Python gives them (`step_deg` as is).
fn kw(field: &str) -> String {
    field.to_string()
}

/// The reader options from a dict of keyword arguments, every bound checked.
fn reader(d: &Bound<'_, PyDict>) -> PyResult<Reader> {
    use enginedyn_session::options as o;
    let known = o::READER_KEYS;
    for k in d.keys() {
        let k: String = k.extract()?;
        if !known.contains(&k.as_str()) {
            return Err(UsageError::new_err(format!(
                "Reader: unknown argument `{k}`; it takes {}",
                known.join(", ")
            )));
        }
    }
    let peg = match get::<String>(d, "peg")? {
        Some(s) => Some(o::read_peg(&s).map_err(|w| UsageError::new_err(format!("peg: {w}")))?),
        None => None,
    };
    let r = Reader {
        cylinder_axis: named(d, "cylinder_axis", o::CYLINDER_AXES)?,
        tdc_deg: get(d, "tdc_deg")?,
        gauge: get(d, "gauge")?.unwrap_or(false),
        columns: get(d, "columns")?,
        peg_bar: get(d, "peg_bar")?,
        peg_polytropic: peg,
        pv_start_bdc: named(d, "pv_start", o::PV_STARTS)?.unwrap_or(false),
        skip_lines: get(d, "skip_lines")?,
        sheet: match d.get_item("sheet")? {
            Some(v) if !v.is_none() => Some(v.str()?.to_string()),
            _ => None,
        },
        max_gap_deg: get(d, "max_gap_deg")?,
        tdc_time: get(d, "tdc_time")?,
        gain_bar_per_v: get(d, "gain_bar_per_v")?,
        rpm: get(d, "rpm")?,
        group: get(d, "group")?,
        encoder_ppr: get(d, "encoder_ppr")?,
        wheel: match get::<String>(d, "wheel")? {
            Some(w) => Some(
                enginedyn_ingest::Wheel::parse(&w)
                    .map_err(|e| UsageError::new_err(format!("wheel: {e}")))?,
            ),
            None => None,
        },
        wheel_tdc_deg: get(d, "wheel_tdc_deg")?,
        no_compression_check: !get::<bool>(d, "compression_check")?.unwrap_or(true),
        despike: get::<bool>(d, "despike")?.unwrap_or(false),
        angle_step_deg: get(d, "angle_step")?,
    };
    r.check(kw).py()?;
    Ok(r)
}

/// The method options from a dict of keyword arguments, every bound checked.
fn method(d: &Bound<'_, PyDict>) -> PyResult<Method> {
    use enginedyn_session::options as o;
    let known = o::METHOD_KEYS;
    for k in d.keys() {
        let k: String = k.extract()?;
        if !known.contains(&k.as_str()) {
            return Err(UsageError::new_err(format!(
                "Method: unknown argument `{k}`; it takes {}",
                known.join(", ")
            )));
        }
    }
    let m = Method {
        step_deg: get(d, "step_deg")?,
        kinematics: named(d, "kinematics", o::KINEMATICS)?,
        rod_model: named(d, "rod_model", o::ROD_MODELS)?,
        interp: named(d, "interp", o::INTERPOLANTS)?,
        integration: named(d, "integration", o::INTEGRATIONS)?,
        tolerance: get(d, "tolerance")?,
        burn: burn(d)?,
    };
    m.check(kw).py()?;
    Ok(m)
}

/// The combustion keywords, each as a string the session's parser reads
/// (`burn_points=[5, 50]` or `"5,50"`, `burn_window=(-90, 120)` or
/// `"-90:120"`, `gamma=1.32` or `"brunt"`, `smooth="SG:2"` or `"off"`).
fn burn(d: &Bound<'_, PyDict>) -> PyResult<enginedyn_session::burn::BurnMethod> {
    use enginedyn_session::burn as b;
    let text = |key: &str, sep: &str| -> PyResult<Option<String>> {
        match d.get_item(key)? {
            Some(v) if v.is_none() => Ok(None),
            Some(v) => {
                if let Ok(s) = v.extract::<String>() {
                    Ok(Some(s))
                } else if let Ok(l) = v.extract::<Vec<f64>>() {
                    Ok(Some(
                        l.iter().map(f64::to_string).collect::<Vec<_>>().join(sep),
                    ))
                } else if let Ok(x) = v.extract::<f64>() {
                    Ok(Some(x.to_string()))
                } else {
                    Err(UsageError::new_err(format!(
                        "{key}: give a number, a list or a string"
                    )))
                }
            }
            None => Ok(None),
        }
    };
    let read = |key: &str, sep: &str| -> PyResult<Option<String>> { text(key, sep) };
    fn fail(key: &'static str) -> impl Fn(String) -> PyErr {
        move |e| UsageError::new_err(format!("{key}={e}"))
    }
    Ok(b::BurnMethod {
        levels: read("burn_points", ",")?
            .map(|s| b::Levels::parse(&s).map_err(fail("burn_points")))
            .transpose()?,
        window_deg: read("burn_window", ":")?
            .map(|s| b::parse_window(&s).map_err(fail("burn_window")))
            .transpose()?,
        gamma: read("gamma", "")?
            .map(|s| b::parse_gamma(&s).map_err(fail("gamma")))
            .transpose()?,
        smooth: read("smooth", "")?
            .map(|s| b::parse_smooth(&s).map_err(fail("smooth")))
            .transpose()?,
        intake_temp_k: get(d, "intake_temp_k")?,
        ivc_deg: get(d, "ivc_deg")?,
        wall_heat: read("wall_heat", "")?
            .map(|s| b::parse_wall_heat(&s).map_err(fail("wall_heat")))
            .transpose()?,
        wall_temp_k: read("wall_temp_k", "")?
            .map(|s| b::parse_wall_temp_k(&s).map_err(fail("wall_temp_k")))
            .transpose()?,
        knock: get::<bool>(d, "knock")?.unwrap_or(false),
        knock_band_hz: read("knock_band", ":")?
            .map(|s| b::parse_knock_band(&s).map_err(fail("knock_band")))
            .transpose()?,
        knock_window_deg: read("knock_window", ":")?
            .map(|s| b::parse_knock_window(&s).map_err(fail("knock_window")))
            .transpose()?,
        knock_threshold_pa: read("knock_threshold", "")?
            .map(|s| b::parse_knock_threshold(&s).map_err(fail("knock_threshold")))
            .transpose()?,
        off: false,
    })
}

/// Checks reader keyword arguments (raises `UsageError` naming the argument).
#[pyfunction]
fn check_reader(options: &Bound<'_, PyDict>) -> PyResult<()> {
    reader(options).map(|_| ())
}

/// Checks method keyword arguments (raises `UsageError` naming the argument).
#[pyfunction]
fn check_method(options: &Bound<'_, PyDict>) -> PyResult<()> {
    method(options).map(|_| ())
}

/// An engine, reader options and method options, checked once.
#[pyclass(module = "enginedyn._native", frozen)]
struct NativeSession {
    session: Arc<Session>,
}

#[pymethods]
impl NativeSession {
    #[new]
    #[pyo3(signature = (engine, method_options, reader_options, full=true))]
    fn new(
        engine: &Engine,
        method_options: &Bound<'_, PyDict>,
        reader_options: &Bound<'_, PyDict>,
        full: bool,
    ) -> PyResult<Self> {
        let m = method(method_options)?;
        let r = reader(reader_options)?;
        let scope = if full {
            enginedyn_pipeline::Scope::Full
        } else {
            enginedyn_pipeline::Scope::Summary
        };
        let loaded = (*engine.loaded).clone();
        let mut session = Session::new(loaded, r, m, scope).py()?;
        // A batch's rows feed the cycles table and `write_parquet`.
        session.keep_grid = true;
        Ok(Self {
            session: Arc::new(session),
        })
    }

    /// One operating point from diagram files (one, or one per cylinder;
    /// none: the engine's own diagram), as `enginedyn run` reads them.
    fn analyse(&self, py: Python<'_>, paths: Vec<PathBuf>) -> PyResult<Run> {
        let s = self.session.clone();
        let cancel = enginedyn_ingest::Cancel::new();
        let token = cancel.clone();
        interruptible(py, &cancel, move || {
            let own;
            let mut inputs: Vec<Input<'_>> = paths.iter().map(|p| Input::File(p)).collect();
            if inputs.is_empty() {
                // A bundled engine's own diagram is bundled too.
                match (&s.loaded.path, s.loaded.bundled) {
                    (None, Some(b)) => inputs.push(Input::Bundled(b)),
                    _ => {
                        own = enginedyn_session::diagram::diagram_path(None, &s.loaded)?;
                        inputs.push(Input::File(&own));
                    }
                }
            }
            let outcome = s.analyse_cancellable(&inputs, &token)?;
            let inputs =
                enginedyn_session::inputs::of_hashed(&s.loaded, &inputs, &outcome.diagram_blake3)?;
            Ok(Run::new(&s, outcome, inputs))
        })
    }

    /// One operating point from a turning-moment file.
    fn analyse_torque(&self, py: Python<'_>, path: PathBuf) -> PyResult<Run> {
        let s = self.session.clone();
        py.detach(move || {
            let outcome = s.analyse_torque(Input::File(&path))?;
            let inputs = enginedyn_session::inputs::of(&s.loaded, &[Input::File(&path)])?;
            Ok(Run::new(&s, outcome, inputs))
        })
        .py()
    }

    /// One operating point from named float64 columns (C-contiguous);
    /// with `pressure` and `pressures` (2-D, one row a cylinder), one
    /// pressure column per cylinder, read as a record whose header names
    /// its cylinders.
    #[pyo3(signature = (names, columns, rpm=None, pressure=None, pressures=None))]
    fn analyse_columns(
        &self,
        py: Python<'_>,
        names: Vec<String>,
        columns: Vec<PyReadonlyArray1<'_, f64>>,
        rpm: Option<f64>,
        pressure: Option<String>,
        pressures: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Run> {
        let type_error =
            |e: numpy::AsSliceError| pyo3::exceptions::PyTypeError::new_err(e.to_string());
        let slices: Vec<&[f64]> = columns
            .iter()
            .map(|c| c.as_slice())
            .collect::<Result<_, _>>()
            .map_err(type_error)?;
        let rows: Vec<&[f64]> = match &pressures {
            Some(p) => {
                let n = p.shape()[1].max(1);
                p.as_slice().map_err(type_error)?.chunks(n).collect()
            }
            None => Vec::new(),
        };
        let s = self.session.clone();
        let cancel = enginedyn_ingest::Cancel::new();
        let token = cancel.clone();
        interruptible(py, &cancel, move || {
            let outcome = match &pressure {
                Some(name) => {
                    s.analyse_cylinder_columns(&names, &slices, name, &rows, rpm, &token)?
                }
                None => s.analyse_columns(&names, &slices, rpm, &token)?,
            };
            // Hashed from the borrowed slices: no copy of the arrays.
            let all: Vec<&[f64]> = slices.iter().chain(rows.iter()).copied().collect();
            let hash = enginedyn_session::inputs::arrays_blake3(&all);
            let arrays = enginedyn_report::Source::Hashed(std::path::Path::new("arrays"), &hash);
            let engine = enginedyn_session::inputs::of(&s.loaded, &[])?;
            let inputs = engine.with_diagrams(&[arrays]).map_err(Error::from)?;
            Ok(Run::new(&s, outcome, inputs))
        })
    }

    /// The torsion study (the engine file's `[torsion]`) excited by the
    /// diagram at `path` (none: the engine's own), over `rpms` (none: 20 %
    /// to 120 % of the speed): `(torsion.json, modes.csv, torsion.csv,
    /// notes, charts)`, the texts `enginedyn torsion --out` writes.
    #[pyo3(signature = (rpms=None, path=None))]
    fn torsion(
        &self,
        py: Python<'_>,
        rpms: Option<Vec<f64>>,
        path: Option<PathBuf>,
    ) -> PyResult<TorsionTexts> {
        let s = self.session.clone();
        py.detach(move || {
            let loaded = &s.loaded;
            let spec = enginedyn_session::torsion::spec(loaded)?;
            let input = match (&path, loaded.bundled) {
                (Some(p), _) => Some(Input::File(p)),
                (None, Some(b)) if loaded.path.is_none() => Some(Input::Bundled(b)),
                (None, _) => None,
            };
            let t = enginedyn_session::torsion::study(
                loaded, &spec, &s.reader, &s.method, input, rpms,
            )?;
            let engine = &loaded.engine;
            let notes = t.all_notes();
            let json = enginedyn_report::torsion_json(engine, &t.study, &t.opts, &notes);
            let charts = enginedyn_report::torsion_charts(engine.name(), &t.study)?;
            Ok((
                serde_json::to_string_pretty(&json).unwrap_or_default() + "\n",
                enginedyn_report::modes_csv(&t.study),
                enginedyn_report::torsion_csv(&t.study),
                notes,
                charts,
            ))
        })
        .py()
    }

    /// Before any work on a campaign in `dir` (`map_campaign`): refuses a
    /// folder holding another campaign's parts, naming both, unless
    /// `overwrite`, which removes enginedyn's own parts first; refuses
    /// anything else at a part's path. Returns the parts removed.
    #[pyo3(signature = (dir, paths, parts, traces=false, overwrite=false))]
    fn plan_campaign(
        &self,
        py: Python<'_>,
        dir: PathBuf,
        paths: Vec<PathBuf>,
        parts: usize,
        traces: bool,
        overwrite: bool,
    ) -> PyResult<Vec<PathBuf>> {
        let shard = enginedyn_session::batch::Shard::new(0, parts)
            .map_err(|e| UsageError::new_err(format!("parts: {e}")))?;
        let s = &self.session;
        py.detach(|| s.plan_parts(&dir, shard, &paths, traces, overwrite))
            .map(|p| p.removed)
            .py()
    }

    /// Many files on `jobs` threads (0: one per core): a row per file;
    /// a failed file is a row with its error, never an exception.
    #[pyo3(signature = (paths, jobs=0))]
    fn batch(&self, py: Python<'_>, paths: Vec<PathBuf>, jobs: usize) -> PyResult<NativeBatch> {
        if jobs > enginedyn_session::options::MAX_JOBS {
            return Err(UsageError::new_err(format!(
                "jobs: {jobs} is outside 0 to {}",
                enginedyn_session::options::MAX_JOBS
            )));
        }
        // One file, one row: a file named twice (`a.csv`, `./a.csv`) is
        // analysed once, by its canonical path, as a campaign's list is.
        let (keyed, twice) = enginedyn_session::batch::unique(paths);
        let paths: Vec<PathBuf> = keyed.into_iter().map(|(_, p)| p).collect();
        let s = self.session.clone();
        let cancel = enginedyn_ingest::Cancel::new();
        let token = cancel.clone();
        interruptible(py, &cancel, move || {
            let engine = enginedyn_session::inputs::of(&s.loaded, &[])?;
            let items = s.batch_cancellable(
                &paths,
                jobs,
                Work::Analyse,
                |_, f, an, _| {
                    let Some(an) = an else {
                        return Err(Error::usage("nothing analysed"));
                    };
                    let hashed = enginedyn_report::Source::Hashed(f, &an.diagram_blake3);
                    let inputs = engine.with_diagrams(&[hashed])?;
                    let json = enginedyn_report::summary_json(&an.analysis.summary, &inputs);
                    let text = serde_json::to_string(&json).unwrap_or_default();
                    Ok((
                        text,
                        s.row(f, &an.analysis, an.resampled, an.diagram_blake3),
                    ))
                },
                |_| {},
                &token,
            )?;
            if token.is_cancelled() {
                return Err(
                    enginedyn_ingest::IngestError::Io(enginedyn_ingest::cancel_error()).into(),
                );
            }
            let mut rows = Vec::with_capacity(items.len());
            let mut summaries = Vec::with_capacity(items.len());
            for item in items {
                token
                    .check()
                    .map_err(|e| Error::from(e).in_file(item.file.display()))?;
                match item.result {
                    Ok((json, row)) => {
                        summaries.push(Some(json));
                        rows.push(row);
                    }
                    Err(e) => {
                        summaries.push(None);
                        rows.push(enginedyn_session::campaign::Row::failed(&item.file, &e));
                    }
                }
            }
            Ok(NativeBatch {
                session: s.clone(),
                rows,
                summaries,
                listed: twice.into_iter().collect(),
            })
        })
    }
}

/// A batch's rows, for Python and for the campaign's Parquet tables.
#[pyclass(module = "enginedyn._native", frozen)]
struct NativeBatch {
    session: Arc<Session>,
    rows: Vec<enginedyn_session::campaign::Row>,
    summaries: Vec<Option<String>>,
    /// What the list itself gave (a file named twice).
    listed: Vec<String>,
}

#[pymethods]
impl NativeBatch {
    /// The files, as given.
    fn files(&self) -> Vec<String> {
        self.rows.iter().map(|r| r.file.clone()).collect()
    }

    /// The notes of the file list itself (a file named more than once).
    fn listed(&self) -> Vec<String> {
        self.listed.clone()
    }

    /// Each file's error (`None` when it ran).
    fn errors(&self) -> Vec<Option<String>> {
        self.rows.iter().map(|r| r.error.clone()).collect()
    }

    /// Each file's notes apart by the CLI's severity: (`note:` lines,
    /// `warning:` lines); empty for a failed file.
    fn notes(&self) -> Vec<(Vec<String>, Vec<String>)> {
        use enginedyn_pipeline::notes::{Severity, severity};
        self.rows
            .iter()
            .map(|r| {
                let all = r.summary.as_ref().map_or(&[][..], |s| &s.notes[..]);
                let (warned, noted): (Vec<String>, Vec<String>) = all
                    .iter()
                    .cloned()
                    .partition(|n| severity(n) == Severity::Warning);
                (noted, warned)
            })
            .collect()
    }

    /// Each file's `summary.json` as text (`None` when it failed).
    fn summaries(&self) -> Vec<Option<String>> {
        self.summaries.clone()
    }

    /// The `summary/2` table as Parquet bytes (what a part holds).
    fn summary_parquet<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let bytes = self.session.summary_bytes(&self.rows).py()?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// The `cycles/2` table as Parquet bytes.
    fn cycles_parquet<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let bytes = self.session.cycles_bytes(&self.rows).py()?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// Writes part `part` of `parts` into the campaign folder `dir`: the
    /// same files `batch --shard part/parts --parquet dir` writes. `paths`:
    /// the whole campaign's files (every shard's; default: this batch's);
    /// `overwrite`: replace another campaign's parts (`--replace`).
    /// `list_blake3`: the whole list's hash from `list_plan` (then `paths`
    /// is not needed: each task of a campaign handles its own files only).
    #[pyo3(signature = (dir, part=0, parts=1, traces=false, paths=None, overwrite=false, list_blake3=None))]
    #[allow(clippy::too_many_arguments)]
    fn write_parquet(
        &self,
        py: Python<'_>,
        dir: PathBuf,
        part: usize,
        parts: usize,
        traces: bool,
        paths: Option<Vec<PathBuf>>,
        overwrite: bool,
        list_blake3: Option<String>,
    ) -> PyResult<Vec<PathBuf>> {
        let shard = enginedyn_session::batch::Shard::new(part, parts)
            .map_err(|e| UsageError::new_err(format!("part/parts: {e}")))?;
        py.detach(|| match list_blake3 {
            Some(hash) => {
                let plan = self
                    .session
                    .plan_listed(&dir, shard, hash, traces, overwrite)?;
                self.session.write_plan(&plan, &self.rows)
            }
            None => self.session.write_parts(
                &dir,
                shard,
                paths.as_deref(),
                &self.rows,
                traces,
                overwrite,
            ),
        })
        .py()
    }
}

/// The paths of shard `part` of `parts`: sorted bytewise, path k to shard
/// k mod N (the rule of `batch --shard`).
/// A campaign's list planned once: its BLAKE3 and each part's files.
#[pyfunction]
fn list_plan(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    parts: usize,
) -> PyResult<(String, Vec<Vec<PathBuf>>)> {
    py.detach(|| enginedyn_session::campaign::list_plan(&paths, parts))
        .py()
}

#[pyfunction]
fn shard(paths: Vec<PathBuf>, part: usize, parts: usize) -> PyResult<Vec<PathBuf>> {
    let s = enginedyn_session::batch::Shard::new(part, parts)
        .map_err(|e| UsageError::new_err(format!("part/parts: {e}")))?;
    Ok(s.take(&paths))
}

/// `Result.to_folder`: the files written into `dir` as `run --out DIR`
/// writes its own (`enginedyn_report::write_run`, the one function):
/// checked, staged, then moved into place, a link or anything else in the
/// way refused. Returns the notes on earlier outputs kept.
#[pyfunction]
fn write_run_folder(
    py: Python<'_>,
    dir: PathBuf,
    files: Vec<(String, Vec<u8>)>,
) -> PyResult<Vec<String>> {
    py.detach(|| enginedyn_report::write_run(&dir, &files).map_err(Error::from))
        .py()
}

/// `Result.load`: the files `names` of the folder `dir`, each a plain name
/// of a regular file inside it, never read through a link
/// (`enginedyn_report::read_output`).
#[pyfunction]
fn read_run_folder<'py>(
    py: Python<'py>,
    dir: PathBuf,
    names: Vec<String>,
) -> PyResult<Bound<'py, PyList>> {
    let read = py
        .detach(|| {
            names
                .iter()
                .map(|n| enginedyn_report::read_output(&dir, n).map(|b| (n.clone(), b)))
                .collect::<Result<Vec<_>, _>>()
        })
        .map_err(|e| {
            // Not the folder `to_folder` wrote: an enginedyn error naming
            // the file.
            let (path, why) = match &e {
                enginedyn_report::ReportError::Read { path, source } => {
                    (path.display().to_string(), source.to_string())
                }
                other => (dir.display().to_string(), other.to_string()),
            };
            let err = EnginedynError::new_err(format!(
                "{path}: not a result Result.to_folder wrote: {why}"
            ));
            let _ = err.value(py).setattr("path", path);
            err
        })?;
    let list = PyList::empty(py);
    for (name, bytes) in read {
        list.append((name, pyo3::types::PyBytes::new(py, &bytes)))?;
    }
    Ok(list)
}

/// Cancels every call of this process that is computing now (the
/// package's SIGINT handler calls it, so that a batch running in another
/// thread stops with the main thread's `KeyboardInterrupt`).
#[pyfunction]
fn interrupt_all() {
    INTERRUPTS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
}

/// `enginedyn merge DIR [--parts N]`: checks the campaign and writes
/// `DIR/_manifest.json`; returns the manifest as JSON text.
#[pyfunction]
#[pyo3(signature = (dir, parts=None))]
fn merge(py: Python<'_>, dir: PathBuf, parts: Option<usize>) -> PyResult<String> {
    let (m, _) = py
        .detach(|| enginedyn_session::campaign::merge(&dir, parts))
        .py()?;
    Ok(serde_json::to_string_pretty(&m).unwrap_or_default())
}

/// What a torsion study writes: `torsion.json`, `modes.csv`,
/// `torsion.csv`, the notes, and the charts as (file name, SVG).
type TorsionTexts = (String, String, String, Vec<String>, Vec<(String, String)>);

/// The speeds FROM, FROM + STEP, … TO (TO included when it falls on the
/// step), held to the bounds of `--rpm FROM:TO:STEP`.
#[pyfunction]
fn speeds(start: f64, stop: f64, step: f64) -> PyResult<Vec<f64>> {
    enginedyn_session::speed::speed_range(start, stop, step, &format!("{start}:{stop}:{step}")).py()
}

/// One operating point analysed.
#[pyclass(module = "enginedyn._native", frozen)]
struct Run {
    session: Arc<Session>,
    engine: Arc<Loaded>,
    analysis: Arc<enginedyn_pipeline::Analysis>,
    resampled: Option<Arc<enginedyn_ingest::Resampled>>,
    inputs: enginedyn_report::Inputs,
}

impl Run {
    fn new(
        s: &Arc<Session>,
        outcome: enginedyn_session::Outcome,
        inputs: enginedyn_report::Inputs,
    ) -> Self {
        Self {
            session: s.clone(),
            engine: Arc::new(s.loaded.clone()),
            analysis: Arc::new(outcome.analysis),
            resampled: outcome.resampled.map(Arc::new),
            inputs,
        }
    }
}

/// How a table's column gets its value from a row.
type Getter<R> = for<'r> fn(&'r R) -> enginedyn_pipeline::schema::Cell<'r>;

/// Columns of one of the tables (`pipeline::schema`) as a dict: float64
/// arrays (NaN for null), int64 arrays, bool arrays, lists of str or None.
fn table_dict<'py, R>(
    py: Python<'py>,
    columns: &[enginedyn_pipeline::schema::Column<Getter<R>>],
    rows: &[R],
) -> PyResult<Bound<'py, PyDict>> {
    use enginedyn_pipeline::schema::{Cell, ColumnType};
    let d = PyDict::new(py);
    for c in columns {
        let cells = rows.iter().map(|r| (c.get)(r));
        match c.ty {
            ColumnType::Float64 => {
                let v: Vec<f64> = cells
                    .map(|x| match x {
                        Cell::Float(f) => f,
                        Cell::Int(i) => i as f64,
                        _ => f64::NAN,
                    })
                    .collect();
                d.set_item(c.name, PyArray1::from_vec(py, v))?;
            }
            ColumnType::Bool => {
                let v: Vec<bool> = cells.map(|x| matches!(x, Cell::Bool(true))).collect();
                d.set_item(c.name, PyArray1::from_vec(py, v))?;
            }
            ColumnType::Float64List => {
                let v: Vec<Option<Vec<f64>>> = cells
                    .map(|x| match x {
                        Cell::Floats(v) => Some(v),
                        _ => None,
                    })
                    .collect();
                d.set_item(c.name, v)?;
            }
            ColumnType::Utf8 => {
                let v: Vec<Option<String>> = cells
                    .map(|x| match x {
                        Cell::Text(t) => Some(t.into_owned()),
                        _ => None,
                    })
                    .collect();
                d.set_item(c.name, v)?;
            }
            _ => {
                let v: Vec<i64> = cells
                    .map(|x| match x {
                        Cell::Int(i) => i,
                        _ => 0,
                    })
                    .collect();
                d.set_item(c.name, PyArray1::from_vec(py, v))?;
            }
        }
    }
    Ok(d)
}

fn columns_dict<'py>(
    py: Python<'py>,
    columns: Vec<(String, Vec<f64>)>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, values) in columns {
        d.set_item(name, PyArray1::from_vec(py, values))?;
    }
    Ok(d)
}

#[pymethods]
impl Run {
    /// `summary.json` as the CLI writes it (text).
    fn summary_json(&self) -> String {
        let json = enginedyn_report::summary_json(&self.analysis.summary, &self.inputs);
        serde_json::to_string_pretty(&json).unwrap_or_default() + "\n"
    }

    /// The notes, as the CLI says them.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.analysis.summary.notes.clone()
    }

    /// The columns of `curves.csv` (NaN where its cell is empty).
    #[pyo3(signature = (centered=false))]
    fn curves<'py>(&self, py: Python<'py>, centered: bool) -> PyResult<Bound<'py, PyDict>> {
        columns_dict(
            py,
            enginedyn_report::curve_columns(&self.analysis, centered),
        )
    }

    /// The columns of `harmonics.csv` (NaN where its cell is empty).
    fn harmonics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 5];
        for row in enginedyn_report::harmonic_rows(&self.analysis) {
            for (c, x) in cols.iter_mut().zip(row) {
                c.push(x.unwrap_or(f64::NAN));
            }
        }
        columns_dict(
            py,
            enginedyn_report::HARMONIC_NAMES
                .iter()
                .map(|n| n.to_string())
                .zip(cols)
                .collect(),
        )
    }

    /// The `cycles` table's columns for this run (`file` as given).
    fn cycles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let file = self.inputs.diagram_files.join(" | ");
        let rows = match &self.resampled {
            Some(r) => enginedyn_pipeline::schema::cycle_rows(&file, r, self.analysis.summary.rpm),
            None => Vec::new(),
        };
        table_dict(py, enginedyn_pipeline::schema::CYCLES, &rows)
    }

    /// This run as the `summary/2` table's one row, as Parquet bytes (the
    /// schema and metadata a campaign's parts have).
    fn summary_parquet<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let row = enginedyn_session::campaign::Row {
            file: self.inputs.diagram_files.join(" | "),
            key: self.inputs.diagram_files.join(" | ").into_bytes(),
            error: None,
            diagram_blake3: (self.inputs.diagram_blake3.len() == 1)
                .then(|| self.inputs.diagram_blake3[0].clone()),
            summary: Some(self.analysis.summary.clone()),
            resampled: None,
        };
        let bytes = self.session.summary_bytes(&[row]).py()?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// The chart names (`torque`, `pressure`, …) `svg` takes.
    fn charts(&self) -> Vec<String> {
        enginedyn_report::run_figures(&self.engine.engine, &self.analysis)
            .into_iter()
            .map(|f| f.file.trim_end_matches(".svg").to_string())
            .collect()
    }

    /// A chart as SVG text, by name (`torque` or `torque.svg`).
    fn svg(&self, py: Python<'_>, name: &str) -> PyResult<String> {
        let want = name.trim_end_matches(".svg").to_string();
        let engine = self.engine.clone();
        let analysis = self.analysis.clone();
        py.detach(move || {
            let figs = enginedyn_report::run_figures(&engine.engine, &analysis);
            let names: Vec<String> = figs
                .iter()
                .map(|f| f.file.trim_end_matches(".svg").to_string())
                .collect();
            match figs
                .iter()
                .find(|f| f.file.trim_end_matches(".svg") == want)
            {
                Some(f) => f.render().map_err(Error::from),
                None => Err(Error::usage(format!(
                    "no chart `{want}`: the charts are {}",
                    names.join(", ")
                ))),
            }
        })
        .py()
    }

    /// Every file of `run --out DIR`, as (name, bytes).
    #[pyo3(signature = (centered=false))]
    fn files<'py>(&self, py: Python<'py>, centered: bool) -> PyResult<Bound<'py, PyList>> {
        let engine = self.engine.clone();
        let analysis = self.analysis.clone();
        let inputs = self.inputs.clone();
        let files = py
            .detach(move || {
                enginedyn_report::run_files(&engine.engine, &analysis, centered, &inputs)
                    .map_err(Error::from)
            })
            .py()?;
        let list = PyList::empty(py);
        for (name, bytes) in files {
            list.append((name, pyo3::types::PyBytes::new(py, &bytes)))?;
        }
        Ok(list)
    }
}

/// What a channel or column name (with its unit) reads as: the canonical
/// column and the factor from its unit, by the reader's own resolver.
/// How the readable tables head the summary key `key`: (label, unit,
/// SI-to-display scale, decimals); `KeyError` for a key that is not a
/// figure of the summary.
#[pyfunction]
fn shown(key: &str) -> PyResult<(&'static str, &'static str, f64, usize)> {
    enginedyn_pipeline::Summary::key(key)
        .and_then(enginedyn_report::key_heading)
        .ok_or_else(|| pyo3::exceptions::PyKeyError::new_err(key.to_string()))
}

#[pyfunction]
fn canonical(name: &str) -> Option<(&'static str, f64)> {
    enginedyn_ingest::canonical(name)
}

/// How the CLI prints a note: `"note"` (what was decided) or `"warning"`
/// (what may be wrong), by the one rule every front end uses.
#[pyfunction]
fn severity(note: &str) -> &'static str {
    enginedyn_pipeline::notes::severity(note).label()
}

/// Many items' notes (`(name, notes)` each) grouped by kind, one
/// `(severity, line)` a kind with its count and the range of its numbers:
/// the CLI's one grouping (`pipeline::notes::grouped`); `items` names the
/// items in the plural (`"files"`).
#[pyfunction]
fn grouped(per_item: Vec<(String, Vec<String>)>, items: &str) -> Vec<(&'static str, String)> {
    enginedyn_pipeline::notes::grouped(
        per_item
            .iter()
            .map(|(n, notes)| (n.as_str(), notes.as_slice())),
        items,
    )
    .into_iter()
    .map(|(s, line)| (s.label(), line))
    .collect()
}

/// `message` with the CLI's flags as the package's keywords (`--step` as
/// `step_deg=`), by the session's one table.
#[pyfunction]
fn in_keywords(message: &str) -> String {
    enginedyn_session::options::in_keywords(message)
}

/// The module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("EnginedynError", py.get_type::<EnginedynError>())?;
    m.add("DiagramError", py.get_type::<DiagramError>())?;
    m.add("EngineFileError", py.get_type::<EngineFileError>())?;
    m.add("UsageError", py.get_type::<UsageError>())?;
    m.add_class::<Engine>()?;
    m.add_class::<NativeSession>()?;
    m.add_class::<Run>()?;
    m.add_class::<NativeBatch>()?;
    m.add_function(wrap_pyfunction!(check_reader, m)?)?;
    m.add_function(wrap_pyfunction!(check_method, m)?)?;
    m.add_function(wrap_pyfunction!(canonical, m)?)?;
    m.add_function(wrap_pyfunction!(shown, m)?)?;
    m.add_function(wrap_pyfunction!(speeds, m)?)?;
    m.add_function(wrap_pyfunction!(shard, m)?)?;
    m.add_function(wrap_pyfunction!(list_plan, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(write_run_folder, m)?)?;
    m.add_function(wrap_pyfunction!(read_run_folder, m)?)?;
    m.add_function(wrap_pyfunction!(interrupt_all, m)?)?;
    m.add_function(wrap_pyfunction!(severity, m)?)?;
    m.add_function(wrap_pyfunction!(grouped, m)?)?;
    m.add_function(wrap_pyfunction!(in_keywords, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
