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
//! The checks of what is read live here, beside the source, not in the
//! crate that decodes: master units converted by the reader's unit table
//! (`time [ms]`, `crank angle [gon]` as a header names them; an unknown
//! master unit an error), pressure units the table lacks named, a unit
//! ending in `g` read as gauge; the records read held to the count the
//! channel group declares in its own block ([`Records`]: falcon_mdf lowers
//! its count to what the data hold).
//!
//! What a hostile file cannot do here:
//! - stop the command with a panic, or print one: the whole read runs in
//!   [`crate::sheet::guarded`];
//! - make falcon_mdf walk more than it may: before it opens the file, its
//!   blocks are walked from the bytes ([`survey`]): at most
//!   [`MAX_MDF_GROUPS`] channel groups and [`MAX_MDF_CHANNELS`] channels,
//!   data blocks expanding to at most [`MAX_MDF_DECODED`] in all, no block
//!   named twice in a data list;
//! - allocate from a size it declares: falcon_mdf caps an allocation sized
//!   from the file at [`MAX_MDF_ALLOC`], and a compressed block's expansion
//!   at [`MAX_MDF_BLOCK`] (a block that would expand further is an error);
//! - hold a table of its channels: the group is decoded a window at a time
//!   (at most [`WINDOW_BYTES`] of records and [`WINDOW_VALUES`] values),
//!   each channel in one pass into its column ([`crate::decode`] for sorted
//!   records in `##DT` blocks and deflated `##DZ` ones, a block expanded at
//!   a time; falcon_mdf for the rest), and the window's
//!   columns handed to the reader whole ([`Reader::columns`]): a record is
//!   read cell by cell only where a cycle starts or a value is refused.
//!
//! So memory is bounded by the file (held whole, at most [`MAX_MDF`]: an
//! MDF4 file is read where its links point), one expanded block and one
//! window.

use crate::columns::{Role, recognise, same};
use crate::decode::{block, u64_at};
use crate::error::IngestError;
use crate::reader::Reader;
use crate::row::Cells;
use crate::{Header, ParseOptions, Streamed};
use falcon_mdf::blocks::{ChannelType, SyncType};
use falcon_mdf::{Channel, Mf4File, OpenOptions};
use std::borrow::Cow;
use std::sync::Arc;

/// The largest MDF4 file read (bytes): it is held in memory.
pub const MAX_MDF: usize = 1 << 30;

/// The most bytes one compressed data block (`##DZ`) may expand to.
pub const MAX_MDF_BLOCK: u64 = 256 << 20;

/// The largest allocation falcon_mdf sizes from a number the file declares
/// (a larger buffer grows as data arrives).
pub const MAX_MDF_ALLOC: usize = 16 << 20;

/// Bytes of records decoded at once.
pub const WINDOW_BYTES: usize = 1 << 20;

/// Values (one channel's sample each) decoded at once: 128 KiB of
/// columns, which stay in the core's cache while the reader takes them
/// (a window of 2¹⁷ values took 11 % longer on the MDF4 bench file:
/// `benches/RESULTS.md`, session 20).
pub const WINDOW_VALUES: usize = 1 << 14;

/// The most groups an error lists by name.
const LISTED: usize = 20;

