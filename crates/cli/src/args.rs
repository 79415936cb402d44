//! Flags as the user writes them (INTERFACE.md), before any checking.

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// Engine dynamics from indicator diagrams: kinematics, forces, torque by
/// firing order, journal torques, uniformity and flywheel, charts.
#[derive(Debug, Parser)]
#[command(name = "enginedyn", version, about, propagate_version = true)]
pub struct Cli {
    /// The command; none at all is `run` on the bundled example.
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// The whole pipeline for one operating point (no arguments: the bundled example).
    Run(RunArgs),
    /// Many diagrams, each its own operating point, one summary row each, in parallel.
    Batch(BatchArgs),
    /// One diagram over a range of speeds, charted against speed.
    Sweep(SweepArgs),
    /// Piston path, speed, acceleration and rod angle table.
    Kinematics(KinematicsArgs),
    /// The firing orders a crank admits (or every crank), ranked, with their criteria.
    FiringOrders(FiringOrdersArgs),
    /// Manufacturing and measurement tolerances: influences, stack-up, Monte Carlo check.
    Tolerance(ToleranceArgs),
    /// Each method's error against the most exact one and its run time, charted.
    Accuracy(AccuracyArgs),
    /// The crankshaft's torsional vibration: modes, Campbell diagram, forced response over speed.
    Torsion(TorsionArgs),
    /// Print a commented engine file (every key: unit, default, meaning) that runs as it is.
    Template(TemplateArgs),
    /// Write the diagram of the engine file's `[combustion]` burn law (a synthesised, not measured, CSV).
    Synth(SynthArgs),
    /// Check a campaign's Parquet parts (`batch --parquet DIR`) and write DIR/_manifest.json.
    Merge(MergeArgs),
    /// The engine design report: full-load line, map, flywheel, crank-train loads, torsion, firing orders, tolerances, in one HTML page.
    Report(ReportArgs),
}

/// `enginedyn report`.
#[derive(Debug, Clone, Args)]
pub struct ReportArgs {
    /// Engine file (TOML): with `[combustion]` the report covers the speed × load map; else its diagram's one operating point.
    #[arg(long, value_name = "FILE")]
    pub engine: PathBuf,
    /// Write report.html, its charts and tables/ into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// A measured diagram: the report at its one operating point (no map).
    #[arg(long, value_name = "FILE")]
    pub diagram: Option<PathBuf>,
    /// The map's speeds FROM:TO:STEP (rpm) [default: the full-load line's span, about 16 round steps].
    #[arg(long, value_name = "FROM:TO:STEP", allow_hyphen_values = true)]
    pub rpm: Option<String>,
    /// The map's loads FROM:TO:STEP in percent of the full-load line [default: 10:100:10].
    #[arg(long, value_name = "FROM:TO:STEP", allow_hyphen_values = true)]
    pub load: Option<String>,
    /// Also write the map as tables/map.parquet.
    #[arg(long)]
    pub parquet: bool,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
    #[command(flatten)]
    pub method: MethodArgs,
}

/// `enginedyn merge`.
#[derive(Debug, Clone, Args)]
pub struct MergeArgs {
    /// The campaign folder every shard wrote its parts into.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// The number of parts expected (N of `--shard I/N`) [default: from the part names].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub parts: Option<u64>,
}

/// `enginedyn template`: the layouts it writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TemplateLayoutArg {
    Inline,
    Vee,
    Boxer,
}

