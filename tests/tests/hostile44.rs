//! Issue 44, the fourth hostile round: nothing hangs (a device or a FIFO
//! in a `batch --parquet` list), nothing of the user's is overwritten
//! (`synth --out` over a measured file), and flags that do not fit
//! together, or an engine file's `[combustion]` out of physical bounds,
//! are refused with exit 2 before any work. Every run has a deadline, so
//! that a regression fails instead of hanging.

use enginedyn_tests::{binary, data};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs the binary with `args` in `dir`, killed (and the test failed)
/// after `limit`.
fn run_within(dir: &Path, args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(binary())
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start enginedyn");
    let started = Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("output");
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().expect("output");
            panic!(
                "enginedyn {args:?} still running after {limit:?} (killed); stderr: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn run(dir: &Path, args: &[&str]) -> Output {
    run_within(dir, args, Duration::from_secs(120))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn mkfifo(at: &Path) -> bool {
    Command::new("mkfifo")
        .arg(at)
        .status()
        .is_ok_and(|s| s.success())
}

/// `template --combustion petrol` with `edit` applied to its text.
fn petrol(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let out = run(dir, &["template", "--combustion", "petrol"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let path = dir.join(name);
    std::fs::write(&path, edit(String::from_utf8(out.stdout).unwrap())).unwrap();
    path
}

/// Item 1: `batch --parquet` with `/dev/zero` and a FIFO in its list
/// refuses them at once (their rows failed, no hash), writes its parts and
/// ends.
#[test]
fn batch_parquet_with_a_device_and_a_fifo_ends() {
    let t = tempfile::tempdir().unwrap();
    let fifo = t.path().join("pipe.csv");
    assert!(mkfifo(&fifo), "mkfifo");
    let good = data("vaz2108.csv");
    let engine = data("vaz2108.toml");
    let out = run_within(
        t.path(),
        &[
            "batch",
            "--engine",
            &engine,
            "/dev/zero",
            "pipe.csv",
            &good,
            "--parquet",
            "pq",
            "--quiet",
        ],
        Duration::from_secs(60),
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("/dev/zero: not a regular file"), "{err}");
    assert!(err.contains("pipe.csv: not a regular file"), "{err}");
    assert!(
        t.path()
            .join("pq/summary/part-00000-of-00001.parquet")
            .is_file()
    );
}

/// Item 4: `synth --out` never replaces a file enginedyn did not write (a
/// measured diagram): exit 2 with the output folders' message, the file
/// as it was; a diagram `synth` wrote is replaced.
#[test]
fn synth_out_replaces_only_its_own_diagram() {
    let t = tempfile::tempdir().unwrap();
    let engine = petrol(t.path(), "petrol.toml", |s| s);
    let e = engine.to_str().unwrap();
    let measured = std::fs::read(data("vaz2108.csv")).unwrap();
    std::fs::write(t.path().join("bench.csv"), &measured).unwrap();
    let out = run(t.path(), &["synth", "--engine", e, "--out", "bench.csv"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("bench.csv: a file enginedyn did not write is in the way; enginedyn replaces only a file it wrote"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read(t.path().join("bench.csv")).unwrap(), measured);
    // Its own diagram, written twice: replaced.
    for _ in 0..2 {
        let out = run(t.path(), &["synth", "--engine", e, "--out", "own.csv"]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    }
    let out = run(
        t.path(),
        &["synth", "--engine", e, "--imep", "8", "--out", "own.csv"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let own = std::fs::read_to_string(t.path().join("own.csv")).unwrap();
    assert!(own.contains("imep_bar = 8 (target)"), "{own}");
}

/// Item 13: `--ivc-deg` (or `--intake-temp-k`) with a constant γ is a
/// usage error, as in Python.
#[test]
fn ivc_deg_with_a_constant_gamma_is_refused() {
    let t = tempfile::tempdir().unwrap();
    for extra in [["--ivc-deg", "-100"], ["--intake-temp-k", "330"]] {
        let mut args = vec!["run", "--gamma", "1.32"];
        args.extend(extra);
        let out = run(t.path(), &args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains("--gamma brunt"), "{}", stderr(&out));
    }
}

/// Item 14: a burn window the grid cannot resolve is a usage error before
/// any work, for `run` and for `batch --parquet` (no part written).
#[test]
fn burn_window_too_short_for_the_step_is_a_usage_error() {
    let t = tempfile::tempdir().unwrap();
    let out = run(t.path(), &["run", "--burn-window", "0:10", "--step", "5"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("--burn-window 0:10 with --step 5") && !err.contains("vaz2108.csv"),
        "{err}"
    );
    let engine = data("vaz2108.toml");
    let good = data("vaz2108.csv");
    let out = run(
        t.path(),
        &[
            "batch",
            "--engine",
            &engine,
            &good,
            "--burn-window",
            "0:10",
            "--step",
            "5",
            "--parquet",
            "pq",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("--burn-window"), "{}", stderr(&out));
    assert!(!t.path().join("pq/summary").exists());
}

/// Item 15: a two-stroke's `--ivc-deg` is held to the engine file's bound
/// for a two-stroke (−155° to below 0°).
#[test]
fn two_stroke_ivc_flag_has_the_engine_file_bound() {
    let t = tempfile::tempdir().unwrap();
    let engine = data("i3_two_stroke.toml");
    let out = run(
        t.path(),
        &[
            "run",
            "--engine",
            &engine,
            "--gamma",
            "brunt",
            "--ivc-deg",
            "-200",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("--ivc-deg -200: expected -155 to below 0° for a two-stroke"),
        "{}",
        stderr(&out)
    );
    let out = run(
        t.path(),
        &[
            "run",
            "--engine",
            &engine,
            "--gamma",
            "brunt",
            "--ivc-deg",
            "-150",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// Item 16: an IMEP, a heat or an intake pressure no engine has is
/// refused in the engine file (exit 2 naming the key and the bound), by
/// `synth` and by `run` alike.
#[test]
fn combustion_loads_out_of_physical_bounds_name_the_key() {
    let t = tempfile::tempdir().unwrap();
    let cases = [
        (
            "imep_bar = 10.0",
            "imep_bar = 500",
            "combustion.imep_bar",
            "up to 40 bar",
        ),
        (
            "imep_bar = 10.0",
            "heat_released_j = 1e7",
            "combustion.heat_released_j",
            "what its trapped air can burn",
        ),
        (
            "# intake_pressure_bar = 1.0",
            "intake_pressure_bar = 0.1",
            "combustion.intake_pressure_bar",
            "0.2 to 6 bar absolute",
        ),
    ];
    for (k, (from, to, key, bound)) in cases.into_iter().enumerate() {
        let name = format!("e{k}.toml");
        let engine = petrol(t.path(), &name, |s| {
            assert!(s.contains(from), "{from}");
            s.replacen(from, to, 1)
        });
        let e = engine.to_str().unwrap();
        for args in [
            vec!["synth", "--engine", e, "--out", "x.csv"],
            vec!["run", "--engine", e],
        ] {
            let out = run(t.path(), &args);
            assert_eq!(out.status.code(), Some(2), "{to}: {}", stderr(&out));
            let err = stderr(&out);
            assert!(err.contains(key) && err.contains(bound), "{to}: {err}");
        }
    }
    // The template's loads are within them.
    let engine = petrol(t.path(), "ok.toml", |s| {
        s.replacen("imep_bar = 10.0", "heat_released_j = 900", 1)
    });
    let out = run(
        t.path(),
        &[
            "synth",
            "--engine",
            engine.to_str().unwrap(),
            "--out",
            "ok.csv",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}
