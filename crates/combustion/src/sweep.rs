//! The window pass of a filter with running sums, in one sweep (issue
//! 42.1): at every window point the smoothed pressure and slope (the
//! stretches and steps of [`Filter::values_slopes_into`]), the cumulative
//! heat release (the trapezoidal work and the energy term), the noise fit's
//! residual, the volume law's window figures and the pressure peak.
//!
//! The window's two halves go side by side in the two lanes of one vector
//! register, each a run of the filter's stretches ([`Moments::refresh`]
//! points, each from fresh sums), split at the stretch boundary nearest the
//! middle ([`split`]); the longer lane's rest goes alone. Lane by lane the
//! same IEEE steps as one stretch after the other, so the smoothed values
//! and slopes are `values_slopes_into`'s bit for bit, and the first half's
//! cumulative is the serial pass's. The second half's work starts from 0
//! and takes the first half's at its end afterwards (one addition a point,
//! in the extremes' scan: its last bits may differ from the serial sum's).
//! The pressure and the volume law are read where they lie in the cycle,
//! runs of whole stretches a call (a stretch over the cycle's end is copied
//! out, a few dozen points); with the volume law's window figures given
//! (`burn::WindowLaw`) the law comes laid out for the two lanes
//! ([`law_pairs`]).
//!
//! [`Filter::values_slopes_into`]: crate::smooth::Filter::values_slopes_into

use crate::burn::{CycleGrid, copy_periodic, wrap};
use crate::smooth::{Lane, Moments, Outputs, Slope, Value, ValueSlope, moments, slide, two_starts};
use wide::f64x2;

/// The energy term `E(pV)` of the cumulative, lane by lane.
pub(crate) trait Energy {
    /// `E(pv)` in each lane.
    fn of<T: Lane>(&self, pv: T) -> T;
}

/// A constant γ: `pV / (γ − 1)` as `pV · inv`.
pub(crate) struct Linear(pub(crate) f64);

impl Energy for Linear {
    #[inline(always)]
    fn of<T: Lane>(&self, pv: T) -> T {
        pv * T::splat(self.0)
    }
}

/// Any `E(pV)`, a call a point.
pub(crate) struct ByPoint<F: Fn(f64) -> f64>(pub(crate) F);

impl<F: Fn(f64) -> f64> Energy for ByPoint<F> {
    #[inline(always)]
    fn of<T: Lane>(&self, pv: T) -> T {
        pv.map(&self.0)
    }
}

/// The buffers of a stretch that lies over the cycle's end (its samples
/// copied out in order), and the stretches' pressure peaks; kept from
/// cycle to cycle.
#[derive(Debug, Default)]
pub(crate) struct Bufs {
    lane: [Vec<f64>; 6],
    /// Each stretch's largest pressure.
    peaks: Vec<f64>,
}

/// What the sweep writes: the cumulative (J) and the slope (Pa/°) at
/// every window point, and the smoothed pressure (Pa) when asked for.
pub(crate) struct Outs<'a> {
    pub(crate) qs: &'a mut Vec<f64>,
    pub(crate) slope: &'a mut Vec<f64>,
    pub(crate) ps: Option<&'a mut Vec<f64>>,
}

/// What the sweep finds besides the curves.
pub(crate) struct Swept {
    /// The largest pressure in the window and its index (the first, if
    /// tied; NaN passed over; `(−∞, 0)` when none is over −∞).
    pub(crate) peak: (f64, usize),
    /// `Σ (p − p_smooth)²` over the window.
    pub(crate) res2: f64,
    /// `Σ (h dV)²` over the window (m⁶).
    pub(crate) dv2: f64,
    /// The largest volume in the window (at least 0).
    pub(crate) v_max: f64,
    /// The cumulative from this window index on still lacks the work
    /// before it (the second lane starts from 0): add this (J).
    pub(crate) rest: (usize, f64),
}

