//! A part's tables committed as one unit: each table's part written into
//! one staging folder in the campaign's folder
//! (`.enginedyn-part-IIIII-of-NNNNN-XXXXXX`), then moved into place, the
//! summary part last: a summary part is the marker that its part is whole.

use crate::{Meta, PartWriter, Table, TablesError, part_name, staging_prefix};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// One part of a campaign being staged: its tables' files, written with
/// [`PartSet::bytes`] or [`PartSet::writer`], then [`PartSet::commit`].
/// Dropped uncommitted (a failure), the staging folder goes and nothing in
/// the campaign changes; a killed run's is removed by the next run of the
/// part ([`crate::prepare`]).
#[derive(Debug)]
pub struct PartSet {
    dir: PathBuf,
    part: usize,
    parts: usize,
    stage: tempfile::TempDir,
    staged: Vec<Table>,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> TablesError + '_ {
    move |source| {
        TablesError::Write(enginedyn_report::ReportError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

impl PartSet {
    /// Starts staging part `part` of `parts` in the campaign `dir` (made
    /// when missing).
    pub fn new(dir: &Path, part: usize, parts: usize) -> Result<Self, TablesError> {
        let prefix = staging_prefix(part, parts)?;
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        let stage = tempfile::Builder::new()
            .prefix(&prefix)
            .tempdir_in(dir)
            .map_err(io_err(dir))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            part,
            parts,
            stage,
            staged: Vec::new(),
        })
    }

    fn staged_path(&self, table: Table) -> PathBuf {
        self.stage.path().join(table.folder())
    }

    fn create(&mut self, table: Table) -> Result<File, TablesError> {
        let path = self.staged_path(table);
        let file = File::create_new(&path).map_err(io_err(&path))?;
        if let Some(e) = enginedyn_report::injected_failure() {
            return Err(io_err(&path)(e));
        }
        self.staged.push(table);
        Ok(file)
    }

    /// Stages `table`'s part as these bytes.
    pub fn bytes(&mut self, table: Table, bytes: &[u8]) -> Result<(), TablesError> {
        let path = self.staged_path(table);
        let mut f = self.create(table)?;
        f.write_all(bytes).map_err(io_err(&path))?;
        f.sync_all().map_err(io_err(&path))
    }

    /// Stages `table`'s part written a file at a time (traces): add rows
    /// with [`PartWriter::write`], then [`PartSet::finish`].
    pub fn writer(
        &mut self,
        table: Table,
        meta: &Meta,
    ) -> Result<PartWriter<BufWriter<File>>, TablesError> {
        let f = self.create(table)?;
        PartWriter::new(table, BufWriter::with_capacity(1 << 16, f), meta)
    }

    /// Ends a part begun by [`PartSet::writer`] (flushed to the disk).
    pub fn finish(&self, w: PartWriter<BufWriter<File>>) -> Result<(), TablesError> {
        let path = self.staged_path(w.table);
        let f = w
            .finish()?
            .into_inner()
            .map_err(|e| io_err(&path)(e.into_error()))?;
        f.sync_all().map_err(io_err(&path))
    }

    /// Moves every staged part into place: first the old summary part
    /// (the marker) goes, and an old part of a table this run does not
    /// write; then the other tables' parts, the summary part last.
    /// Returns the paths, summary first.
    pub fn commit(self) -> Result<Vec<PathBuf>, TablesError> {
        let name = part_name(self.part, self.parts)?;
        let target = |t: Table| self.dir.join(t.folder()).join(&name);
        for t in Table::ALL {
            let old = target(t);
            if (t == Table::Summary || !self.staged.contains(&t))
                && std::fs::symlink_metadata(&old).is_ok_and(|m| m.is_file())
            {
                std::fs::remove_file(&old).map_err(io_err(&old))?;
            }
        }
        let mut order: Vec<Table> = self.staged.clone();
        order.sort_by_key(|t| *t == Table::Summary);
        for &t in &order {
            let folder = self.dir.join(t.folder());
            std::fs::create_dir_all(&folder).map_err(io_err(&folder))?;
            let to = target(t);
            if std::fs::symlink_metadata(&to).is_ok_and(|m| !m.is_file()) {
                return Err(TablesError::InTheWay {
                    path: to,
                    what: "something other than a file",
                });
            }
            std::fs::rename(self.staged_path(t), &to).map_err(io_err(&to))?;
        }
        let mut written: Vec<PathBuf> = order.iter().rev().map(|&t| target(t)).collect();
        written.sort_by_key(|p| {
            Table::ALL
                .iter()
                .position(|t| p.parent().is_some_and(|f| f.ends_with(t.folder())))
        });
        Ok(written)
    }
}
