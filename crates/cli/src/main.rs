//! The `enginedyn` command line: parses flags, reads files, calls the
//! pipeline, prints and writes results. Errors become exit codes: 1 for a
//! bad diagram or torque file, 2 for a bad command line or engine file.

mod accuracy;
mod args;
mod batch;
mod firing;
mod kinematics;
mod merge;
mod report;
mod run;
mod sweep_map;
mod synth;
mod template;
mod tolerance;
mod torsion;

use clap::Parser;
use std::process::ExitCode;

/// An error on its way to the user: the library's error, which carries
/// its class (`enginedyn_session::Class`); `main` maps the class to the
/// exit code.
pub use enginedyn_session::Error as Failure;

/// A number as people write it in a message: up to six significant
/// digits, no trailing zeros, no exponent between 1e-4 and 1e9 (`4900`,
/// `0.086`, `1.5e-7`).
pub fn human(x: f64) -> String {
    enginedyn_numerics::format::human(x)
}

/// A value from the user's input as a message quotes it
/// (`numerics::format::quote`).
pub fn quote(s: &str) -> String {
    enginedyn_numerics::format::quote(s)
}

/// Says a note on standard error, once per command: `note:` for what was
/// decided or assumed, `warning:` for what may be wrong
/// (`enginedyn_pipeline::notes::severity`, the one home of that choice).
/// `about` names the file a batch note is about.
pub fn say(about: Option<&str>, note: &str) {
    use std::collections::HashSet;
    use std::sync::{Mutex, OnceLock};
    static SAID: OnceLock<Mutex<HashSet<String>>> = OnceLock::new();
    let line = match about {
        Some(f) => format!("{f}: {note}"),
        None => note.to_string(),
    };
    if let Ok(mut said) = SAID.get_or_init(Mutex::default).lock()
        && !said.insert(line.clone())
    {
        return;
    }
    let label = enginedyn_pipeline::notes::severity(note).label();
    eprintln!("{label}: {line}");
}

/// [`say`] for each of `notes`.
pub fn say_all<'a>(notes: impl IntoIterator<Item = &'a String>) {
    for n in notes {
        say(None, n);
    }
}

/// Says many items' notes (a batch's files, a sweep's points: `(name,
/// notes)`, `items` their plural) grouped by kind, one line a kind
/// (`enginedyn_pipeline::notes::grouped`, the one grouping); with
/// `warnings_only` (`--quiet`) the notes that only say what was decided are
/// left out.
pub fn say_grouped<'a>(
    per_item: impl IntoIterator<Item = (&'a str, &'a [String])>,
    items: &str,
    warnings_only: bool,
) {
    use enginedyn_pipeline::notes::{Severity, grouped};
    for (severity, line) in grouped(per_item, items) {
        if !warnings_only || severity == Severity::Warning {
            eprintln!("{}: {line}", severity.label());
        }
    }
}

/// Writes to standard output; a closed pipe (`enginedyn run | head`) ends the
/// program quietly instead of panicking.
pub fn emit(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

/// Opens `--out DIR` (when given) before a command's work, checked for the
/// `files` it will write (`report::OutDir::open_for`): something in the way
/// is refused (exit 2) before anything is computed or written.
/// `command` names the writer in the folder's manifest: a rerun of it
/// removes its own stale outputs, never another command's.
pub fn open_out(
    dir: Option<&std::path::Path>,
    files: &[&str],
    command: &str,
) -> Result<Option<enginedyn_report::OutDir>, Failure> {
    Ok(dir
        .map(|d| {
            enginedyn_report::OutDir::open_for(d, files, &[] as &[&str])
                .map(|o| o.for_command(command))
        })
        .transpose()?)
}

/// Writes an output folder (each file whole or not at all) and, unless the
/// standard output carries JSON, says so.
pub fn write_out(
    dir: &std::path::Path,
    files: &[(String, Vec<u8>)],
    quiet: bool,
) -> Result<(), Failure> {
    for note in enginedyn_report::write_run(dir, files)? {
        say(None, &note);
    }
    if !quiet {
        emit(&format!(
            "wrote {} files to {}\n",
            files.len(),
            dir.display()
        ));
    }
    Ok(())
}

/// [`write_out`] into a folder already open ([`open_out`]).
pub fn write_out_to(
    out: &enginedyn_report::OutDir,
    files: &[(String, Vec<u8>)],
    quiet: bool,
) -> Result<(), Failure> {
    for note in out.write(files)? {
        say(None, &note);
    }
    if !quiet {
        emit(&format!(
            "wrote {} files to {}\n",
            files.len(),
            out.path().display()
        ));
    }
    Ok(())
}

/// glibc gives the top of the heap back to the system as soon as more than
/// 128 KiB of it is free, and every analysis frees a few MB of curves: the
/// next file then faults all those pages in again (an ad-hoc profile, not
/// in the tree, put that at half of `analyse` in a batch; criterion's loop
/// does not trim, so its benches cannot show it). Keeping up to 64 MiB
/// free for reuse costs no memory growth across files (each reuses what the
/// previous one freed).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[allow(unsafe_code)]
fn keep_freed_memory() {
    // SAFETY: mallopt only sets a malloc tuning parameter; it is called
    // first thing in `main`, before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}

fn main() -> ExitCode {
    keep_freed_memory();
    let cli = args::Cli::parse();
    let command = cli.command.unwrap_or_else(|| {
        // `enginedyn` alone is `enginedyn run`: the bundled example.
        eprintln!(
            "enginedyn: no command given, so running the bundled example (`enginedyn run`); `enginedyn --help` lists the commands"
        );
        args::Command::Run(args::RunArgs::bare())
    });
    let result = match command {
        args::Command::Run(a) => run::run(&a),
        args::Command::Batch(a) => batch::run(&a),
        args::Command::Sweep(a) if a.map.imep.is_some() || a.map.load.is_some() => {
            sweep_map::run(&a)
        }
        args::Command::Sweep(a) if a.map.parquet.is_some() => Err(Failure::usage(
            "--parquet writes a speed × load map's table: give --imep or --load".to_string(),
        )),
        args::Command::Sweep(a) => batch::sweep(&a),
        args::Command::Kinematics(a) => kinematics::run(&a),
        args::Command::FiringOrders(a) => firing::run(&a),
        args::Command::Tolerance(a) => tolerance::run(&a),
        args::Command::Accuracy(a) => accuracy::run(&a),
        args::Command::Torsion(a) => torsion::run(&a),
        args::Command::Template(a) => template::run(&a),
        args::Command::Synth(a) => synth::run(&a),
        args::Command::Merge(a) => merge::run(&a),
        args::Command::Report(a) => report::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {f}");
            ExitCode::from(f.exit_code())
        }
    }
}