/// The running figures of one lane (or two side by side).
#[derive(Clone, Copy)]
struct State<T> {
    /// The moments about `r` ([`Moments`]).
    t: [T; 4],
    r: T,
    /// The work since the lane's start and the last `p dV/dφ`.
    w: T,
    prev: T,
    /// `Σ (p − p_smooth)²`, `Σ (h dV)²`, the largest volume, the stretch's
    /// largest pressure.
    res2: T,
    dv2: T,
    vmax: T,
    pk: T,
}

/// The constants of a sweep.
struct Consts {
    /// Half the filter and the stretch (points).
    m: usize,
    l: usize,
    /// The slide's offsets ([`slide`]).
    c: [f64; 6],
    y: ValueSlope,
    /// `h/2` and `h` (rad).
    hh: f64,
    h: f64,
}

/// One lane's inputs over a run of steps: the pressure from `m + 1` points
/// before the first centre (the sample a slide there drops) to `m` after
/// the last, the volume law at the centres.
#[derive(Clone, Copy)]
struct Src<'a> {
    s: &'a [f64],
    v: &'a [f64],
    dv: &'a [f64],
}

impl<'a> Src<'a> {
    /// The same from step `j` on.
    fn from(self, j: usize) -> Self {
        Src {
            s: &self.s[j..],
            v: &self.v[j..],
            dv: &self.dv[j..],
        }
    }
}

/// One lane's outputs over a run of steps (`ps` empty when not wanted),
/// and its stretches' largest pressures (the first: the stretch of the
/// run's first step).
struct Dst<'a> {
    q: &'a mut [f64],
    d: &'a mut [f64],
    ps: &'a mut [f64],
    peaks: &'a mut [f64],
}

impl Dst<'_> {
    /// The same from step `j` on (the peaks from that step's stretch:
    /// `stretch_from` of them passed over).
    fn from(&mut self, j: usize, stretch_from: usize) -> Dst<'_> {
        Dst {
            q: &mut self.q[j..],
            d: &mut self.d[j..],
            ps: if self.ps.is_empty() {
                &mut []
            } else {
                &mut self.ps[j..]
            },
            peaks: &mut self.peaks[stretch_from..],
        }
    }
}

/// One lane (`f64`) or two side by side (`f64x2`): how a step reads its
/// lanes' inputs and writes their outputs (the second lane's slices are
/// empty for one lane).
trait Lanes: Lane {
    /// Two lanes.
    const TWO: bool;
    fn pick(x: [&[f64]; 2], i: usize) -> Self;
    fn put(self, x: [&mut [f64]; 2], i: usize);
    /// The fresh moments of each lane's window `w` (`2m + 1` points) about
    /// `r` ([`moments`], [`two_starts`]).
    fn starts(w: [&[f64]; 2], r: Self, m: usize) -> [Self; 4];
    /// Lane 0's (and lane 1's) number.
    fn lanes(self) -> [f64; 2];
    /// The volume and `dV/dφ` of the lanes' step from the law laid out as
    /// the lanes read it ([`law_pairs`]; two lanes only).
    fn law(x: &[f64x2; 2]) -> (Self, Self);
}

impl Lanes for f64 {
    const TWO: bool = false;
    #[inline(always)]
    fn pick(x: [&[f64]; 2], i: usize) -> Self {
        x[0][i]
    }
    #[inline(always)]
    fn put(self, x: [&mut [f64]; 2], i: usize) {
        let [a, _] = x;
        a[i] = self;
    }
    #[inline(always)]
    fn starts(w: [&[f64]; 2], r: Self, m: usize) -> [Self; 4] {
        moments::<4>(w[0], r, m)
    }
    #[inline(always)]
    fn lanes(self) -> [f64; 2] {
        [self, self]
    }
    #[inline(always)]
    fn law(x: &[f64x2; 2]) -> (Self, Self) {
        (x[0].to_array()[0], x[1].to_array()[0])
    }
}

