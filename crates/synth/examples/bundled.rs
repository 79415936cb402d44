//! Writes every bundled diagram of `enginedyn_synth::bundled::DIAGRAMS`
//! into a folder, `data/` unless one is given (the `justfile`'s `data`
//! recipe):
//!
//! ```text
//! cargo run --release -q -p enginedyn-synth --example bundled [FOLDER]
//! ```
//!
//! Each file is written whole or not at all (a temporary file beside it,
//! renamed over it) and named on standard error; the bytes are the same
//! whatever the folder.

use enginedyn_synth::bundled::DIAGRAMS;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args_os().skip(1);
    let folder = args
        .next()
        .map_or_else(|| PathBuf::from("data"), PathBuf::from);
    if args.next().is_some() {
        eprintln!("usage: bundled [FOLDER] (default data/)");
        return ExitCode::from(2);
    }
    for d in &DIAGRAMS {
        let path = folder.join(d.file);
        let written = d
            .text()
            .map_err(|e| e.to_string())
            .and_then(|text| write_whole(&path, text.as_bytes()).map_err(|e| e.to_string()));
        if let Err(e) = written {
            eprintln!("{}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        eprintln!("{}", path.display());
    }
    ExitCode::SUCCESS
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
