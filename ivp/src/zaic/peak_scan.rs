//! ZAIC_PEAK pieces without sampling every grid point (same pieces, bit for bit).
//!
//! The sampled peak sum is linear between its kinks (each component's summit, the ends
//! of its peak and base, and with wrap the points where the distance goes round the
//! other way). The piece scan (`pieces_from_samples`) does nothing at a sample that lies on
//! the current piece's line, so once a piece's line is fitted on two samples of one
//! linear stretch, the scan may jump to the stretch's last sample: every sample in
//! between is within about 1e-9 of that line (tolerance 0.001), and its step to the
//! next sample has the line's sign, provided the stretch is exactly flat (every
//! component constant there) or its slope is far from 0. Near kinks every sample is
//! still evaluated, with the sampler's own arithmetic. A course ZAIC of 360 points then
//! looks at a few dozen of them.
//!
//! Where that argument needs care it is not used (the caller samples every point):
//! small grids, the max of several components, a component that could be all
//! `minutil` (the summit-insist rule), a wrapped summit outside the domain, utilities
//! large enough that rounding could approach the tolerance.

use super::shape::{dist_of, Component, Shape};
use super::Pieces1;

/// Below this many points sampling them all is as cheap as finding the kinks (the
/// Waypoint's 41-point speed ZAIC is cheaper skipped: measured).
const MIN_POINTS: usize = 32;
/// Components handled (kinks on the stack).
const MAX_COMPS: usize = 4;
/// Kinks per component: summit, peak and base ends both sides, and with wrap the same
/// the other way round plus the antipode.
const KINKS_PER_COMP: usize = 14;
/// A sample this close (in grid steps) to a kink counts as on it.
const NEAR: f64 = 1e-6;
/// Slopes (utility per grid step) this small are not trusted to keep their sign.
const MIN_SLOPE: f64 = 1e-6;
/// The piece scan's tolerance (`pieces_from_samples`).
const TOL: f64 = 0.001;
/// Utilities up to this size keep rounding far below the scan's 0.001 tolerance.
const MAX_UTIL: f64 = 1e6;

/// The grid the ZAIC is sampled on.
#[derive(Clone, Copy)]
pub(crate) struct Grid {
    pub low: f64,
    pub high: f64,
    pub delta: f64,
    pub points: usize,
    pub wrap: bool,
}

/// The pieces of the sum of `comps` on `grid` into `out` (emptied first), or `None`
/// (`out` untouched) where every point must be sampled (see the module docs).
pub(crate) fn pieces(
    comps: &[Component],
    grid: Grid,
    maxval: bool,
    out: &mut Pieces1,
) -> Option<()> {
    // With `wrap` a constant in each copy, a sample's distance tests no flag.
    if grid.wrap {
        pieces_of::<true>(comps, grid, maxval, out)
    } else {
        pieces_of::<false>(comps, grid, maxval, out)
    }
}