impl Lanes for f64x2 {
    const TWO: bool = true;
    #[inline(always)]
    fn pick(x: [&[f64]; 2], i: usize) -> Self {
        f64x2::new([x[0][i], x[1][i]])
    }
    #[inline(always)]
    fn put(self, x: [&mut [f64]; 2], i: usize) {
        let [a, b] = x;
        let v = self.to_array();
        (a[i], b[i]) = (v[0], v[1]);
    }
    #[inline(always)]
    fn starts(w: [&[f64]; 2], r: Self, m: usize) -> [Self; 4] {
        two_starts::<true>((w[0], w[1]), r, m)
    }
    #[inline(always)]
    fn lanes(self) -> [f64; 2] {
        self.to_array()
    }
    #[inline(always)]
    fn law(x: &[f64x2; 2]) -> (Self, Self) {
        (x[0], x[1])
    }
}

/// One window point from the moments in `st` (slid there already): its
/// cumulative, smoothed pressure and slope; the running sums take it in.
/// The same operations in the same order as the serial pass
/// (`burn::piece`).
#[inline(always)]
fn point<T: Lane, E: Energy, const LAW: bool>(
    st: &mut State<T>,
    k: &Consts,
    (p, v, dv): (T, T, T),
    e: &E,
) -> (T, T, T) {
    let [ps, d] = k.y.y(&st.t, st.r);
    let pdv = p * dv;
    st.w = st.w + T::splat(k.hh) * (st.prev + pdv);
    st.prev = pdv;
    let r = p - ps;
    st.res2 = st.res2 + r * r;
    if !LAW {
        let hd = T::splat(k.h) * dv;
        st.dv2 = st.dv2 + hd * hd;
        st.vmax = v.gt_max(st.vmax);
    }
    st.pk = p.gt_max(st.pk);
    (st.w + e.of(ps * v), ps, d)
}

/// The lane's state alone.
fn lane(st: &State<f64x2>, i: usize) -> State<f64> {
    let x = |v: f64x2| v.to_array()[i];
    State {
        t: st.t.map(x),
        r: x(st.r),
        w: x(st.w),
        prev: x(st.prev),
        res2: x(st.res2),
        dv2: x(st.dv2),
        vmax: x(st.vmax),
        pk: x(st.pk),
    }
}

