//! The integration tests are one binary a crate (`tests/main.rs` and its
//! modules, `autotests = false`): a test file that no `mod` line and no
//! `[[test]]` names would never be built or run. None is left out.

use std::path::Path;

#[test]
fn every_test_file_is_built() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut crates: Vec<_> = std::fs::read_dir(root.join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    crates.push(root.join("tests"));
    let mut missing = Vec::new();
    let mut checked = 0;
    for krate in crates {
        let dir = krate.join("tests");
        let Ok(main) = std::fs::read_to_string(dir.join("main.rs")) else {
            continue;
        };
        let manifest = std::fs::read_to_string(krate.join("Cargo.toml")).unwrap();
        assert!(
            manifest.contains("autotests = false"),
            "{}",
            krate.display()
        );
        for e in std::fs::read_dir(&dir).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            let Some(stem) = name.strip_suffix(".rs") else {
                continue;
            };
            checked += 1;
            let listed = stem == "main"
                || main.lines().any(|l| l.trim() == format!("mod {stem};"))
                || manifest.contains(&format!("path = \"tests/{name}\""));
            if !listed {
                missing.push(dir.join(&name).display().to_string());
            }
        }
    }
    assert!(checked > 60, "{checked} test files seen");
    assert!(
        missing.is_empty(),
        "test files not built (add `mod NAME;` to the folder's main.rs): {missing:?}"
    );
}