/// [`pieces`] on a grid whose `wrap` is `W`.
#[inline(always)]
fn pieces_of<const W: bool>(
    comps: &[Component],
    grid: Grid,
    maxval: bool,
    out: &mut Pieces1,
) -> Option<()> {
    debug_assert_eq!(grid.wrap, W);
    let n = grid.points;
    if n < MIN_POINTS || comps.is_empty() || comps.len() > MAX_COMPS {
        return None;
    }
    if maxval && comps.len() > 1 {
        return None;
    }
    let Grid {
        low, high, delta, ..
    } = grid;
    if delta.is_nan() || delta <= 0.0 {
        return None;
    }
    let mut util = 0.0;
    for c in comps {
        util += c.maxutil.abs().max(c.minutil.abs());
        if grid.wrap && (c.summit < low - delta || c.summit > high + delta) {
            return None;
        }
    }
    if util > MAX_UTIL {
        return None;
    }
    let mut kinks = [0.0f64; MAX_COMPS * KINKS_PER_COMP];
    let nk = find_kinks(comps, &grid, &mut kinks)?;
    let kinks = &kinks[..nk];
    // Exactly the sampler's arithmetic: the first component, then each next one added
    // (one and two components, the usual counts, unrolled). Each component's shape is
    // made once, the summit-insist rule checked on it before `out` is touched.
    match comps {
        [ca] => {
            let a = Peak::of(ca);
            if insists::<W>(&a, ca, &grid) {
                return None;
            }
            let (value, flat) = (|i| a.value::<W>(i, &grid), |i| a.flat::<W>(i, &grid));
            scan(n, kinks, value, flat, out)
        }
        [ca, cb] => {
            let (a, b) = (Peak::of(ca), Peak::of(cb));
            if insists::<W>(&a, ca, &grid) || insists::<W>(&b, cb, &grid) {
                return None;
            }
            let value = |i| a.value::<W>(i, &grid) + b.value::<W>(i, &grid);
            let flat = |i| a.flat::<W>(i, &grid) && b.flat::<W>(i, &grid);
            scan(n, kinks, value, flat, out)
        }
        _ => {
            let mut peaks = [Peak::of(&comps[0]); MAX_COMPS];
            for (p, c) in peaks.iter_mut().zip(comps) {
                *p = Peak::of(c);
                if insists::<W>(p, c, &grid) {
                    return None;
                }
            }
            let (first, rest) = (peaks[0], &peaks[1..comps.len()]);
            let value = |i| {
                rest.iter().fold(first.value::<W>(i, &grid), |t, p| {
                    t + p.value::<W>(i, &grid)
                })
            };
            let flat = |i| first.flat::<W>(i, &grid) && rest.iter().all(|p| p.flat::<W>(i, &grid));
            scan(n, kinks, value, flat, out)
        }
    }
    Some(())
}

/// The summit-insist rule rewrites a component whose every sample is `minutil`: its
/// sample nearest the summit then is `minutil` too, so that case samples everything.
#[inline(always)]
fn insists<const W: bool>(p: &Peak, c: &Component, g: &Grid) -> bool {
    let near = ((c.summit - g.low) / g.delta).round();
    p.value::<W>(near.clamp(0.0, (g.points - 1) as f64) as usize, g) == c.minutil
}

/// Sample index `i` as a float: the sampler's `f64::from(i as u32)` (grids are
/// u32-sized), converted as a signed integer, one instruction where `u32` and `usize`
/// take several.
#[inline(always)]
fn fl(i: usize) -> f64 {
    i as i64 as f64
}

/// One component as the scan evaluates it.
#[derive(Clone, Copy)]
struct Peak {
    summit: f64,
    shape: Shape,
}

impl Peak {
    fn of(c: &Component) -> Peak {
        Peak {
            summit: c.summit,
            shape: Shape::of(c),
        }
    }

    /// Its sample `i`: the sampler's arithmetic.
    #[inline(always)]
    fn value<const W: bool>(&self, i: usize, g: &Grid) -> f64 {
        let x = fl(i) * g.delta + g.low;
        self.shape.utility(dist_to::<W>(self.summit, x, g))
    }

    /// Constant on the stretch that holds sample `i` (off any kink)?
    #[inline(always)]
    fn flat<const W: bool>(&self, i: usize, g: &Grid) -> bool {
        let x = fl(i) * g.delta + g.low;
        let (d, s) = (dist_to::<W>(self.summit, x, g), &self.shape);
        d > s.reach || (d <= s.pwidth && s.sd <= 0.0)
    }
}

/// [`dist_of`] on the grid (whose `wrap` is `W`): the sampler's own expression (so
/// the same value), whose selects the compiler may keep free of branches (the side of
/// the summit is data).
#[inline(always)]
fn dist_to<const W: bool>(summit: f64, x: f64, g: &Grid) -> f64 {
    dist_of(summit, x, W, g.low, g.high, g.delta)
}

