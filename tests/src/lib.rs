//! End-to-end tests of the `enginedyn` binary live beside this file
//! (`tests/end_to_end.rs`); this crate exists so that a virtual workspace
//! compiles and runs them with `cargo test --workspace`.
//!
//! [`binary`] finds (and if needed builds) the binary under test.

use std::path::PathBuf;

/// Path of the `enginedyn` binary of this build profile, built on demand.
pub fn binary() -> PathBuf {
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
