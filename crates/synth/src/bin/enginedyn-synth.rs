//! `enginedyn-synth`: writes an indicator-diagram CSV from the documented
//! cycle model of the `enginedyn-synth` crate. Deterministic: the same
//! flags give the same bytes, whatever the output path.
//!
//! ```text
//! enginedyn-synth --preset petrol --bore-mm 76 --stroke-mm 71 --lambda 0.26 \
//!     --cr 9.9 --rpm 4900 --step 0.5 --out data/vaz2108.csv
//! ```

use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
use enginedyn_synth::{
    BurnLaw, CombustionError, CycleModel, CycleSolution, Gas, Wiebe, indicated_work, peak_pressure,
    pressure_trace, write_csv,
};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const HELP: &str = "\
enginedyn-synth: a synthetic indicator diagram (CSV) from the single-zone cycle model

USAGE:
    enginedyn-synth [OPTIONS]

OPTIONS:
    --preset NAME     petrol (default), diesel or two-stroke: CycleModel::petrol_full_load /
                      diesel_full_load / petrol_two_stroke
    --bore-mm D       bore (petrol 76, diesel 84)
    --stroke-mm S     stroke, twice the crank radius (petrol 71, diesel 90)
    --lambda L        R/L, crank radius over rod length (petrol 0.26, diesel 0.3)
    --offset-mm E     piston pin offset (0)
    --cr EPS          compression ratio (petrol 9.9, diesel 17)
    --rpm N           speed written as `# rpm = N` (petrol 4900, diesel 4000)
    --step DEG        output step, dividing 720 (0.5)
    --heat-j Q        override the preset's heat released per cycle (J)
    --soc-deg A       override the preset's start of combustion (deg from firing TDC)
    --burn-deg B      override the preset's combustion duration (deg)
    --woschni K       wall heat transfer: Woschni's coefficient times K (0: none, the default)
    --blowby-mm2 A    blow-by through an equivalent orifice of A mm² (0: none, the default)
    --wall-k T        wall temperature with --woschni (400 K)
    --ivc-k T         gas temperature at IVC with --woschni or --blowby-mm2 (330 K)
    --out FILE        write FILE (whole or not at all); `-` or none: standard output
    -h, --help        this text

The CSV's comment lines record the command (without --out), the geometry,
every model parameter and the resulting IMEP and peak pressure. --heat-j 0 gives a
motored (fuel-cut) cycle; the losses take their time scale from --rpm.";

/// A bad command line (exit 2) or a failed write (exit 1).
enum Failure {
    Usage(String),
    Io(String),
}

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(m)) => {
            eprintln!("enginedyn-synth: {m}\n(see enginedyn-synth --help)");
            ExitCode::from(2)
        }
        Err(Failure::Io(m)) => {
            eprintln!("enginedyn-synth: {m}");
            ExitCode::from(1)
        }
    }
}

/// The flags as given (step one: raw, unchecked).
#[derive(Default)]
struct Flags {
    preset: Option<String>,
    bore_mm: Option<f64>,
    stroke_mm: Option<f64>,
    lambda: Option<f64>,
    offset_mm: Option<f64>,
    cr: Option<f64>,
    rpm: Option<f64>,
    step: Option<f64>,
    heat_j: Option<f64>,
    soc_deg: Option<f64>,
    burn_deg: Option<f64>,
    woschni: Option<f64>,
    blowby_mm2: Option<f64>,
    wall_k: Option<f64>,
    ivc_k: Option<f64>,
    out: Option<PathBuf>,
    help: bool,
}

