//! Issue 30, item 6: a folder written again holds this run's outputs alone
//! (INTERFACE.md, "Output folders"). `DIR/.enginedyn-manifest` lists what
//! each run wrote with its SHA-256; an earlier run's output that this run
//! does not write is removed when it is unchanged, kept with a warning when
//! the user changed it; a file the user added is never touched.

use enginedyn_tests::sha256sum;
use enginedyn_tests::{binary, data};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

const MANIFEST: &str = ".enginedyn-manifest";

fn run(args: &[&str]) -> Output {
    std::process::Command::new(binary())
        .args(args)
        .output()
        .expect("run enginedyn")
}

fn ok(args: &[&str]) -> String {
    let out = run(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {err}");
    err
}

/// Every name in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The manifest as path → hash, each line `HASH  PATH` under a
/// `# enginedyn COMMAND` heading.
fn manifest(dir: &Path) -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(dir.join(MANIFEST)).expect("the manifest");
    text.lines()
        .filter(|l| !l.starts_with("# enginedyn "))
        .map(|l| {
            let (hash, path) = l.split_once("  ").expect("HASH  PATH");
            (path.to_string(), hash.to_string())
        })
        .collect()
}

/// Every file under `dir` but the manifest, as paths relative to it.
fn files_under(dir: &Path) -> Vec<String> {
    let mut v = Vec::new();
    for name in names(dir) {
        let p = dir.join(&name);
        if p.is_dir() {
            v.extend(names(&p).into_iter().map(|f| format!("{name}/{f}")));
        } else if name != MANIFEST {
            v.push(name);
        }
    }
    v
}

/// The manifest lists exactly the files `expected` (relative paths), each
/// with the hash `sha256sum` gives.
fn manifest_lists(dir: &Path, expected: &[String]) {
    let m = manifest(dir);
    let listed: Vec<&String> = m.keys().collect();
    let mut want: Vec<&String> = expected.iter().collect();
    want.sort();
    assert_eq!(listed, want);
    for (path, hash) in &m {
        assert_eq!(hash, &sha256sum(dir.join(path)), "{path}");
    }
}

/// `run` into one folder: the bundled engine, then the six-cylinder diesel
/// (tolerance and torsion charts), then the bundled engine again. The
/// diesel's Campbell diagram is gone after the third run; its torsion
/// chart, which the user edited, is kept with a warning; the user's own
/// file stays.
#[test]
fn run_again_removes_what_the_earlier_run_wrote_alone() {
    let t = tempfile::tempdir().unwrap();
    let d = t.path().join("out");
    let out = d.to_str().unwrap();
    ok(&["run", "--out", out]);
    let bundled = names(&d);
    assert!(bundled.contains(&MANIFEST.to_string()), "{bundled:?}");
    assert!(!bundled.contains(&"campbell.svg".to_string()));
    manifest_lists(&d, &files_under(&d));

    let diesel = data("i6_diesel.toml");
    ok(&["run", "--engine", &diesel, "--out", out]);
    let all = names(&d);
    for f in ["campbell.svg", "torsion.svg", "tolerance.svg"] {
        assert!(all.contains(&f.to_string()), "{f}: {all:?}");
    }
    manifest_lists(&d, &files_under(&d));

    // The user edits one of the diesel's outputs and adds a file of their own.
    std::fs::write(d.join("torsion.svg"), "<svg>annotated by hand</svg>").unwrap();
    std::fs::write(d.join("my_notes.txt"), "the user's").unwrap();
    let err = ok(&["run", "--out", out]);

    let mut expected = bundled.clone();
    expected.extend(["my_notes.txt".to_string(), "torsion.svg".to_string()]);
    expected.sort();
    assert_eq!(names(&d), expected, "campbell.svg is stale and unchanged");
    assert_eq!(
        std::fs::read_to_string(d.join("torsion.svg")).unwrap(),
        "<svg>annotated by hand</svg>"
    );
    assert_eq!(
        std::fs::read_to_string(d.join("my_notes.txt")).unwrap(),
        "the user's"
    );
    let warning = err
        .lines()
        .find(|l| l.contains("torsion.svg"))
        .unwrap_or_else(|| panic!("no note on torsion.svg: {err}"));
    assert!(
        warning.starts_with("warning: ")
            && warning.contains("changed since")
            && warning.contains("kept")
            && warning.contains("may be stale"),
        "{warning}"
    );
    assert!(!err.contains("my_notes.txt"), "{err}");
    // The manifest lists this run's files alone: neither the kept file nor
    // the user's.
    let now: Vec<String> = files_under(&d)
        .into_iter()
        .filter(|f| f != "torsion.svg" && f != "my_notes.txt")
        .collect();
    manifest_lists(&d, &now);

    // Neither is ever removed by a later run either.
    ok(&["run", "--out", out]);
    assert_eq!(names(&d), expected);
}

