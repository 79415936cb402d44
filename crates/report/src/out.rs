//! The one writer of output folders (INTERFACE.md, "Output folders"):
//! every command writes `--out DIR` through an [`OutDir`].
//!
//! - **A lock on DIR** for the whole command: the folder itself is locked
//!   (`flock` on its descriptor, so no lock file is left behind). A second
//!   command writing the same DIR waits up to [`LOCK_WAIT`] for it, then
//!   refuses ([`ReportError::Locked`]); two writers never mix.
//! - **A staging folder per write**, created exclusively inside DIR with an
//!   unpredictable name (`tempfile`): a link planted in DIR cannot redirect
//!   a write, and nothing is written outside it until every file is whole.
//! - **Moved into place only when complete**: the old files the write
//!   replaces are moved aside into the staging folder first, then the new
//!   ones in; a failure on the way moves the old ones back, and the staging
//!   folder is removed in every case. A run folder of a batch
//!   (`DIR/NNNN_STEM/`) is staged whole and renamed into place in one step.
//! - **Leftovers of a killed run** (staging folders, whose names start with
//!   [`STAGING_PREFIX`]) are removed when the next command takes the lock.

use crate::ReportError;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How long a command waits for another one writing the same folder.
pub const LOCK_WAIT: Duration = Duration::from_secs(30);

/// The start of every staging folder's name.
pub const STAGING_PREFIX: &str = ".enginedyn-staging-";

/// An output folder held by this command: locked, cleaned of what a killed
/// run left, written file set by file set.
#[derive(Debug)]
pub struct OutDir {
    dir: PathBuf,
    /// The lock: held while this value lives.
    _lock: File,
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    }
}

impl OutDir {
    /// Creates `dir` if needed, takes its lock (waiting up to
    /// [`LOCK_WAIT`]) and removes the staging folders a killed run left.
    pub fn open(dir: &Path) -> Result<Self, ReportError> {
        Self::open_waiting(dir, LOCK_WAIT)
    }