/// The components' kinks in grid steps from `low`, sorted, into `kinks`; their count,
/// `None` if one is not finite. Inlined (in both copies of `pieces_of`): it runs once
/// per build, and out of line its call cost more than the copy.
#[inline(always)]
fn find_kinks(comps: &[Component], grid: &Grid, kinks: &mut [f64]) -> Option<usize> {
    let (low, delta, n) = (grid.low, grid.delta, grid.points);
    let mut nk = 0;
    let span = (grid.high - low) + delta;
    // The last kink kept, converted once (`usize` to `f64` takes several instructions).
    let top = (n + 1) as f64;
    for c in comps {
        // A component's kink values listed first, then converted in one loop: the
        // conversion's code once, not once per kink (it runs once per build).
        let mut xs = [0.0f64; KINKS_PER_COMP];
        let mut m = 0;
        let reach = c.pwidth + c.bwidth;
        for w in [0.0, c.pwidth, reach] {
            if !grid.wrap {
                xs[m..m + 2].copy_from_slice(&[c.summit - w, c.summit + w]);
                m += 2;
            } else if w <= span / 2.0 + 1e-9 * span {
                // Going round, the distance never exceeds half the span: a width past
                // it is no kink (a stretch wrongly cut there is scanned to its end).
                let far = span - w;
                xs[m..m + 4].copy_from_slice(&[
                    c.summit - w,
                    c.summit + w,
                    c.summit - far,
                    c.summit + far,
                ]);
                m += 4;
            }
        }
        if grid.wrap {
            xs[m..m + 2].copy_from_slice(&[c.summit - span / 2.0, c.summit + span / 2.0]);
            m += 2;
        }
        // Kinks off the grid (by more than a step) cut no stretch, nor does one just
        // added again (a peak of no width, half the span round both ways): left out.
        for &x in &xs[..m] {
            let k = (x - low) / delta;
            let again = nk > 0 && kinks[nk - 1] == k;
            if again || (!(-2.0..=top).contains(&k) && k.is_finite()) {
                continue;
            }
            kinks[nk] = k;
            nk += 1;
        }
    }
    let kinks = &mut kinks[..nk];
    if kinks.iter().any(|k| !k.is_finite()) {
        return None;
    }
    // All finite: `<` orders them (a -0.0 beside a 0.0 either way compares the same
    // below). Insertion: a dozen kinks, mostly in order already.
    for i in 1..nk {
        let (k, mut j) = (kinks[i], i);
        while j > 0 && k < kinks[j - 1] {
            kinks[j] = kinks[j - 1];
            j -= 1;
        }
        kinks[j] = k;
    }
    Some(nk)
}