/// One channel group: where it is and its columns.
struct Group {
    /// 1-based, as `--group` counts.
    number: usize,
    dg: usize,
    cg: usize,
    name: String,
    /// The channels read, as columns (the master first): each channel's
    /// index in its group (no copy: a file may hold 65,536 groups).
    columns: Vec<(usize, String)>,
    /// Channels left out, and why (`text`, `an array`).
    left_out: Vec<(String, &'static str)>,
    /// Its column names say it holds what is asked for (a pressure).
    holds: bool,
    /// The pressure columns whose unit ends in `g` (`barg`, `psig`): gauge.
    gauge: Vec<String>,
    /// The pressure columns in an absolute unit.
    absolute: Vec<String>,
    /// Pressure channels in a unit the table lacks: (channel, unit).
    unknown_pressure: Vec<(String, String)>,
    /// A master channel in a unit the table lacks: (channel, unit, what).
    unknown_master: Option<(String, String, &'static str)>,
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

/// Column names for a message: `` `PCYL1 [bar]`, `PCYL2 [bar]` ``.
fn names(columns: &[String]) -> String {
    columns
        .iter()
        .map(|n| format!("`{}`", enginedyn_numerics::format::quote(n)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The damaged-file error, with falcon_mdf's reason.
fn damaged(why: impl std::fmt::Display) -> IngestError {
    IngestError::Data(format!(
        "the MDF4 file is damaged or cut short ({why}): write it again, or export the channels as CSV"
    ))
}

/// The most channel groups a file may hold (all data groups together).
pub const MAX_MDF_GROUPS: usize = 1 << 16;

/// The most channels a file may hold (every group's, composed ones too).
pub const MAX_MDF_CHANNELS: usize = 1 << 16;

/// The most bytes the file's data blocks may expand to, every block counted
/// each time a data group names it (as a sheet unpacks to at most 1 GiB).
pub const MAX_MDF_DECODED: u64 = 1 << 30;

/// The most data blocks the file's data lists may name.
pub const MAX_MDF_BLOCKS: usize = 1 << 20;

/// What the file declares, read from its bytes before falcon_mdf opens it,
/// with the bounds on groups, channels and decoded bytes checked.
struct Survey {
    /// Each channel group's block, the record count it declares
    /// (`cg_cycle_count`) and its data group's block, sorted by block.
    declared: Vec<(u64, u64, u64)>,
    /// An unfinished file whose record counts are not up to date.
    counts_stale: bool,
}

impl Survey {
    /// The record count the group at block `cg` declares.
    fn declared(&self, cg: u64) -> Option<u64> {
        self.declared
            .binary_search_by_key(&cg, |&(at, ..)| at)
            .ok()
            .map(|i| self.declared[i].1)
    }

    /// The block of the data group holding the channel group at block `cg`.
    fn data_group(&self, cg: u64) -> Option<u64> {
        self.declared
            .binary_search_by_key(&cg, |&(at, ..)| at)
            .ok()
            .map(|i| self.declared[i].2)
    }
}

/// Walks the file's data groups, channel groups, channels and data lists
/// from its bytes: the bounds checked, the declared record counts kept.
fn survey(bytes: &[u8]) -> Result<Survey, IngestError> {
    use std::collections::HashSet;
    let unfinished = bytes.starts_with(b"UnFinMF ");
    // id_unfin_flags bit 0: the CG and CA cycle counters are not updated.
    let counts_stale = unfinished && bytes.get(60).is_some_and(|f| f & 1 != 0);
    let mut declared = Vec::new();
    let mut channels = 0usize;
    let mut blocks = 0usize;
    let mut decoded = 0u64;
    let Some(hd) = block(bytes, 64) else {
        return Ok(Survey {
            declared,
            counts_stale,
        });
    };
    let mut dgs = HashSet::new();
    let mut dg = hd.links.first().copied().unwrap_or(0);
    let mut dg_number = 0usize;
    while dg != 0 && dgs.insert(dg) {
        dg_number += 1;
        let Some(d) = block(bytes, dg).filter(|b| b.id == b"##DG") else {
            break;
        };
        // Channel groups and their channels.
        let mut cgs = HashSet::new();
        let mut cg = d.links.get(1).copied().unwrap_or(0);
        while cg != 0 && cgs.insert(cg) {
            let Some(c) = block(bytes, cg).filter(|b| b.id == b"##CG") else {
                break;
            };
            if declared.len() == MAX_MDF_GROUPS {
                return Err(IngestError::Data(format!(
                    "the MDF4 file holds more than {MAX_MDF_GROUPS} channel groups, the bound on those read (a damaged or hostile file?): keep the groups wanted (asammdf's `filter`), or export the channels as CSV"
                )));
            }
            declared.push((cg, u64_at(c.data, 8).unwrap_or(0), dg));
            // The channels: the `cn_next` chain and what each composes.
            let mut seen = HashSet::new();
            let mut stack = vec![c.links.get(1).copied().unwrap_or(0)];
            while let Some(cn) = stack.pop() {
                if cn == 0 || !seen.insert(cn) {
                    continue;
                }
                let Some(ch) = block(bytes, cn).filter(|b| b.id == b"##CN") else {
                    continue;
                };
                channels += 1;
                if channels > MAX_MDF_CHANNELS {
                    return Err(IngestError::Data(format!(
                        "the MDF4 file holds more than {MAX_MDF_CHANNELS} channels, the bound on those read (a damaged or hostile file?): keep the channels wanted (asammdf's `filter`), or export them as CSV"
                    )));
                }
                stack.extend(ch.links.iter().take(2).copied());
            }
            cg = c.links.first().copied().unwrap_or(0);
        }
        // The data: one block, or a list (##DL, under a ##HL) of them.
        let mut named = HashSet::new();
        let mut lists = vec![d.links.get(2).copied().unwrap_or(0)];
        while let Some(at) = lists.pop() {
            if at == 0 {
                continue;
            }
            if !named.insert(at) {
                return Err(IngestError::Data(format!(
                    "the MDF4 file is damaged: data group {dg_number}'s data list names the block at byte {at} twice (a hostile file?): write it again, or export the channels as CSV"
                )));
            }
            blocks += 1;
            if blocks > MAX_MDF_BLOCKS {
                return Err(IngestError::Data(format!(
                    "the MDF4 file's data lists name more than {MAX_MDF_BLOCKS} data blocks, the bound on those read (a damaged or hostile file?): export the channels as CSV"
                )));
            }
            let Some(b) = block(bytes, at) else {
                continue;
            };
            match b.id {
                // A list: the next list first, then its blocks, in order.
                b"##DL" | b"##LD" => {
                    lists.push(b.links.first().copied().unwrap_or(0));
                    lists.extend(b.links.iter().skip(1).rev().copied());
                }
                b"##HL" => lists.push(b.links.first().copied().unwrap_or(0)),
                b"##DZ" => decoded = decoded.saturating_add(u64_at(b.data, 8).unwrap_or(0)),
                _ => decoded = decoded.saturating_add(b.data.len() as u64),
            }
            if decoded > MAX_MDF_DECODED {
                return Err(IngestError::Data(format!(
                    "the MDF4 file's data blocks expand to more than {} GiB, the bound on what is decoded (every block counted each time a data group names it; a compression bomb?): cut it to the records wanted (asammdf's `cut` or `filter`), or export the channels as CSV",
                    MAX_MDF_DECODED >> 30
                )));
            }
        }
        dg = d.links.first().copied().unwrap_or(0);
    }
    declared.sort_unstable();
    Ok(Survey {
        declared,
        counts_stale,
    })
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
    let survey = survey(&bytes)?;
    // The bytes shared with falcon_mdf, so that records are decoded where
    // they lie ([`crate::decode`]).
    let bytes = Arc::new(bytes);
    let source = Arc::new(Shared(Arc::clone(&bytes)));
    let file = Mf4File::from_source_with_options(source, options).map_err(damaged)?;
    let groups = groups(&file, opts);
    let group = choose(&groups, opts)?;
    if let Some((name, unit, what)) = &group.unknown_master {
        return Err(IngestError::Data(format!(
            "group {}: the {what} master channel `{}` is in `{}`, a unit the reader does not know ({}): convert the master, or export the channels as CSV",
            group.number,
            enginedyn_numerics::format::quote(name),
            enginedyn_numerics::format::quote(unit),
            if *what == "time" {
                "s, ms, us or min"
            } else {
                "deg, rad, gon or rev"
            }
        )));
    }
    let gauge_opts;
    let opts = if group.gauge.is_empty() {
        opts
    } else if !group.absolute.is_empty() {
        return Err(IngestError::Data(format!(
            "group {}: gauge pressure channels ({}) beside absolute ones ({}): read one kind (--columns, `_` skipping a channel), or export the channels as CSV",
            group.number,
            names(&group.gauge),
            names(&group.absolute)
        )));
    } else {
        gauge_opts = ParseOptions {
            gauge: true,
            ..opts.clone()
        };
        &gauge_opts
    };
    let cg = &file.data_groups()[group.dg].channel_groups[group.cg];
    let declared = match survey.declared(cg.block_offset()) {
        Some(n) if !survey.counts_stale => n,
        _ => cg.sample_count,
    };
    let records = Records {
        declared,
        held: cg.sample_count,
    };
    records.check(group)?;
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
    if !group.gauge.is_empty() {
        notes.push(format!(
            "group {}: {} read as gauge pressure (its unit ends in g), 1.01325 bar added",
            group.number,
            names(&group.gauge)
        ));
    }
    if survey.counts_stale {
        notes.push(format!(
            "an unfinished MDF4 file (its record counts not brought up to date): group {} read to the {} records its data hold",
            group.number, records.held
        ));
    }
    if opts.sheet.is_some() {
        notes.push(
            "--sheet applies to spreadsheets; this file is MDF4 (--group picks a channel group)"
                .into(),
        );
    }
    let mut rd = Reader::new(opts, sink);
    let plain = survey
        .data_group(cg.block_offset())
        .and_then(|dg| plain(&bytes, dg, &file, group));
    let streamed = stream(&file, plain, group, records.declared, &mut rd);
    let named = |e: IngestError| in_group(e, group);
    streamed.map_err(named)?;
    let mut head = rd.end().map_err(named)?;
    head.notes.extend(notes);
    // The buffer kept for the next file, once falcon_mdf lets go of it.
    drop(file);
    if let Ok(bytes) = Arc::try_unwrap(bytes) {
        crate::spare(bytes);
    }
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
            let mut gauge = Vec::new();
            let mut absolute = Vec::new();
            let mut unknown_pressure = Vec::new();
            let mut unknown_master = None;
            for (i, ch) in g.channels.iter().enumerate() {
                match usable(ch) {
                    Err(why) => left_out.push((ch.name.clone(), why)),
                    Ok(()) => {
                        let (name, unit) = column(ch, columns.len() + 1);
                        match unit {
                            Unit::Known => {
                                if matches!(recognise(&name), Ok(Role::Pressure { .. })) {
                                    absolute.push(name.clone());
                                }
                            }
                            Unit::Gauge => gauge.push(name.clone()),
                            Unit::UnknownPressure(u) => {
                                unknown_pressure.push((ch.name.trim().to_string(), u))
                            }
                            Unit::UnknownMaster(u, what) => {
                                unknown_master.get_or_insert((ch.name.trim().to_string(), u, what));
                            }
                        }
                        if master.is_none() && is_master(ch) {
                            master = Some(columns.len());
                        }
                        columns.push((i, name));
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
                gauge,
                absolute,
                unknown_pressure,
                unknown_master,
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

/// What a channel's unit says, beside its column name.
enum Unit {
    /// A unit the table knows, or none.
    Known,
    /// A pressure unit ending in `g` (`barg`, `psig`): gauge pressure, its
    /// column named with the unit without the `g`.
    Gauge,
    /// A pressure channel in a unit the table lacks.
    UnknownPressure(String),
    /// A time or angle master in a unit the table lacks (and which).
    UnknownMaster(String, &'static str),
}

/// A channel's column name and what its unit says: `crank_deg` for an
/// angle master in degrees, `time_s` for a time master in seconds, else the
/// master as a header names one (`time [ms]`, `crank angle [gon]`), converted
/// by the reader's unit table as a CSV header is; any other channel its name
/// with its unit (`PCYL1 [bar]`).
fn column(ch: &Channel, k: usize) -> (String, Unit) {
    let unit = ch.unit.trim();
    if is_master(ch) {
        let (word, what) = match ch.sync_type {
            SyncType::Angle => ("crank angle", "angle"),
            SyncType::Time => ("time", "time"),
            _ => ("", ""),
        };
        if !word.is_empty() {
            let name = format!("{word} [{unit}]");
            return match recognise(&name) {
                _ if unit.is_empty() && what == "angle" => ("crank_deg".into(), Unit::Known),
                _ if unit.is_empty() => ("time_s".into(), Unit::Known),
                Ok(Role::Angle(s)) if same(s, 1.0) => ("crank_deg".into(), Unit::Known),
                Ok(Role::Time(s)) if same(s, 1.0) => ("time_s".into(), Unit::Known),
                Ok(Role::Angle(_) | Role::Time(_)) => (name, Unit::Known),
                _ => (name, Unit::UnknownMaster(unit.to_string(), what)),
            };
        }
    }
    let name = ch.name.trim();
    let name = if name.is_empty() {
        format!("channel {k}")
    } else {
        name.to_string()
    };
    if unit.is_empty() || name.ends_with(']') || name.ends_with(')') {
        return (name, Unit::Known);
    }
    let with = |u: &str| format!("{name} [{u}]");
    let pressure = |u: &str| {
        matches!(
            recognise(&with(u)),
            Ok(Role::Pressure { .. } | Role::Volts { .. })
        )
    };
    if recognise(&with(unit)).is_ok() || !pressure("bar") {
        return (with(unit), Unit::Known);
    }
    // A pressure channel in a unit the table lacks: gauge when the unit
    // without a trailing `g` is one the table has (`barg`, `psig`).
    if let Some(stem) = unit.strip_suffix(['g', 'G'])
        && matches!(recognise(&with(stem)), Ok(Role::Pressure { .. }))
    {
        return (with(stem), Unit::Gauge);
    }
    (with(unit), Unit::UnknownPressure(unit.to_string()))
}

/// The pressure units the table has, for messages.
const PRESSURE_UNITS: &str =
    "bar, mbar, MPa, kPa, Pa, psi, kgf/cm2, atm, Torr or V; a trailing g (`barg`, `psig`) is gauge";

/// The channels of every group in a pressure unit the table lacks, for an
/// error: `` `PCYL1` (group 1) in `mmH2O` ``.
fn unknown_pressure(groups: &[&Group]) -> Option<String> {
    let all: Vec<String> = groups
        .iter()
        .flat_map(|g| {
            g.unknown_pressure.iter().map(move |(c, u)| {
                format!(
                    "`{}` (group {}) in `{}`",
                    enginedyn_numerics::format::quote(c),
                    g.number,
                    enginedyn_numerics::format::quote(u)
                )
            })
        })
        .collect();
    if all.is_empty() {
        return None;
    }
    let n = all.len();
    Some(format!(
        "{}{}, a pressure unit the reader does not know ({PRESSURE_UNITS}): convert the channel, or export it as CSV",
        all.into_iter().take(4).collect::<Vec<_>>().join(", "),
        if n > 4 { ", …" } else { "" }
    ))
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
        if !g.holds
            && opts.columns.is_none()
            && !opts.torque
            && let Some(m) = unknown_pressure(&[g])
        {
            return Err(IngestError::Data(format!("--group {n}: {m}")));
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
    if !opts.torque
        && let Some(m) = unknown_pressure(&groups.iter().collect::<Vec<_>>())
    {
        return Err(IngestError::Data(format!(
            "no channel group holds a pressure channel in a unit the reader knows: {m}; the groups: {}",
            list(groups)
        )));
    }
    Err(IngestError::Data(format!(
        "no channel group holds {what} channel (by its name and unit, as in `PCYL1 [bar]` or `pressure_v`): {}; --group N with --columns names a group's channels in order, the master first",
        list(groups)
    )))
}

/// The file's bytes, shared: falcon_mdf reads its blocks from them as from
/// its own in-memory source (the same bounds, the same errors), and
/// [`crate::decode`] its records.
struct Shared(Arc<Vec<u8>>);

impl falcon_mdf::io::ByteSource for Shared {
    fn len(&self) -> u64 {
        self.0.len() as u64
    }

    /// As falcon_mdf's `MemorySource`: a range past the end is its
    /// `truncated` error.
    fn read_bytes(
        &self,
        offset: u64,
        len: usize,
    ) -> falcon_mdf::error::Result<falcon_mdf::io::ByteSlice<'_>> {
        let data = &self.0;
        let truncated = falcon_mdf::error::Mf4Error::truncated;
        if offset >= data.len() as u64 {
            return Err(truncated(offset, len, 0));
        }
        let start = offset as usize;
        let available = data.len() - start;
        if len > available {
            return Err(truncated(offset, len, available));
        }
        Ok(falcon_mdf::io::ByteSlice::borrowed(
            &data[start..start + len],
        ))
    }
}

/// The group's channels (the columns, in order).
fn channels<'f>(file: &'f Mf4File, group: &Group) -> Vec<&'f Channel> {
    let cg = &file.data_groups()[group.dg].channel_groups[group.cg];
    group
        .columns
        .iter()
        .map(|(i, _)| &cg.channels[*i])
        .collect()
}

/// The group in the plain shape [`crate::decode`] reads (`dg` its data
/// group's block), else `None`: falcon_mdf decodes it.
fn plain<'f>(
    bytes: &'f [u8],
    dg: u64,
    file: &Mf4File,
    group: &Group,
) -> Option<crate::decode::Plain<'f>> {
    let cg = &file.data_groups()[group.dg].channel_groups[group.cg];
    crate::decode::Plain::new(
        bytes,
        dg,
        cg.data_bytes_len(),
        cg.inval_bytes_len(),
        cg.sample_count,
        &channels(file, group),
    )
}

/// The group's records, a window at a time, as columns: the header (the
/// column names) first, then each window's channels whole, decoded from
/// the bytes where the group is `plain`, else by falcon_mdf.
fn stream<F: FnMut(Streamed) -> Result<(), IngestError>>(
    file: &Mf4File,
    plain: Option<crate::decode::Plain<'_>>,
    group: &Group,
    declared: u64,
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
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(k);
    let held = match plain {
        Some(p) => p.read(chunk, &mut cols, damaged, |cols, first, n| {
            rd.columns(first + 2, cols, n, |r| Values { cols, r })
        })?,
        None => falcon_windows(file, group, chunk, &mut cols, rd)?,
    };
    Records {
        declared,
        held: held as u64,
    }
    .check(group)
}

/// The group's records decoded by falcon_mdf, a window of `chunk` at a
/// time (each channel's samples, NaN where its invalidation bit says so),
/// handed to the reader as columns. Returns the records read.
fn falcon_windows<F: FnMut(Streamed) -> Result<(), IngestError>>(
    file: &Mf4File,
    group: &Group,
    chunk: usize,
    cols: &mut Vec<Vec<f64>>,
    rd: &mut Reader<'_, F>,
) -> Result<usize, IngestError> {
    let windows = file
        .signals_chunks(&channels(file, group), chunk)
        .map_err(damaged)?;
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
        let cols = &*cols;
        rd.columns(record + 2, cols, n, |r| Values { cols, r })?;
        record += n;
    }
    Ok(record)
}

/// The records a channel group declares (its own `cg_cycle_count`, read
/// from the file: falcon_mdf lowers its count to what the data hold) and
/// those its data hold or gave.
struct Records {
    declared: u64,
    held: u64,
}

impl Records {
    /// Fewer records than declared is an error naming the group and both
    /// counts: a data block cut short, a data list with a null link, a record
    /// of an unknown id in unsorted data would each read part of the record.
    fn check(&self, group: &Group) -> Result<(), IngestError> {
        if self.held >= self.declared {
            return Ok(());
        }
        Err(damaged(format!(
            "group {}{} declares {} records, its data hold {}: a data block cut short, a data list missing a block, or a record of unknown id",
            group.number,
            if group.name.is_empty() {
                String::new()
            } else {
                format!(" `{}`", enginedyn_numerics::format::quote(&group.name))
            },
            self.declared,
            self.held
        )))
    }
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

/// One record's values (record `r` of the window's columns), NaN for an
/// invalid sample or a value that is no number: the cells of a row the
/// columns' path leaves to the general one.
struct Values<'a> {
    cols: &'a [Vec<f64>],
    r: usize,
}

impl Values<'_> {
    fn get(&self, i: usize) -> Option<&f64> {
        self.cols.get(i).and_then(|c| c.get(self.r))
    }
}

impl Cells for Values<'_> {
    fn len(&self) -> usize {
        self.cols.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        i >= self.cols.len()
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Owned(self.get(i).map(|v| v.to_string()).unwrap_or_default())
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        match self.get(i) {
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