#[derive(Debug, Clone, Args)]
pub struct TemplateArgs {
    /// Number of cylinders (1 to 24; even for a vee or a boxer).
    #[arg(long, value_name = "N", default_value_t = 4, value_parser = clap::value_parser!(u8).range(1..=24))]
    pub cylinders: u8,
    /// Cylinder layout.
    #[arg(long, value_enum, default_value_t = TemplateLayoutArg::Inline)]
    pub layout: TemplateLayoutArg,
    /// Add the `[torsion]` section (the crankshaft's torsional chain).
    #[arg(long)]
    pub torsion: bool,
    #[command(flatten)]
    pub combustion: TemplateCombustionArgs,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum KinematicsArg {
    Exact,
    Series2,
    Series4,
    Series6,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RodModelArg {
    TwoMass,
    ThreeMass,
    Rigid,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum InterpArg {
    Auto,
    Linear,
    Spline,
    Pchip,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegrationArg {
    Trapezoid,
    Simpson,
}

/// `--cylinder-axis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CylinderAxisArg {
    /// Every cylinder over cylinder 1's crank angle.
    Shared,
    /// Each cylinder over its own angle from its own firing TDC.
    Own,
}

/// Where p–V data starts (`--pv-start`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum PvStart {
    /// At firing TDC.
    #[default]
    Tdc,
    /// At the BDC before firing TDC.
    Bdc,
}

/// How angles are written (`--angles`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum Angles {
    /// [0, cycle) from firing TDC.
    #[default]
    Cycle,
    /// [−cycle/2, cycle/2), as indicating software shows them.
    Centered,
}

/// `--peg polytropic[=N]`: the offset fitted so that p V^N is constant on
/// compression.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PegArg {
    /// The polytropic exponent N (1 < N < 2).
    Polytropic(f64),
}

// Every bound and its message lives in `enginedyn_session::options`, for
// the flags here and the Python package's keyword arguments alike.
use enginedyn_session::options::{self as bounds, MAX_JOBS, MAX_SAMPLES};

fn parse_rpm(s: &str) -> Result<f64, String> {
    bounds::read_rpm(s)
}

fn parse_step(s: &str) -> Result<f64, String> {
    bounds::STEP.read(s)
}

fn parse_tdc(s: &str) -> Result<f64, String> {
    bounds::TDC_DEG.read(s)
}

fn parse_peg_bar(s: &str) -> Result<f64, String> {
    bounds::PEG_BAR.read(s)
}

fn parse_peg(s: &str) -> Result<PegArg, String> {
    bounds::read_peg(s).map(PegArg::Polytropic)
}

/// How the computation is done (INTERFACE.md's method options). Each is
/// `None` unless given, so that `--tolerance` can keep the ones given.
#[derive(Debug, Clone, Args)]
pub struct MethodArgs {
    /// Grid step of the crank-angle grid (deg, 0.001 to 10); must divide the cycle [default: 0.1].
    #[arg(long, value_name = "DEG", value_parser = parse_step)]
    pub step: Option<f64>,
    /// Piston kinematics [default: exact].
    #[arg(long, value_enum)]
    pub kinematics: Option<KinematicsArg>,
    /// Connecting-rod mass model [default: the engine file's `rod_model`].
    #[arg(long, value_enum)]
    pub rod_model: Option<RodModelArg>,
    /// Interpolation onto the grid (`auto`: linear on grid data, else the
    /// periodic spline unless it overshoots by > 0.5 % of the peak, then
    /// pchip) [default: auto].
    #[arg(long, value_enum)]
    pub interp: Option<InterpArg>,
    /// Integration rule for means and the running integral E(φ) [default: trapezoid].
    #[arg(long, value_enum)]
    pub integration: Option<IntegrationArg>,
    /// The combustion analysis.
    #[command(flatten)]
    pub burn: BurnArgs,
}

// ---- the combustion analysis' flags (INTERFACE.md "Combustion") ----