/// `pieces_from_samples` over the `n` samples `value(i)`, step for step, except that once a
/// piece's line is fitted it jumps to the last sample before the next kink when the
/// samples up to there provably lie on that line (module docs): there the scan would do
/// nothing. `flat(i)`: every component is constant on the stretch holding sample `i`.
#[inline(always)]
fn scan(
    n: usize,
    kinks: &[f64],
    value: impl Fn(usize) -> f64,
    flat: impl Fn(usize) -> bool,
    out: &mut Pieces1,
) {
    out.reset();
    let chord = |first: usize, fv: f64, end: usize, ve: f64| {
        if end == first {
            0.0
        } else {
            (ve - fv) / fl(end - first)
        }
    };
    let (mut first, mut fv) = (0usize, value(0));
    let (mut trend, mut m, mut b, mut v1) = (false, 0.0f64, 0.0f64, 0.0f64);
    // The previous sample's value: the scan always looks at it just before.
    let mut vp = fv;
    let mut cursor = 0usize;
    let mut i = 1;
    while i < n {
        if trend {
            // The piece's line went through samples `first` and `f1`; the samples from
            // `f1` on must share one linear stretch (sample `first` may lie before a
            // kink: the line is then checked against the stretch below).
            let f1 = first + 1;
            let from = fl(f1) - NEAR;
            while cursor < kinks.len() && kinks[cursor] < from {
                cursor += 1;
            }
            let next = kinks.get(cursor).copied().unwrap_or(f64::INFINITY);
            if next > fl(i) + NEAR {
                // Last sample strictly before the kink (by more than NEAR): `ceil(t) - 1`
                // in integers (here `t > i >= 1`), and never the last sample (its step
                // closes the final piece).
                let t = next - NEAR;
                let j = if t >= fl(n) {
                    n - 2
                } else {
                    // `1 < t < n`: through i64, one conversion (`as usize` takes two).
                    let c = t as i64 as usize;
                    let c = if fl(c) < t { c + 1 } else { c };
                    c.saturating_sub(1).min(n - 2)
                };
                if j > i {
                    if let Some(vj) = on_line(j, value(j), f1, v1, (m, b), &flat) {
                        // The jump's last sample is the next one's predecessor.
                        vp = vj;
                        i = j + 1;
                        continue;
                    }
                }
            }
        }
        let vi = value(i);
        let fi = fl(i);
        if !trend {
            m = (vi - fv) / fl(i - first);
            b = vi - m * fi;
            v1 = vi;
            trend = true;
        }
        let mut brk = ((m * fi + b) - vi).abs() > TOL;
        let lm = vi - vp;
        if (lm < 0.0 && m > 0.0) || (lm > 0.0 && m < 0.0) {
            brk = true;
        }
        if i == n - 1 {
            if brk {
                out.push(i as i32, i as i32, 0.0, vi);
            } else {
                let s = chord(first, fv, i, vi);
                out.push(first as i32, i as i32, s, fv - s * fl(first));
            }
        }
        if brk {
            let s = chord(first, fv, i - 1, vp);
            out.push(first as i32, (i - 1) as i32, s, fv - s * fl(first));
            trend = false;
            first = i;
            fv = vi;
        }
        vp = vi;
        i += 1;
    }
}

/// `Some(vj)` when the samples `f1..=j` of one linear stretch provably lie on the
/// scan's line (fitted on samples `f1 - 1` and `f1`, value `v1` at `f1`, slope `m`,
/// intercept `b`) and step with its sign: no break up to `j`. Not inlined: inlined, the
/// compiler hoists the `flat` test out of it into every step of the scan.
#[inline(never)]
fn on_line(
    j: usize,
    vj: f64,
    f1: usize,
    v1: f64,
    (m, b): (f64, f64),
    flat: impl Fn(usize) -> bool,
) -> Option<f64> {
    // Along a straight stretch the gap is affine in the index, about 0 at `f1`, so if
    // it is small at `j` it is small all the way (no break).
    let gap = ((m * fl(j) + b) - vj).abs();
    if gap.is_nan() || gap > TOL / 2.0 {
        return None;
    }
    // No break by the sign rule either: the stretch is exactly flat (every step 0), or
    // its steps keep one sign, far from 0, not against the line's slope.
    if !flat(f1) {
        let slope = (vj - v1) / fl(j - f1);
        if slope.is_nan() || slope.abs() < MIN_SLOPE {
            return None;
        }
        if (slope < 0.0 && m > 0.0) || (slope > 0.0 && m < 0.0) {
            return None;
        }
    }
    Some(vj)
}

#[cfg(test)]
mod tests {
    use super::super::pieces_from_samples;
    use super::*;
    use crate::zaic::ZaicPeak;
    use crate::Domain;

