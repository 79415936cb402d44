//! Hostile input and unattended runs (issue 23, INTERFACE.md's "Limits",
//! "Output folders" and "Bounds"): every class of failure that was found,
//! run on the binary with generated inputs. Each case asserts the exit
//! code, no panic, a time bound, a bound on the child's peak memory, and
//! that nothing partial or hidden is left in the output folder.
//!
//! One test function runs the cases in turn (a kill and a race among
//! them); each child's peak memory comes from its own `wait4`.

use enginedyn_tests::{binary, data};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// What one run of the binary did.
struct Ran {
    out: Output,
    took: Duration,
}

impl Ran {
    fn code(&self) -> Option<i32> {
        self.out.status.code()
    }
    fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.out.stderr).into_owned()
    }
}

/// Runs the binary with `args` (and `env`), killed after `limit`; asserts
/// no panic, the time bound and a peak memory of the child (its own
/// maximum resident set, from `wait4`) under 300 MB.
// The child is reaped by `wait4` (which gives its own peak memory), not by
// `Child::wait`.
#[allow(unsafe_code, clippy::zombie_processes)]
fn run_env(args: &[&str], env: &[(&str, &str)], limit: Duration) -> Ran {
    use std::io::Read as _;
    use std::os::unix::process::ExitStatusExt as _;
    let started = Instant::now();
    let mut child = Command::new(binary())
        .args(args)
        .envs(env.iter().copied())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start enginedyn");
    let drain = |mut r: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let pid = child.id() as libc::pid_t;
    let (mut status, mut usage): (libc::c_int, libc::rusage) = (0, unsafe { std::mem::zeroed() });
    loop {
        // SAFETY: wait4 on our own child, with valid out-pointers.
        let got = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if got == pid {
            break;
        }
        assert!(got == 0, "wait4 failed for {args:?}");
        if started.elapsed() > limit {
            let _ = child.kill();
            // SAFETY: as above; reaps the killed child.
            unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
            panic!("{args:?} did not finish within {limit:?} (a hang)");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let took = started.elapsed();
    let out = Output {
        status: std::process::ExitStatus::from_raw(status),
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    };
    let ran = Ran { out, took };
    let err = ran.stderr();
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        err.len() < 20_000,
        "{args:?}: {} bytes on stderr (input echoed?)",
        err.len()
    );
    let peak_mb = usage.ru_maxrss as f64 / 1024.0;
    assert!(peak_mb < 300.0, "{args:?}: peak memory {peak_mb:.0} MB");
    ran
}

fn run(args: &[&str]) -> Ran {
    run_env(args, &[], Duration::from_secs(60))
}

/// Every entry of `dir`, hidden ones included, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

fn no_hidden(dir: &Path) {
    // The manifest of what the run wrote is the one hidden name of ours.
    let hidden: Vec<String> = entries(dir)
        .into_iter()
        .filter(|n| n.starts_with('.') && n != enginedyn_report::MANIFEST)
        .collect();
    assert!(hidden.is_empty(), "{}: {hidden:?} left", dir.display());
}

/// The bundled diagram with its header, for variants.
fn diagram() -> String {
    std::fs::read_to_string(data("vaz2108.csv")).unwrap()
}

fn engine() -> String {
    data("vaz2108.toml")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A few rows with a `cylinder` column holding `cell`.
fn cylinder_file(cell: &str) -> String {
    let mut s = String::from("cylinder,crank_deg,pressure_bar\n");
    for k in 0..8 {
        s.push_str(&format!("{cell},{},{}\n", k * 90, 1.0 + k as f64));
    }
    s
}

#[test]
fn hostile_inputs_and_unattended_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let e = engine();
    let s = |p: &Path| p.to_str().unwrap().to_string();

    // 1. A pressure cell of 1e-310 bar: charts render in bounded time (the
    //    log p–V chart's ticks hung forever).
    let tiny = diagram().replacen("\n0,", "\n0,1e-310\n0.0001,", 1);
    let tiny = write(t, "tiny.csv", &tiny);
    let out = t.join("tiny_out");
    let r = run(&[
        "run",
        "--engine",
        &e,
        "--diagram",
        &s(&tiny),
        "--out",
        &s(&out),
    ]);
    assert!(matches!(r.code(), Some(0 | 1)), "{}", r.stderr());
    assert!(r.took < Duration::from_secs(30));
    no_hidden(&out);
    // A flat trace (a degenerate axis) and one spanning 300 decades.
    for (name, low) in [("flat", 1.0), ("decades", 1e-300)] {
        let text: String = (0..1440)
            .map(|k| {
                format!(
                    "{},{}\n",
                    k as f64 * 0.5,
                    if k % 7 == 0 {
                        low
                    } else {
                        1.0 + 49.0 * (name == "decades") as u8 as f64
                    }
                )
            })
            .collect();
        let f = write(
            t,
            &format!("{name}.csv"),
            &format!("crank_deg,pressure_bar\n{text}"),
        );
        let out = t.join(format!("{name}_out"));
        let r = run(&[
            "run",
            "--engine",
            &e,
            "--diagram",
            &s(&f),
            "--out",
            &s(&out),
        ]);
        assert!(matches!(r.code(), Some(0 | 1)), "{name}: {}", r.stderr());
        assert!(r.took < Duration::from_secs(30), "{name}");
        no_hidden(&out);
    }

    // 2. One cell takes no batch down: huge, fractional and out-of-range
    //    cylinder numbers are errors at their line, the good file finishes.
    let batch_dir = t.join("batch_in");
    std::fs::create_dir(&batch_dir).unwrap();
    write(&batch_dir, "a_good.csv", &diagram());
    for (name, cell) in [
        ("b_u64.csv", "18446744073709551617"),
        ("c_2pow32.csv", "4294967296"),
        ("d_3e8.csv", "3e8"),
        ("e_half.csv", "1.5"),
        ("f_99.csv", "99"),
    ] {
        write(&batch_dir, name, &cylinder_file(cell));
    }
    let out = t.join("batch_out");
    let r = run(&["batch", "--engine", &e, &s(&batch_dir), "--out", &s(&out)]);
    assert_eq!(r.code(), Some(1), "{}", r.stderr());
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    let good = csv.lines().find(|l| l.contains("a_good.csv")).unwrap();
    assert!(good.contains(",,4900,"), "{good}");
    for l in csv.lines().skip(2) {
        assert!(l.contains("line 2, column 1: cylinder"), "{l}");
    }
    assert!(csv.contains("cylinder 4294967296:") && csv.contains("cylinder 1.5:"));
    no_hidden(&out);

    // 3. Unbounded buffering: a 2 MiB line, /dev/zero and a FIFO are
    //    refused at once, never held or waited on, and never echoed.
    let long = write(
        t,
        "long.csv",
        &format!("crank_deg,pressure_bar\n0,{}\n", "1".repeat(2 << 20)),
    );
    let r = run(&["run", "--engine", &e, "--diagram", &s(&long)]);
    assert_eq!(r.code(), Some(1));
    assert!(
        r.stderr()
            .contains("line 2: this line is longer than the 1 MiB bound"),
        "{}",
        r.stderr()
    );
    assert!(r.stderr().len() < 1000);
    let r = run(&["run", "--engine", &e, "--diagram", "/dev/zero"]);
    assert_eq!(r.code(), Some(1));
    assert!(r.stderr().contains("not a regular file"), "{}", r.stderr());
    let fifo = t.join("fifo_dir");
    std::fs::create_dir(&fifo).unwrap();
    write(&fifo, "a.csv", &diagram());
    let pipe = fifo.join("b.csv");
    let made = Command::new("mkfifo").arg(&pipe).status();
    if made.is_ok_and(|s| s.success()) {
        let r = run_env(
            &["run", "--engine", &e, "--diagram", &s(&pipe)],
            &[],
            Duration::from_secs(20),
        );
        assert_eq!(r.code(), Some(1));
        let r = run_env(
            &["batch", "--engine", &e, &s(&fifo), "--csv"],
            &[],
            Duration::from_secs(30),
        );
        assert_eq!(r.code(), Some(1));
        let text = String::from_utf8_lossy(&r.out.stdout).into_owned();
        assert!(
            text.contains("not a regular file") && text.contains(",,4900,"),
            "{text}"
        );
    }

    // 4. A full disk (an injected ENOSPC on the third file): nothing of the
    //    run is left, hidden or not; an old complete run stays as it was.
    let out = t.join("full_out");
    let r = run_env(
        &["run", "--out", &s(&out)],
        &[("ENGINEDYN_TEST_WRITE_FAIL", "3")],
        Duration::from_secs(60),
    );
    assert_eq!(r.code(), Some(1));
    assert!(r.stderr().contains("No space left"), "{}", r.stderr());
    assert!(entries(&out).is_empty(), "{:?}", entries(&out));
    let r = run(&["run", "--out", &s(&out)]);
    assert_eq!(r.code(), Some(0));
    let before = entries(&out);
    let summary = std::fs::read(out.join("summary.json")).unwrap();
    let r = run_env(
        &["run", "--rpm", "3000", "--out", &s(&out)],
        &[("ENGINEDYN_TEST_WRITE_FAIL", "5")],
        Duration::from_secs(60),
    );
    assert_eq!(r.code(), Some(1));
    assert_eq!(entries(&out), before);
    assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), summary);

    // 5. kill -9 during batch --detail: the finished run folders are whole,
    //    and the next run removes what the killed one left.
    let many = t.join("many");
    std::fs::create_dir(&many).unwrap();
    for k in 0..60 {
        write(&many, &format!("d{k:02}.csv"), &diagram());
    }
    let out = t.join("killed_out");
    let reference = t.join("reference_out");
    let r = run(&[
        "batch",
        "--engine",
        &e,
        &s(&many.join("d00.csv")),
        "--out",
        &s(&reference),
        "--detail",
    ]);
    assert_eq!(r.code(), Some(0));
    let whole = entries(&reference.join("0001_d00")).len();
    let mut child = Command::new(binary())
        .args([
            "batch",
            "--engine",
            &e,
            &s(&many),
            "--out",
            &s(&out),
            "--detail",
            "--jobs",
            "1",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Killed in the middle: once two run folders are in place (a third is
    // being written), never before anything was written (that would test
    // nothing) nor after the end.
    let started = Instant::now();
    let folders = |out: &Path| entries(out).iter().filter(|n| n.starts_with('0')).count();
    while folders(&out) < 2 && started.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(2));
    }
    let _ = child.kill();
    let _ = child.wait();
    let done = folders(&out);
    assert!(
        (2..60).contains(&done),
        "killed after {done} of 60 run folders"
    );
    assert!(
        !out.join("summary.csv").exists(),
        "the batch finished before the kill"
    );
    for name in entries(&out).iter().filter(|n| n.starts_with('0')) {
        assert_eq!(entries(&out.join(name)).len(), whole, "{name} is partial");
    }
    let r = run(&[
        "batch",
        "--engine",
        &e,
        &s(&many.join("d00.csv")),
        "--out",
        &s(&out),
    ]);
    assert_eq!(r.code(), Some(0));
    no_hidden(&out);

    // 6. Two batches into one folder at once: the second waits (or exits
    //    2), never a mix: every run folder agrees with summary.csv.
    let (a_in, b_in) = (t.join("a_in"), t.join("b_in"));
    for (dir, rpm) in [(&a_in, 2000), (&b_in, 3000)] {
        std::fs::create_dir(dir).unwrap();
        for k in 0..30 {
            write(
                dir,
                &format!("d{k:02}.csv"),
                &diagram().replace("# rpm = 4900", &format!("# rpm = {rpm}")),
            );
        }
    }
    let out = t.join("shared_out");
    let spawn = |dir: &Path| {
        Command::new(binary())
            .args([
                "batch",
                "--engine",
                &e,
                &s(dir),
                "--out",
                &s(&out),
                "--detail",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (spawn(&a_in), spawn(&b_in));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    for o in [&a, &b] {
        assert!(
            matches!(o.status.code(), Some(0 | 2)),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let rpm = if csv.contains(",2000,") {
        "2000"
    } else {
        "3000"
    };
    assert!(
        !csv.contains(if rpm == "2000" { ",3000," } else { ",2000," }),
        "{csv}"
    );
    for name in entries(&out).iter().filter(|n| n.starts_with('0')) {
        let j = std::fs::read_to_string(out.join(name).join("summary.json")).unwrap();
        assert!(
            j.contains(&format!("\"rpm\": {rpm}.0")),
            "{name} is from the other batch"
        );
    }
    no_hidden(&out);

    // 7. Sizes have bounds: exit 2 naming the flag, at once.
    for args in [
        &["run", "--step", "0.00001"][..],
        &["kinematics", "--engine", &e, "--step", "1e-9"],
        &["tolerance", "--engine", &e, "--samples", "1000000000"],
        &[
            "batch",
            "--engine",
            &e,
            &data("vaz2108.csv"),
            "--jobs",
            "20000",
        ],
        &["sweep", "--engine", &e, "--rpm", "1:100000:0.001"],
    ] {
        let r = run_env(args, &[], Duration::from_secs(10));
        assert_eq!(r.code(), Some(2), "{args:?}: {}", r.stderr());
        let flag = args
            .iter()
            .find(|a| a.starts_with("--") && **a != "--engine")
            .unwrap();
        assert!(r.stderr().contains(flag), "{args:?}: {}", r.stderr());
    }

    // 8. Exit classes: bad flags and engine values are 2 naming the flag
    //    or key; a bad `# rpm` line is 1 at its line.
    let r = run(&["run", "--tdc-deg", "nan"]);
    assert_eq!(r.code(), Some(2));
    assert!(r.stderr().contains("--tdc-deg"));
    let text = std::fs::read_to_string(&e).unwrap();
    for (from, to, key) in [
        ("bore_mm = 76.0", "bore_mm = 1e300", "bore_mm"),
        ("lambda = 0.26", "lambda = 1e-20", "lambda"),
        ("lambda = 0.26", "lambda = 1e-15", "lambda"),
        ("rpm = 4900", "rpm = 1e-300", "operating.rpm"),
        ("rpm = 4900", "rpm = 1e12", "operating.rpm"),
        (
            "firing_order = [1, 3, 4, 2]",
            "firing_order = [1, -3, 4, 2]",
            "[1, -3, 4, 2]",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let bad = write(t, "bad.toml", &text.replace(from, to));
        let r = run(&[
            "run",
            "--engine",
            &s(&bad),
            "--diagram",
            &data("vaz2108.csv"),
        ]);
        assert_eq!(r.code(), Some(2), "{to}: {}", r.stderr());
        assert!(r.stderr().contains(key), "{to}: {}", r.stderr());
    }
    let fast = write(
        t,
        "fast.csv",
        &diagram().replace("# rpm = 4900", "# rpm = 1e300"),
    );
    let r = run(&["run", "--engine", &e, "--diagram", &s(&fast)]);
    assert_eq!(r.code(), Some(1));
    assert!(r.stderr().contains("line 7"), "{}", r.stderr());
    let r = run(&["run", "--rpm", "1e12"]);
    assert_eq!(r.code(), Some(2));

    // 9. Names: a 10 MB name is refused in a few hundred bytes; links to
    //    `run#1.csv` and `a?b.csv` stay links.
    let huge = write(
        t,
        "huge.toml",
        &text.replacen(
            "name = \"",
            &format!("name = \"{}", "n".repeat(10 << 20)),
            1,
        ),
    );
    let r = run(&[
        "run",
        "--engine",
        &s(&huge),
        "--diagram",
        &data("vaz2108.csv"),
    ]);
    assert_eq!(r.code(), Some(2));
    assert!(r.stderr().len() < 500, "{}", r.stderr().len());
    let odd = t.join("odd");
    std::fs::create_dir(&odd).unwrap();
    write(&odd, "run#1.csv", &diagram());
    write(&odd, "a?b.csv", &diagram());
    let out = t.join("odd_out");
    let r = run(&[
        "batch",
        "--engine",
        &e,
        &s(&odd),
        "--out",
        &s(&out),
        "--detail",
    ]);
    assert_eq!(r.code(), Some(0), "{}", r.stderr());
    let index = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(index.contains("href=\"0001_a_b/report.html\""), "{index}");
    assert!(
        index.contains("href=\"0002_run%231/report.html\""),
        "{index}"
    );
    assert!(out.join("0002_run#1/report.html").exists());
    no_hidden(&out);
}
