//! OF_Coupler (spec §4): two functions over disjoint variables → one function.

use std::cell::RefCell;

use crate::domain::{Domain, DomainVar};
use crate::error::{invalid, IvpError};
use crate::function::IvpFunction;

/// The coupler's working lists, kept per thread (it runs for every Waypoint every
/// iteration): f2's boxes, slopes and emptiness, one f1 box and its slopes.
#[derive(Default)]
struct Scratch {
    q_boxes: Vec<i32>,
    q_slopes: Vec<f64>,
    q_ok: Vec<bool>,
    p_box: Vec<i32>,
    p_slopes: Vec<f64>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// `couple(f1, f2, w1, w2)`: normalize f1 to `[0,w1]` and f2 to `[0,w2]`,
/// then every `p ∩ q` (f1 outer, f2 inner) with summed weights over
/// `union(dom f1, dom f2)`; if `normalize`, the result is normalized to `[0,100]`.
/// `None` if `w1 <= 0`, `w2 <= 0`, or the variable sets overlap.
pub fn couple(
    f1: IvpFunction,
    f2: IvpFunction,
    w1: f64,
    w2: f64,
    normalize: bool,
) -> Option<IvpFunction> {
    try_couple(f1, f2, w1, w2, normalize).ok()
}

/// As [`couple`] with a typed error.
pub fn try_couple(
    f1: IvpFunction,
    mut f2: IvpFunction,
    w1: f64,
    w2: f64,
    normalize: bool,
) -> Result<IvpFunction, IvpError> {
    f2.normalize(0.0, w2);
    let out = try_couple_normalized(f1, &f2, w1, w2, normalize);
    f2.recycle();
    out
}

/// [`try_couple`] given `f2` after `f2.normalize(0.0, w2)`, only borrowed: the same
/// function, bit for bit, for a caller that keeps `f2` across iterations.
pub fn try_couple_normalized(
    mut f1: IvpFunction,
    f2: &IvpFunction,
    w1: f64,
    w2: f64,
    normalize: bool,
) -> Result<IvpFunction, IvpError> {
    check(f1.domain().vars(), f2, w1, w2)?;
    f1.normalize(0.0, w1);
    let d1 = f1.dim();
    // f1's variables, moved, then f2's.
    let mut dom = f1.take_domain();
    dom.append_disjoint(crate::domain::domain_of(f2.domain().vars()));
    let out = pair_into(dom, d1, (f1.bounds(), f1.weights()), f2, normalize);
    // f1's storage goes to the next builds.
    f1.recycle();
    Ok(out)
}

/// [`try_couple_normalized`] with f1 the one-variable function over `var` whose pieces
/// are `b1`/`w1s` (a builder's, not made a function: its weights are normalized here).
pub(crate) fn try_couple_line(
    var: &DomainVar,
    (b1, w1s): (&[i32], &mut [f64]),
    f2: &IvpFunction,
    (w1, w2): (f64, f64),
    normalize: bool,
) -> Result<IvpFunction, IvpError> {
    let var = std::slice::from_ref(var);
    check(var, f2, w1, w2)?;
    crate::function::normalize_line_pieces(b1, w1s, 0.0, w1);
    // The variables of both, copied at once into one spare domain (the previous
    // coupled function's, its names reused).
    let dom = crate::domain::domain_of(var.iter().chain(f2.domain().vars()));
    Ok(pair_into(dom, 1, (b1, w1s), f2, normalize))
}

/// The coupler's refusals: weights not above 0, variables shared.
fn check(vars1: &[DomainVar], f2: &IvpFunction, w1: f64, w2: f64) -> Result<(), IvpError> {
    if w1.is_nan() || w1 <= 0.0 {
        return Err(invalid("w1", format!("must be > 0 (got {w1})")));
    }
    if w2.is_nan() || w2 <= 0.0 {
        return Err(invalid("w2", format!("must be > 0 (got {w2})")));
    }
    if vars1
        .iter()
        .any(|v| f2.domain().index_of(&v.name).is_some())
    {
        return Err(IvpError::Couple("the functions share a variable".into()));
    }
    Ok(())
}

/// The coupled function, over `dom` (f1's `d1` variables then f2's), of f1 (its pieces
/// normalized) and f2.
fn pair_into(
    dom: Domain,
    d1: usize,
    (b1, w1s): (&[i32], &[f64]),
    f2: &IvpFunction,
    normalize: bool,
) -> IvpFunction {
    // The two share no variable, so the coupled domain is f1's variables then f2's:
    // each piece of f1 spans f2's dimensions whole and the other way round. A coupled
    // piece is then f1's box beside f2's, with the weights each function's translation
    // would give summed (`+ 0.0` where the other has no slope, as that sum is), without
    // translating both functions first (this runs for every Waypoint every iteration).
    let d2 = f2.dim();
    let (n1, n2) = (w1s.len() / (d1 + 1), f2.piece_count());
    let td = dom.size();
    debug_assert_eq!(td, d1 + d2);
    let (bl, wl) = (2 * td, td + 1);
    let mut bounds = mbutil::spare::ints();
    let mut weights = mbutil::spare::floats();
    bounds.reserve(n1 * n2 * bl);
    weights.reserve(n1 * n2 * wl);
    let (b2, w2s) = (f2.bounds(), f2.weights());
    let full = |d: usize| (0, dom.var(d).points as i32 - 1);
    // Two one-variable functions (the Waypoint's course and speed) are paired in one
    // pass that also folds the result's least and greatest values.
    let min_max = SCRATCH.with_borrow_mut(|scratch| {
        let (bw, ws, out) = ([b1, b2], [w1s, w2s], (&mut bounds, &mut weights));
        if d1 == 1 && d2 == 1 {
            return Some(pair_lines(scratch, bw, ws, [full(0).1, full(1).1], out));
        }
        pair_pieces(scratch, bw, ws, [d1, d2], full, out);
        None
    });
    let mut out = IvpFunction::assemble(dom, bounds, weights);
    if normalize {
        match min_max {
            Some(mm) => out.normalize_from(mm, 0.0, 100.0),
            None => out.normalize(0.0, 100.0),
        }
    }
    out
}

/// [`pair_pieces`] for two one-variable functions, returning what
/// [`IvpFunction::min_max_wt`] gives for the result: each coupled piece's least and
/// greatest value with the same operations in the same order (intercept, then the
/// course term, then the speed term), folded over the pieces in order the same way.
/// `tops[d]` is the highest index of dimension `d`.
fn pair_lines(
    scratch: &mut Scratch,
    [b1, b2]: [&[i32]; 2],
    [w1s, w2s]: [&[f64]; 2],
    tops: [i32; 2],
    (bounds, weights): (&mut Vec<i32>, &mut Vec<f64>),
) -> (f64, f64) {
    // A piece's box within `[0, top]`, `None` if that leaves it empty.
    let clip = |b: &[i32], top: i32| {
        let (lo, hi) = (b[0].max(0), b[1].min(top));
        (lo <= hi).then_some((lo, hi))
    };
    // The least and greatest term `slope * x` adds over the box `[lo, hi]`.
    let ends = |lo: i32, hi: i32, s: f64| {
        let (l, h) = (f64::from(lo), f64::from(hi));
        (
            s * if s < 0.0 { h } else { l },
            s * if s < 0.0 { l } else { h },
        )
    };
    // f2's side of every coupled piece, worked out once: its box (empty ones left out)
    // and its slope, least and greatest term and intercept.
    let (q_boxes, q_vals) = (&mut scratch.q_boxes, &mut scratch.q_slopes);
    q_boxes.clear();
    q_vals.clear();
    for (qb, qw) in b2.chunks_exact(2).zip(w2s.chunks_exact(2)) {
        if let Some((lo, hi)) = clip(qb, tops[1]) {
            let qs = 0.0 + qw[0];
            let (q_min, q_max) = ends(lo, hi, qs);
            q_boxes.extend([lo, hi]);
            q_vals.extend([qs, q_min, q_max, qw[1]]);
        }
    }
    // Written in place, room for every pair cut to those used: no capacity checks.
    let most = (b1.len() / 2) * (q_boxes.len() / 2);
    bounds.resize(4 * most, 0);
    weights.resize(3 * most, 0.0);
    // As arrays: the loops below index nothing (no bounds checks).
    let (qs, vs) = (q_boxes.as_chunks::<2>().0, q_vals.as_chunks::<4>().0);
    let nq = qs.len();
    let (mut mn, mut mx, mut used) = (0.0, 0.0, 0);
    for (pb, pw) in b1.as_chunks::<2>().0.iter().zip(w1s.as_chunks::<2>().0) {
        let Some((plo, phi)) = clip(pb, tops[0]) else {
            continue;
        };
        let ps = pw[0] + 0.0;
        let (p_min, p_max) = ends(plo, phi, ps);
        // This p's pairs go to the next `nq` slots.
        let bs = bounds[4 * used..4 * (used + nq)].as_chunks_mut::<4>().0;
        let ws = weights[3 * used..3 * (used + nq)].as_chunks_mut::<3>().0;
        for (((q, v), b), w) in qs.iter().zip(vs).zip(bs).zip(ws) {
            let c = pw[1] + v[3];
            *b = [plo, phi, q[0], q[1]];
            *w = [ps, v[0], c];
            let (lo, hi) = ((c + p_min) + v[1], (c + p_max) + v[2]);
            if used == 0 {
                (mn, mx) = (lo, hi);
            } else {
                mn = if lo < mn { lo } else { mn };
                mx = if hi > mx { hi } else { mx };
            }
            used += 1;
        }
    }
    bounds.truncate(4 * used);
    weights.truncate(3 * used);
    (mn, mx)
}

/// Every coupled piece: f1's piece `p` (outer) beside f2's `q` (inner), each box within
/// the full ranges (`full(d)` in the union's dimension order), skipped when empty.
fn pair_pieces(
    scratch: &mut Scratch,
    [b1, b2]: [&[i32]; 2],
    [w1s, w2s]: [&[f64]; 2],
    [d1, d2]: [usize; 2],
    full: impl Fn(usize) -> (i32, i32),
    (bounds, weights): (&mut Vec<i32>, &mut Vec<f64>),
) {
    let (n1, n2) = (w1s.len() / (d1 + 1), w2s.len() / (d2 + 1));
    let Scratch {
        q_boxes,
        q_slopes,
        q_ok,
        p_box,
        p_slopes,
    } = scratch;
    q_boxes.clear();
    q_slopes.clear();
    q_ok.clear();
    // f2's side of every coupled piece, worked out once: its box within the full
    // ranges (None if that leaves it empty) and its slopes as `0.0 + b`.
    for q in 0..n2 {
        let qb = &b2[q * 2 * d2..(q + 1) * 2 * d2];
        let mut ok = true;
        for d in 0..d2 {
            let (flo, fhi) = full(d1 + d);
            let (lo, hi) = (flo.max(qb[2 * d]), fhi.min(qb[2 * d + 1]));
            ok &= lo <= hi;
            q_boxes.push(lo);
            q_boxes.push(hi);
        }
        q_slopes.extend(w2s[q * (d2 + 1)..q * (d2 + 1) + d2].iter().map(|b| 0.0 + b));
        q_ok.push(ok);
    }
    for p in 0..n1 {
        let (pb, pw) = (
            &b1[p * 2 * d1..(p + 1) * 2 * d1],
            &w1s[p * (d1 + 1)..(p + 1) * (d1 + 1)],
        );
        p_box.clear();
        let mut ok = true;
        for d in 0..d1 {
            let (flo, fhi) = full(d);
            let (lo, hi) = (pb[2 * d].max(flo), pb[2 * d + 1].min(fhi));
            ok &= lo <= hi;
            p_box.push(lo);
            p_box.push(hi);
        }
        if !ok {
            continue;
        }
        p_slopes.clear();
        p_slopes.extend(pw[..d1].iter().map(|a| a + 0.0));
        for q in 0..n2 {
            if !q_ok[q] {
                continue;
            }
            bounds.extend_from_slice(p_box);
            bounds.extend_from_slice(&q_boxes[q * 2 * d2..(q + 1) * 2 * d2]);
            weights.extend_from_slice(p_slopes);
            weights.extend_from_slice(&q_slopes[q * d2..(q + 1) * d2]);
            weights.push(pw[d1] + w2s[q * (d2 + 1) + d2]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::function::{dim_map, translate_into};
    use crate::zaic::ZaicPeak;
    use crate::Domain;

    /// The coupling as the spec states it: both functions translated into the union
    /// domain, every intersecting pair of pieces summed (what `try_couple` computes
    /// without translating).
    fn by_translation(f1: &IvpFunction, f2: &IvpFunction) -> (Vec<i32>, Vec<f64>) {
        let dom = f1.domain().union(f2.domain());
        let td = dom.size();
        let (mut b1, mut w1, mut b2, mut w2) = (vec![], vec![], vec![], vec![]);
        let m1 = dim_map(f1.domain(), &dom).unwrap();
        let m2 = dim_map(f2.domain(), &dom).unwrap();
        translate_into(
            f1.bounds(),
            f1.weights(),
            f1.dim(),
            &m1,
            &dom,
            &mut b1,
            &mut w1,
        );
        translate_into(
            f2.bounds(),
            f2.weights(),
            f2.dim(),
            &m2,
            &dom,
            &mut b2,
            &mut w2,
        );
        let (bl, wl) = (2 * td, td + 1);
        let (mut bounds, mut weights) = (vec![], vec![]);
        for p in 0..f1.piece_count() {
            let (pb, pw) = (&b1[p * bl..(p + 1) * bl], &w1[p * wl..(p + 1) * wl]);
            for q in 0..f2.piece_count() {
                let (qb, qw) = (&b2[q * bl..(q + 1) * bl], &w2[q * wl..(q + 1) * wl]);
                if (0..td).any(|d| pb[2 * d].max(qb[2 * d]) > pb[2 * d + 1].min(qb[2 * d + 1])) {
                    continue;
                }
                for d in 0..td {
                    bounds.push(pb[2 * d].max(qb[2 * d]));
                    bounds.push(pb[2 * d + 1].min(qb[2 * d + 1]));
                }
                weights.extend(pw.iter().zip(qw).map(|(a, b)| a + b));
            }
        }
        (bounds, weights)
    }

    /// The waypoint's build (two peaks, coupled, normalized) for parameters `k`.
    fn build(d: &Domain, k: u32) -> IvpFunction {
        let x = f64::from(k);
        let mut c = ZaicPeak::new(d, "course").unwrap();
        c.set_value_wrap(true);
        c.set_params((x * 37.0) % 360.0, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
        let i = c.add_component();
        c.set_params((x * 71.0) % 360.0, 30.0, 180.0, 5.0, 0.0, 20.0, i);
        let mut s = ZaicPeak::new(d, "speed").unwrap();
        s.set_params((x * 0.13) % 4.0, 1.0, 1.6, 20.0, 0.0, 100.0, 0);
        let (c, s) = (c.extract(false).unwrap(), s.extract(true).unwrap());
        couple(c, s, 50.0, 50.0, true).unwrap()
    }

    #[test]
    fn functions_built_in_recycled_storage_equal_fresh_ones() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        // On a thread of its own, every function built in fresh storage.
        let fresh: Vec<IvpFunction> = std::thread::spawn({
            let d = d.clone();
            move || (0..60).map(|k| build(&d, k)).collect()
        })
        .join()
        .unwrap();
        // Here, each in the storage of the ones recycled before it (of other sizes).
        for (k, want) in (0..60).zip(&fresh) {
            let got = build(&d, k);
            assert_eq!(&got, want, "build {k}");
            let bits =
                |f: &IvpFunction| f.weights().iter().map(|w| w.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&got), bits(want));
            assert_eq!(got.grid_bounds(), want.grid_bounds());
            got.recycle();
            build(&d, k + 1000).recycle();
        }
    }

    /// A random one-variable function on `points` points: consecutive pieces with
    /// awkward weights (negative, zero and signed-zero slopes, ties).
    fn random_line(var: &str, points: u32, next: &mut impl FnMut() -> u64) -> IvpFunction {
        let d = Domain::parse(&format!("{var}:0:{}:{points}", points - 1)).unwrap();
        let mut pieces = vec![];
        let mut lo = 0i32;
        let top = points as i32 - 1;
        while lo <= top {
            let hi = (lo + (next() % 40) as i32).min(top);
            let pick = |r: u64| match r % 6 {
                0 => 0.0,
                1 => -0.0,
                2 => 1.5,
                _ => (r % 2001) as f64 / 7.0 - 140.0,
            };
            let (s, c) = (pick(next()), pick(next()));
            pieces.push((vec![(lo, hi)], vec![s, c]));
            lo = hi + 1;
        }
        IvpFunction::from_pieces(d, &pieces).unwrap()
    }

    /// The one-pass pairing of two one-variable functions (with its folded least and
    /// greatest values) gives what pairing then `normalize` gives, bit for bit.
    #[test]
    fn paired_lines_fold_what_min_max_wt_gives() {
        let mut seed = 3u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            seed >> 33
        };
        for round in 0..500 {
            let a = random_line("course", 1 + (next() % 360) as u32, &mut next);
            let b = random_line("speed", 1 + (next() % 41) as u32, &mut next);
            let (w1, w2) = (1.0 + (next() % 99) as f64, 1.0 + (round % 50) as f64);
            let plain = try_couple(a.clone(), b.clone(), w1, w2, false).unwrap();
            let (bounds, weights) = {
                let (mut na, mut nb) = (a.clone(), b.clone());
                na.normalize(0.0, w1);
                nb.normalize(0.0, w2);
                by_translation(&na, &nb)
            };
            assert_eq!(plain.bounds(), &bounds[..], "round {round}");
            let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(plain.weights()), bits(&weights), "round {round}");
            let mut want = plain.clone();
            want.normalize(0.0, 100.0);
            let got = try_couple(a, b, w1, w2, true).unwrap();
            assert_eq!(got.bounds(), want.bounds(), "round {round}");
            assert_eq!(bits(got.weights()), bits(want.weights()), "round {round}");
        }
    }

    /// Couplings whose range is not positive (flat: every value the same) or not a
    /// number (a NaN weight) are left as `normalize` leaves them, bit for bit, as are
    /// ones with signed zeros everywhere.
    #[test]
    fn paired_lines_left_unnormalized_as_normalize_leaves_them() {
        let line = |var: &str, pieces: &[(i32, i32, f64, f64)]| {
            let top = pieces.last().map_or(0, |p| p.1);
            let d = Domain::parse(&format!("{var}:0:{top}:{}", top + 1)).unwrap();
            let spec: Vec<_> = pieces
                .iter()
                .map(|&(lo, hi, s, c)| (vec![(lo, hi)], vec![s, c]))
                .collect();
            IvpFunction::from_pieces(d, &spec).unwrap()
        };
        let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let cases = [
            (vec![(0, 9, 0.0, 5.0)], vec![(0, 4, 0.0, 5.0)]),
            (
                vec![(0, 3, -0.0, -0.0), (4, 9, 0.0, 0.0)],
                vec![(0, 4, -0.0, -0.0)],
            ),
            (
                vec![(0, 3, 1.0, f64::NAN), (4, 9, 0.0, 2.0)],
                vec![(0, 4, 0.5, 1.0)],
            ),
            (
                vec![(0, 9, 0.0, 1.0)],
                vec![(0, 2, f64::NAN, 0.0), (3, 4, 1.0, 0.0)],
            ),
            (vec![(0, 9, 2.0, -0.0)], vec![(0, 4, -0.0, 0.0)]),
        ];
        for (k, (a, b)) in cases.iter().enumerate() {
            let (a, b) = (line("course", a), line("speed", b));
            for (w1, w2) in [(50.0, 50.0), (1.0, 99.0)] {
                let mut want = try_couple(a.clone(), b.clone(), w1, w2, false).unwrap();
                want.normalize(0.0, 100.0);
                let got = try_couple(a.clone(), b.clone(), w1, w2, true).unwrap();
                assert_eq!(got.bounds(), want.bounds(), "case {k}");
                assert_eq!(bits(got.weights()), bits(want.weights()), "case {k}");
            }
        }
    }

    /// One normalized f2, lent to many couplings, gives each what coupling a fresh f2
    /// gives, bit for bit, and is left as it was.
    #[test]
    fn a_lent_normalized_f2_couples_as_an_owned_one() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let mut s = ZaicPeak::new(&d, "speed").unwrap();
        s.set_params(1.5, 0.75, 1.6, 20.0, 0.0, 100.0, 0);
        let spd = s.extract(true).unwrap();
        let mut kept = spd.clone();
        kept.normalize(0.0, 40.0);
        let before = kept.clone();
        for k in 0..40 {
            let mut c = ZaicPeak::new(&d, "course").unwrap();
            c.set_params(f64::from(k) * 9.1, 10.0, 90.0, 30.0, 0.0, 100.0, 0);
            let crs = c.extract(true).unwrap();
            let want = try_couple(crs.clone(), spd.clone(), 60.0, 40.0, k % 2 == 0).unwrap();
            let got = try_couple_normalized(crs, &kept, 60.0, 40.0, k % 2 == 0).unwrap();
            let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(got.bounds(), want.bounds(), "{k}");
            assert_eq!(bits(got.weights()), bits(want.weights()), "{k}");
            assert_eq!(got.domain(), want.domain());
            assert_eq!(bits(kept.weights()), bits(before.weights()));
        }
    }