/// Steps `0..n` of a run (each lane: `src` and `dst` from its first step;
/// `phase`: that step's place in its stretch), fresh sums at each
/// stretch's first step and a slide on at every other: a function of its
/// own, so that the compiler keeps the running figures in vector
/// registers. Each stretch's largest pressure so far goes to the peaks.
#[inline(never)]
fn run<T: Lanes, E: Energy, const PS: bool, const LAW: bool>(
    st: &mut State<T>,
    ([a, b], il): ([Src; 2], &[[f64x2; 2]]),
    [oa, ob]: [&mut Dst; 2],
    (phase, n): (usize, usize),
    k: &Consts,
    e: &E,
) {
    // With the law's figures given, two lanes read the law laid out for
    // them (`il`, from the run's first step).
    let paired = LAW && T::TWO;
    let (m, l) = (k.m, k.l);
    let c = k.c.map(T::splat);
    // The second lane's slice of `x`, when there is one.
    fn sub(two: bool, x: &[f64], r: std::ops::Range<usize>) -> &[f64] {
        if two { &x[r] } else { &[] }
    }
    let mut i = 0;
    while i < n {
        let ph = (phase + i) % l;
        let end = (i + l - ph).min(n);
        let stretch = (phase + i) / l;
        let mut j = i;
        if ph == 0 {
            let w = [
                &a.s[j + 1..=j + 2 * m + 1],
                sub(T::TWO, b.s, j + 1..j + 2 * m + 2),
            ];
            st.r = T::pick([a.s, b.s], j + m + 1);
            st.t = T::starts(w, st.r, m);
            st.pk = T::splat(f64::NEG_INFINITY);
            let (v, dv) = if paired {
                T::law(&il[j])
            } else {
                (T::pick([a.v, b.v], j), T::pick([a.dv, b.dv], j))
            };
            let x = (T::pick([a.s, b.s], j + m + 1), v, dv);
            let (q, ps, d) = point::<T, E, LAW>(st, k, x, e);
            q.put([&mut *oa.q, &mut *ob.q], j);
            d.put([&mut *oa.d, &mut *ob.d], j);
            if PS {
                ps.put([&mut *oa.ps, &mut *ob.ps], j);
            }
            j += 1;
        }
        let len = end.saturating_sub(j);
        if len > 0 {
            let two = <T as Lanes>::TWO;
            let (ao, ai, ac) = (
                &a.s[j..j + len],
                &a.s[2 * m + 1 + j..2 * m + 1 + j + len],
                &a.s[m + 1 + j..m + 1 + j + len],
            );
            let (bo, bi, bc) = if two {
                (
                    &b.s[j..j + len],
                    &b.s[2 * m + 1 + j..2 * m + 1 + j + len],
                    &b.s[m + 1 + j..m + 1 + j + len],
                )
            } else {
                (&[][..], &[][..], &[][..])
            };
            let (av, adv) = if paired {
                (&[][..], &[][..])
            } else {
                (&a.v[j..j + len], &a.dv[j..j + len])
            };
            let (bv, bdv) = if paired {
                (&[][..], &[][..])
            } else {
                (sub(T::TWO, b.v, j..j + len), sub(T::TWO, b.dv, j..j + len))
            };
            let ilj = if paired { &il[j..j + len] } else { &[][..] };
            let (qa, da) = (&mut oa.q[j..j + len], &mut oa.d[j..j + len]);
            let (qb, db): (&mut [f64], &mut [f64]) = if two {
                (&mut ob.q[j..j + len], &mut ob.d[j..j + len])
            } else {
                (&mut [], &mut [])
            };
            let (pa, pb): (&mut [f64], &mut [f64]) = match (PS, two) {
                (true, true) => (&mut oa.ps[j..j + len], &mut ob.ps[j..j + len]),
                (true, false) => (&mut oa.ps[j..j + len], &mut []),
                _ => (&mut [], &mut []),
            };
            for i in 0..len {
                let qo = T::pick([ao, bo], i) - st.r;
                let qi = T::pick([ai, bi], i) - st.r;
                slide::<T, true>(&mut st.t, qo, qi, &c);
                let (v, dv) = if paired {
                    T::law(&ilj[i])
                } else {
                    (T::pick([av, bv], i), T::pick([adv, bdv], i))
                };
                let x = (T::pick([ac, bc], i), v, dv);
                let (q, ps, d) = point::<T, E, LAW>(st, k, x, e);
                q.put([&mut *qa, &mut *qb], i);
                d.put([&mut *da, &mut *db], i);
                if PS {
                    ps.put([&mut *pa, &mut *pb], i);
                }
            }
        }
        let s0 = phase / l;
        let [pa, pb] = st.pk.lanes();
        oa.peaks[stretch - s0] = pa;
        if <T as Lanes>::TWO {
            ob.peaks[stretch - s0] = pb;
        }
        i = end;
    }
}

/// [`run`] with the smoothed pressure written or not (`ps`), the volume
/// law's figures taken or given (`law`).
#[inline(always)]
fn run_as<T: Lanes, E: Energy>(
    (ps, law): (bool, bool),
    st: &mut State<T>,
    src: ([Src; 2], &[[f64x2; 2]]),
    dst: [&mut Dst; 2],
    span: (usize, usize),
    k: &Consts,
    e: &E,
) {
    match (ps, law) {
        (false, false) => run::<T, E, false, false>(st, src, dst, span, k, e),
        (false, true) => run::<T, E, false, true>(st, src, dst, span, k, e),
        (true, false) => run::<T, E, true, false>(st, src, dst, span, k, e),
        (true, true) => run::<T, E, true, true>(st, src, dst, span, k, e),
    }
}

/// `v[start..start + len]` of the periodic `v`: borrowed where it lies in
/// one piece, else copied into `buf`.
fn periodic<'a>(v: &'a [f64], start: i64, len: usize, buf: &'a mut Vec<f64>) -> &'a [f64] {
    let k = wrap(start, v.len() as i64);
    if k + len <= v.len() {
        &v[k..k + len]
    } else {
        copy_periodic(v, start, len, buf);
        &buf[..]
    }
}

