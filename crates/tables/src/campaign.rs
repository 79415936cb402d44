//! A campaign's identity (INTERFACE.md, "Campaigns"): the BLAKE3 of its
//! sorted, canonical file list, its count of parts and each part's number,
//! and the tables a part holds; the names of files as a table holds them
//! (escaped without loss); and the check, before any work, that a folder
//! holds no other campaign's parts and nothing else in their way.

use crate::{Table, TablesError, parse_part_name, part_name};
use std::path::{Path, PathBuf};

/// The metadata key of a part's campaign identity.
pub const CAMPAIGN_KEY: &str = "enginedyn.campaign";

/// The metadata key of a summary part's files: a JSON array of the
/// canonical paths of its rows, in row order, escaped ([`escape_name`]).
pub const FILES_KEY: &str = "enginedyn.files";

/// Who a part belongs to: `enginedyn.campaign` =
/// `{"list_blake3", "parts", "part", "tables"}`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Campaign {
    /// BLAKE3 of the sorted, canonical file list ([`list_blake3`]).
    pub list_blake3: String,
    /// N, the parts of the campaign.
    pub parts: usize,
    /// This part's number (0 ≤ part < N).
    pub part: usize,
    /// The tables this part holds (summary and cycles, traces when asked).
    pub tables: Vec<Table>,
}

impl Campaign {
    /// The metadata value (compact JSON).
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "list_blake3": self.list_blake3,
            "parts": self.parts,
            "part": self.part,
            "tables": self.tables.iter().map(|t| t.folder()).collect::<Vec<_>>(),
        })
    }

    /// Reads the metadata value; `None` when it is not one.
    pub fn parse(text: &str) -> Option<Self> {
        let v: serde_json::Value = serde_json::from_str(text).ok()?;
        let tables = v["tables"]
            .as_array()?
            .iter()
            .map(|t| {
                Table::ALL
                    .into_iter()
                    .find(|x| Some(x.folder()) == t.as_str())
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Self {
            list_blake3: v["list_blake3"].as_str()?.to_string(),
            parts: usize::try_from(v["parts"].as_u64()?).ok()?,
            part: usize::try_from(v["part"].as_u64()?).ok()?,
            tables,
        })
    }

    /// The tables' names joined for a message: `summary, cycles`.
    pub fn tables_shown(&self) -> String {
        self.tables
            .iter()
            .map(|t| t.folder())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The BLAKE3 of a campaign's file list: the canonical paths' bytes sorted
/// bytewise, each ended by a zero byte (no path holds one), in hex.
pub fn list_blake3<B: AsRef<[u8]>>(paths: &[B]) -> String {
    let mut sorted: Vec<&[u8]> = paths.iter().map(AsRef::as_ref).collect();
    sorted.sort_unstable();
    let mut h = blake3::Hasher::new();
    for p in sorted {
        h.update(p);
        h.update(&[0]);
    }
    h.finalize().to_hex().to_string()
}

/// A path's bytes as a table holds them, without loss: valid UTF-8 as it
/// is, each byte that is not as `\xNN`, and a backslash followed by `x`
/// as `\x5c` (so that no name ever reads like another's escape).
/// [`unescape_name`] gives the bytes back.
pub fn escape_name(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len());
    for chunk in bytes.utf8_chunks() {
        let valid = chunk.valid();
        let mut rest = valid;
        while let Some(k) = rest.find("\\x") {
            out.push_str(&rest[..k]);
            out.push_str("\\x5c");
            rest = &rest[k + 1..];
        }
        out.push_str(rest);
        for b in chunk.invalid() {
            out.push_str(&format!("\\x{b:02x}"));
        }
    }
    out
}

/// The bytes [`escape_name`] wrote `s` from.
pub fn unescape_name(s: &str) -> Vec<u8> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut k = 0;
    while k < b.len() {
        if b[k] == b'\\'
            && b.get(k + 1) == Some(&b'x')
            && let Some(Ok(v)) = s.get(k + 2..k + 4).map(|h| u8::from_str_radix(h, 16))
        {
            out.push(v);
            k += 4;
            continue;
        }
        out.push(b[k]);
        k += 1;
    }
    out
}