/// How each fired cycle's combustion is analysed; parsed and bounded by
/// `enginedyn_session::burn`.
#[derive(Debug, Clone, Args)]
#[command(next_help_heading = "Combustion analysis")]
pub struct BurnArgs {
    /// Burn levels to report, in percent burnt (whole numbers 1-99) [default: 5,10,50,90].
    #[arg(long, value_name = "K,K,...", value_parser = enginedyn_session::burn::Levels::parse)]
    pub burn_points: Option<enginedyn_session::burn::Levels>,
    /// Window for SOC and EOC (deg from firing TDC) [default: -90:120].
    #[arg(long, value_name = "A:B", allow_hyphen_values = true, value_parser = enginedyn_session::burn::parse_window)]
    pub burn_window: Option<(f64, f64)>,
    /// Ratio of specific heats: a constant, or `brunt` for γ(T) [default: 1.32].
    #[arg(long, value_name = "G|brunt", value_parser = enginedyn_session::burn::parse_gamma)]
    pub gamma: Option<enginedyn_session::burn::Gamma>,
    /// Smoothing before dp/dφ and the SOC/EOC search: Savitzky-Golay cubic over DEG, or off [default: SG:2].
    #[arg(long, value_name = "SG:DEG|off", value_parser = enginedyn_session::burn::parse_smooth)]
    pub smooth: Option<enginedyn_session::burn::Smoothing>,
    /// With --gamma brunt or --wall-heat: charge temperature at intake valve closing (K, 200 to 1000) [default: 320].
    #[arg(long, value_name = "K", value_parser = enginedyn_session::burn::parse_intake_temp_k)]
    pub intake_temp_k: Option<f64>,
    /// With --gamma brunt or --wall-heat: intake valve closing (deg from firing TDC, -270 to 0) [default: -140].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = enginedyn_session::burn::parse_ivc_deg)]
    pub ivc_deg: Option<f64>,
    /// Heat lost to the walls, for the gross heat release and its burn points: woschni, hohenberg or off [default: off].
    #[arg(long, value_name = "MODEL", value_parser = enginedyn_session::burn::parse_wall_heat)]
    pub wall_heat: Option<enginedyn_session::burn::WallSetting>,
    /// With --wall-heat: mean wall temperature (K, 250 to 1000) [default: 450].
    #[arg(long, value_name = "K", value_parser = enginedyn_session::burn::parse_wall_temp_k)]
    pub wall_temp_k: Option<f64>,
    /// Measure knock: MAPO and IMPO of each cycle's band-passed pressure (an FFT a cycle; also on with any --knock-… value).
    #[arg(long)]
    pub knock: bool,
    /// Knock band, kHz [default: 4:20].
    #[arg(long, value_name = "LO:HI", value_parser = enginedyn_session::burn::parse_knock_band)]
    pub knock_band: Option<(f64, f64)>,
    /// Knock window (deg from firing TDC) [default: -10:70].
    #[arg(long, value_name = "A:B", allow_hyphen_values = true, value_parser = enginedyn_session::burn::parse_knock_window)]
    pub knock_window: Option<(f64, f64)>,
    /// A cycle knocks when its MAPO exceeds this (bar) [default: 1.0].
    #[arg(long, value_name = "BAR", value_parser = enginedyn_session::burn::parse_knock_threshold)]
    pub knock_threshold: Option<f64>,
    /// No combustion analysis (benches: what it costs).
    #[arg(long, hide = true)]
    pub no_burn: bool,
}

impl BurnArgs {
    /// The options as given.
    pub fn method(&self) -> enginedyn_session::burn::BurnMethod {
        enginedyn_session::burn::BurnMethod {
            levels: self.burn_points,
            window_deg: self.burn_window,
            gamma: self.gamma,
            smooth: self.smooth,
            intake_temp_k: self.intake_temp_k,
            ivc_deg: self.ivc_deg,
            wall_heat: self.wall_heat,
            wall_temp_k: self.wall_temp_k,
            knock: self.knock,
            knock_band_hz: self.knock_band,
            knock_window_deg: self.knock_window,
            knock_threshold_pa: self.knock_threshold,
            off: self.no_burn,
        }
    }
}

// ---- end of the combustion analysis' flags ----

