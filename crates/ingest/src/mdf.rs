//! The MDF4 source: ASAM MDF 4 (`.mf4`) files, read by falcon_mdf, one
//! channel group's channels handed to the reader as columns (INTERFACE.md,
//! "MDF4"). Each channel is a column named as the file names it, with its
//! unit (`PCYL1 [bar]`), so the column resolver and the layouts read it by
//! the same rules as a text header; an angle master channel is `crank_deg`
//! and a time master `time_s`. Messages name the group, the record (the
//! 0-based sample) and the channel instead of a line and a column.
//!
//! Which group: `--group N` (1-based, every data group's channel groups in
//! file order), else the first whose channels hold a pressure (or, for a
//! turning-moment file, a torque).
//!
//! What a hostile file cannot do here:
//! - stop the command with a panic, or print one: the whole read runs in
//!   [`crate::sheet::guarded`];
//! - allocate from a size it declares: falcon_mdf caps an allocation sized
//!   from the file at [`MAX_MDF_ALLOC`], and a compressed block's expansion
//!   at [`MAX_MDF_BLOCK`] (a block that would expand further is an error);
//! - hold a table of its channels: the group is decoded a window at a time
//!   (at most [`WINDOW_BYTES`] of records and [`WINDOW_VALUES`] values),
//!   and the window's rows handed on one by one.
//!
//! So memory is bounded by the file (held whole, at most [`MAX_MDF`]: an
//! MDF4 file is read where its links point), one expanded block and one
//! window.

use crate::columns::{Role, recognise};
use crate::error::IngestError;
use crate::reader::Reader;
use crate::row::Cells;
use crate::{Header, ParseOptions, Streamed};
use falcon_mdf::blocks::{ChannelType, SyncType};
use falcon_mdf::{Channel, Mf4File, OpenOptions};
use std::borrow::Cow;

/// The largest MDF4 file read (bytes): it is held in memory.
pub const MAX_MDF: usize = 1 << 30;

/// The most bytes one compressed data block (`##DZ`) may expand to.
pub const MAX_MDF_BLOCK: u64 = 256 << 20;

/// The largest allocation falcon_mdf sizes from a number the file declares
/// (a larger buffer grows as data arrives).
pub const MAX_MDF_ALLOC: usize = 16 << 20;

/// Bytes of records decoded at once.
pub const WINDOW_BYTES: usize = 1 << 20;

/// Values (one channel's sample each) decoded at once.
pub const WINDOW_VALUES: usize = 1 << 17;

/// The most groups an error lists by name.
const LISTED: usize = 20;