    #[test]
    fn coupling_equals_the_translated_sum_bit_for_bit() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let mut seed = 7u64;
        let mut next = |lo: f64, hi: f64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
        };
        for _ in 0..200 {
            let mut c = ZaicPeak::new(&d, "course").unwrap();
            c.set_value_wrap(true);
            c.set_params(
                next(0.0, 360.0),
                next(0.0, 40.0),
                next(0.0, 180.0),
                next(0.0, 60.0),
                0.0,
                100.0,
                0,
            );
            let mut s = ZaicPeak::new(&d, "speed").unwrap();
            s.set_params(
                next(0.0, 4.0),
                next(0.0, 2.0),
                next(0.0, 2.0),
                next(0.0, 30.0),
                0.0,
                100.0,
                0,
            );
            let (c, s) = (c.extract(false).unwrap(), s.extract(true).unwrap());
            for (a, b) in [(c.clone(), s.clone()), (s, c)] {
                let (w1, w2) = (next(1.0, 99.0), next(1.0, 99.0));
                let (mut na, mut nb) = (a.clone(), b.clone());
                na.normalize(0.0, w1);
                nb.normalize(0.0, w2);
                let (bounds, weights) = by_translation(&na, &nb);
                let got = try_couple(a, b, w1, w2, false).unwrap();
                assert_eq!(got.bounds(), &bounds[..]);
                let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(got.weights()), bits(&weights));
            }
        }
    }
}
