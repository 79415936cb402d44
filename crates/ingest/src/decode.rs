//! MDF4 records decoded by columns, straight from the file's bytes: each
//! channel's samples read out of the records in one pass a channel, into
//! the column the reader takes whole ([`crate::reader::Reader::columns`]).
//!
//! Only the plain shape is read here, which is what indicating systems and
//! asammdf write: sorted records (no record id) in data blocks as they lie
//! (`##DT`) or deflated (`##DZ`, transposed or not), alone or under data
//! lists of them (and a header list), each channel a little-endian
//! integer (any bit offset and width up to 64 bits) or an aligned float32
//! or float64, with no conversion or, for an integer or a float64, a
//! linear one (raw counts of an indicating system's ADC, scaled); a
//! channel's invalidation bit makes its sample NaN. Anything else
//! (another compression, unsorted records, another data type or
//! conversion, a block that is not whole) is [`Plain::new`]'s `None`, and the caller
//! decodes by falcon_mdf instead: what each sample is stays falcon_mdf's
//! rule, and the tests hold this decoder to it bit for bit.
//!
//! Nothing is copied but the samples: the records are read where they lie
//! (a record split across two blocks through a buffer of one record), and
//! the columns hold one window at a time. A deflated block is expanded
//! into a buffer kept from block to block (and un-transposed into a
//! second), then read as a plain one. What is read is bounded by the
//! blocks present: a count the file declares is never allocated from, and
//! a deflated block expands to at most [`MAX_MDF_BLOCK`] (falcon_mdf's
//! bound, with its messages).

use crate::mdf::{MAX_MDF_ALLOC, MAX_MDF_BLOCK};
use crate::number::word;
use falcon_mdf::error::Mf4Error;

use falcon_mdf::Channel;
use falcon_mdf::blocks::{ChannelType, Conversion, DataType};

/// How one channel's sample is read from a record.
#[derive(Debug, Clone, Copy)]
struct Field {
    /// The first byte the value touches (from the record's start).
    byte: usize,
    /// Bytes it touches: at most 8.
    span: usize,
    /// The bit offset within the first byte, and the width.
    shift: u32,
    bits: u32,
    kind: Kind,
    /// The invalidation bit: its byte in the record and its bit.
    invalid: Option<(usize, u32)>,
}

/// The channel's data type and conversion, as falcon_mdf reads them;
/// `Some((factor, offset))`: a linear conversion.
#[derive(Debug, Clone, Copy)]
enum Kind {
    Unsigned(Option<(f64, f64)>),
    Signed(Option<(f64, f64)>),
    F32,
    /// A float64; `Some((factor, offset))`: a linear conversion.
    F64(Option<(f64, f64)>),
}

impl Field {
    /// The field of `ch`, in records of `data` data bytes and `inval`
    /// invalidation bytes; `None` outside the plain shape.
    fn of(ch: &Channel, data: usize, inval: usize) -> Option<Self> {
        if ch.unreadable().is_some()
            || ch.is_array()
            || ch.all_invalid
            || !matches!(
                ch.channel_type,
                ChannelType::FixedLength | ChannelType::Master
            )
        {
            return None;
        }
        let (shift, bits) = (u32::from(ch.bit_offset), ch.bit_count);
        let identity = ch.conversion.is_identity();
        let linear = match ch.conversion {
            _ if identity => Some(None),
            Conversion::Linear { offset, factor } => Some(Some((factor, offset))),
            _ => None,
        };
        let kind = match (ch.data_type, bits, shift) {
            (DataType::FloatLe, 64, 0) => match ch.conversion {
                Conversion::None => Kind::F64(None),
                Conversion::Linear { offset, factor } => Kind::F64(Some((factor, offset))),
                _ => return None,
            },
            (DataType::FloatLe, 32, 0) if identity => Kind::F32,
            (DataType::UIntLe, 1..=64, 0..=7) => Kind::Unsigned(linear?),
            (DataType::IntLe, 1..=64, 0..=7) => Kind::Signed(linear?),
            _ => return None,
        };
        let span = (shift + bits).div_ceil(8) as usize;
        let byte = ch.byte_offset as usize;
        if span > 8 || byte.checked_add(span)? > data {
            return None;
        }
        // falcon_mdf reads no validity from a bit past the invalidation bytes.
        let invalid = if ch.invalidation_bit && inval > 0 {
            let at = (ch.inval_bit_pos / 8) as usize;
            (at < inval).then_some((data + at, ch.inval_bit_pos % 8))
        } else {
            None
        };
        Some(Self {
            byte,
            span,
            shift,
            bits,
            kind,
            invalid,
        })
    }