/// How the diagram file is read.
#[derive(Debug, Clone, Args)]
pub struct DiagramArgs {
    /// Per-cylinder traces over cylinder 1's crank angle (`shared`) or each
    /// over its own from its firing TDC (`own`) [default: from the peaks].
    #[arg(long, value_enum, value_name = "shared|own")]
    pub cylinder_axis: Option<CylinderAxisArg>,
    /// The file's angle value that is firing TDC.
    #[arg(long, value_name = "X", allow_hyphen_values = true, value_parser = parse_tdc)]
    pub tdc_deg: Option<f64>,
    /// Pressures are gauge (relative to 1.01325 bar).
    #[arg(long)]
    pub gauge: bool,
    /// Column names for a file without a header (or replacing it); `_` skips a column.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub columns: Option<Vec<String>>,
    /// Peg each cycle so its mean pressure ±5° around intake BDC is P bar absolute.
    #[arg(long, value_name = "P", value_parser = parse_peg_bar, allow_hyphen_values = true)]
    pub peg_bar: Option<f64>,
    /// Peg each cycle so p V^N is constant on compression (N = 1.32 by default).
    #[arg(long, value_name = "polytropic[=N]", value_parser = parse_peg, conflicts_with = "peg_bar")]
    pub peg: Option<PegArg>,
    /// Where p–V data starts: at firing TDC or at the BDC before it.
    #[arg(long, value_enum, default_value = "tdc")]
    pub pv_start: PvStart,
    /// Skip N lines at the top of the file (a preamble; titles and banners
    /// above a header are skipped without it).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=bounds::MAX_SKIP_LINES as i64))]
    pub skip_lines: Option<u32>,
    /// The sheet of a spreadsheet (.xlsx, .xls, .ods): its name or its number from 1.
    #[arg(long, value_name = "NAME|N")]
    pub sheet: Option<String>,
    /// The channel group of an MDF4 file (.mf4), numbered from 1 [default: the first that holds a pressure].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=bounds::MAX_GROUP as i64))]
    pub group: Option<u32>,
    /// The widest gap (deg) bridged in a single digitised cycle [default: 30].
    #[arg(long, value_name = "DEG", value_parser = parse_max_gap)]
    pub max_gap: Option<f64>,
    /// A time record's firing TDC time T in seconds (with --rpm, when it has no tdc column).
    #[arg(long, value_name = "T", allow_hyphen_values = true, value_parser = parse_tdc_time)]
    pub tdc_time: Option<f64>,
    /// A charge amplifier's gain (bar per volt) for a `pressure_v` column.
    #[arg(long, value_name = "BAR_PER_V", value_parser = parse_gain)]
    pub gain: Option<f64>,
    /// A time record's `encoder` column gives N pulses a revolution (1 to 100,000).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=bounds::MAX_ENCODER_PPR as i64))]
    pub encoder_ppr: Option<u32>,
    /// A time record's `wheel` column is a tooth wheel T-M: 60-2, 36-1, 36-2 or 58x.
    #[arg(long, value_name = "T-M", value_parser = enginedyn_ingest::Wheel::parse)]
    pub wheel: Option<enginedyn_ingest::Wheel>,
    /// The angle (deg) from the wheel's first tooth after the gap to cylinder 1's TDC.
    #[arg(long, value_name = "A", allow_hyphen_values = true, value_parser = parse_wheel_tdc)]
    pub wheel_tdc_deg: Option<f64>,
    /// Read the trace as the cylinder's pressure without the checks that
    /// assume a compressing engine (a steam engine, a compressor, a
    /// textbook problem): the compression bound and the peak-angle rule.
    #[arg(long)]
    pub no_compression_check: bool,
    /// Replace each glitch (a lone sample off the cubic through its
    /// neighbours, two each side, by more than 10 bar and 20 % of the
    /// cycle's peak) by that cubic; without it each is a warning.
    #[arg(long)]
    pub despike: bool,
    /// A pressure-only record sampled on the crank angle: row k lies at k
    /// times DEG (--tdc-deg places firing TDC on that axis).
    #[arg(long, value_name = "DEG", value_parser = parse_angle_step)]
    pub angle_step: Option<f64>,
}

fn parse_shard(s: &str) -> Result<enginedyn_session::batch::Shard, String> {
    enginedyn_session::batch::Shard::read(s)
}

fn parse_max_gap(s: &str) -> Result<f64, String> {
    bounds::MAX_GAP.read(s)
}

fn parse_tdc_time(s: &str) -> Result<f64, String> {
    bounds::TDC_TIME.read(s)
}