fn parse(args: Vec<String>) -> Result<Flags, String> {
    const VALUED: [&str; 16] = [
        "--preset",
        "--out",
        "--bore-mm",
        "--stroke-mm",
        "--lambda",
        "--offset-mm",
        "--cr",
        "--rpm",
        "--step",
        "--heat-j",
        "--soc-deg",
        "--burn-deg",
        "--woschni",
        "--blowby-mm2",
        "--wall-k",
        "--ivc-k",
    ];
    let mut f = Flags::default();
    let mut it = args.into_iter();
    while let Some(arg) = it.next() {
        if arg == "-h" || arg == "--help" {
            f.help = true;
            continue;
        }
        let (name, inline) = match arg.split_once('=') {
            Some((n, v)) if n.starts_with("--") => (n.to_string(), Some(v.to_string())),
            _ => (arg.clone(), None),
        };
        if !VALUED.contains(&name.as_str()) {
            return Err(format!("unknown argument `{arg}`"));
        }
        let v = match inline {
            Some(v) => v,
            None => it.next().ok_or_else(|| format!("{name} needs a value"))?,
        };
        let n = &name;
        match name.as_str() {
            "--preset" => set(&mut f.preset, n, v)?,
            "--out" => set(&mut f.out, n, PathBuf::from(v))?,
            "--bore-mm" => set(&mut f.bore_mm, n, number(n, &v)?)?,
            "--stroke-mm" => set(&mut f.stroke_mm, n, number(n, &v)?)?,
            "--lambda" => set(&mut f.lambda, n, number(n, &v)?)?,
            "--offset-mm" => set(&mut f.offset_mm, n, number(n, &v)?)?,
            "--cr" => set(&mut f.cr, n, number(n, &v)?)?,
            "--rpm" => set(&mut f.rpm, n, number(n, &v)?)?,
            "--step" => set(&mut f.step, n, number(n, &v)?)?,
            "--heat-j" => set(&mut f.heat_j, n, number(n, &v)?)?,
            "--soc-deg" => set(&mut f.soc_deg, n, number(n, &v)?)?,
            "--woschni" => set(&mut f.woschni, n, number(n, &v)?)?,
            "--blowby-mm2" => set(&mut f.blowby_mm2, n, number(n, &v)?)?,
            "--wall-k" => set(&mut f.wall_k, n, number(n, &v)?)?,
            "--ivc-k" => set(&mut f.ivc_k, n, number(n, &v)?)?,
            _ => set(&mut f.burn_deg, n, number(n, &v)?)?,
        }
    }
    Ok(f)
}

fn set<T>(slot: &mut Option<T>, name: &str, value: T) -> Result<(), String> {
    if slot.replace(value).is_some() {
        return Err(format!("{name} given twice"));
    }
    Ok(())
}

fn number(name: &str, v: &str) -> Result<f64, String> {
    match v.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{name} {v}: expected a number")),
    }
}

/// Everything checked and ready (step two).
struct Job {
    preset: &'static str,
    bore_mm: f64,
    stroke_mm: f64,
    lambda: f64,
    offset_mm: f64,
    cr: f64,
    rpm: f64,
    step: f64,
    heat_j: Option<f64>,
    soc_deg: Option<f64>,
    burn_deg: Option<f64>,
    /// The loss flags as given, for the command line: woschni, blow-by
    /// (mm²), wall and IVC temperatures.
    losses: [Option<f64>; 4],
    cylinder: Cylinder,
    model: CycleModel,
}