    fn rng(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Every random peak sum gives, with the skipping scan, the pieces of sampling
    /// every point, bit for bit (bounds and weights).
    #[test]
    fn skipping_scan_equals_sampling_every_point() {
        let domains = [
            "x:0:359:360",
            "x:0:4:41",
            "x:-50:50:201",
            "x:0:10:101",
            "x:0:359:72",
            "x:0:3.2:33",
        ];
        let mut seed = 11u64;
        let mut used = 0;
        for spec in domains {
            let d = Domain::parse(spec).unwrap();
            let v = d.var(0).clone();
            for round in 0..1500 {
                let mut z = ZaicPeak::new(&d, "x").unwrap();
                let wrap = round % 2 == 0;
                z.set_value_wrap(wrap);
                let comps = 1 + (round / 2) % 3;
                for k in 0..comps {
                    let k = if k == 0 { 0 } else { z.add_component() };
                    let r = |s: &mut u64| rng(s);
                    let span = v.high - v.low;
                    let summit = v.low - 0.1 * span + 1.2 * span * r(&mut seed);
                    // Some round numbers, so kinks fall on grid points too.
                    let summit = if round % 5 == 0 {
                        summit.round()
                    } else {
                        summit
                    };
                    let pw = if round % 7 == 0 {
                        0.0
                    } else {
                        span * 0.2 * r(&mut seed)
                    };
                    let bw = if round % 11 == 0 {
                        0.0
                    } else {
                        span * 0.6 * r(&mut seed)
                    };
                    let delta = 100.0 * r(&mut seed);
                    let max = 10.0 + 90.0 * r(&mut seed);
                    if round % 4 == 1 {
                        // The Waypoint's shape: a peak of no width over half the span,
                        // and the heading's, on whole numbers (kinks on samples).
                        let (pw, bw) = if k == 0 {
                            (0.0, span / 2.0)
                        } else {
                            (30.0, 180.0)
                        };
                        let summit = if k == 0 { summit } else { summit.round() };
                        z.set_params(summit, pw, bw, [50.0, 5.0][k.min(1)], 0.0, max, k);
                        continue;
                    }
                    let (pw, bw) = if round % 13 == 0 {
                        (pw.round(), bw.round())
                    } else {
                        (pw, bw)
                    };
                    z.set_params(summit, pw, bw, delta, 0.0, max, k);
                }
                let maxval = round % 3 == 0;
                let comps_now = z.comps.clone();
                let grid = Grid {
                    low: v.low,
                    high: v.high,
                    delta: v.delta(),
                    points: v.points as usize,
                    wrap,
                };
                // Into a buffer holding other pieces: they are cleared.
                let mut fast = Pieces1::default();
                fast.push(1, 2, 3.0, 4.0);
                if pieces(&comps_now, grid, maxval, &mut fast).is_none() {
                    continue;
                }
                used += 1;
                let n = v.points as usize;
                let (mut total, mut vals) = (vec![0.0; n], vec![0.0; n]);
                z.sample_into(maxval, &mut total, &mut vals);
                let slow = pieces_from_samples(&total);
                assert_eq!(fast.bounds, slow.bounds, "{spec} round {round}");
                let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&fast.weights), bits(&slow.weights), "{spec} {round}");
            }
        }
        assert!(used > 3000, "the skipping scan ran on {used} cases only");
    }

    /// The Waypoint's course function (two wrapped components on 360 points) takes the
    /// skipping scan: that is what it is for.
    #[test]
    fn the_waypoint_course_function_skips() {
        let d = Domain::parse("course:0:359:360").unwrap();
        let mut z = ZaicPeak::new(&d, "course").unwrap();
        z.set_value_wrap(true);
        z.set_params(123.4, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
        let k = z.add_component();
        z.set_params(100.2, 30.0, 180.0, 5.0, 0.0, 20.0, k);
        let grid = Grid {
            low: 0.0,
            high: 359.0,
            delta: 1.0,
            points: 360,
            wrap: true,
        };
        let mut p = Pieces1::default();
        pieces(&z.comps, grid, false, &mut p).expect("the skipping scan applies");
        assert_eq!(
            p.bounds,
            [0, 70, 71, 100, 101, 123, 124, 130, 131, 280, 281, 303, 304, 359]
        );
    }
}