    /// The samples of `records` (whole ones, `stride` bytes each) appended
    /// to `out`.
    fn decode(&self, records: &[u8], stride: usize, out: &mut Vec<f64>) {
        let start = out.len();
        let rows = records.chunks_exact(stride);
        let at = self.byte;
        match self.kind {
            // The usual channels: whole aligned bytes, one load each.
            Kind::F64(None) => whole(records, stride, at, out, f64::from_le_bytes),
            Kind::F64(Some((f, o))) => {
                whole(records, stride, at, out, |b| f * f64::from_le_bytes(b) + o)
            }
            Kind::F32 => whole(records, stride, at, out, |b| {
                f64::from(f32::from_le_bytes(b))
            }),
            // Whole aligned bytes, as a DAQ writes its counts.
            Kind::Signed(c) if self.whole(16) => whole(records, stride, at, out, |b| {
                scaled(i16::from_le_bytes(b).into(), c)
            }),
            Kind::Unsigned(c) if self.whole(16) => whole(records, stride, at, out, |b| {
                scaled(u16::from_le_bytes(b).into(), c)
            }),
            Kind::Signed(c) if self.whole(32) => whole(records, stride, at, out, |b| {
                scaled(i32::from_le_bytes(b).into(), c)
            }),
            Kind::Unsigned(c) if self.whole(32) => whole(records, stride, at, out, |b| {
                scaled(u32::from_le_bytes(b).into(), c)
            }),
            Kind::Unsigned(c) => out.extend(rows.map(|r| scaled(self.raw(r) as f64, c))),
            Kind::Signed(c) => {
                let up = 64 - self.bits;
                out.extend(rows.map(|r| scaled((((self.raw(r) << up) as i64) >> up) as f64, c)))
            }
        }
        if let Some((byte, bit)) = self.invalid {
            for (x, r) in out[start..].iter_mut().zip(records.chunks_exact(stride)) {
                if (r[byte] >> bit) & 1 != 0 {
                    *x = f64::NAN;
                }
            }
        }
    }

    /// True for a field of `bits` whole bytes from a byte's first bit.
    fn whole(&self, bits: u32) -> bool {
        self.shift == 0 && self.bits == bits
    }

    /// The field's bits, shifted down and masked: the bytes it touches read
    /// little-endian.
    #[inline(always)]
    fn raw(&self, record: &[u8]) -> u64 {
        let mut b = [0u8; 8];
        b[..self.span].copy_from_slice(&record[self.byte..self.byte + self.span]);
        let v = u64::from_le_bytes(b) >> self.shift;
        if self.bits == 64 {
            v
        } else {
            v & ((1u64 << self.bits) - 1)
        }
    }
}

/// A raw value through the channel's linear conversion, as falcon_mdf
/// applies it (`factor * raw + offset`), or as it is.
#[inline(always)]
fn scaled(raw: f64, linear: Option<(f64, f64)>) -> f64 {
    match linear {
        Some((f, o)) => f * raw + o,
        None => raw,
    }
}

/// The samples of a field of whole bytes (`N` from `at` in each record of
/// `stride` bytes), each read by `value`, appended to `out`: four records
/// a step, the field's bounds checked once.
#[inline(always)]
fn whole<const N: usize>(
    records: &[u8],
    stride: usize,
    at: usize,
    out: &mut Vec<f64>,
    value: impl Fn([u8; N]) -> f64,
) {
    // The field lies within the record (`Field::of`); said here, the reads
    // below need no check of their own.
    if at + N > stride {
        return;
    }
    out.reserve(records.len() / stride);
    let mut fours = records.chunks_exact(4 * stride);
    for four in &mut fours {
        let (s1, s2, s3) = (stride, 2 * stride, 3 * stride);
        out.extend_from_slice(&[
            value(bytes(four, at)),
            value(bytes(four, at + s1)),
            value(bytes(four, at + s2)),
            value(bytes(four, at + s3)),
        ]);
    }
    let rest = fours.remainder().chunks_exact(stride);
    out.extend(rest.map(|r| value(bytes(r, at))));
}