/// One channel group: where it is and its columns.
struct Group {
    /// 1-based, as `--group` counts.
    number: usize,
    dg: usize,
    cg: usize,
    name: String,
    /// The channels read, as columns (the master first).
    columns: Vec<(Channel, String)>,
    /// Channels left out, and why (`text`, `an array`).
    left_out: Vec<(String, &'static str)>,
    /// Its column names say it holds what is asked for (a pressure).
    holds: bool,
}

impl Group {
    /// `group 2 `Fast` (time_s, `PCYL1 [V]`, …)`, for lists.
    fn describe(&self) -> String {
        let names: Vec<String> =
            self.columns
                .iter()
                .take(6)
                .map(|(_, n)| format!("`{}`", enginedyn_numerics::format::quote(n)))
                .chain(
                    self.left_out.iter().take(2).map(|(n, why)| {
                        format!("`{}` ({why})", enginedyn_numerics::format::quote(n))
                    }),
                )
                .collect();
        let more = self.columns.len().saturating_sub(6) + self.left_out.len().saturating_sub(2);
        format!(
            "group {}{}: {}{}",
            self.number,
            if self.name.is_empty() {
                String::new()
            } else {
                format!(" `{}`", enginedyn_numerics::format::quote(&self.name))
            },
            if names.is_empty() {
                "no channels".to_string()
            } else {
                names.join(", ")
            },
            if more > 0 {
                format!(", and {more} more")
            } else {
                String::new()
            }
        )
    }
}

/// Every group, listed for an error (at most [`LISTED`]).
fn list(groups: &[Group]) -> String {
    let mut s: Vec<String> = groups.iter().take(LISTED).map(Group::describe).collect();
    if groups.len() > LISTED {
        s.push(format!("and {} more groups", groups.len() - LISTED));
    }
    s.join("; ")
}

/// The damaged-file error, with falcon_mdf's reason.
fn damaged(why: impl std::fmt::Display) -> IngestError {
    IngestError::Data(format!(
        "the MDF4 file is damaged or cut short ({why}): write it again, or export the channels as CSV"
    ))
}

/// Reads the MDF4 file in `bytes`: the chosen group's records, a window at
/// a time, as rows.
pub(crate) fn read<F: FnMut(Streamed) -> Result<(), IngestError>>(
    bytes: Vec<u8>,
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    let mut sink = sink;
    crate::sheet::guarded(|| read_file(bytes, opts, &mut sink))
        .unwrap_or_else(|| Err(damaged("the MDF reader failed on it")))
}

/// The version an MDF file's identification block states (`4.10`), and
/// whether it is MDF 4.
fn version(bytes: &[u8]) -> (String, bool) {
    let v = bytes
        .get(8..16)
        .map(|b| {
            String::from_utf8_lossy(b)
                .trim()
                .trim_matches('\0')
                .to_string()
        })
        .unwrap_or_default();
    let four = v.starts_with('4');
    (v, four)
}

fn read_file<F: FnMut(Streamed) -> Result<(), IngestError>>(
    bytes: Vec<u8>,
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    let (v, four) = version(&bytes);
    if !four && !v.is_empty() && v.starts_with(['2', '3']) {
        return Err(IngestError::Data(format!(
            "an MDF {v} file: enginedyn reads MDF 4 (.mf4); convert it (asammdf: `MDF(path).convert(\"4.10\").save(new)`) or export the channels as CSV",
            v = enginedyn_numerics::format::quote(&v)
        )));
    }
    let options = OpenOptions {
        build_channels_db: false,
        parallel_parsing: false,
        max_alloc: MAX_MDF_ALLOC,
        max_decompressed: MAX_MDF_BLOCK,
        ..OpenOptions::default()
    };
    let file = Mf4File::from_bytes_with_options(bytes, options).map_err(damaged)?;
    let groups = groups(&file, opts);
    let group = choose(&groups, opts)?;
    let mut notes = Vec::new();
    if opts.group.is_none() && groups.len() > 1 {
        notes.push(format!(
            "read group {} of {} ({}); --group N reads another",
            group.number,
            groups.len(),
            if group.holds {
                "the first that holds a pressure"
            } else {
                "the first with channels"
            }
        ));
    }
    if !group.left_out.is_empty() {
        let names: Vec<String> = group
            .left_out
            .iter()
            .take(4)
            .map(|(n, why)| format!("`{}` ({why})", enginedyn_numerics::format::quote(n)))
            .collect();
        notes.push(format!(
            "{} channel{} of group {} left out, holding no numbers: {}{}",
            group.left_out.len(),
            if group.left_out.len() > 1 { "s" } else { "" },
            group.number,
            names.join(", "),
            if group.left_out.len() > 4 {
                ", …"
            } else {
                ""
            }
        ));
    }
    if opts.sheet.is_some() {
        notes.push(
            "--sheet applies to spreadsheets; this file is MDF4 (--group picks a channel group)"
                .into(),
        );
    }
    let mut rd = Reader::new(opts, sink);
    let streamed = stream(&file, group, &mut rd);
    let named = |e: IngestError| in_group(e, group);
    streamed.map_err(named)?;
    let mut head = rd.end().map_err(named)?;
    head.notes.extend(notes);
    Ok(head)
}

/// An error at a line and column of the rows as the group's record and
/// channel: line 1 is the header (the channel names), line `r + 2` record
/// `r`.
fn in_group(e: IngestError, group: &Group) -> IngestError {
    let channel = |c: Option<usize>| {
        c.and_then(|c| group.columns.get(c.wrapping_sub(1)))
            .map(|(_, n)| format!(", channel `{}`", enginedyn_numerics::format::quote(n)))
            .unwrap_or_default()
    };
    match e {
        IngestError::At {
            line: 1,
            column,
            message,
        } => IngestError::Data(format!(
            "group {}{}: {message}",
            group.number,
            channel(column)
        )),
        IngestError::At {
            line,
            column,
            message,
        } => IngestError::Data(format!(
            "group {}, record {}{}: {message}",
            group.number,
            line - 2,
            channel(column)
        )),
        IngestError::Data(m)
            if m == "no data rows" || m.ends_with("no data rows after the header") =>
        {
            IngestError::Data(format!("group {} holds no records", group.number))
        }
        e => e,
    }
}

/// The file's channel groups, numbered from 1, and their columns.
fn groups(file: &Mf4File, opts: &ParseOptions) -> Vec<Group> {
    let mut out = Vec::new();
    for (dg, d) in file.data_groups().iter().enumerate() {
        for (cg, g) in d.channel_groups.iter().enumerate() {
            let mut columns = Vec::new();
            let mut left_out = Vec::new();
            let mut master = None;
            for ch in &g.channels {
                match usable(ch) {
                    Err(why) => left_out.push((ch.name.clone(), why)),
                    Ok(()) => {
                        let name = column_name(ch, columns.len() + 1);
                        if master.is_none() && is_master(ch) {
                            master = Some(columns.len());
                        }
                        columns.push((ch.clone(), name));
                    }
                }
            }
            if let Some(m) = master {
                let c = columns.remove(m);
                columns.insert(0, c);
            }
            let holds = columns.iter().any(|(_, n)| match recognise(n) {
                Ok(Role::Pressure { .. } | Role::Volts { .. }) => !opts.torque,
                Ok(Role::Torque(_)) => opts.torque,
                _ => false,
            });
            out.push(Group {
                number: out.len() + 1,
                dg,
                cg,
                name: g.acquisition_name.clone(),
                columns,
                left_out,
                holds,
            });
        }
    }
    out
}

fn is_master(ch: &Channel) -> bool {
    matches!(
        ch.channel_type,
        ChannelType::Master | ChannelType::VirtualMaster
    )
}

/// Whether a channel is read as a column: numbers, one a record.
fn usable(ch: &Channel) -> Result<(), &'static str> {
    if ch.unreadable().is_some() {
        return Err("not decodable");
    }
    if ch.is_array() {
        return Err("an array");
    }
    if !matches!(
        ch.channel_type,
        ChannelType::FixedLength | ChannelType::Master | ChannelType::VirtualMaster
    ) {
        return Err("variable length");
    }
    if !ch.is_numeric() {
        return Err("text or bytes");
    }
    Ok(())
}