fn parse_wheel_tdc(s: &str) -> Result<f64, String> {
    bounds::WHEEL_TDC_DEG.read(s)
}

fn parse_angle_step(s: &str) -> Result<f64, String> {
    bounds::ANGLE_STEP.read(s)
}

fn parse_gain(s: &str) -> Result<f64, String> {
    bounds::GAIN.read(s)
}

impl DiagramArgs {
    /// The reader options, with the speed flag of the command (if it has one).
    pub fn reader(&self, rpm: Option<f64>) -> enginedyn_session::Reader {
        enginedyn_session::Reader {
            cylinder_axis: self.cylinder_axis.map(|a| match a {
                CylinderAxisArg::Shared => enginedyn_ingest::CylinderAxis::Shared,
                CylinderAxisArg::Own => enginedyn_ingest::CylinderAxis::Own,
            }),
            tdc_deg: self.tdc_deg,
            gauge: self.gauge,
            columns: self.columns.clone(),
            peg_bar: self.peg_bar,
            peg_polytropic: self.peg.map(|PegArg::Polytropic(n)| n),
            pv_start_bdc: self.pv_start == PvStart::Bdc,
            skip_lines: self.skip_lines,
            sheet: self.sheet.clone(),
            max_gap_deg: self.max_gap,
            tdc_time: self.tdc_time,
            gain_bar_per_v: self.gain,
            rpm,
            group: self.group,
            encoder_ppr: self.encoder_ppr,
            wheel: self.wheel,
            wheel_tdc_deg: self.wheel_tdc_deg,
            no_compression_check: self.no_compression_check,
            despike: self.despike,
            angle_step_deg: self.angle_step,
        }
    }
}

#[derive(Debug, Clone, Args)]
pub struct RunArgs {
    /// Engine file (TOML) [default: the bundled VAZ-2108 type example].
    #[arg(long, value_name = "FILE")]
    pub engine: Option<PathBuf>,
    /// Indicator diagram (CSV); several: one per cylinder, in order 1..z.
    #[arg(long, value_name = "FILE", num_args = 1..)]
    pub diagram: Vec<PathBuf>,
    /// Turning-moment diagram (CSV) instead of pressure.
    #[arg(long, value_name = "FILE", conflicts_with = "diagram")]
    pub torque: Option<PathBuf>,
    /// Engine speed (rpm); overrides the diagram's `# rpm` line and the engine file.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_rpm)]
    pub rpm: Option<f64>,
    /// Write summary.json, curves.csv, harmonics.csv and charts into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON only.
    #[arg(long)]
    pub json: bool,
    /// Pick the cheapest method setting whose estimated relative error is below REL.
    #[arg(long, value_name = "REL")]
    pub tolerance: Option<f64>,
    /// Angles in the output: `cycle` [0, cycle) or `centered` [-cycle/2, cycle/2).
    #[arg(long, value_enum, default_value = "cycle")]
    pub angles: Angles,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
    #[command(flatten)]
    pub method: MethodArgs,
}

impl RunArgs {
    /// `run` with no flags at all: the bundled example with every default.
    pub fn bare() -> Self {
        match Cli::parse_from(["enginedyn", "run"]).command {
            Some(Command::Run(a)) => a,
            _ => unreachable!("`enginedyn run` parses as the run command"),
        }
    }
}

#[derive(Debug, Clone, Args)]
pub struct KinematicsArgs {
    /// Engine file (TOML).
    #[arg(long, value_name = "FILE")]
    pub engine: PathBuf,
    /// Angle step of the table (deg, 0.001 to 10) [default: 30 for the printed table, 0.1 for --csv and --out].
    #[arg(long, value_name = "DEG", value_parser = parse_step)]
    pub step: Option<f64>,
    /// Piston kinematics.
    #[arg(long, value_enum, default_value = "exact")]
    pub kinematics: KinematicsArg,
    /// Engine speed (rpm) [default: the engine file's].
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_rpm)]
    pub rpm: Option<f64>,
    /// Write kinematics.csv and kinematics.svg into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the table as CSV.
    #[arg(long)]
    pub csv: bool,
}

