//! `summary.json`'s `inputs`: what a result came from (the engine file and
//! the diagram files as given, their BLAKE3 hashes, the version).

use crate::diagram::Input;
use crate::engine::Loaded;
use crate::error::Result;
use enginedyn_report::{Inputs, Source};

/// The engine's record (its file, the bundled example's text, or the text
/// it was given as) with the `diagrams`.
pub fn of(loaded: &Loaded, diagrams: &[Input<'_>]) -> Result<Inputs> {
    of_hashed(loaded, diagrams, &[])
}

/// [`of`], with the diagram files' BLAKE3 as their read hashed them
/// (`hashes[k]` for `diagrams[k]`; a file without one is read again to
/// hash it). The engine file is hashed from the text that was read.
pub fn of_hashed(
    loaded: &Loaded,
    diagrams: &[Input<'_>],
    hashes: &[Option<String>],
) -> Result<Inputs> {
    let engine_hash;
    let engine = match (&loaded.path, loaded.bundled) {
        (Some(p), _) => {
            // `text` holds the file's bytes as read (UTF-8, unchanged).
            engine_hash = blake3::hash(loaded.text.as_bytes()).to_hex().to_string();
            Source::Hashed(p, &engine_hash)
        }
        (None, Some(b)) => Source::Bundled(b.engine.as_bytes()),
        (None, None) => Source::Text("text", loaded.text.as_bytes()),
    };
    // A synthesised diagram kept as samples: the hash of its columns.
    let sampled: Vec<Option<String>> = diagrams
        .iter()
        .map(|d| match d {
            Input::Synthesised(s) if s.text.is_empty() => {
                Some(arrays_blake3(&[&s.samples.0, &s.samples.1]))
            }
            _ => None,
        })
        .collect();
    let diagrams: Vec<Source<'_>> = diagrams
        .iter()
        .enumerate()
        .map(
            |(k, d)| match (d, hashes.get(k).and_then(Option::as_deref)) {
                (Input::File(p), Some(h)) => Source::Hashed(p, h),
                (Input::File(p), None) => Source::File(p),
                (Input::Bundled(b), _) => Source::Bundled(b.diagram.as_bytes()),
                (Input::Synthesised(_), _) if sampled[k].is_some() => Source::Hashed(
                    std::path::Path::new("synthesised"),
                    sampled[k].as_deref().unwrap_or_default(),
                ),
                (Input::Synthesised(s), _) => Source::Text("synthesised", s.text.as_bytes()),
            },
        )
        .collect();
    Ok(Inputs::new(engine, &diagrams)?)
}

/// The BLAKE3 of columns of numbers in memory (`analyse_arrays`), as the
/// hash of their little-endian bytes one column after another, read from
/// the borrowed slices through an 8 KiB buffer: no copy of the arrays
/// (at 1e8 points a copy was 0.8 GB a column).
pub fn arrays_blake3(columns: &[&[f64]]) -> String {
    const CHUNK: usize = 1024;
    let mut h = blake3::Hasher::new();
    let mut buf = [0u8; CHUNK * 8];
    for c in columns {
        for part in c.chunks(CHUNK) {
            for (k, v) in part.iter().enumerate() {
                buf[8 * k..8 * k + 8].copy_from_slice(&v.to_le_bytes());
            }
            h.update(&buf[..8 * part.len()]);
        }
    }
    h.finalize().to_hex().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same hash as the bytes copied out (what `inputs` held before),
    /// across a chunk's edge.
    #[test]
    fn arrays_hash_without_a_copy() {
        let a: Vec<f64> = (0..2500).map(|k| k as f64 * 0.1).collect();
        let b = [1.5, -2.0, f64::MAX];
        let copied: Vec<u8> = [&a[..], &b[..]]
            .iter()
            .flat_map(|c| c.iter().flat_map(|v| v.to_le_bytes()))
            .collect();
        assert_eq!(
            arrays_blake3(&[&a, &b]),
            blake3::hash(&copied).to_hex().to_string()
        );
        assert_eq!(arrays_blake3(&[]), blake3::hash(b"").to_hex().to_string());
    }
}