/// `N` bytes of `record` from `at` (the field was checked to lie within).
#[inline(always)]
fn bytes<const N: usize>(record: &[u8], at: usize) -> [u8; N] {
    let mut b = [0u8; N];
    b.copy_from_slice(&record[at..at + N]);
    b
}

/// A channel group in the plain shape: its data blocks' bytes in order,
/// its record stride and the channels' fields.
pub(crate) struct Plain<'f> {
    blocks: Vec<Body<'f>>,
    stride: usize,
    records: usize,
    fields: Vec<Field>,
}

/// A data block's records: where they lie (`##DT`), or deflated
/// (`##DZ`: the packed stream, the length it expands to, and for a
/// transposed block the bytes of a record, its columns).
#[derive(Debug, Clone, Copy)]
enum Body<'f> {
    Plain(&'f [u8]),
    Deflated {
        packed: &'f [u8],
        size: usize,
        columns: Option<usize>,
    },
}

impl<'f> Body<'f> {
    /// A `##DZ` block's body (its data after the links) in the plain
    /// shape: records of a `##DT`, deflated (zip type 0) or transposed and
    /// deflated (1, by a record's bytes), expanding to at most
    /// [`MAX_MDF_BLOCK`]; `None` for anything else.
    fn deflated(data: &'f [u8]) -> Option<Self> {
        let size_at = |at: usize| usize::try_from(u64_at(data, at)?).ok();
        if data.get(..2)? != b"DT" {
            return None;
        }
        let param = u32::from_le_bytes(data.get(4..8)?.try_into().ok()?);
        let columns = match (*data.get(2)?, param) {
            (0, _) => None,
            (1, 1..) => Some(usize::try_from(param).ok()?),
            _ => return None,
        };
        let (size, packed) = (size_at(8)?, size_at(16)?);
        if size as u64 > MAX_MDF_BLOCK {
            return None;
        }
        Some(Body::Deflated {
            packed: data.get(24..24usize.checked_add(packed)?)?,
            size,
            columns,
        })
    }

    /// The bytes of records the block holds.
    fn len(&self) -> usize {
        match *self {
            Body::Plain(b) => b.len(),
            Body::Deflated { size, .. } => size,
        }
    }

    /// The block's records: as they lie, or expanded into `buf` (and
    /// un-transposed through `flat`) as falcon_mdf expands them, with its
    /// errors.
    fn records<'b>(&self, buf: &'b mut Vec<u8>, flat: &'b mut Vec<u8>) -> Result<&'b [u8], Mf4Error>
    where
        'f: 'b,
    {
        let (packed, size, columns) = match *self {
            Body::Plain(b) => return Ok(b),
            Body::Deflated {
                packed,
                size,
                columns,
            } => (packed, size, columns),
        };
        use std::io::Read;
        buf.clear();
        // As falcon_mdf: no more reserved from a declared length than
        // `MAX_MDF_ALLOC`; the buffer grows with what the stream gives.
        buf.reserve(size.min(MAX_MDF_ALLOC));
        flate2::bufread::ZlibDecoder::new(packed)
            .take(MAX_MDF_BLOCK)
            .read_to_end(buf)
            .map_err(|e| Mf4Error::Decompression(e.to_string()))?;
        if buf.len() != size {
            return Err(Mf4Error::Decompression(format!(
                "Decompressed size mismatch: expected {size} bytes, got {}",
                buf.len()
            )));
        }
        match columns {
            None => Ok(buf),
            Some(c) => {
                un_transpose(buf, c, flat);
                Ok(flat)
            }
        }
    }
}