/// A channel's column name: `crank_deg` for an angle master, `time_s` for a
/// time master, else its name with its unit (`PCYL1 [bar]`).
fn column_name(ch: &Channel, k: usize) -> String {
    let unit = ch.unit.trim();
    if is_master(ch) {
        match ch.sync_type {
            SyncType::Angle if unit.eq_ignore_ascii_case("rad") => {
                return "crank angle [rad]".into();
            }
            SyncType::Angle => return "crank_deg".into(),
            SyncType::Time => return "time_s".into(),
            _ => {}
        }
    }
    let name = ch.name.trim();
    let name = if name.is_empty() {
        format!("channel {k}")
    } else {
        name.to_string()
    };
    if unit.is_empty() || name.ends_with(']') || name.ends_with(')') {
        name
    } else {
        format!("{name} [{unit}]")
    }
}

/// The group `--group` names, or the first holding a pressure.
fn choose<'g>(groups: &'g [Group], opts: &ParseOptions) -> Result<&'g Group, IngestError> {
    let what = if opts.torque {
        "a torque"
    } else {
        "a pressure"
    };
    if groups.is_empty() {
        return Err(IngestError::Data(
            "the MDF4 file holds no channel group: no measurement in it".into(),
        ));
    }
    if let Some(n) = opts.group {
        let Some(g) = n.checked_sub(1).and_then(|i| groups.get(i)) else {
            return Err(IngestError::Data(format!(
                "--group {n}: the MDF4 file has {} channel group{}, numbered from 1: {}",
                groups.len(),
                if groups.len() > 1 { "s" } else { "" },
                list(groups)
            )));
        };
        if g.columns.is_empty() {
            return Err(IngestError::Data(format!(
                "--group {n}: group {n} holds no channel of numbers; the groups: {}",
                list(groups)
            )));
        }
        if !g.holds && opts.columns.is_none() {
            return Err(IngestError::Data(format!(
                "--group {n}: group {n} holds no {} channel (by its name and unit){}; the groups: {}",
                &what[2..],
                if groups.iter().any(|g| g.holds) {
                    String::new()
                } else {
                    " (--columns names its channels in order, the master first)".to_string()
                },
                list(groups)
            )));
        }
        return Ok(g);
    }
    if let Some(g) = groups.iter().find(|g| g.holds) {
        return Ok(g);
    }
    if opts.columns.is_some()
        && let Some(g) = groups.iter().find(|g| g.columns.len() > 1)
    {
        return Ok(g);
    }
    Err(IngestError::Data(format!(
        "no channel group holds {what} channel (by its name and unit, as in `PCYL1 [bar]` or `pressure_v`): {}; --group N with --columns names a group's channels in order, the master first",
        list(groups)
    )))
}

