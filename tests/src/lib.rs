//! End-to-end tests of the `enginedyn` binary live beside this file
//! (`tests/end_to_end.rs`); this crate exists so that a virtual workspace
//! compiles and runs them with `cargo test --workspace`.
//!
//! [`binary`] finds (and if needed builds) the binary under test.

pub mod fuzz;

use std::path::PathBuf;

/// Path of the `enginedyn` binary of this build profile, built on demand;
/// or `ENGINEDYN_BIN`, a binary already built from these sources (CI runs
/// the end-to-end tests against the one release build it also runs and
/// ships, so the tests never build a second CLI).
pub fn binary() -> PathBuf {
    if let Some(bin) = std::env::var_os("ENGINEDYN_BIN") {
        return PathBuf::from(bin);
    }
    let exe = std::env::current_exe().expect("test executable path");
    // target/<profile>/deps/end_to_end-xxxx → target/<profile>/enginedyn
    let dir = exe
        .parent()
        .and_then(|d| d.parent())
        .expect("target profile folder")
        .to_path_buf();
    let bin = dir.join(format!("enginedyn{}", std::env::consts::EXE_SUFFIX));
    // Build (or confirm up to date) once per test process: a stale binary
    // from an earlier build must never be the one under test.
    static BUILT: std::sync::OnceLock<()> = std::sync::OnceLock::new();
    BUILT.get_or_init(|| {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| env!("CARGO").into());
        let release = dir.file_name().is_some_and(|n| n == "release");
        let mut cmd = std::process::Command::new(cargo);
        cmd.args(["build", "-q", "-p", "enginedyn", "--bin", "enginedyn"]);
        if release {
            cmd.arg("--release");
        }
        let status = cmd.status().expect("cargo build");
        assert!(status.success(), "building enginedyn failed");
    });
    bin
}

/// Runs the binary with `args` and returns what it did.
pub fn run(args: &[&str]) -> std::process::Output {
    std::process::Command::new(binary())
        .args(args)
        .output()
        .expect("run enginedyn")
}

/// `sha256sum` of a file: the system's tool, not enginedyn's code, to hold
/// the hashes enginedyn writes against.
pub fn sha256sum(path: impl AsRef<std::path::Path>) -> String {
    let out = std::process::Command::new("sha256sum")
        .arg(path.as_ref())
        .output()
        .expect("sha256sum");
    assert!(out.status.success());
    String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .next()
        .unwrap_or_default()
        .to_string()
}

/// A bundled data file's path (`data/NAME`).
pub fn data(name: &str) -> String {
    format!("{}/../data/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// A bundled diagram's data rows as (angle as written, pressure in bar):
/// the material tests build multi-cycle and damaged files from.
pub fn data_rows(name: &str) -> Vec<(String, f64)> {
    std::fs::read_to_string(data(name))
        .expect("a bundled diagram")
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .filter_map(|l| {
            let (a, p) = l.split_once(',')?;
            Some((a.to_string(), p.trim().parse().ok()?))
        })
        .collect()
}

/// Runs the binary, asserts it succeeded and returns the JSON it printed.
pub fn ok_json(args: &[&str]) -> serde_json::Value {
    let out = run(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

/// The fixed `summary.json` keys as the contract lists them: the first
/// column of INTERFACE.md's `summary.json` table (`../shared/spec`, beside
/// the checkout), `models` and `notes` left out. `None` when the spec is
/// not beside the checkout (CI always has it).
pub fn contract_summary_keys() -> Option<Vec<String>> {
    let spec = format!(
        "{}/../../shared/spec/INTERFACE.md",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(spec).ok()?;
    let table = text.split("## `summary.json`").nth(1)?;
    let table = table.split("Present when they apply").next()?;
    let mut keys = Vec::new();
    for line in table.lines().filter(|l| l.starts_with("| `")) {
        let first = line.split('|').nth(1).unwrap_or("");
        for key in first.split('`').skip(1).step_by(2) {
            if key != "models" && key != "notes" {
                keys.push(key.to_string());
            }
        }
    }
    Some(keys)
}

/// `enginedyn template` with `args` (`["--combustion", "petrol"]`), each
/// `(from, to)` of `edit` replaced once (a missing `from` fails the test),
/// written as `name` in `dir`: the file's path as text.
pub fn edited_template(
    dir: &std::path::Path,
    args: &[&str],
    name: &str,
    edit: &[(&str, &str)],
) -> String {
    let mut full = vec!["template"];
    full.extend(args);
    let o = run(&full);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let mut text = String::from_utf8(o.stdout).unwrap();
    for (from, to) in edit {
        assert!(text.contains(from), "the template has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}