impl KinematicsArg {
    pub fn model(self) -> enginedyn_kinematics::Model {
        use enginedyn_kinematics::Model;
        match self {
            KinematicsArg::Exact => Model::Exact,
            KinematicsArg::Series2 => Model::Series2,
            KinematicsArg::Series4 => Model::Series4,
            KinematicsArg::Series6 => Model::Series6,
        }
    }
}

impl RodModelArg {
    pub fn model(self) -> enginedyn_engine::RodModel {
        use enginedyn_engine::RodModel;
        match self {
            RodModelArg::TwoMass => RodModel::TwoMass,
            RodModelArg::ThreeMass => RodModel::ThreeMass,
            RodModelArg::Rigid => RodModel::Rigid,
        }
    }
}

impl InterpArg {
    pub fn interp(self) -> enginedyn_ingest::Interp {
        use enginedyn_ingest::Interp;
        match self {
            InterpArg::Auto => Interp::Auto,
            InterpArg::Linear => Interp::Linear,
            InterpArg::Spline => Interp::Spline,
            InterpArg::Pchip => Interp::Pchip,
        }
    }
}

impl IntegrationArg {
    pub fn rule(self) -> enginedyn_numerics::integrate::Rule {
        use enginedyn_numerics::integrate::Rule;
        match self {
            IntegrationArg::Trapezoid => Rule::Trapezoid,
            IntegrationArg::Simpson => Rule::Simpson,
        }
    }
}

impl MethodArgs {
    /// The method options as given (`tolerance`: the command's `--tolerance`).
    pub fn method(&self, tolerance: Option<f64>) -> enginedyn_session::Method {
        enginedyn_session::Method {
            step_deg: self.step,
            kinematics: self.kinematics.map(KinematicsArg::model),
            rod_model: self.rod_model.map(RodModelArg::model),
            interp: self.interp.map(InterpArg::interp),
            integration: self.integration.map(IntegrationArg::rule),
            tolerance,
            burn: self.burn.method(),
        }
    }
}

#[derive(Debug, Clone, Args)]
pub struct BatchArgs {
    /// Engine file (TOML).
    #[arg(long, value_name = "FILE")]
    pub engine: PathBuf,
    /// Diagram files, folders (every .csv, .txt, .dat, .tsv, .xlsx, .xls, .ods, .mf4 inside) or glob patterns.
    #[arg(value_name = "DIAGRAM", required_unless_present = "files_from")]
    pub diagrams: Vec<String>,
    /// Also the diagram paths listed in LIST, one a line (a line loses only its line end; blank and `#` lines skipped; relative to LIST's folder; a file named twice is analysed once).
    #[arg(long, value_name = "LIST")]
    pub files_from: Option<PathBuf>,
    /// Only the I-th of N slices of the files, sorted bytewise by canonical path (file k goes to slice k mod N; 0 ≤ I < N ≤ 100000).
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub shard: Option<enginedyn_session::batch::Shard>,
    /// Write the summary and cycles tables as Parquet parts: DIR/summary/part-IIIII-of-NNNNN.parquet, DIR/cycles/….
    #[arg(long, value_name = "DIR")]
    pub parquet: Option<PathBuf>,
    /// With --parquet: the traces table too (DIR/traces/…), the cycle-averaged pressure on the grid.
    #[arg(long, requires = "parquet")]
    pub traces: bool,
    /// With --parquet: replace the parts of another campaign in DIR (enginedyn's own parts only).
    #[arg(long, requires = "parquet")]
    pub replace: bool,
    /// For job logs (--parquet runs, Slurm): one line on standard output (files read, failed, where written), never the table; on standard error only the errors (one a file) and the warnings grouped by kind; no progress bar, no notes.
    #[arg(long, conflicts_with_all = ["json", "csv"])]
    pub quiet: bool,
    /// Write summary.csv (and with --detail one run folder per diagram) into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Worker threads, 1 to 256 [default: one per core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=MAX_JOBS as u64))]
    pub jobs: Option<u64>,
    /// One run folder per diagram, DIR/NNNN_STEM/, and index.html.
    #[arg(long, requires = "out")]
    pub detail: bool,
    /// Angles in the run folders (--detail): `cycle` [0, cycle) or `centered` [-cycle/2, cycle/2).
    #[arg(long, value_enum, default_value = "cycle")]
    pub angles: Angles,
    /// Without --out: print summary.csv instead of the readable table.
    #[arg(long, conflicts_with = "out")]
    pub csv: bool,
    /// Print a JSON array of the summary.json objects (each with `file` and `error`) on standard output.
    #[arg(long, conflicts_with = "csv")]
    pub json: bool,
    /// Benchmarks only: read and check every file, compute nothing (the parse floor).
    #[arg(long, hide = true)]
    pub parse_only: bool,
    /// Benchmarks only: print to stderr the time spent after parsing (grid,
    /// analysis, summary row), summed over every file and thread (not
    /// measured with --tolerance, which reads each file whole first).
    #[arg(long, hide = true)]
    pub stage_times: bool,
    /// Pick the cheapest method setting whose estimated relative error is below REL.
    #[arg(long, value_name = "REL")]
    pub tolerance: Option<f64>,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
    #[command(flatten)]
    pub method: MethodArgs,
}