/// A lane of the window: its first window index, its length, and the
/// grid's arrays.
#[derive(Clone, Copy)]
struct LaneOf<'a> {
    g: &'a CycleGrid<'a>,
    /// The grid index of the window's first point, and this lane's first
    /// window index.
    i0: i64,
    w0: usize,
    len: usize,
}

impl<'a> LaneOf<'a> {
    /// The lane's steps `c0..c1` lie in one piece of the cycle (their
    /// pressure with the filter's reach, and their volume law).
    fn direct(&self, (c0, c1): (usize, usize), m: usize) -> bool {
        let n = self.g.pressure.len();
        let at = self.i0 + (self.w0 + c0) as i64;
        wrap(at - m as i64 - 1, n as i64) + (c1 - c0) + 2 * m < n
            && wrap(at, n as i64) + (c1 - c0) <= n
    }

    /// The lane's inputs over steps `c0..c1`: borrowed where they lie in
    /// one piece, else copied into `bufs`.
    fn src<'b>(&self, (c0, c1): (usize, usize), m: usize, bufs: &'b mut [Vec<f64>]) -> Src<'b>
    where
        'a: 'b,
    {
        let [bp, bv, bd] = bufs else {
            unreachable!("three buffers a lane")
        };
        let at = self.i0 + (self.w0 + c0) as i64;
        let g = self.g;
        Src {
            s: periodic(g.pressure, at - m as i64 - 1, c1 - c0 + 2 * m + 1, bp),
            v: periodic(g.volume, at, c1 - c0, bv),
            dv: periodic(g.dvolume, at, c1 - c0, bd),
        }
    }

    /// The end of the run of steps from `c0` (a stretch's first) up to `to`
    /// that lies in one piece, whole stretches; a stretch that does not is
    /// a run of its own. The run's end and whether it lies in one piece.
    fn run_end(&self, c0: usize, to: usize, l: usize, m: usize) -> (usize, bool) {
        let first = (c0 - c0 % l + l).min(to);
        if !self.direct((c0, first), m) {
            return (first, false);
        }
        // The farthest step whose pressure (with the reach) and volume law
        // still lie in the piece from `c0`'s, back to a stretch's end.
        let n = self.g.pressure.len();
        let at = self.i0 + (self.w0 + c0) as i64;
        let room = (n - wrap(at - m as i64 - 1, n as i64) - 2 * m - 1).min(n - wrap(at, n as i64));
        let reach = c0 + room;
        let end = if reach >= to { to } else { reach - reach % l };
        (end.max(first), true)
    }
}

