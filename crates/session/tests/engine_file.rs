//! Engine files are regular files of at most 1 MiB (issue 36, item 14;
//! INTERFACE.md, "Engine file"): a device, a FIFO, a folder or a larger
//! file is an engine-file error (exit 2) naming it, at once and without
//! reading it; text from Python (`Engine.from_str`) is held to the same
//! bound.

use enginedyn_session::{Bundled, Class, Loaded};
use std::time::{Duration, Instant};

fn refused(path: &std::path::Path) -> String {
    let t = Instant::now();
    let e = Loaded::from_file(path).unwrap_err();
    assert!(t.elapsed() < Duration::from_secs(5), "{:?}", t.elapsed());
    assert_eq!(e.class, Class::EngineFile, "{e}");
    assert_eq!(e.exit_code(), 2);
    e.to_string()
}

#[test]
fn an_engine_file_is_a_regular_file_of_at_most_1_mib() {
    // /dev/zero was read until memory ran out.
    let e = refused(std::path::Path::new("/dev/zero"));
    assert_eq!(
        e,
        "/dev/zero: the engine file is not a regular file (a FIFO, a device or a socket): an engine file is TOML text"
    );
    let dir = tempfile::tempdir().unwrap();
    // A FIFO: opening it would wait for a writer.
    let fifo = dir.path().join("engine.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let e = refused(&fifo);
        assert!(e.ends_with("engine.toml: the engine file is not a regular file (a FIFO, a device or a socket): an engine file is TOML text"), "{e}");
    }
    let e = refused(dir.path());
    assert!(e.contains("not a regular file (a folder)"), "{e}");
    // A valid engine file padded with comments past 1 MiB.
    let b = Bundled::find("single").unwrap();
    let mut text = b.engine.to_string();
    while text.len() <= 1 << 20 {
        text.push_str("# a comment line to pad the file past its bound ............\n");
    }
    let big = dir.path().join("big.toml");
    std::fs::write(&big, &text).unwrap();
    let e = refused(&big);
    assert!(
        e.ends_with(&format!(
            "big.toml: the engine file holds {} bytes, more than the 1 MiB bound on one (an engine file is a page of TOML)",
            text.len()
        )),
        "{e}"
    );
    // The same text from Python's Engine.from_str.
    let e = Loaded::from_text(text, None).unwrap_err();
    assert_eq!(e.class, Class::EngineFile);
    assert!(e.to_string().contains("more than the 1 MiB bound"), "{e}");
    // Just under the bound, it reads.
    let mut text = b.engine.to_string();
    while text.len() + 64 <= 1 << 20 {
        text.push_str("# a comment line to pad the file up to its bound .............\n");
    }
    let fine = dir.path().join("fine.toml");
    std::fs::write(&fine, &text).unwrap();
    Loaded::from_file(&fine).unwrap();
}
