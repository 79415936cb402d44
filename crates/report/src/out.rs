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
//! - **Only what enginedyn wrote is replaced**: a regular, writable file of
//!   a name the command writes, or a run folder that holds an earlier
//!   run's `summary.json`. Anything else in the way (a folder, a symbolic
//!   link, a FIFO, a device, a read-only file) is never moved or removed:
//!   [`OutDir::check`] refuses it ([`ReportError::InTheWay`]) before
//!   anything is written, and every move re-checks what it moves aside.
//! - **Leftovers of a killed run** (staging folders, whose names start with
//!   [`STAGING_PREFIX`]) are removed when the next command takes the lock.
//! - **A folder written again holds this run's outputs alone**: every
//!   command's last [`OutDir::write`] records what the command wrote
//!   ([`MANIFEST`], `DIR/.enginedyn-manifest`: each file, run folders'
//!   files too, with its SHA-256, in `sha256sum` format) and removes what
//!   the earlier run's manifest lists and this run did not write, when it is
//!   still as that run wrote it (its hash unchanged; a run folder when every
//!   file in it is, and it holds nothing else). A file or run folder changed
//!   since is kept, with a note; a file the manifest does not list (the
//!   user's own) is never touched. The manifest is staged with the other files and
//!   moved into place last: a killed run leaves the earlier run's manifest,
//!   never one that lists files this run did not write.

use crate::ReportError;
use sha2::{Digest as _, Sha256};
use std::collections::BTreeSet;
use std::fs::File;
use std::io::{BufRead as _, Read as _, Write as _};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How long a command waits for another one writing the same folder.
pub const LOCK_WAIT: Duration = Duration::from_secs(30);

/// The start of every staging folder's name.
pub const STAGING_PREFIX: &str = ".enginedyn-staging-";

/// The record of what the last run wrote into an output folder: one line
/// per file, `HASH  PATH` as `sha256sum` writes it (`sha256sum -c
/// .enginedyn-manifest` inside the folder checks it), PATH relative to the
/// folder (`report.html`, `0001_a/summary.json`), sorted.
pub const MANIFEST: &str = ".enginedyn-manifest";

/// The largest manifest read: one larger (not enginedyn's) is ignored, and
/// then nothing is removed.
const MAX_MANIFEST: u64 = 256 << 20;

/// An output folder held by this command: locked, cleaned of what a killed
/// run left, written file set by file set.
#[derive(Debug)]
pub struct OutDir {
    dir: PathBuf,
    /// The lock: held while this value lives.
    _lock: File,
    /// The command writing (`run`, `batch`, …): a folder written again
    /// by the same command holds its outputs alone; another command's
    /// outputs in the folder are left as they are.
    command: String,
    /// What the earlier runs' manifest lists: (command, path, SHA-256 in hex).
    earlier: Vec<(String, String, String)>,
    /// What this command has written so far: (path, SHA-256 in hex), run
    /// folders' files as `FOLDER/NAME`.
    written: Mutex<Vec<(String, String)>>,
}

/// The BLAKE3 of `bytes` in lowercase hex, as `b3sum` prints it.
pub fn blake3_hex(bytes: &[u8]) -> String {
    blake3::hash(bytes).to_hex().to_string()
}

/// The BLAKE3 of a regular file's bytes, read in blocks (a file an
/// analysis did not read: an engine file). A FIFO or a device is refused
/// before it is opened, and no more than the size it had is read.
pub fn blake3_file(path: &Path) -> Result<String, ReportError> {
    let read = |source| ReportError::Read {
        path: path.to_path_buf(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(read)?;
    if !meta.is_file() {
        return Err(read(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        )));
    }
    let mut h = blake3::Hasher::new();
    let file = File::open(path).map_err(io(path))?;
    std::io::copy(
        &mut std::io::BufReader::with_capacity(1 << 16, file).take(meta.len()),
        &mut h,
    )
    .map_err(io(path))?;
    Ok(h.finalize().to_hex().to_string())
}

/// The SHA-256 of `bytes` in lowercase hex, as `sha256sum` prints it.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// The SHA-256 of the regular file at `path` in lowercase hex, read in
/// blocks (a FIFO or device is refused before it is opened).
pub fn sha256_file(path: &Path) -> Result<String, ReportError> {
    let read = |source| ReportError::Read {
        path: path.to_path_buf(),
        source,
    };
    if !std::fs::metadata(path).map_err(read)?.is_file() {
        return Err(read(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        )));
    }
    let mut f = File::open(path).map_err(read)?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = f.read(&mut buf).map_err(read)?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
    }
    Ok(hex(&h.finalize()))
}

fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write as _;
    let mut s = String::with_capacity(2 * bytes.len());
    for b in bytes {
        let _ = write!(s, "{b:02x}");
    }
    s
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
        // A file (or anything but a folder) where the folder goes is in the
        // way, as one where a file goes is: refused, untouched.
        if let Ok(meta) = std::fs::metadata(dir)
            && !meta.is_dir()
        {
            return Err(ReportError::InTheWay {
                path: dir.to_path_buf(),
                what: if meta.is_file() {
                    "a file"
                } else {
                    special(&meta.file_type())
                },
                run_folder: false,
                tables: false,
            });
        }
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
        let mut out = Self {
            dir: dir.to_path_buf(),
            _lock: lock,
            command: String::new(),
            earlier: Vec::new(),
            written: Mutex::new(Vec::new()),
        };
        out.remove_leftovers();
        out.earlier = read_manifest(&out.dir.join(MANIFEST));
        Ok(out)
    }

    /// The command that writes (`run`, `accuracy`, …), as the manifest
    /// records it: a rerun of the same command removes its own stale
    /// outputs, never another command's.
    #[must_use]
    pub fn for_command(mut self, command: &str) -> Self {
        self.command = command.to_string();
        self
    }

    /// [`OutDir::open`], then [`OutDir::check`] of the `files` and run
    /// `folders` the command will write: a command calls it before its
    /// work, so that a thing in the way is refused before anything is
    /// computed or written.
    pub fn open_for<F: AsRef<str>, D: AsRef<str>>(
        dir: &Path,
        files: &[F],
        folders: &[D],
    ) -> Result<Self, ReportError> {
        let out = Self::open(dir)?;
        out.check(files, folders)?;
        Ok(out)
    }

    /// Whether every name the command will write may be written: each of
    /// `files` is absent or a regular, writable file (an earlier run's), each
    /// of `folders` absent or a real folder holding an earlier run's
    /// `summary.json`; and so is the [`MANIFEST`]. The first thing in the
    /// way is refused ([`ReportError::InTheWay`], naming it); nothing is
    /// changed. Links are never followed.
    pub fn check<F: AsRef<str>, D: AsRef<str>>(
        &self,
        files: &[F],
        folders: &[D],
    ) -> Result<(), ReportError> {
        self.replaceable(MANIFEST, Target::File)?;
        for name in files {
            check_name(name.as_ref())?;
            self.replaceable(name.as_ref(), Target::File)?;
        }
        for name in folders {
            check_name(name.as_ref())?;
            self.replaceable(name.as_ref(), Target::RunFolder)?;
        }
        Ok(())
    }

    /// `Ok(true)` when `name` exists and may be replaced, `Ok(false)` when
    /// it does not exist, the refusal when something else is in the way.
    fn replaceable(&self, name: &str, target: Target) -> Result<bool, ReportError> {
        replaceable(self.dir.join(name), target)
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

    /// Writes `files` (name, bytes) into DIR, the command's last write
    /// (after its run folders, [`OutDir::write_folder`]): each appears whole
    /// or not at all, and either every one of them is the new version or
    /// (after a failure) every one is as it was.
    /// Nothing but a regular, writable file is replaced: anything else of
    /// one of the names is refused ([`OutDir::check`]) before anything is
    /// written, and checked again as it is moved aside.
    ///
    /// Then the folder is made to hold this command's outputs alone: what
    /// the earlier run's [`MANIFEST`] lists and this command did not write
    /// is removed when it is unchanged (a run folder whole, when every file
    /// in it is and it holds nothing else),
    /// and the new manifest, staged with the files, is moved into place
    /// last. Returns the notes to print as warnings: the earlier outputs
    /// kept because they changed since (they may be stale).
    pub fn write(&self, files: &[(String, Vec<u8>)]) -> Result<Vec<String>, ReportError> {
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        self.check::<&str, &str>(&names, &[])?;
        let stage = self.staging()?;
        let new = stage.path().join("new");
        let old = stage.path().join("old");
        std::fs::create_dir(&new).map_err(io(&new))?;
        std::fs::create_dir(&old).map_err(io(&old))?;
        let mut record = Vec::with_capacity(files.len());
        for (name, bytes) in files {
            check_name(name)?;
            write_new(&new.join(name), bytes)?;
            record.push((name.clone(), sha256_hex(bytes)));
        }
        let mut listed = self
            .written
            .lock()
            .map_or_else(|e| e.into_inner().clone(), |w| w.clone());
        listed.extend(record.iter().cloned());
        listed.sort();
        listed.dedup_by(|a, b| a.0 == b.0);
        // Other commands' outputs stay listed under their own heading,
        // but for a name this command now writes.
        let mine: BTreeSet<&str> = listed.iter().map(|(p, _)| p.as_str()).collect();
        let mut manifest_text = String::new();
        let mut heading: Option<&str> = None;
        for (cmd, path, hash) in &self.earlier {
            if cmd == &self.command || mine.contains(path.as_str()) {
                continue;
            }
            if heading != Some(cmd.as_str()) {
                manifest_text.push_str(&format!("# enginedyn {cmd}\n"));
                heading = Some(cmd);
            }
            manifest_text.push_str(&format!("{hash}  {path}\n"));
        }
        manifest_text.push_str(&format!("# enginedyn {}\n", self.command));
        for (path, hash) in &listed {
            manifest_text.push_str(&format!("{hash}  {path}\n"));
        }
        let staged_manifest = stage.path().join("manifest");
        write_new(&staged_manifest, manifest_text.as_bytes())?;
        // Old aside, new in; on a failure undo what was done.
        let mut moved_aside: Vec<&str> = Vec::new();
        let mut moved_in: Vec<&str> = Vec::new();
        let result = (|| {
            for (name, _) in files {
                let target = self.dir.join(name);
                if self.replaceable(name, Target::File)? {
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
        result?;
        if let Ok(mut w) = self.written.lock() {
            *w = listed.clone();
        }
        let notes = self.remove_stale(&listed);
        // The manifest last: it lists only what is now in place.
        let target = self.dir.join(MANIFEST);
        self.replaceable(MANIFEST, Target::File)?;
        std::fs::rename(&staged_manifest, &target).map_err(io(&target))?;
        drop(stage);
        Ok(notes)
    }

    /// Removes what the earlier run's manifest lists and `listed` (this
    /// command's outputs) does not, when it is still as that run wrote it:
    /// a file when its hash is unchanged; a run folder whole when every
    /// file it lists is unchanged (or gone) and the folder holds nothing
    /// else. A file changed since, or a run folder holding such a file or
    /// one the user added, is kept, and the note saying so returned. Links
    /// are never followed.
    fn remove_stale(&self, listed: &[(String, String)]) -> Vec<String> {
        use std::collections::BTreeMap;
        let ours: BTreeSet<&str> = listed.iter().map(|(p, _)| p.as_str()).collect();
        // A run folder this command wrote was replaced whole.
        let our_folders: BTreeSet<&str> = listed
            .iter()
            .filter_map(|(p, _)| p.split_once('/').map(|(f, _)| f))
            .collect();
        let mut notes = Vec::new();
        let mut folders: BTreeMap<&str, Vec<(&str, &str)>> = BTreeMap::new();
        for (cmd, path, hash) in &self.earlier {
            // Another command's outputs are not this one's to judge.
            if cmd != &self.command || ours.contains(path.as_str()) {
                continue;
            }
            match path.split_once('/') {
                Some((folder, file)) => {
                    if !our_folders.contains(folder) {
                        folders.entry(folder).or_default().push((file, hash));
                    }
                }
                None => match self.unchanged(path, hash) {
                    Some(true) => {
                        let file = self.dir.join(path);
                        if let Err(e) = std::fs::remove_file(&file) {
                            notes.push(format!(
                                "{}: an earlier run's output that this run does not write; cannot remove it ({e}), so it may be stale",
                                file.display()
                            ));
                        }
                    }
                    Some(false) => notes.push(format!(
                        "{}: an earlier run wrote it and this run does not, but it changed since, so it is kept; it may be stale",
                        self.dir.join(path).display()
                    )),
                    None => {}
                },
            }
        }
        for (folder, files) in folders {
            let dir = self.dir.join(folder);
            // Only a real folder, never a link to one.
            if !std::fs::symlink_metadata(&dir).is_ok_and(|m| m.is_dir()) {
                continue;
            }
            let changed: Vec<&str> = files
                .iter()
                .filter(|(f, h)| self.unchanged(&format!("{folder}/{f}"), h) == Some(false))
                .map(|(f, _)| *f)
                .collect();
            let listed: BTreeSet<&str> = files.iter().map(|(f, _)| *f).collect();
            let mut others: Vec<String> = std::fs::read_dir(&dir)
                .map(|r| {
                    r.flatten()
                        .map(|e| e.file_name().to_string_lossy().into_owned())
                        .filter(|n| !listed.contains(n.as_str()))
                        .collect()
                })
                .unwrap_or_default();
            others.sort();
            if changed.is_empty() && others.is_empty() {
                // Every file as the earlier run wrote it: the folder goes.
                for (f, _) in &files {
                    let _ = std::fs::remove_file(dir.join(f));
                }
                if let Err(e) = std::fs::remove_dir(&dir) {
                    notes.push(format!(
                        "{}: an earlier run's run folder that this run does not write; cannot remove it ({e}), so it may be stale",
                        dir.display()
                    ));
                }
            } else {
                let why = if changed.is_empty() {
                    format!(
                        "it holds files that run did not write ({})",
                        others.join(", ")
                    )
                } else {
                    format!("{} changed since", changed.join(", "))
                };
                notes.push(format!(
                    "{}: an earlier run wrote this run folder and this run does not, but {why}, so it is kept whole; it may be stale",
                    dir.display()
                ));
            }
        }
        notes
    }

    /// Whether the file `path` (relative to DIR) is still as the earlier
    /// run wrote it (`hash`): `None` when it is gone or no longer a regular
    /// file (then it is not ours to judge).
    fn unchanged(&self, path: &str, hash: &str) -> Option<bool> {
        let file = self.dir.join(path);
        let meta = std::fs::symlink_metadata(&file).ok()?;
        if !meta.file_type().is_file() {
            return None;
        }
        Some(sha256_file(&file).is_ok_and(|h| h == hash))
    }

    /// Writes `files` as the subfolder `name` of DIR (a batch's run
    /// folder): staged whole, then renamed into place in one step, the old
    /// folder of that name (an earlier run's, holding its `summary.json`)
    /// removed; anything else of that name is refused, never touched.
    pub fn write_folder(&self, name: &str, files: &[(String, Vec<u8>)]) -> Result<(), ReportError> {
        self.write_subfolder(name, files, Target::RunFolder)
    }

    /// Whether the design report's `tables` folder may be written: absent,
    /// or a real, writable folder holding an earlier report's
    /// [`TABLES_MARKER`]; else the refusal, before any work.
    pub fn check_tables(&self) -> Result<(), ReportError> {
        self.replaceable(TABLES, Target::Tables).map(|_| ())
    }

    /// Writes the design report's `tables` folder as [`OutDir::write_folder`]
    /// writes a run folder; `files` must hold the [`TABLES_MARKER`] (what
    /// makes the folder enginedyn's to replace next time).
    pub fn write_tables(&self, files: &[(String, Vec<u8>)]) -> Result<(), ReportError> {
        self.write_subfolder(TABLES, files, Target::Tables)
    }

    fn write_subfolder(
        &self,
        name: &str,
        files: &[(String, Vec<u8>)],
        kind: Target,
    ) -> Result<(), ReportError> {
        check_name(name)?;
        self.replaceable(name, kind)?;
        let stage = self.staging()?;
        let folder = stage.path().join("new");
        std::fs::create_dir(&folder).map_err(io(&folder))?;
        for (file, bytes) in files {
            check_name(file)?;
            write_new(&folder.join(file), bytes)?;
        }
        let target = self.dir.join(name);
        if self.replaceable(name, kind)? {
            let old = stage.path().join("old");
            std::fs::rename(&target, &old).map_err(io(&target))?;
        }
        std::fs::rename(&folder, &target).map_err(io(&target))?;
        drop(stage);
        let record = files
            .iter()
            .map(|(file, bytes)| (format!("{name}/{file}"), sha256_hex(bytes)));
        match self.written.lock() {
            Ok(mut w) => w.extend(record),
            Err(e) => e.into_inner().extend(record),
        }
        Ok(())
    }
}

/// `Ok(true)` when `path` exists and may be replaced by a `target`,
/// `Ok(false)` when it does not exist, the refusal when something else is
/// in the way.
fn replaceable(path: PathBuf, target: Target) -> Result<bool, ReportError> {
    let meta = match std::fs::symlink_metadata(&path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(io(&path)(e)),
    };
    match in_the_way(&path, &meta, target) {
        None => Ok(true),
        Some(what) => Err(ReportError::InTheWay {
            path,
            what,
            run_folder: target == Target::RunFolder,
            tables: target == Target::Tables,
        }),
    }
}

/// One file of a folder that several writers share (a campaign's Parquet
/// parts, written by every shard, and its `_manifest.json`), written
/// beside its final place and moved into it whole: no lock and no
/// [`MANIFEST`] (each name has one writer, and a folder written again does
/// not hold one run's outputs alone). It is staged in a folder made
/// exclusively inside the target folder with an unpredictable name
/// ([`STAGING_PREFIX`]), flushed to the disk, and renamed into place on
/// [`Staged::commit`]; dropped uncommitted, nothing is left but what a
/// killed process leaves (a hidden staging folder). What it replaces must
/// be a regular, writable file (checked before and again at the move):
/// anything else is [`ReportError::InTheWay`].
#[derive(Debug)]
pub struct Staged {
    stage: tempfile::TempDir,
    staged: PathBuf,
    file: std::io::BufWriter<File>,
    target: PathBuf,
    /// What may be replaced there.
    kind: Target,
}

impl Staged {
    /// Starts writing `name` (a plain file name) in `dir`, which is made
    /// when missing.
    pub fn new(dir: &Path, name: &str) -> Result<Self, ReportError> {
        Self::replacing(dir, name, Target::File)
    }

    /// [`Staged::new`] of a file whose name the user chose (`synth --out
    /// P.csv`): what is there is replaced only when enginedyn wrote it,
    /// a regular, writable file that begins with `marker` (the first line
    /// enginedyn writes in such a file); anything else, a measured diagram
    /// of that name too, is [`ReportError::InTheWay`].
    pub fn new_marked(dir: &Path, name: &str, marker: &'static str) -> Result<Self, ReportError> {
        Self::replacing(dir, name, Target::Marked(marker))
    }

    fn replacing(dir: &Path, name: &str, kind: Target) -> Result<Self, ReportError> {
        check_name(name)?;
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let target = dir.join(name);
        replaceable(target.clone(), kind)?;
        let stage = tempfile::Builder::new()
            .prefix(STAGING_PREFIX)
            .tempdir_in(dir)
            .map_err(io(dir))?;
        let staged = stage.path().join(name);
        let file = File::create_new(&staged).map_err(io(&staged))?;
        if let Some(err) = injected_failure() {
            return Err(io(&staged)(err));
        }
        Ok(Self {
            stage,
            file: std::io::BufWriter::with_capacity(1 << 16, file),
            staged,
            target,
            kind,
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// Flushes the file to the disk and moves it into place.
    pub fn commit(self) -> Result<(), ReportError> {
        let file = self
            .file
            .into_inner()
            .map_err(|e| io(&self.staged)(e.into_error()))?;
        file.sync_all().map_err(io(&self.staged))?;
        drop(file);
        replaceable(self.target.clone(), self.kind)?;
        std::fs::rename(&self.staged, &self.target).map_err(io(&self.target))?;
        drop(self.stage);
        Ok(())
    }
}

impl std::io::Write for Staged {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// Writes `bytes` as `dir/name` whole or not at all ([`Staged`]).
pub fn replace_file(dir: &Path, name: &str, bytes: &[u8]) -> Result<(), ReportError> {
    let mut s = Staged::new(dir, name)?;
    s.write_all(bytes).map_err(io(&s.staged))?;
    s.commit()
}

/// [`replace_file`] of a name the user chose, replacing only a file
/// enginedyn wrote, one that begins with `marker` ([`Staged::new_marked`]).
pub fn replace_marked_file(
    dir: &Path,
    name: &str,
    bytes: &[u8],
    marker: &'static str,
) -> Result<(), ReportError> {
    let mut s = Staged::new_marked(dir, name, marker)?;
    s.write_all(bytes).map_err(io(&s.staged))?;
    s.commit()
}

/// Whether `dir/name` may be written by [`replace_marked_file`]: absent,
/// or a regular, writable file that begins with `marker`; checked before
/// any work, and again when the file is moved into place.
pub fn check_marked(dir: &Path, name: &str, marker: &'static str) -> Result<(), ReportError> {
    check_name(name)?;
    replaceable(dir.join(name), Target::Marked(marker)).map(|_| ())
}

/// The largest file [`read_output`] reads back (bytes).
pub const MAX_OUTPUT_READ: u64 = 1 << 30;

/// One file of an output folder read back (Python's `Result.load`): `name`
/// must be one of ours, a plain file name inside `dir` (never a path, `..`
/// or a hidden name), and a regular file there of at most
/// [`MAX_OUTPUT_READ`] bytes, never read through a link (a link planted in
/// the folder would give another file's bytes) nor from a FIFO or device.
pub fn read_output(dir: &Path, name: &str) -> Result<Vec<u8>, ReportError> {
    let path = dir.join(name);
    let read = |source| ReportError::Read {
        path: path.clone(),
        source,
    };
    let refuse = |why: &str| {
        read(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            why.to_string(),
        ))
    };
    if check_name(name).is_err() {
        return Err(refuse(
            "not a plain file name inside the folder (a result's folder names only its own files)",
        ));
    }
    let meta = std::fs::symlink_metadata(&path).map_err(read)?;
    let kind = meta.file_type();
    if !kind.is_file() {
        let what = if kind.is_symlink() {
            "a symbolic link"
        } else if kind.is_dir() {
            "a folder"
        } else {
            special(&kind)
        };
        return Err(refuse(&format!(
            "{what}, not a regular file of the folder (a result's files are read from the folder itself)"
        )));
    }
    if meta.len() > MAX_OUTPUT_READ {
        return Err(refuse(&format!(
            "larger than {} MiB",
            MAX_OUTPUT_READ >> 20
        )));
    }
    let f = File::open(&path).map_err(read)?;
    if !f.metadata().map_err(read)?.is_file() {
        return Err(refuse("not a regular file"));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    f.take(MAX_OUTPUT_READ)
        .read_to_end(&mut bytes)
        .map_err(read)?;
    Ok(bytes)
}

/// The design report's folder of tables (`DIR/tables`).
pub const TABLES: &str = "tables";
/// The file that marks a `tables` folder as enginedyn's: it says what each
/// table holds.
pub const TABLES_MARKER: &str = "README.txt";

/// What a name of ours is written as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    /// A file (`summary.csv`, `report.html`).
    File,
    /// A file of a name the user chose: enginedyn's only when it begins
    /// with this marker.
    Marked(&'static str),
    /// A batch's run folder (`NNNN_STEM`).
    RunFolder,
    /// The design report's `tables` folder: enginedyn's when it holds the
    /// [`TABLES_MARKER`] an earlier report wrote.
    Tables,
}

/// What is in the way of writing `target` at `path` (`meta` its own
/// metadata, the link's when it is a link), `None` when it may be replaced:
/// a regular writable file for a file, a real writable folder holding a
/// regular `summary.json` for a run folder.
fn in_the_way(path: &Path, meta: &std::fs::Metadata, target: Target) -> Option<&'static str> {
    let kind = meta.file_type();
    if kind.is_symlink() {
        return Some("a symbolic link");
    }
    match target {
        Target::File if kind.is_file() => read_only(meta).then_some("a read-only file"),
        Target::Marked(_) if kind.is_file() && read_only(meta) => Some("a read-only file"),
        Target::Marked(marker) if kind.is_file() => {
            (!begins_with(path, marker)).then_some("a file enginedyn did not write")
        }
        Target::File | Target::Marked(_) if kind.is_dir() => Some("a folder"),
        Target::RunFolder if kind.is_dir() => {
            let ours = std::fs::symlink_metadata(path.join("summary.json"))
                .is_ok_and(|m| m.file_type().is_file());
            if !ours {
                Some("a folder without an earlier run's summary.json")
            } else if read_only(meta) {
                Some("a read-only folder")
            } else {
                None
            }
        }
        Target::Tables if kind.is_dir() => {
            let ours = std::fs::symlink_metadata(path.join(TABLES_MARKER))
                .is_ok_and(|m| m.file_type().is_file());
            if !ours {
                Some("a folder without an earlier report's README.txt")
            } else if read_only(meta) {
                Some("a read-only folder")
            } else {
                None
            }
        }
        Target::RunFolder | Target::Tables if kind.is_file() => Some("a file"),
        _ => Some(special(&kind)),
    }
}

/// Whether the regular file at `path` begins with `marker` (its first
/// bytes read, no more; never through a link or from anything but a
/// regular file).
fn begins_with(path: &Path, marker: &str) -> bool {
    let Ok(f) = File::open(path) else {
        return false;
    };
    if !f.metadata().is_ok_and(|m| m.is_file()) {
        return false;
    }
    let mut head = Vec::with_capacity(marker.len());
    f.take(marker.len() as u64).read_to_end(&mut head).is_ok() && head == marker.as_bytes()
}

/// Whether the owner may not write it: enginedyn writes its files
/// writable, so a read-only one is the user protecting it.
#[cfg(unix)]
fn read_only(meta: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::PermissionsExt as _;
    meta.permissions().mode() & 0o200 == 0
}

#[cfg(not(unix))]
fn read_only(meta: &std::fs::Metadata) -> bool {
    meta.permissions().readonly()
}

/// Neither file, folder nor link: what it is, as a message names it.
#[cfg(unix)]
fn special(kind: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt as _;
    if kind.is_fifo() {
        "a FIFO"
    } else if kind.is_socket() {
        "a socket"
    } else if kind.is_block_device() || kind.is_char_device() {
        "a device"
    } else {
        "something that is not a regular file"
    }
}

#[cfg(not(unix))]
fn special(_: &std::fs::FileType) -> &'static str {
    "something that is not a regular file"
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

/// The earlier run's manifest at `path`: (path, hash) of every well-formed
/// line naming a file of ours (`NAME` or `FOLDER/NAME`, plain names). A
/// manifest that is missing, not a regular file or too large lists nothing.
fn read_manifest(path: &Path) -> Vec<(String, String, String)> {
    let regular = std::fs::symlink_metadata(path)
        .is_ok_and(|m| m.file_type().is_file() && m.len() <= MAX_MANIFEST);
    if !regular {
        return Vec::new();
    }
    let Ok(f) = File::open(path) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut command = String::new();
    for line in std::io::BufReader::new(f.take(MAX_MANIFEST)).lines() {
        let Ok(line) = line else {
            break;
        };
        // `# enginedyn COMMAND` heads the outputs of that command.
        if let Some(c) = line.strip_prefix("# enginedyn ") {
            command = c.trim().to_string();
            continue;
        }
        let Some((hash, file)) = line.split_once("  ") else {
            continue;
        };
        let hash_ok =
            hash.len() == 64 && hash.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'));
        let parts: Vec<&str> = file.split('/').collect();
        let path_ok = (1..=2).contains(&parts.len()) && parts.iter().all(|p| check_name(p).is_ok());
        if hash_ok && path_ok {
            out.push((command.clone(), file.to_string(), hash.to_string()));
        }
    }
    out
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
#[doc(hidden)]
pub fn injected_failure() -> Option<std::io::Error> {
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
            [MANIFEST, "f0.txt", "f1.txt", "f2.txt", "f3.txt", "f4.txt"]
        );
        assert_eq!(
            std::fs::read_to_string(d.path().join("f3.txt")).unwrap(),
            "b 3"
        );
        // A run folder holds its summary.json: the next run replaces it.
        let run = |tag: &str| {
            let mut f = files(tag);
            f.push(("summary.json".into(), b"{}".to_vec()));
            f
        };
        out.write_folder("0001_x", &run("c")).unwrap();
        out.write_folder("0001_x", &run("d")).unwrap();
        assert_eq!(
            std::fs::read_to_string(d.path().join("0001_x/f0.txt")).unwrap(),
            "d 0"
        );
        assert_eq!(listing(d.path()).len(), 7);
    }

    /// The manifest: what the earlier run wrote and this one does not is
    /// removed when unchanged, kept with a note when changed; a file the
    /// manifest does not list, or a line that names something outside the
    /// folder, is never touched.
    #[test]
    fn a_folder_written_again_holds_this_runs_outputs_alone() {
        let d = tempfile::tempdir().unwrap();
        let outside = tempfile::tempdir().unwrap();
        type Files = [(String, Vec<u8>)];
        let write = |files: &Files, folders: &[(&str, &Files)]| {
            let out = OutDir::open(d.path()).unwrap();
            for (name, f) in folders {
                out.write_folder(name, f).unwrap();
            }
            out.write(files).unwrap()
        };
        let summary = [
            ("summary.json".to_string(), b"{}".to_vec()),
            ("a.svg".to_string(), b"<svg/>".to_vec()),
        ];
        let notes = write(&files("a"), &[("0001_x", &summary), ("0002_y", &summary)]);
        assert!(notes.is_empty(), "{notes:?}");
        let manifest = std::fs::read_to_string(d.path().join(MANIFEST)).unwrap();
        assert_eq!(
            manifest.lines().filter(|l| !l.starts_with("# ")).count(),
            9,
            "{manifest}"
        );
        assert!(manifest.contains(&format!("{}  0002_y/a.svg\n", sha256_hex(b"<svg/>"))));
        assert!(manifest.contains(&format!("{}  f4.txt\n", sha256_hex(b"a 4"))));
        // The user changes one output, adds a file of their own (one in a
        // run folder too), and a line pointing outside the folder.
        std::fs::write(d.path().join("f3.txt"), "edited").unwrap();
        std::fs::write(d.path().join("mine.txt"), "the user's").unwrap();
        std::fs::write(d.path().join("0002_y/mine.txt"), "the user's").unwrap();
        std::fs::write(outside.path().join("victim"), "x").unwrap();
        let evil = format!(
            "{}{}  ../{}/victim\n",
            manifest,
            sha256_hex(b"x"),
            outside.path().file_name().unwrap().to_string_lossy()
        );
        std::fs::write(d.path().join(MANIFEST), evil).unwrap();
        // The next run writes f0 and f1 and one run folder only.
        let fewer: Vec<_> = files("b").into_iter().take(2).collect();
        let notes = write(&fewer, &[("0001_x", &summary)]);
        assert_eq!(
            listing(d.path()),
            [
                MANIFEST, "0001_x", "0002_y", "f0.txt", "f1.txt", "f3.txt", "mine.txt"
            ]
        );
        // A run folder holding a file of the user's is kept whole.
        assert_eq!(
            listing(&d.path().join("0002_y")),
            ["a.svg", "mine.txt", "summary.json"]
        );
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(
            notes[0].contains("f3.txt") && notes[0].contains("may be stale"),
            "{}",
            notes[0]
        );
        assert!(
            notes[1].contains("0002_y") && notes[1].contains("(mine.txt)"),
            "{}",
            notes[1]
        );
        assert!(outside.path().join("victim").exists());
        let manifest = std::fs::read_to_string(d.path().join(MANIFEST)).unwrap();
        let listed: Vec<&str> = manifest
            .lines()
            .filter(|l| !l.starts_with("# "))
            .map(|l| &l[66..])
            .collect();
        assert_eq!(
            listed,
            ["0001_x/a.svg", "0001_x/summary.json", "f0.txt", "f1.txt"]
        );
        // A run folder as the earlier run wrote it goes whole; one with a
        // file changed since is kept whole.
        let with_y = format!(
            "{manifest}{}  0002_y/a.svg\n{}  0002_y/summary.json\n",
            sha256_hex(b"<svg/>"),
            sha256_hex(b"{}")
        );
        std::fs::remove_file(d.path().join("0002_y/mine.txt")).unwrap();
        std::fs::write(d.path().join("0002_y/a.svg"), "<svg>edited</svg>").unwrap();
        std::fs::write(d.path().join(MANIFEST), &with_y).unwrap();
        let notes = write(&fewer, &[]);
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("a.svg changed since"), "{}", notes[0]);
        assert_eq!(listing(&d.path().join("0002_y")), ["a.svg", "summary.json"]);
        std::fs::write(d.path().join("0002_y/a.svg"), "<svg/>").unwrap();
        std::fs::write(d.path().join(MANIFEST), &with_y).unwrap();
        let notes = write(&fewer, &[]);
        assert!(notes.is_empty(), "{notes:?}");
        assert_eq!(
            listing(d.path()),
            [MANIFEST, "f0.txt", "f1.txt", "f3.txt", "mine.txt"]
        );
    }

    /// The manifest is one of the names written: something in its way is
    /// refused before anything is written.
    #[test]
    fn a_link_at_the_manifest_is_in_the_way() {
        let d = tempfile::tempdir().unwrap();
        let outside = tempfile::tempdir().unwrap();
        std::os::unix::fs::symlink(outside.path().join("m"), d.path().join(MANIFEST)).unwrap();
        let out = OutDir::open(d.path()).unwrap();
        let e = out.write(&files("a")).unwrap_err();
        assert!(
            matches!(
                e,
                ReportError::InTheWay {
                    what: "a symbolic link",
                    ..
                }
            ),
            "{e}"
        );
        assert_eq!(listing(d.path()), [MANIFEST]);
        assert!(!outside.path().join("m").exists());
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

    /// Every kind of thing in the way of a file or a run folder is refused,
    /// named, and left as it was; nothing else appears.
    #[test]
    fn only_what_enginedyn_wrote_is_replaced() {
        use std::os::unix::fs::{PermissionsExt as _, symlink};
        let outside = tempfile::tempdir().unwrap();
        std::fs::write(outside.path().join("mine.txt"), "the user's").unwrap();
        std::fs::create_dir(outside.path().join("folder")).unwrap();
        type Make = fn(&Path, &Path);
        let kinds: [(&str, Make); 6] = [
            ("a folder", |p, _| {
                std::fs::create_dir(p).unwrap();
                std::fs::write(p.join("kept.txt"), "x").unwrap();
            }),
            ("a symbolic link", |p, o| {
                symlink(o.join("folder"), p).unwrap()
            }),
            ("a symbolic link", |p, o| {
                symlink(o.join("mine.txt"), p).unwrap();
            }),
            ("a FIFO", |p, _| {
                let ok = std::process::Command::new("mkfifo").arg(p).status();
                assert!(ok.unwrap().success());
            }),
            ("a read-only file", |p, _| {
                std::fs::write(p, "protected").unwrap();
                std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o444)).unwrap();
            }),
            ("a folder without an earlier run's summary.json", |p, _| {
                std::fs::create_dir(p).unwrap();
            }),
        ];
        for (what, make) in kinds {
            let d = tempfile::tempdir().unwrap();
            let out = OutDir::open(d.path()).unwrap();
            let as_file = what != "a folder without an earlier run's summary.json";
            let target = d.path().join(if as_file { "f1.txt" } else { "0001_x" });
            make(&target, outside.path());
            let before = listing(d.path());
            let e = if as_file {
                out.write(&files("a")).unwrap_err()
            } else {
                out.write_folder("0001_x", &files("a")).unwrap_err()
            };
            match &e {
                ReportError::InTheWay { path, what: w, .. } => {
                    assert_eq!(path, &target);
                    assert!(w.starts_with(what) || what.starts_with(w), "{w} for {what}");
                }
                other => panic!("{what}: {other}"),
            }
            assert!(e.to_string().contains(&target.display().to_string()), "{e}");
            assert_eq!(listing(d.path()), before, "{what}");
            assert!(std::fs::symlink_metadata(&target).is_ok(), "{what} kept");
        }
        assert_eq!(
            std::fs::read_to_string(outside.path().join("mine.txt")).unwrap(),
            "the user's"
        );
        // A file where a run folder goes, a folder where a file goes.
        let d = tempfile::tempdir().unwrap();
        let out = OutDir::open(d.path()).unwrap();
        std::fs::write(d.path().join("0002_y"), "x").unwrap();
        std::fs::create_dir(d.path().join("f0.txt")).unwrap();
        let e = out.check(&["f0.txt"], &["0002_y"]).unwrap_err();
        assert!(
            matches!(
                e,
                ReportError::InTheWay {
                    what: "a folder",
                    ..
                }
            ),
            "{e}"
        );
        let e = out.check::<&str, _>(&[], &["0002_y"]).unwrap_err();
        assert!(
            matches!(e, ReportError::InTheWay { what: "a file", .. }),
            "{e}"
        );
        // An earlier run's folder (its summary.json inside) is replaced.
        out.write_folder("0003_z", &[("summary.json".into(), b"{}".to_vec())])
            .unwrap();
        out.write_folder("0003_z", &[("summary.json".into(), b"[]".to_vec())])
            .unwrap();
        assert_eq!(
            std::fs::read_to_string(d.path().join("0003_z/summary.json")).unwrap(),
            "[]"
        );
    }

    /// A shared folder's file: written whole, replaced only when it is a
    /// regular file, nothing staged left behind either way.
    #[test]
    fn staged_files_replace_only_a_regular_file() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("summary");
        replace_file(&dir, "part-00000-of-00001.parquet", b"one").unwrap();
        replace_file(&dir, "part-00000-of-00001.parquet", b"two").unwrap();
        assert_eq!(
            std::fs::read(dir.join("part-00000-of-00001.parquet")).unwrap(),
            b"two"
        );
        std::fs::create_dir(dir.join("b.parquet")).unwrap();
        let e = replace_file(&dir, "b.parquet", b"x").unwrap_err();
        assert!(
            matches!(
                e,
                ReportError::InTheWay {
                    what: "a folder",
                    ..
                }
            ),
            "{e}"
        );
        // Dropped uncommitted: nothing in place, nothing staged left.
        let s = Staged::new(&dir, "c.parquet").unwrap();
        drop(s);
        let mut names = listing(&dir);
        names.sort();
        assert_eq!(names, ["b.parquet", "part-00000-of-00001.parquet"]);
        assert!(replace_file(&dir, "../x", b"x").is_err());
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
