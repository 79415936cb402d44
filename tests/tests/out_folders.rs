//! Output folders never touch the user's things (issue 29, INTERFACE.md
//! "Output folders"): every writing command, against every kind of thing
//! in the way of every name it writes (a folder with the user's files, a
//! link to a folder, a link to a file outside DIR, a FIFO, a read-only
//! file), exits 2 naming it, leaves it as it was (contents, link target,
//! mode) and writes nothing. What enginedyn wrote itself (a regular file, a
//! run folder holding an earlier run's `summary.json`) is replaced.

use enginedyn_tests::{binary, data};
use std::collections::BTreeMap;
use std::os::unix::fs::{FileTypeExt as _, PermissionsExt as _, symlink};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// Runs the binary with `args` then `--out DIR`.
fn run_into(args: &[String], dir: &Path) -> Output {
    Command::new(binary())
        .args(args)
        .arg("--out")
        .arg(dir)
        .stdin(Stdio::null())
        .output()
        .expect("run enginedyn")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Every command that writes `--out DIR`, with arguments that make it fast.
fn commands() -> Vec<(&'static str, Vec<String>)> {
    let single = data("single.toml");
    let owned = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        ("run", owned(&["run"])),
        (
            "batch",
            owned(&["batch", "--engine", &single, &data("single.csv")]),
        ),
        (
            "batch --detail",
            owned(&[
                "batch",
                "--engine",
                &single,
                "--detail",
                &data("single.csv"),
                &data("single.csv"),
            ]),
        ),
        (
            "sweep",
            owned(&["sweep", "--engine", &single, "--rpm", "1000:2000:1000"]),
        ),
        ("kinematics", owned(&["kinematics", "--engine", &single])),
        (
            "firing-orders",
            owned(&["firing-orders", "--engine", &data("vaz2108.toml")]),
        ),
        (
            "tolerance",
            owned(&["tolerance", "--engine", &single, "--samples", "0"]),
        ),
        (
            "torsion",
            owned(&["torsion", "--engine", &data("i6_diesel.toml")]),
        ),
        ("accuracy", owned(&["accuracy", "--engine", &single])),
    ]
}

/// What a path is, never following a link: kind, mode, contents or target;
/// a folder's entries recursively.
fn snapshot(root: &Path) -> BTreeMap<PathBuf, String> {
    fn walk(p: &Path, into: &mut BTreeMap<PathBuf, String>) {
        let m = std::fs::symlink_metadata(p).unwrap();
        let t = m.file_type();
        let mode = m.permissions().mode() & 0o7777;
        let what = if t.is_symlink() {
            format!("link -> {}", std::fs::read_link(p).unwrap().display())
        } else if t.is_fifo() {
            format!("fifo {mode:o}")
        } else if t.is_file() {
            format!("file {mode:o} {:?}", std::fs::read(p).unwrap())
        } else if t.is_dir() {
            let mut names: Vec<PathBuf> = std::fs::read_dir(p)
                .unwrap()
                .map(|e| e.unwrap().path())
                .collect();
            names.sort();
            for n in &names {
                walk(n, into);
            }
            format!("folder {mode:o}")
        } else {
            "other".into()
        };
        into.insert(p.to_path_buf(), what);
    }
    let mut into = BTreeMap::new();
    walk(root, &mut into);
    into
}

/// The kinds of thing in the way, made at `at`; `outside` holds a file
/// and a folder of the user's beside DIR.
const KINDS: [&str; 5] = [
    "folder",
    "link to a folder",
    "link to a file",
    "FIFO",
    "read-only file",
];

fn make(kind: &str, at: &Path, outside: &Path) {
    match kind {
        "folder" => {
            std::fs::create_dir(at).unwrap();
            std::fs::write(at.join("thesis.tex"), "the user's work").unwrap();
        }
        "link to a folder" => symlink(outside.join("photos"), at).unwrap(),
        "link to a file" => symlink(outside.join("notes.txt"), at).unwrap(),
        "FIFO" => {
            let ok = Command::new("mkfifo").arg(at).status().unwrap();
            assert!(ok.success(), "mkfifo");
        }
        "read-only file" => {
            std::fs::write(at, "protected").unwrap();
            std::fs::set_permissions(at, std::fs::Permissions::from_mode(0o444)).unwrap();
        }
        other => unreachable!("{other}"),
    }
}

/// What the message calls it, for a file's name or a run folder's.
fn called(kind: &str, run_folder: bool) -> &'static str {
    match kind {
        "folder" if run_folder => "a folder without an earlier run's summary.json",
        "folder" => "a folder",
        "link to a folder" | "link to a file" => "a symbolic link",
        "FIFO" => "a FIFO",
        "read-only file" if run_folder => "a file",
        _ => "a read-only file",
    }
}