/// A transposed block's bytes in record order, into `out`: the first
/// `lines = len / columns` records were stored column by column (byte `k`
/// of every record, then byte `k + 1`), the bytes after them as they are.
/// Eight records by eight bytes at a time, as one 8 × 8 transposition of
/// words ([`transpose8`]); the edges byte by byte.
fn un_transpose(t: &[u8], columns: usize, out: &mut Vec<u8>) {
    let lines = t.len() / columns;
    out.clear();
    if lines == 0 {
        // No whole record (a block shorter than the file's record length):
        // as it is, without a pass over the columns.
        out.extend_from_slice(t);
        return;
    }
    out.resize(t.len(), 0);
    let body = lines * columns;
    let (rows8, cols8) = (lines / 8 * 8, columns / 8 * 8);
    // Tiles of records whose bytes stay in the first-level cache while
    // every eight columns are written into them.
    let tile = (16_384 / columns).max(8) / 8 * 8;
    for r0 in (0..rows8).step_by(tile) {
        let r1 = (r0 + tile).min(rows8);
        let records = &mut out[r0 * columns..r1 * columns];
        for k in (0..cols8).step_by(8) {
            let from: [&[u8]; 8] = std::array::from_fn(|j| &t[(k + j) * lines + r0..][..r1 - r0]);
            for (b, eight) in records.chunks_exact_mut(8 * columns).enumerate() {
                let square = transpose8(std::array::from_fn(|j| word(from[j], 8 * b)));
                for (i, row) in square.iter().enumerate() {
                    eight[i * columns + k..][..8].copy_from_slice(&row.to_le_bytes());
                }
            }
        }
    }
    // The columns beyond the last eight for every record, then the records
    // beyond the last eight.
    for k in cols8..columns {
        for r in 0..rows8 {
            out[r * columns + k] = t[k * lines + r];
        }
    }
    for k in 0..columns {
        for r in rows8..lines {
            out[r * columns + k] = t[k * lines + r];
        }
    }
    out[body..].copy_from_slice(&t[body..]);
}

/// An 8 × 8 matrix of bytes transposed: byte `i` of word `j` becomes byte
/// `j` of word `i`. Three exchanges, of 4 × 4, 2 × 2 and single bytes
/// across the diagonal, each swapping one bit of the row index with the
/// same bit of the column index.
#[inline(always)]
fn transpose8(mut a: [u64; 8]) -> [u64; 8] {
    for (shift, mask, pairs) in [
        (32, 0x0000_0000_ffff_ffff_u64, [0, 1, 2, 3]),
        (16, 0x0000_ffff_0000_ffff, [0, 1, 4, 5]),
        (8, 0x00ff_00ff_00ff_00ff, [0, 2, 4, 6]),
    ] {
        let step = shift / 8;
        for i in pairs {
            let x = ((a[i] >> shift) ^ a[i + step]) & mask;
            a[i] ^= x << shift;
            a[i + step] ^= x;
        }
    }
    a
}

/// A block's header: its four-byte id, its length and its links.
pub(crate) struct Block<'a> {
    pub(crate) id: &'a [u8],
    pub(crate) links: Vec<u64>,
    /// The block's data (after its links).
    pub(crate) data: &'a [u8],
}

/// The little-endian u64 of a block's field at `at` in `data`, if there.
pub(crate) fn u64_at(data: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(
        data.get(at..at.checked_add(8)?)?.try_into().ok()?,
    ))
}

/// The block at `at`, when one is there whole; `None` otherwise (falcon_mdf
/// then names the damage).
pub(crate) fn block(bytes: &[u8], at: u64) -> Option<Block<'_>> {
    let at = usize::try_from(at).ok()?;
    let head = bytes.get(at..at.checked_add(24)?)?;
    if &head[..2] != b"##" {
        return None;
    }
    let len = usize::try_from(u64_at(head, 8)?).ok()?;
    let n = usize::try_from(u64_at(head, 16)?).ok()?;
    let links_end = n.checked_mul(8)?.checked_add(24)?;
    if len < links_end {
        return None;
    }
    let whole = bytes.get(at..at.checked_add(len)?)?;
    let links = whole[24..links_end]
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().unwrap_or_default()))
        .collect();
    Some(Block {
        id: &whole[..4],
        links,
        data: &whole[links_end..],
    })
}