fn job(f: &Flags) -> Result<Job, String> {
    // Preset defaults: model, bore, stroke, lambda, compression ratio, rpm.
    let (preset, mut model, bore, stroke, lambda, cr, rpm) = match f.preset.as_deref() {
        None | Some("petrol") => (
            "petrol",
            CycleModel::petrol_full_load(),
            76.0,
            71.0,
            0.26,
            9.9,
            4900.0,
        ),
        Some("diesel") => (
            "diesel",
            CycleModel::diesel_full_load(),
            84.0,
            90.0,
            0.3,
            17.0,
            4000.0,
        ),
        Some("two-stroke") => (
            "two-stroke",
            CycleModel::petrol_two_stroke(),
            73.5,
            78.0,
            0.27,
            7.5,
            4200.0,
        ),
        Some(other) => {
            return Err(format!(
                "--preset {other}: expected petrol, diesel or two-stroke"
            ));
        }
    };
    let bore_mm = f.bore_mm.unwrap_or(bore);
    let stroke_mm = f.stroke_mm.unwrap_or(stroke);
    let lambda = f.lambda.unwrap_or(lambda);
    let offset_mm = f.offset_mm.unwrap_or(0.0);
    let cr = f.cr.unwrap_or(cr);
    let rpm = f.rpm.unwrap_or(rpm);
    if !(lambda > 0.0) {
        return Err(format!("--lambda {lambda}: expected a positive number"));
    }
    if !(rpm > 0.0) {
        return Err(format!("--rpm {rpm}: expected a positive number"));
    }
    let r = stroke_mm / 2e3;
    let crank = CrankSlider::new(r, r / lambda, offset_mm / 1e3)
        .map_err(|e| format!("--stroke-mm/--lambda/--offset-mm: {e}"))?;
    let cylinder = Cylinder::new(Mechanism::CrankSlider(crank), bore_mm / 1e3, cr)
        .map_err(|e| format!("--bore-mm/--cr: {e}"))?;
    if let Some(q) = f.heat_j {
        model.heat_released_j = q;
    }
    if f.soc_deg.is_some() || f.burn_deg.is_some() {
        let w = *model.burn.first();
        let start = f.soc_deg.unwrap_or(w.start_deg());
        let duration = f.burn_deg.unwrap_or(w.duration_deg());
        let law = Wiebe::new(start, duration, w.a(), w.m()).map_err(|e| {
            let flag = match e {
                CombustionError::Range {
                    name: "duration_deg",
                    ..
                } => "--burn-deg",
                _ => "--soc-deg",
            };
            format!("{flag}: {e}")
        })?;
        model.burn = BurnLaw::single(law);
    }
    let l = &mut model.losses;
    l.woschni_scale = f.woschni.unwrap_or(0.0);
    l.blowby_area_m2 = f.blowby_mm2.unwrap_or(0.0) / 1e6;
    if let Some(t) = f.wall_k {
        l.wall_temperature_k = t;
    }
    if let Some(t) = f.ivc_k {
        l.ivc_temperature_k = t;
    }
    if l.any() {
        l.rpm = rpm;
    }
    model.check().map_err(|e| e.to_string())?;
    Ok(Job {
        preset,
        bore_mm,
        stroke_mm,
        lambda,
        offset_mm,
        cr,
        rpm,
        step: f.step.unwrap_or(0.5),
        heat_j: f.heat_j,
        soc_deg: f.soc_deg,
        burn_deg: f.burn_deg,
        losses: [f.woschni, f.blowby_mm2, f.wall_k, f.ivc_k],
        cylinder,
        model,
    })
}

impl Job {
    /// The command that regenerates this output (without `--out`).
    fn command(&self) -> String {
        let mut c = format!(
            "enginedyn-synth --preset {} --bore-mm {} --stroke-mm {} --lambda {}",
            self.preset, self.bore_mm, self.stroke_mm, self.lambda
        );
        if self.offset_mm.abs() > 0.0 {
            c += &format!(" --offset-mm {}", self.offset_mm);
        }
        c += &format!(" --cr {} --rpm {} --step {}", self.cr, self.rpm, self.step);
        if let Some(q) = self.heat_j {
            c += &format!(" --heat-j {q}");
        }
        if let Some(a) = self.soc_deg {
            c += &format!(" --soc-deg {a}");
        }
        if let Some(b) = self.burn_deg {
            c += &format!(" --burn-deg {b}");
        }
        for (flag, value) in ["--woschni", "--blowby-mm2", "--wall-k", "--ivc-k"]
            .iter()
            .zip(self.losses)
        {
            if let Some(v) = value {
                c += &format!(" {flag} {v}");
            }
        }
        c
    }
}