#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    /// Engine file (TOML).
    #[arg(long, value_name = "FILE")]
    pub engine: PathBuf,
    /// Indicator diagram [default: the engine file's `diagram`].
    #[arg(long, value_name = "FILE")]
    pub diagram: Option<PathBuf>,
    /// Speeds FROM:TO:STEP (rpm); TO is included when it falls on the step; at most 10,000 speeds (with --imep, 10,000 points: speeds × loads).
    #[arg(long, value_name = "FROM:TO:STEP", allow_hyphen_values = true)]
    pub rpm: String,
    /// Write sweep.csv and sweep.svg into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Without --out: print sweep.csv instead of the readable table.
    #[arg(long, conflicts_with = "out")]
    pub csv: bool,
    /// Print a JSON array of the per-speed summary.json objects on standard output.
    #[arg(long, conflicts_with = "csv")]
    pub json: bool,
    #[command(flatten)]
    pub map: SweepMapArgs,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
    #[command(flatten)]
    pub method: MethodArgs,
}

#[derive(Debug, Clone, Args)]
pub struct TorsionArgs {
    /// Engine file (TOML) with a `[torsion]` section.
    #[arg(long, value_name = "FILE")]
    pub engine: PathBuf,
    /// Indicator diagram [default: the engine file's `diagram`].
    #[arg(long, value_name = "FILE")]
    pub diagram: Option<PathBuf>,
    /// Speeds FROM:TO:STEP (rpm) [default: 20 % to 120 % of operating.rpm, 50 speeds].
    #[arg(long, value_name = "FROM:TO:STEP", allow_hyphen_values = true)]
    pub rpm: Option<String>,
    /// Write modes.csv, torsion.csv, torsion.json, campbell.svg and torsion.svg into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print torsion.json on standard output.
    #[arg(long)]
    pub json: bool,
    /// Also write chain.json (the chain and its excitation, for benches/torsion_compare.py).
    #[arg(long, hide = true)]
    pub chain: bool,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
    #[command(flatten)]
    pub method: MethodArgs,
}

#[derive(Debug, Clone, Args)]
pub struct FiringOrdersArgs {
    #[command(flatten)]
    pub input: StudyInput,
    /// Every crank arrangement for the cylinder count, each with its orders.
    #[arg(long)]
    pub all_cranks: bool,
    /// Score weights, e.g. `intervals=1,neighbours=1,journal=1,balance=1`.
    #[arg(long, value_name = "LIST")]
    pub weights: Option<String>,
    /// Print the result as JSON only.
    #[arg(long)]
    pub json: bool,
    /// Write firing_orders.csv and crank_end_view.svg into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
    #[command(flatten)]
    pub method: MethodArgs,
}

