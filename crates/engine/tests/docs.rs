//! The user's documentation of the engine file (`docs/engine-file.md`) is
//! the key table of `enginedyn_engine::keys`: each section's table between
//! `<!-- keys: SECTION -->` and `<!-- end keys -->` must be what
//! `keys::markdown` writes, so a key added, renamed or given another
//! default fails here until the page says so. `ENGINEDYN_BLESS=1 cargo test
//! -p enginedyn-engine --test docs` rewrites the tables in place.

use enginedyn_engine::keys::{KEYS, markdown};

const PAGE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/engine-file.md");
const END: &str = "<!-- end keys -->";

/// The sections with a table, as the markers name them (`top`: the keys
/// before any `[section]`).
fn sections() -> Vec<&'static str> {
    let mut s: Vec<&'static str> = Vec::new();
    for k in KEYS {
        if !s.contains(&k.section) {
            s.push(k.section);
        }
    }
    s
}

fn marker(section: &str) -> String {
    format!(
        "<!-- keys: {} -->",
        if section.is_empty() { "top" } else { section }
    )
}

/// The page with every table replaced by what `markdown` writes.
fn regenerated(page: &str) -> Result<String, String> {
    let mut out = page.to_string();
    for section in sections() {
        let m = marker(section);
        let start = out
            .find(&m)
            .ok_or_else(|| format!("docs/engine-file.md has no `{m}` table"))?
            + m.len();
        let end = start
            + out[start..]
                .find(END)
                .ok_or_else(|| format!("`{m}` has no `{END}`"))?;
        out.replace_range(start..end, &format!("\n{}", markdown(section)));
    }
    Ok(out)
}

#[test]
fn key_tables_are_the_key_table() {
    let page = std::fs::read_to_string(PAGE).expect("docs/engine-file.md");
    let want = regenerated(&page).unwrap_or_else(|e| panic!("{e}"));
    if want != page {
        if std::env::var_os("ENGINEDYN_BLESS").is_some() {
            std::fs::write(PAGE, &want).unwrap();
            return;
        }
        let first = want
            .lines()
            .zip(page.lines())
            .find(|(a, b)| a != b)
            .map(|(a, b)| format!("expected:\n{a}\nfound:\n{b}"))
            .unwrap_or_else(|| "the lengths differ".into());
        panic!(
            "docs/engine-file.md's key tables are not crates/engine/src/keys.rs's \
             (ENGINEDYN_BLESS=1 cargo test -p enginedyn-engine --test docs rewrites them):\n{first}"
        );
    }
}

/// Every key the reader takes appears in the page with its section, and
/// the page names no key in a table that the reader does not take.
#[test]
fn every_key_and_only_known_keys() {
    let page = std::fs::read_to_string(PAGE).expect("docs/engine-file.md");
    for k in KEYS {
        assert!(
            page.contains(&format!("| `{}` |", k.key)),
            "{} is not in docs/engine-file.md",
            k.path()
        );
    }
    // Rows of the key tables name known keys only.
    for section in sections() {
        let m = marker(section);
        let Some(start) = page.find(&m) else { continue };
        let block = &page[start..];
        let block = &block[..block.find(END).unwrap_or(block.len())];
        for row in block.lines().filter(|l| l.starts_with("| `")) {
            let key = row.split('`').nth(1).unwrap_or("");
            assert!(
                KEYS.iter().any(|k| k.section == section && k.key == key),
                "docs/engine-file.md lists `{key}` under {m}, which the reader does not take"
            );
        }
    }
    // The example runs: the page's example is the bundled engine file.
    let bundled = include_str!("../../../data/vaz2108.toml");
    let example = page
        .split("```toml\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .expect("an example in docs/engine-file.md");
    assert_eq!(example, bundled, "the page's example is data/vaz2108.toml");
}