/// One command against every kind of thing in the way of every name it
/// writes (learnt from a run into an empty folder).
fn refuses_everything_in_the_way(command: &str) {
    let (_, args) = commands().into_iter().find(|(c, _)| *c == command).unwrap();
    let fresh = tempfile::tempdir().unwrap();
    let out = run_into(&args, fresh.path());
    assert_eq!(
        out.status.code(),
        Some(0),
        "{command}: {}",
        text(&out.stderr)
    );
    let mut names: Vec<(String, bool)> = std::fs::read_dir(fresh.path())
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            (name, e.file_type().unwrap().is_dir())
        })
        .collect();
    names.sort();
    assert!(!names.is_empty(), "{command} wrote nothing");
    if command == "batch --detail" {
        let folders: Vec<&str> = names
            .iter()
            .filter(|(_, d)| *d)
            .map(|(n, _)| n.as_str())
            .collect();
        assert_eq!(folders, ["0001_single", "0002_single"]);
    }
    for (name, run_folder) in &names {
        for kind in KINDS {
            let t = tempfile::tempdir().unwrap();
            let outside = t.path().join("outside");
            std::fs::create_dir_all(outside.join("photos")).unwrap();
            std::fs::write(outside.join("photos/cat.jpg"), "meow").unwrap();
            std::fs::write(outside.join("notes.txt"), "the user's notes").unwrap();
            let dir = t.path().join("out");
            std::fs::create_dir(&dir).unwrap();
            let at = dir.join(name);
            make(kind, &at, &outside);
            let before = (snapshot(&dir), snapshot(&outside));
            let out = run_into(&args, &dir);
            let err = text(&out.stderr);
            let case = format!("{command}: {kind} as {name}");
            assert_eq!(out.status.code(), Some(2), "{case}: {err}");
            assert!(!err.contains("panicked"), "{case}: {err}");
            let named = format!(
                "{}: {} is in the way",
                at.display(),
                called(kind, *run_folder)
            );
            assert!(err.contains(&named), "{case}: wanted `{named}` in {err}");
            assert_eq!(
                (snapshot(&dir), snapshot(&outside)),
                before,
                "{case}: touched, or something written"
            );
        }
    }
}

#[test]
fn run_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("run");
}

#[test]
fn batch_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("batch");
    refuses_everything_in_the_way("batch --detail");
}

#[test]
fn sweep_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("sweep");
}

#[test]
fn kinematics_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("kinematics");
}

#[test]
fn firing_orders_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("firing-orders");
}

#[test]
fn tolerance_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("tolerance");
}

#[test]
fn torsion_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("torsion");
}

#[test]
fn accuracy_refuses_what_is_in_the_way() {
    refuses_everything_in_the_way("accuracy");
}

/// The second run folder in the way stops the batch before the first is
/// written: every name is checked before anything is.
#[test]
fn batch_checks_every_run_folder_first() {
    let (_, args) = commands()
        .into_iter()
        .find(|(c, _)| *c == "batch --detail")
        .unwrap();
    let t = tempfile::tempdir().unwrap();
    let dir = t.path().join("out");
    std::fs::create_dir(&dir).unwrap();
    // A folder of the user's that happens to have a run folder's name.
    std::fs::create_dir(dir.join("0002_single")).unwrap();
    std::fs::write(dir.join("0002_single/data.csv"), "1,2").unwrap();
    let before = snapshot(&dir);
    let out = run_into(&args, &dir);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("0002_single: a folder without an earlier run's summary.json"),
        "{}",
        text(&out.stderr)
    );
    assert_eq!(snapshot(&dir), before);
}

/// What enginedyn wrote is replaced: a regular file of a name it writes,
/// and a run folder holding an earlier run's summary.json; the second run
/// leaves the same names as the first.
#[test]
fn what_enginedyn_wrote_is_replaced() {
    for command in ["run", "batch --detail", "kinematics"] {
        let (_, args) = commands().into_iter().find(|(c, _)| *c == command).unwrap();
        let t = tempfile::tempdir().unwrap();
        let first = run_into(&args, t.path());
        assert_eq!(first.status.code(), Some(0), "{}", text(&first.stderr));
        let names = |d: &Path| {
            let mut v: Vec<String> = std::fs::read_dir(d)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        };
        let listed = names(t.path());
        // A file of ours the user overwrote is still a writable file of
        // ours: replaced.
        // An output, not the manifest (which sorts first).
        let some_file = listed
            .iter()
            .find(|n| !n.starts_with('.') && n.contains('.'))
            .unwrap();
        std::fs::write(t.path().join(some_file), "stale").unwrap();
        let again = run_into(&args, t.path());
        assert_eq!(
            again.status.code(),
            Some(0),
            "{command}: {}",
            text(&again.stderr)
        );
        assert_eq!(names(t.path()), listed, "{command}");
        assert_ne!(
            std::fs::read(t.path().join(some_file)).unwrap(),
            b"stale",
            "{command}: {some_file} replaced"
        );
    }
}