/// The group's records, a window at a time, as rows: the header (the
/// column names) first, then one row a record.
fn stream<F: FnMut(Streamed) -> Result<(), IngestError>>(
    file: &Mf4File,
    group: &Group,
    rd: &mut Reader<'_, F>,
) -> Result<(), IngestError> {
    let names: Vec<String> = group.columns.iter().map(|(_, n)| n.clone()).collect();
    rd.row(1, &Names(&names), || None)?;
    let cg = &file.data_groups()[group.dg].channel_groups[group.cg];
    // The record ID (at most 8 bytes) and the payload.
    let stride = cg.payload_size().saturating_add(8);
    if stride > WINDOW_BYTES {
        return Err(IngestError::Data(format!(
            "group {}: a record of {} bytes, more than the {} MiB bound on one (a damaged file?)",
            group.number,
            cg.payload_size(),
            WINDOW_BYTES >> 20
        )));
    }
    let k = group.columns.len().max(1);
    let chunk = (WINDOW_BYTES / stride).min(WINDOW_VALUES / k).max(1);
    let channels: Vec<&Channel> = group.columns.iter().map(|(c, _)| c).collect();
    let windows = file.signals_chunks(&channels, chunk).map_err(damaged)?;
    let mut row = vec![f64::NAN; k];
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(k);
    let mut record = 0usize;
    for window in windows {
        let signals = window.map_err(damaged)?;
        cols.clear();
        let mut n = usize::MAX;
        for s in &signals {
            let mut v = s.values_f64().map_err(damaged)?;
            if let Some(valid) = s.validity() {
                for (x, ok) in v.iter_mut().zip(valid) {
                    if !ok {
                        *x = f64::NAN;
                    }
                }
            }
            n = n.min(v.len());
            cols.push(v);
        }
        if cols.is_empty() {
            break;
        }
        for r in 0..n {
            for (x, c) in row.iter_mut().zip(&cols) {
                *x = c[r];
            }
            rd.row(record + 2, &Values(&row), || None)?;
            record += 1;
        }
    }
    if (record as u64) < cg.sample_count {
        return Err(damaged(format!(
            "group {} declares {} records, its data holds {record}",
            group.number, cg.sample_count
        )));
    }
    Ok(())
}

/// The header row: the column names. Never a data row, whatever a name.
struct Names<'a>(&'a [String]);

impl Cells for Names<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        self.0.get(i).is_none_or(|s| s.trim().is_empty())
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Borrowed(self.0.get(i).map_or("", String::as_str))
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        Err(crate::error::at(
            line,
            Some(i + 1),
            "a channel name, not a number",
        ))
    }
    fn is_data(&self) -> bool {
        false
    }
}

/// One record's values, NaN for an invalid sample or a value that is no
/// number.
struct Values<'a>(&'a [f64]);

impl Cells for Values<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        i >= self.0.len()
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Owned(self.0.get(i).map(|v| v.to_string()).unwrap_or_default())
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        match self.0.get(i) {
            Some(v) if v.is_finite() => Ok(*v),
            Some(v) => Err(crate::error::at(
                line,
                Some(i + 1),
                if v.is_nan() {
                    "a sample marked invalid, or no number (NaN), where a number is needed"
                        .to_string()
                } else {
                    format!("the sample is {v}, where a finite number is needed")
                },
            )),
            None => Err(crate::error::at(line, Some(i + 1), "no such channel")),
        }
    }
    /// Every record is data, even one whose first value is invalid (an
    /// error where a layout reads it).
    fn is_data(&self) -> bool {
        true
    }
}
