//! `enginedyn merge DIR [--parts N]`: a campaign's parts checked (every
//! part of every table, one schema) and `DIR/_manifest.json` written.

use crate::Failure;
use crate::args::MergeArgs;

pub fn run(a: &MergeArgs) -> Result<(), Failure> {
    let parts = a.parts.map(|n| n as usize);
    let (manifest, path) = enginedyn_session::campaign::merge(&a.dir, parts)?;
    crate::emit(&(serde_json::to_string_pretty(&manifest).unwrap_or_default() + "\n"));
    eprintln!("wrote {}", path.display());
    Ok(())
}