/// `batch --detail` into one folder, with two files and then one: the
/// second file's run folder is gone, index.html and summary.csv list one
/// row; a run folder the user changed is kept whole with a warning; the
/// user's own files stay.
#[test]
fn batch_again_with_fewer_files_removes_their_run_folders() {
    let t = tempfile::tempdir().unwrap();
    let d = t.path().join("out");
    let out = d.to_str().unwrap();
    let engine = data("single.toml");
    let diagram = std::fs::read_to_string(data("single.csv")).unwrap();
    let files: Vec<String> = ["first", "second", "third"]
        .iter()
        .map(|n| {
            let p = t.path().join(format!("{n}.csv"));
            std::fs::write(&p, &diagram).unwrap();
            p.to_str().unwrap().to_string()
        })
        .collect();
    let batch = |diagrams: &[String]| {
        let mut args = vec!["batch", "--engine", &engine, "--out", out, "--detail"];
        args.extend(diagrams.iter().map(String::as_str));
        ok(&args)
    };

    batch(&files[..2]);
    assert_eq!(
        names(&d),
        [
            MANIFEST,
            "0001_first",
            "0002_second",
            "index.html",
            "summary.csv"
        ]
    );
    manifest_lists(&d, &files_under(&d));
    std::fs::write(d.join("mine.txt"), "the user's").unwrap();
    batch(&files[..1]);
    assert_eq!(
        names(&d),
        [
            MANIFEST,
            "0001_first",
            "index.html",
            "mine.txt",
            "summary.csv"
        ]
    );
    let index = std::fs::read_to_string(d.join("index.html")).unwrap();
    assert!(
        index.contains("0001_first") && !index.contains("0002_"),
        "{index}"
    );
    let csv = std::fs::read_to_string(d.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 2, "{csv}");
    let now: Vec<String> = files_under(&d)
        .into_iter()
        .filter(|f| f != "mine.txt")
        .collect();
    manifest_lists(&d, &now);

    // Three files, then the user edits the third's report, then two: the
    // edited run folder is kept whole (its summary.json with it), with a
    // warning naming the file.
    batch(&files);
    std::fs::write(d.join("0003_third/report.html"), "<p>my comments</p>").unwrap();
    let err = batch(&files[..2]);
    assert!(d.join("0003_third/summary.json").is_file());
    assert_eq!(
        std::fs::read_to_string(d.join("0003_third/report.html")).unwrap(),
        "<p>my comments</p>"
    );
    let warning = err
        .lines()
        .find(|l| l.contains("0003_third"))
        .unwrap_or_else(|| panic!("no note on 0003_third: {err}"));
    assert!(
        warning.starts_with("warning: ")
            && warning.contains("report.html changed since")
            && warning.contains("may be stale"),
        "{warning}"
    );
    // Still a run folder of an earlier run: the next batch of three
    // replaces it.
    batch(&files);
    assert_ne!(
        std::fs::read_to_string(d.join("0003_third/report.html")).unwrap(),
        "<p>my comments</p>"
    );
    assert!(d.join("mine.txt").is_file());
}

/// A manifest line naming something outside the folder (or a hidden name)
/// is never acted on, even when its hash matches.
#[test]
fn the_manifest_never_reaches_outside_the_folder() {
    let t = tempfile::tempdir().unwrap();
    let d = t.path().join("out");
    let victim = t.path().join("victim.txt");
    std::fs::write(&victim, "keep me").unwrap();
    std::fs::create_dir(&d).unwrap();
    std::fs::write(d.join(".hidden"), "keep me").unwrap();
    let hash = sha256sum(&victim);
    std::fs::write(
        d.join(MANIFEST),
        format!(
            "{hash}  ../victim.txt\n{hash}  {}\n{hash}  .hidden\n",
            victim.display()
        ),
    )
    .unwrap();
    ok(&[
        "kinematics",
        "--engine",
        &data("single.toml"),
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    assert!(d.join(".hidden").is_file());
    // The manifest now lists what kinematics wrote, and nothing else.
    let listed: Vec<String> = manifest(&d).into_keys().collect();
    assert_eq!(listed, ["kinematics.csv", "kinematics.svg"]);
}

/// Another command's outputs are not this one's: `accuracy --out D` after
/// `run --out D` (as `reports/` holds both) removes none of the run's files,
/// and a rerun of `run` removes none of the accuracy's.
#[test]
fn another_commands_outputs_stay() {
    let t = tempfile::tempdir().unwrap();
    let d = t.path().join("d");
    let ds = d.to_str().unwrap();
    let engine = enginedyn_tests::data("single.toml");
    for (k, args) in [
        vec!["run", "--engine", &engine, "--out", ds],
        vec!["accuracy", "--engine", &engine, "--out", ds],
        vec!["run", "--engine", &engine, "--out", ds],
    ]
    .into_iter()
    .enumerate()
    {
        let o = enginedyn_tests::run(&args);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        // Right after `accuracy`, the run's outputs are all still there.
        if k == 1 {
            for f in ["report.html", "summary.json", "torque.svg", "curves.csv"] {
                assert!(d.join(f).exists(), "accuracy removed {f}");
            }
        }
    }
    for f in [
        "report.html",
        "summary.json",
        "accuracy.csv",
        "accuracy.svg",
    ] {
        assert!(d.join(f).exists(), "{f}");
    }
}