#[derive(Debug, Clone, Args)]
pub struct ToleranceArgs {
    #[command(flatten)]
    pub input: StudyInput,
    /// Monte Carlo samples over the tolerance box (up to 10^7).
    #[arg(long, value_name = "N", default_value_t = 10000, value_parser = clap::value_parser!(u64).range(0..=MAX_SAMPLES))]
    pub samples: u64,
    /// Seed of the Monte Carlo sampler (reproducible).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Write tolerance.csv, tolerance.json and tolerance.svg into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
    #[command(flatten)]
    pub method: MethodArgs,
}

#[derive(Debug, Clone, Args)]
pub struct AccuracyArgs {
    #[command(flatten)]
    pub input: StudyInput,
    /// Write accuracy.csv and accuracy.svg into DIR.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub diagram_args: DiagramArgs,
}

/// The engine, diagram and speed a study reads.
#[derive(Debug, Clone, Args)]
pub struct StudyInput {
    /// Engine file (TOML).
    #[arg(long, value_name = "FILE")]
    pub engine: PathBuf,
    /// Indicator diagram [default: the engine file's `diagram`].
    #[arg(long, value_name = "FILE")]
    pub diagram: Option<PathBuf>,
    /// Engine speed (rpm); overrides the diagram's `# rpm` line and the engine file.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_rpm)]
    pub rpm: Option<f64>,
}

// ---- synthesis for design (issue 35, section 3): `synth`, `sweep --imep`,
// `template --combustion` ----

fn parse_imep(s: &str) -> Result<f64, String> {
    bounds::IMEP_BAR.read(s)
}

/// `enginedyn synth`.
#[derive(Debug, Clone, Args)]
pub struct SynthArgs {
    /// Engine file (TOML) with a `[combustion]` section.
    #[arg(long, value_name = "FILE")]
    pub engine: PathBuf,
    /// Engine speed (rpm) for the `# rpm` line [default: the engine file's operating.rpm].
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_rpm)]
    pub rpm: Option<f64>,
    /// Net IMEP to meet (bar); stands for `[combustion]`'s imep_bar or heat_released_j.
    #[arg(long, value_name = "X", allow_hyphen_values = true, value_parser = parse_imep)]
    pub imep: Option<f64>,
    /// Step of the rows (deg), dividing the cycle [default: 0.1].
    #[arg(long, value_name = "DEG", value_parser = parse_step)]
    pub step: Option<f64>,
    /// The diagram file to write (`-`: standard output).
    #[arg(long, value_name = "P.csv")]
    pub out: PathBuf,
}

/// `sweep --imep` or `--load`: a speed × load map from the engine file's `[combustion]`.
#[derive(Debug, Clone, Args)]
pub struct SweepMapArgs {
    /// Loads FROM:TO:STEP (net IMEP, bar): a speed × load map synthesised from `[combustion]`; at most 10,000 points (speeds × loads).
    #[arg(long, value_name = "FROM:TO:STEP", conflicts_with_all = ["diagram", "load"])]
    pub imep: Option<String>,
    /// Loads FROM:TO:STEP in percent of the full-load line (`[combustion.full_load]`) at each speed: a speed × load map; the highest load's row names the rated-power and peak-torque points.
    #[arg(long, value_name = "FROM:TO:STEP", conflicts_with = "diagram")]
    pub load: Option<String>,
    /// With --imep or --load: also write the map as DIR/map.parquet (`map/1`: the summary's columns, then imep_target_bar, load_pct and the flywheel's sizing point).
    #[arg(long, value_name = "DIR")]
    pub parquet: Option<std::path::PathBuf>,
}

/// `template --combustion`.
#[derive(Debug, Clone, Args)]
pub struct TemplateCombustionArgs {
    /// Add a commented `[combustion]` section (a burn law for `enginedyn synth`).
    #[arg(long, value_enum, value_name = "KIND")]
    pub combustion: Option<CombustionArg>,
}

/// `template --combustion`'s burn laws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CombustionArg {
    Petrol,
    Diesel,
}
// ---- end synthesis for design ----