impl<'f> Plain<'f> {
    /// The group's plain shape: `dg` the data group's block in `bytes`,
    /// `data` and `inval` its records' data and invalidation bytes,
    /// `records` the count falcon_mdf reads (at most what the blocks hold),
    /// `channels` the columns. `None` when any part is outside it.
    pub(crate) fn new(
        bytes: &'f [u8],
        dg: u64,
        data: usize,
        inval: usize,
        records: u64,
        channels: &[&Channel],
    ) -> Option<Self> {
        let Block {
            id,
            links,
            data: dg_data,
        } = block(bytes, dg)?;
        // Sorted: no record id (dg_rec_id_size 0).
        if id != b"##DG" || dg_data.first() != Some(&0) {
            return None;
        }
        let stride = data.checked_add(inval)?;
        let fields = channels
            .iter()
            .map(|ch| Field::of(ch, data, inval))
            .collect::<Option<Vec<_>>>()?;
        let mut blocks = Vec::new();
        // One ##DT or ##DZ, or data lists (##DL) of them, each link filled,
        // perhaps under a header list (##HL).
        let mut next = *links.get(2)?;
        if let Some(Block {
            id: b"##HL", links, ..
        }) = block(bytes, next)
        {
            next = *links.first()?;
        }
        // A data block has no links; falcon_mdf reads its data at byte 24
        // whatever it declares, so one that declares links is left to it.
        let body = |b: Block<'f>| match b.id {
            _ if !b.links.is_empty() => None,
            b"##DT" => Some(Body::Plain(b.data)),
            b"##DZ" => Body::deflated(b.data),
            _ => None,
        };
        let mut seen = std::collections::HashSet::new();
        while next != 0 {
            if !seen.insert(next) {
                return None;
            }
            let b = block(bytes, next)?;
            if b.id == b"##DL" {
                for &at in b.links.get(1..)? {
                    blocks.push(body(block(bytes, at)?)?);
                }
                next = *b.links.first()?;
            } else {
                blocks.push(body(b)?);
                next = 0;
            }
        }
        let held: usize = blocks.iter().map(Body::len).sum::<usize>() / stride.max(1);
        let records = usize::try_from(records).ok()?;
        (stride > 0 && !blocks.is_empty() && records <= held).then_some(Self {
            blocks,
            stride,
            records,
            fields,
        })
    }

    /// Decodes the records, at most `chunk` a window, into `cols` (one a
    /// channel, cleared each window) and hands each window to `f` with its
    /// first record and its length. Returns the records read; a deflated
    /// block that does not expand to its length is falcon_mdf's error, by
    /// `damaged`.
    pub(crate) fn read<E>(
        &self,
        chunk: usize,
        cols: &mut Vec<Vec<f64>>,
        damaged: impl Fn(Mf4Error) -> E,
        mut f: impl FnMut(&[Vec<f64>], usize, usize) -> Result<(), E>,
    ) -> Result<usize, E> {
        let stride = self.stride;
        let chunk = chunk.max(1);
        cols.resize_with(self.fields.len(), Vec::new);
        for c in cols.iter_mut() {
            c.clear();
        }
        let (mut done, mut first, mut in_window) = (0usize, 0usize, 0usize);
        // A record split across two blocks, completed from the next.
        let mut carry: Vec<u8> = Vec::new();
        // A deflated block's bytes, kept from block to block.
        let (mut buf, mut flat) = (Vec::new(), Vec::new());
        for body in &self.blocks {
            let mut rest = body.records(&mut buf, &mut flat).map_err(&damaged)?;
            if !carry.is_empty() {
                let need = (stride - carry.len()).min(rest.len());
                carry.extend_from_slice(&rest[..need]);
                rest = &rest[need..];
                if carry.len() < stride {
                    continue;
                }
            }
            let whole = rest.len() / stride * stride;
            let carried = std::mem::take(&mut carry);
            // The record carried over, then the block's whole records.
            for mut piece in [carried.as_slice(), &rest[..whole]] {
                while done < self.records && piece.len() >= stride {
                    let take = (chunk - in_window)
                        .min(self.records - done)
                        .min(piece.len() / stride);
                    let (now, later) = piece.split_at(take * stride);
                    for (field, col) in self.fields.iter().zip(cols.iter_mut()) {
                        field.decode(now, stride, col);
                    }
                    piece = later;
                    done += take;
                    in_window += take;
                    if in_window == chunk {
                        f(cols, first, in_window)?;
                        first = done;
                        in_window = 0;
                        for c in cols.iter_mut() {
                            c.clear();
                        }
                    }
                }
            }
            if done == self.records {
                break;
            }
            carry.extend_from_slice(&rest[whole..]);
        }
        if in_window > 0 {
            f(cols, first, in_window)?;
        }
        Ok(done)
    }
}

#[cfg(test)]
mod tests;