fn run(args: Vec<String>) -> Result<(), Failure> {
    let flags = parse(args).map_err(Failure::Usage)?;
    if flags.help {
        println!("{HELP}");
        return Ok(());
    }
    let job = job(&flags).map_err(Failure::Usage)?;
    let (cyl, m) = (&job.cylinder, &job.model);
    let trace = pressure_trace(cyl, m, job.step).map_err(|e| Failure::Usage(e.to_string()))?;
    let imep = indicated_work(cyl, &trace, m.cycle_deg()) / cyl.swept_volume() / 1e5;
    let (peak_deg, peak) = peak_pressure(&trace).unwrap_or((0.0, 0.0));
    // The presets' blended γ and single Wiebe (the only ones this tool makes).
    let (gamma_compression, gamma_expansion) = match m.gas {
        Gas::Blend {
            compression,
            expansion,
        } => (compression, expansion),
        Gas::Model(g) => (g.nominal(), g.nominal()),
    };
    let w = m.burn.first();
    let mut comments = vec![
        "synthetic indicator diagram, not measured: single-zone first-law cycle with a Wiebe heat release (crates/synth)".to_string(),
        format!("generated by: {} (add --out FILE to write a file)", job.command()),
        format!(
            "geometry: bore {} mm, stroke {} mm, lambda {}, pin offset {} mm, compression ratio {}, {}",
            job.bore_mm,
            job.stroke_mm,
            job.lambda,
            job.offset_mm,
            job.cr,
            if m.two_stroke { "two-stroke" } else { "four-stroke" }
        ),
        format!(
            "model: intake_pressure_pa = {}, exhaust_pressure_pa = {}, ivc_deg = {}, evo_deg = {}, gamma_compression = {}, gamma_expansion = {}",
            m.intake_pressure_pa,
            m.exhaust_pressure_pa,
            m.ivc_deg,
            m.evo_deg,
            gamma_compression,
            gamma_expansion
        ),
        format!(
            "model: heat_released_j = {}, soc_deg = {}, burn_duration_deg = {}, wiebe_a = {}, wiebe_m = {}, blowdown_deg = {}, two_stroke = {}",
            m.heat_released_j,
            w.start_deg(),
            w.duration_deg(),
            w.a(),
            w.m(),
            m.blowdown_deg,
            m.two_stroke
        ),
        format!(
            "result: IMEP {imep:.3} bar, peak {:.2} bar at {peak_deg:.1} deg after firing TDC (trapezoid on p dV/dphi, exact volume law)",
            peak / 1e5
        ),
    ];
    let l = &m.losses;
    if l.any() {
        let lost = CycleSolution::new(cyl, m)
            .map(|s| s.blowby_fraction())
            .unwrap_or(0.0);
        comments.insert(
            5,
            format!(
                "losses: Woschni wall heat transfer x {} (walls {} K), blow-by orifice {} mm2 to {} Pa, {} K at IVC, at {} rpm: {:.2} % of the trapped mass blown by",
                l.woschni_scale,
                l.wall_temperature_k,
                l.blowby_area_m2 * 1e6,
                l.crankcase_pressure_pa,
                l.ivc_temperature_k,
                l.rpm,
                100.0 * lost
            ),
        );
    }
    let lines: Vec<&str> = comments.iter().map(String::as_str).collect();
    let mut buf = Vec::new();
    write_csv(&mut buf, &trace, Some(job.rpm), &lines).map_err(|e| Failure::Io(e.to_string()))?;
    match flags.out.as_deref().filter(|p| *p != Path::new("-")) {
        Some(path) => {
            write_whole(path, &buf).map_err(|e| Failure::Io(format!("{}: {e}", path.display())))?;
            eprintln!(
                "{}: IMEP {imep:.3} bar, peak {:.2} bar at {peak_deg:.1}° after firing TDC",
                path.display(),
                peak / 1e5
            );
        }
        None => {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            if let Err(e) = out.write_all(&buf).and_then(|()| out.flush()) {
                // A closed pipe (`| head`) is no failure.
                if e.kind() != std::io::ErrorKind::BrokenPipe {
                    return Err(Failure::Io(format!("standard output: {e}")));
                }
            }
        }
    }
    Ok(())
}

/// Writes `bytes` to a temporary file beside `path`, then renames it over
/// `path`: the file appears whole or not at all.
fn write_whole(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other("not a file name"))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let result = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