/// The sweep over the window `i0..=i1` (grid indices) with the running
/// sums `mo` of the filter (slopes per degree at `step_deg`) and the
/// energy term `e`; `law`: the volume law's window figures are known
/// (`Σ (h dV)²` and the largest volume are then left at 0).
pub(crate) fn sweep<E: Energy>(
    g: &CycleGrid,
    mo: &Moments,
    step_deg: f64,
    (i0, i1): (i64, i64),
    e: &E,
    (out, law): (Outs, Option<&[[f64x2; 2]]>),
    bufs: &mut Bufs,
) -> Swept {
    let h = g.step_deg.to_radians();
    let len = (i1 - i0 + 1) as usize;
    let (m, l) = (mo.m, mo.refresh);
    let (mf, mp) = (m as f64, (m + 1) as f64);
    let k = Consts {
        m,
        l,
        c: [mf, mp, mf * mf, mp * mp, mf * mf * mf, mp * mp * mp],
        y: ValueSlope(Value(mo.value), Slope(mo.slope, step_deg)),
        hh: 0.5 * h,
        h,
    };
    // Lane A: the window's first `z` points, whole stretches; lane B the
    // rest. `z` the stretch boundary nearest the middle (lane A the longer
    // when both are as near).
    let stretches = len.div_ceil(l);
    let z = split(len, l);
    let (na, nb) = (z, len - z);
    let il = law.filter(|il| il.len() == na.min(nb));
    let law = il.is_some();
    let il = il.unwrap_or(&[]);
    out.qs.resize(len, 0.0);
    out.slope.resize(len, 0.0);
    let flags = (out.ps.is_some(), law);
    let ps: &mut [f64] = match out.ps {
        Some(ps) => {
            ps.resize(len, 0.0);
            ps
        }
        None => &mut [],
    };
    bufs.peaks.clear();
    bufs.peaks.resize(stretches, f64::NEG_INFINITY);
    let (qa, qb) = out.qs.split_at_mut(z);
    let (da, db) = out.slope.split_at_mut(z);
    let (pa, pb) = ps.split_at_mut(if ps.is_empty() { 0 } else { z });
    let (ka, kb) = bufs.peaks.split_at_mut(z.div_ceil(l));
    let mut oa = Dst {
        q: qa,
        d: da,
        ps: pa,
        peaks: ka,
    };
    let mut ob = Dst {
        q: qb,
        d: db,
        ps: pb,
        peaks: kb,
    };
    let (ba, bb) = bufs.lane.split_at_mut(3);
    let lane_a = LaneOf {
        g,
        i0,
        w0: 0,
        len: na,
    };
    let lane_b = LaneOf {
        g,
        i0,
        w0: z,
        len: nb,
    };
    let (p, dvol) = (g.pressure, g.dvolume);
    let n = p.len() as i64;
    // The window's first point adds no trapezoid: its work is 0 and its
    // cumulative `0 + E`, as the serial pass has them.
    let first = |t: &[f64; 4], r: f64, v0: f64| {
        let [ps0] = Value(mo.value).y(t, r);
        0.0 + e.of(ps0 * v0)
    };
    let zero = f64x2::splat(0.0);
    let mut st2 = State {
        t: [zero; 4],
        r: zero,
        w: zero,
        prev: zero,
        res2: zero,
        dv2: zero,
        vmax: zero,
        pk: zero,
    };
    if nb > 0 {
        // Lane B takes the trapezoid from the point before its first.
        let before = wrap(i0 + z as i64 - 1, n);
        st2.prev = f64x2::new([0.0, p[before] * dvol[before]]);
    }
    // Both lanes side by side over their common steps.
    let pairs = na.min(nb);
    let mut c0 = 0;
    while c0 < pairs {
        let (ea, da_) = lane_a.run_end(c0, pairs, l, m);
        let (eb, db_) = lane_b.run_end(c0, pairs, l, m);
        // Runs in one piece in both lanes go on together; else stretch by
        // stretch.
        let end = if da_ && db_ {
            ea.min(eb)
        } else {
            (c0 - c0 % l + l).min(pairs)
        };
        let src = [lane_a.src((c0, end), m, ba), lane_b.src((c0, end), m, bb)];
        let il = if law { &il[c0..end] } else { il };
        let s0 = c0 / l;
        let mut from = 0;
        if c0 == 0 {
            run_as(
                flags,
                &mut st2,
                (src, il),
                [&mut oa.from(0, 0), &mut ob.from(0, 0)],
                (0, 1),
                &k,
                e,
            );
            st2.w = f64x2::new([0.0, st2.w.to_array()[1]]);
            let la = lane(&st2, 0);
            oa.q[0] = first(&la.t, la.r, src[0].v[0]);
            from = 1;
        }
        let src = [src[0].from(from), src[1].from(from)];
        let il = if law { &il[from..] } else { il };
        let dst = [&mut oa.from(c0 + from, s0), &mut ob.from(c0 + from, s0)];
        run_as(
            flags,
            &mut st2,
            (src, il),
            dst,
            ((c0 + from) % l, end - c0 - from),
            &k,
            e,
        );
        c0 = end;
    }
    // The longer lane alone over the rest.
    let (mut st1, one, o, bb1) = if na >= nb {
        (lane(&st2, 0), lane_a, &mut oa, ba)
    } else {
        (lane(&st2, 1), lane_b, &mut ob, bb)
    };
    let mut c0 = pairs;
    while c0 < one.len {
        let (end, _) = one.run_end(c0, one.len, l, m);
        let src = one.src((c0, end), m, bb1);
        let empty = Src {
            s: &[],
            v: &[],
            dv: &[],
        };
        let s0 = c0 / l;
        let mut from = 0;
        if c0 == 0 {
            // Lane A alone (lane B empty): the window's first point.
            let mut none = Dst {
                q: &mut [],
                d: &mut [],
                ps: &mut [],
                peaks: &mut [],
            };
            run_as(
                flags,
                &mut st1,
                ([src, empty], &[]),
                [&mut o.from(0, 0), &mut none],
                (0, 1),
                &k,
                e,
            );
            st1.w = 0.0;
            o.q[0] = first(&st1.t, st1.r, src.v[0]);
            from = 1;
        }
        let mut none = Dst {
            q: &mut [],
            d: &mut [],
            ps: &mut [],
            peaks: &mut [],
        };
        let src = ([src.from(from), empty], &[][..]);
        let dst = [&mut o.from(c0 + from, s0), &mut none];
        run_as(
            flags,
            &mut st1,
            src,
            dst,
            ((c0 + from) % l, end - c0 - from),
            &k,
            e,
        );
        c0 = end;
    }
    let (sa, sb) = if na >= nb {
        (st1, lane(&st2, 1))
    } else {
        (lane(&st2, 0), st1)
    };
    let (res2, dv2, v_max) = if nb > 0 {
        (sa.res2 + sb.res2, sa.dv2 + sb.dv2, sb.vmax.gt_max(sa.vmax))
    } else {
        (sa.res2, sa.dv2, sa.vmax)
    };
    Swept {
        peak: peak(p, i0, l, &bufs.peaks),
        res2,
        dv2,
        v_max,
        // The second lane's work from the first's end.
        rest: (z, sa.w),
    }
}

