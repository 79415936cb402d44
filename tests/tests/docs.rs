//! The user's documentation lives in the repository (issue 30, item 8):
//! README.md and docs/ point to nothing outside it, their links resolve,
//! the README gives the install step and the workspace's minimum Rust,
//! and docs/outputs.md names every `summary.json` key and every file and
//! `curves.csv` column a run writes. (docs/engine-file.md's key tables are
//! held to the engine file's key table by crates/engine/tests/docs.rs.)

use enginedyn_tests::run;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn pages() -> Vec<PathBuf> {
    let mut p = vec![root().join("README.md")];
    for e in std::fs::read_dir(root().join("docs")).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "md") {
            p.push(path);
        }
    }
    p.sort();
    p
}

#[test]
fn nothing_outside_the_repository_and_links_resolve() {
    let pages = pages();
    for want in [
        "engine-file.md",
        "diagrams.md",
        "torque.md",
        "outputs.md",
        "README.md",
    ] {
        assert!(
            pages.iter().any(|p| p.ends_with(format!("docs/{want}"))),
            "docs/{want} is missing"
        );
    }
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap();
        assert!(
            !text.contains("shared/"),
            "{} points outside the repository (shared/)",
            page.display()
        );
        // Markdown links: [text](target) to a file of the repository.
        for target in text.split("](").skip(1).filter_map(|s| s.split(')').next()) {
            if target.starts_with("http") || target.starts_with('#') {
                continue;
            }
            let file = target.split('#').next().unwrap();
            let path = page.parent().unwrap().join(file);
            assert!(
                path.exists(),
                "{}: link to {target} does not resolve",
                page.display()
            );
        }
    }
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    for link in [
        "docs/README.md",
        "docs/engine-file.md",
        "docs/diagrams.md",
        "docs/torque.md",
        "docs/outputs.md",
    ] {
        assert!(
            readme.contains(&format!("]({link})")),
            "README does not link {link}"
        );
    }
}

#[test]
fn readme_gives_install_minimum_rust_and_binary() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let version = manifest
        .lines()
        .find_map(|l| l.strip_prefix("rust-version = "))
        .expect("the workspace's rust-version")
        .trim_matches('"');
    assert!(
        readme.contains(&format!("Rust {version} or newer")),
        "{version}"
    );
    for s in [
        "cargo install --path crates/cli",
        "~/.cargo/bin/enginedyn",
        "target/release/enginedyn",
        "enginedyn template",
    ] {
        assert!(readme.contains(s), "README lacks {s}");
    }
}

#[test]
fn outputs_page_names_every_key_file_and_column() {
    let page = std::fs::read_to_string(root().join("docs/outputs.md")).unwrap();
    for k in enginedyn_pipeline::KEYS {
        assert!(
            page.contains(&format!("`{}`", k.key)),
            "docs/outputs.md lacks summary.json's `{}`",
            k.key
        );
    }
    // What a run writes, with [tolerances] and [torsion]: each file, and
    // each curves.csv column (numbers as K).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let engine = format!("{}/data/i6_diesel.toml", root().display());
    let r = run(&["run", "--engine", &engine, "--out", out.to_str().unwrap()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    for e in std::fs::read_dir(&out).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        assert!(
            page.contains(&format!("`{name}`")),
            "docs/outputs.md lacks {name}"
        );
    }
    let curves = std::fs::read_to_string(out.join("curves.csv")).unwrap();
    for col in curves.lines().next().unwrap().split(',') {
        let generic: String = col
            .split('_')
            .map(|w| {
                if w.chars().all(|c| c.is_ascii_digit()) {
                    "K"
                } else {
                    w
                }
            })
            .collect::<Vec<_>>()
            .join("_");
        assert!(
            page.contains(&format!("`{generic}`")),
            "docs/outputs.md lacks curves.csv's {col}"
        );
    }
}