    /// [`OutDir::open`] with another wait for the lock.
    pub fn open_waiting(dir: &Path, wait: Duration) -> Result<Self, ReportError> {
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let meta = std::fs::metadata(dir).map_err(io(dir))?;
        if !meta.is_dir() {
            return Err(ReportError::Io {
                path: dir.to_path_buf(),
                source: std::io::Error::new(std::io::ErrorKind::NotADirectory, "not a folder"),
            });
        }
        let lock = File::open(dir).map_err(io(dir))?;
        let started = Instant::now();
        loop {
            match lock.try_lock() {
                Ok(()) => break,
                Err(std::fs::TryLockError::WouldBlock) if started.elapsed() < wait => {
                    std::thread::sleep(Duration::from_millis(50));
                }
                Err(std::fs::TryLockError::WouldBlock) => {
                    return Err(ReportError::Locked {
                        path: dir.to_path_buf(),
                        waited: wait,
                    });
                }
                Err(std::fs::TryLockError::Error(e)) => return Err(io(dir)(e)),
            }
        }
        let out = Self {
            dir: dir.to_path_buf(),
            _lock: lock,
        };
        out.remove_leftovers();
        Ok(out)
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// Staging folders a killed run left (only this command writes DIR now).
    fn remove_leftovers(&self) {
        let Ok(entries) = std::fs::read_dir(&self.dir) else {
            return;
        };
        for e in entries.flatten() {
            let name = e.file_name();
            let is_staging = name.to_string_lossy().starts_with(STAGING_PREFIX);
            // Never follow a link: only a real folder of ours is removed.
            if is_staging && e.file_type().is_ok_and(|t| t.is_dir()) {
                let _ = std::fs::remove_dir_all(e.path());
            }
        }
    }

    /// A fresh staging folder inside DIR, unpredictable and created
    /// exclusively; removed when dropped.
    fn staging(&self) -> Result<tempfile::TempDir, ReportError> {
        tempfile::Builder::new()
            .prefix(STAGING_PREFIX)
            .tempdir_in(&self.dir)
            .map_err(io(&self.dir))
    }

    /// Writes `files` (name, bytes) into DIR: each appears whole or not at
    /// all, and either every one of them is the new version or (after a
    /// failure) every one is as it was.
    pub fn write(&self, files: &[(String, Vec<u8>)]) -> Result<(), ReportError> {
        let stage = self.staging()?;
        let new = stage.path().join("new");
        let old = stage.path().join("old");
        std::fs::create_dir(&new).map_err(io(&new))?;
        std::fs::create_dir(&old).map_err(io(&old))?;
        for (name, bytes) in files {
            check_name(name)?;
            write_new(&new.join(name), bytes)?;
        }
        // Old aside, new in; on a failure undo what was done.
        let mut moved_aside: Vec<&str> = Vec::new();
        let mut moved_in: Vec<&str> = Vec::new();
        let result = (|| {
            for (name, _) in files {
                let target = self.dir.join(name);
                if std::fs::symlink_metadata(&target).is_ok() {
                    std::fs::rename(&target, old.join(name)).map_err(io(&target))?;
                    moved_aside.push(name);
                }
                std::fs::rename(new.join(name), &target).map_err(io(&target))?;
                moved_in.push(name);
            }
            Ok(())
        })();
        if result.is_err() {
            for name in &moved_in {
                let _ = std::fs::remove_file(self.dir.join(name));
            }
            for name in &moved_aside {
                let _ = std::fs::rename(old.join(name), self.dir.join(name));
            }
        }
        drop(stage);
        result
    }

    /// Writes `files` as the subfolder `name` of DIR (a batch's run
    /// folder): staged whole, then renamed into place in one step, the old
    /// folder of that name (an earlier run's) removed.
    pub fn write_folder(&self, name: &str, files: &[(String, Vec<u8>)]) -> Result<(), ReportError> {
        check_name(name)?;
        let stage = self.staging()?;
        let folder = stage.path().join("new");
        std::fs::create_dir(&folder).map_err(io(&folder))?;
        for (file, bytes) in files {
            check_name(file)?;
            write_new(&folder.join(file), bytes)?;
        }
        let target = self.dir.join(name);
        if std::fs::symlink_metadata(&target).is_ok() {
            let old = stage.path().join("old");
            std::fs::rename(&target, &old).map_err(io(&target))?;
        }
        std::fs::rename(&folder, &target).map_err(io(&target))?;
        drop(stage);
        Ok(())
    }
}

/// A file name of ours: one plain component, never a path or a hidden name.
fn check_name(name: &str) -> Result<(), ReportError> {
    let plain = !name.is_empty()
        && !name.starts_with('.')
        && !name.contains(['/', '\\', '\0'])
        && Path::new(name).components().count() == 1;
    if plain {
        Ok(())
    } else {
        Err(ReportError::Io {
            path: PathBuf::from(name),
            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a plain file name"),
        })
    }
}

/// Creates `path` (which must not exist: never through a link) and writes
/// `bytes` to it, flushed to the disk.
fn write_new(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    let mut f = File::create_new(path).map_err(io(path))?;
    if let Some(err) = injected_failure() {
        return Err(io(path)(err));
    }
    f.write_all(bytes).map_err(io(path))?;
    f.sync_all().map_err(io(path))
}

/// Tests only: `ENGINEDYN_TEST_WRITE_FAIL=N` makes the N-th file this
/// process writes fail as a full disk does (no space left), so that the
/// end-to-end tests can check that a failed write leaves nothing behind.
fn injected_failure() -> Option<std::io::Error> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static WRITTEN: AtomicUsize = AtomicUsize::new(0);
    let n: usize = std::env::var("ENGINEDYN_TEST_WRITE_FAIL")
        .ok()?
        .parse()
        .ok()?;
    let k = WRITTEN.fetch_add(1, Ordering::Relaxed) + 1;
    (k == n).then(|| std::io::Error::from_raw_os_error(28)) // ENOSPC
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(tag: &str) -> Vec<(String, Vec<u8>)> {
        (0..5)
            .map(|k| (format!("f{k}.txt"), format!("{tag} {k}").into_bytes()))
            .collect()
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_whole_and_leaves_nothing_hidden() {
        let d = tempfile::tempdir().unwrap();
        let out = OutDir::open(d.path()).unwrap();
        out.write(&files("a")).unwrap();
        out.write(&files("b")).unwrap();
        assert_eq!(
            listing(d.path()),
            ["f0.txt", "f1.txt", "f2.txt", "f3.txt", "f4.txt"]
        );
        assert_eq!(
            std::fs::read_to_string(d.path().join("f3.txt")).unwrap(),
            "b 3"
        );
        out.write_folder("0001_x", &files("c")).unwrap();
        out.write_folder("0001_x", &files("d")).unwrap();
        assert_eq!(
            std::fs::read_to_string(d.path().join("0001_x/f0.txt")).unwrap(),
            "d 0"
        );
        assert_eq!(listing(d.path()).len(), 6);
    }

    #[test]
    fn a_second_writer_is_refused_and_leftovers_are_removed() {
        let d = tempfile::tempdir().unwrap();
        let first = OutDir::open(d.path()).unwrap();
        let e = OutDir::open_waiting(d.path(), Duration::from_millis(100)).unwrap_err();
        assert!(matches!(e, ReportError::Locked { .. }), "{e}");
        // A killed run's staging folder is removed by the next command.
        std::fs::create_dir(d.path().join(format!("{STAGING_PREFIX}abc"))).unwrap();
        std::fs::write(d.path().join(format!("{STAGING_PREFIX}abc/half")), "x").unwrap();
        drop(first);
        let _second = OutDir::open(d.path()).unwrap();
        assert!(listing(d.path()).is_empty());
    }

    #[test]
    fn names_are_plain() {
        let d = tempfile::tempdir().unwrap();
        let out = OutDir::open(d.path()).unwrap();
        for bad in ["../x", "a/b", ".hidden", ""] {
            assert!(out.write(&[(bad.to_string(), vec![1])]).is_err(), "{bad}");
        }
        assert!(listing(d.path()).is_empty());
    }
}