/// Where the sweep splits a window of `len` points into its two lanes for
/// stretches of `l` points: the stretch boundary nearest the middle (the
/// first lane the longer when both are as near).
pub(crate) fn split(len: usize, l: usize) -> usize {
    let stretches = len.div_ceil(l);
    let (lo, hi) = ((stretches / 2) * l, (stretches.div_ceil(2) * l).min(len));
    if lo > 0 && len.abs_diff(2 * lo) < len.abs_diff(2 * hi) {
        lo
    } else {
        hi
    }
}

/// The volume law over a window of `len` points from grid index `i0`,
/// laid out as the sweep's two lanes read it for stretches of `l` points:
/// `[[V, V], [dV, dV]]` of the lanes' common steps.
pub(crate) fn law_pairs(
    volume: &[f64],
    dvolume: &[f64],
    i0: i64,
    len: usize,
    l: usize,
) -> Vec<[f64x2; 2]> {
    let z = split(len, l);
    let n = volume.len();
    // Each lane's grid index, stepped on (at most one wrap each).
    let (mut a, mut b) = (wrap(i0, n as i64), wrap(i0 + z as i64, n as i64));
    let mut out = Vec::with_capacity(z.min(len - z));
    for _ in 0..z.min(len - z) {
        out.push([
            f64x2::new([volume[a], volume[b]]),
            f64x2::new([dvolume[a], dvolume[b]]),
        ]);
        a = if a + 1 == n { 0 } else { a + 1 };
        b = if b + 1 == n { 0 } else { b + 1 };
    }
    out
}

/// The window's largest pressure and its index from the stretches'
/// largest (`peaks`, in window order): the first stretch that holds it,
/// then its first index there, as a running `if p > max` finds them.
fn peak(p: &[f64], i0: i64, l: usize, peaks: &[f64]) -> (f64, usize) {
    let (mut top, mut at) = (f64::NEG_INFINITY, 0);
    for (s, &x) in peaks.iter().enumerate() {
        if x > top {
            top = x;
            at = s;
        }
    }
    if top == f64::NEG_INFINITY {
        return (top, 0);
    }
    let n = p.len() as i64;
    let equal = |v: f64| v.partial_cmp(&top) == Some(std::cmp::Ordering::Equal);
    let j = (at * l..)
        .find(|&j| equal(p[wrap(i0 + j as i64, n)]))
        .unwrap_or(at * l);
    (p[wrap(i0 + j as i64, n)], j)
}