/// What a folder's part says of its campaign, for a message.
fn describe(meta: &std::collections::BTreeMap<String, String>) -> String {
    match meta.get(CAMPAIGN_KEY).and_then(|c| Campaign::parse(c)) {
        Some(c) => format!(
            "a campaign of {} over the file list {}",
            plural(c.parts, "part"),
            short(&c.list_blake3)
        ),
        None => format!(
            "parts written by enginedyn {} without a campaign identity",
            meta.get("enginedyn.version")
                .map_or("(unknown)", String::as_str)
        ),
    }
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// The first 12 hex digits of a hash, as messages show it.
pub fn short(hash: &str) -> &str {
    hash.get(..12).unwrap_or(hash)
}

/// What a campaign is, compared by meaning: its list and count of parts,
/// the parsed engine and the resolved options (not the engine file's bytes
/// nor the flags' spelling).
#[derive(Debug, Clone, PartialEq)]
pub struct Identity {
    /// BLAKE3 of the file list.
    pub list_blake3: String,
    /// N.
    pub parts: usize,
    /// BLAKE3 of the parsed engine.
    pub engine: String,
    /// The resolved options.
    pub options: serde_json::Value,
}

impl Identity {
    /// The identity a part's metadata gives; `None` without one.
    pub fn of(meta: &std::collections::BTreeMap<String, String>) -> Option<Self> {
        let c = Campaign::parse(meta.get(CAMPAIGN_KEY)?)?;
        Some(Self {
            list_blake3: c.list_blake3,
            parts: c.parts,
            engine: meta.get(crate::ENGINE_PARSED_KEY)?.clone(),
            options: serde_json::from_str(meta.get("options")?).ok()?,
        })
    }

    /// How it (a folder's part) differs from `other` (this run's), in
    /// words; `None` when it does not.
    pub fn difference(&self, other: &Identity) -> Option<String> {
        if self.list_blake3 != other.list_blake3 {
            Some(format!(
                "the file list differs (list_blake3 {} in the folder, {} in this run)",
                short(&self.list_blake3),
                short(&other.list_blake3)
            ))
        } else if self.parts != other.parts {
            Some(format!(
                "the count of parts differs ({} in the folder, {} in this run)",
                self.parts, other.parts
            ))
        } else if self.engine != other.engine {
            Some("the engine differs (as parsed)".into())
        } else if self.options != other.options {
            Some(format!(
                "the options differ ({} in the folder, {} in this run)",
                self.options, other.options
            ))
        } else {
            None
        }
    }
}

/// What [`prepare`] found and did.
#[derive(Debug, Default)]
pub struct Prepared {
    /// Parts of another campaign removed (`replace`).
    pub removed: Vec<PathBuf>,
}

/// The prefix of a part's staging folder in the campaign's folder:
/// `.enginedyn-part-IIIII-of-NNNNN-`.
pub fn staging_prefix(part: usize, parts: usize) -> Result<String, TablesError> {
    let name = part_name(part, parts)?;
    Ok(format!(".enginedyn-{}-", name.trim_end_matches(".parquet")))
}

/// Before any work on part `part` of the campaign `me` in `dir`: refuses a
/// folder that holds parts of another campaign (naming both), unless
/// `replace`, which removes enginedyn's own parts (and `_manifest.json`)
/// first; refuses anything without enginedyn's metadata at a part's path
/// (in the way); and removes the staging folder a killed run of this part
/// left.
pub fn prepare(
    dir: &Path,
    me: &Identity,
    part: usize,
    replace: bool,
) -> Result<Prepared, TablesError> {
    let prefix = staging_prefix(part, me.parts)?;
    let mut done = Prepared::default();
    let mut other: Vec<PathBuf> = Vec::new();
    for table in Table::ALL {
        let folder = dir.join(table.folder());
        let entries = match std::fs::read_dir(&folder) {
            Ok(e) => e,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
            Err(e) => return Err(crate::merge::read_err(&folder, e)),
        };
        let mut names: Vec<(String, PathBuf, std::fs::FileType)> = Vec::new();
        for e in entries.flatten() {
            if let (Some(name), Ok(kind)) = (e.file_name().to_str(), e.file_type())
                && parse_part_name(name).is_some()
            {
                names.push((name.to_string(), e.path(), kind));
            }
        }
        names.sort_by(|a, b| a.0.cmp(&b.0));
        for (_, path, kind) in names {
            let what = if kind.is_symlink() {
                Some("a symbolic link")
            } else if kind.is_dir() {
                Some("a folder")
            } else if !kind.is_file() {
                Some("not a regular file")
            } else {
                None
            };
            let meta = match what {
                Some(_) => None,
                None => match crate::merge::metadata(&path) {
                    Ok(m) => Some(m),
                    // Gone since the folder was listed: the run of that
                    // part replacing it (its commit removes the old part
                    // before the new one is moved in) in a campaign whose
                    // parts run at once.
                    Err(_) if std::fs::symlink_metadata(&path).is_err() => continue,
                    Err(_) => None,
                },
            };
            let Some(meta) = meta.filter(|m| m.contains_key(crate::META_KEYS[0])) else {
                return Err(TablesError::InTheWay {
                    path,
                    what: what.unwrap_or("a file without enginedyn's metadata"),
                });
            };
            match Identity::of(&meta) {
                Some(id) if id.difference(me).is_none() => {}
                _ if replace => other.push(path),
                _ => {
                    return Err(TablesError::OtherCampaign {
                        path,
                        theirs: describe(&meta),
                        ours: format!(
                            "a campaign of {} over the file list {}",
                            plural(me.parts, "part"),
                            short(&me.list_blake3)
                        ),
                        why: Identity::of(&meta)
                            .and_then(|id| id.difference(me))
                            .unwrap_or_else(|| "no campaign identity".into()),
                    });
                }
            }
        }
    }
    for path in other {
        std::fs::remove_file(&path).map_err(|e| crate::merge::read_err(&path, e))?;
        done.removed.push(path);
    }
    if !done.removed.is_empty() {
        crate::merge::remove_manifest(dir)?;
    }
    remove_staging(dir, &prefix);
    Ok(done)
}

/// Removes the staging folders (names starting `prefix`) a killed run
/// left in `dir`; never follows a link.
fn remove_staging(dir: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let ours = e
            .file_name()
            .to_str()
            .is_some_and(|n| n.starts_with(prefix));
        if ours && e.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_never_collide() {
        let names: [&[u8]; 6] = [
            b"a.csv",
            b"a\xff.csv",
            b"a\\xff.csv",
            b"a\\x5c.csv",
            b"a\\\xff.csv",
            " a.csv".as_bytes(),
        ];
        let shown: Vec<String> = names.iter().map(|n| escape_name(n)).collect();
        assert_eq!(shown[1], "a\\xff.csv");
        assert_eq!(shown[2], "a\\x5cxff.csv");
        assert_eq!(shown[5], " a.csv");
        for (n, s) in names.iter().zip(&shown) {
            assert_eq!(unescape_name(s), *n, "{s}");
        }
        let mut unique = shown.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), names.len());
    }

    #[test]
    fn list_hash_is_of_the_sorted_list() {
        assert_eq!(list_blake3(&["b", "a"]), list_blake3(&["a", "b"]));
        assert_ne!(list_blake3(&["ab", "c"]), list_blake3(&["a", "bc"]));
        assert_eq!(list_blake3(&["a"]).len(), 64);
    }

    #[test]
    fn campaign_json_round_trips() {
        let c = Campaign {
            list_blake3: "ab".into(),
            parts: 3,
            part: 2,
            tables: vec![Table::Summary, Table::Cycles, Table::Traces],
        };
        assert_eq!(
            c.json().to_string(),
            r#"{"list_blake3":"ab","parts":3,"part":2,"tables":["summary","cycles","traces"]}"#
        );
        assert_eq!(Campaign::parse(&c.json().to_string()), Some(c));
    }
}
