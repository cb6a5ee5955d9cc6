//! The analytical objective functions of the contact behaviors, evaluated on the
//! decision grid by the reflector (ivp-solver.md §8).

use std::cell::{OnceCell, RefCell};

use behavior_api::contacts::engine::{roc_cosine, roc_index, AvoidRamp};
use behavior_api::contacts::CpaEngine;
use behavior_api::ivp::reflector::eval_grid_pointwise;
use behavior_api::ivp::{Aof, Domain, ValuesKey};
use behavior_api::mbutil::spare;

/// AOF_AvoidCollision (contacts-appcast.md §3.5): utility of the CPA a candidate
/// course/speed gives within `tol` seconds.
pub struct AvoidAof {
    pub engine: CpaEngine,
    pub tol: f64,
    /// Collision distance (utility 0 below).
    pub cd: f64,
    /// All-clear distance (utility 100 above).
    pub acd: f64,
}

impl AvoidAof {
    /// Utility of a CPA distance: 0 below `cd`, 100 above `acd`, else
    /// `25 + 75·(d − cd)/(acd − cd)` (the jump from 0 to 25 at `cd` is the reference's).
    pub fn metric(&self, d: f64) -> f64 {
        if d < self.cd {
            0.0
        } else if d > self.acd {
            100.0
        } else {
            25.0 + 75.0 * (d - self.cd) / (self.acd - self.cd)
        }
    }
}

impl AvoidAof {
    /// Utility at speed `v` of the course whose unit vector is `u` ([`CpaEngine::unit`]).
    #[inline]
    fn utility_of_unit(&self, u: (f64, f64), v: f64) -> f64 {
        self.metric(self.engine.cpa_unit(u, v, self.tol).dist)
    }
}

/// The courses of a grid as the rows read them: their unit vectors as two lists, sines
/// and cosines (for [`CpaEngine::cpa_dists`]), and for [`CutRangeAof`] their
/// rate-of-closure cosines. The lists are kept on the thread for the next grids
/// ([`CourseUnits::give_back`]): a build asks for two grids every iteration, and the
/// plugin's shared spares hand out buffers of any size (taking one that is too small
/// would grow it, an allocation per grid).
#[derive(Default)]
pub(crate) struct CourseUnits {
    pub sins: Vec<f64>,
    pub coss: Vec<f64>,
    /// Empty unless the caller fills it.
    pub cosines: Vec<f64>,
    /// Per course, its entry of a rate-of-closure cosine table ([`roc_index`]): they
    /// depend on the courses alone, so they are kept with them.
    pub cos_at: Vec<u16>,
    /// The courses of `sins` and `coss`. The unit vectors depend on these alone (the
    /// engine's table), and a build asks for the same courses every iteration: kept
    /// lists of the same courses are used as they are.
    courses: ValuesKey,
}

/// More kept course lists than grids evaluated at once on a thread are let go.
const MAX_KEPT: usize = 4;

thread_local! {
    /// The lists of grids done with ([`CourseUnits::give_back`]), emptied.
    static KEPT: RefCell<Vec<CourseUnits>> = const { RefCell::new(Vec::new()) };
}

impl CourseUnits {
    /// The unit vectors of the courses `xs` (indices of the domain's first variable),
    /// in kept lists (empty, with the room of earlier grids) or new ones.
    pub fn of(engine: &CpaEngine, domain: &Domain, xs: &[u32]) -> Self {
        let var = domain.var(0);
        let same = |c: &Self| c.courses.is(var, xs);
        // Else new lists until MAX_KEPT are kept (each grid's courses keep their own),
        // then the least lately used ones made again.
        let mut c = spare::take_kept_matching(&KEPT, same, MAX_KEPT);
        if same(&c) {
            return c;
        }
        c.sins.clear();
        c.coss.clear();
        let courses = var.values_at(xs);
        engine.units_into(courses.clone(), (&mut c.sins, &mut c.coss));
        c.cos_at.clear();
        // Below 360: fits.
        c.cos_at.extend(courses.map(|h| roc_index(h) as u16));
        c.courses.set(var, xs);
        c
    }

    /// The lists kept for the thread's next grids (the unit vectors with their courses;
    /// the cosines, the caller's, emptied).
    pub fn give_back(mut self) {
        self.cosines.clear();
        spare::keep_in(&KEPT, self, MAX_KEPT);
    }
}

impl Aof for AvoidAof {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        let c = domain.value(0, index[0]);
        let v = domain.value(1, index[1]);
        self.utility_of_unit(self.engine.unit(c), v)
    }
    /// The courses' unit vectors once, then a row of CPAs and their metric per speed.
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        let [xs, ys] = axes else {
            return eval_grid_pointwise(self, domain, axes, out);
        };
        if xs.is_empty() {
            return;
        }
        let c = CourseUnits::of(&self.engine, domain, xs);
        // AvoidAof::metric without jumps (the test below compares the two).
        let ramp = AvoidRamp {
            cd: self.cd,
            acd: self.acd,
        };
        let (metric, ends) = (move |d| ramp.at(d), ramp.flat_ends());
        for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
            let v = domain.value(1, j);
            let at = (v, self.tol);
            (self.engine).cpa_dists_flat((&c.sins, &c.coss), at, row, metric, ends);
        }
        c.give_back();
    }
    /// Every slot of every row is written.
    fn eval_grid_fills(&self) -> bool {
        true
    }
}

/// AOF_CutRangeCPA (behaviors-contacts.md §2.4): a blend of the rate of closure and the
/// CPA as a fraction of the current range, weighted by `patience`.
pub struct CutRangeAof {
    engine: CpaEngine,
    tol: f64,
    k: Blend,
    /// The engine's rate-of-closure cosine per integer heading, computed once when first
    /// needed: the reflector asks for thousands of grid points per iteration, and a
    /// function of the CPA alone ([`Self::metric_only`]) needs none. Held in place
    /// (2.9 KB, no allocation per build).
    cos: OnceCell<[f64; 360]>,
}

impl CutRangeAof {
    /// `None` (the reference's init failure) when `tol < 1` or ownship is on the
    /// contact. `vmax` is the speed domain's high value.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        cn: (f64, f64, f64, f64),
        os: (f64, f64),
        tol: f64,
        patience: f64,
        vmax: f64,
    ) -> Option<Self> {
        let engine = CpaEngine::new(cn.0, cn.1, cn.2, cn.3, os.0, os.1);
        let dist = (os.0 - cn.0).hypot(os.1 - cn.1);
        if tol < 1.0 || dist == 0.0 {
            return None;
        }
        // The range of the rate of closure from its four candidates when they tell it,
        // else from the table (which a grid of the CPA's metric alone never needs:
        // metric_only).
        let cos = OnceCell::new();
        let (rmin, rmax) = match engine.min_max_roc_fast(vmax) {
            Some(r) => r,
            None => engine.min_max_roc_with(cos.get_or_init(|| engine.roc_cosines()), vmax),
        };
        let k = Blend {
            dist,
            patience,
            rmin,
            rr: rmax - rmin,
            cn_to_os: engine.cn_to_os,
        };
        Some(CutRangeAof {
            engine,
            tol,
            k,
            cos,
        })
    }

    /// The cosine table ([`CpaEngine::roc_cosines`]), computed on first use.
    fn cosines(&self) -> &[f64; 360] {
        self.cos.get_or_init(|| self.engine.roc_cosines())
    }

    /// Whether every point of a grid of these speeds (`ys` of the domain's second
    /// variable) has the utility [`Self::metric`] of its CPA, bit for bit: at patience
    /// 100 the blend is `0·nroc + metric` (`(1 − p)` is 0, `p` is 1), which is `metric`
    /// (never −0) when `nroc` is 0 (not ranged) or finite. Every cosine is within
    /// [−1, 1] (a finite bearing), so `|nroc|` is at most
    /// `100·((max|s| + |cn_to_os|) + |rmin|) / rr`, each step rounded upward of the
    /// true one's magnitude at most as the real steps are: that bound finite, all are.
    fn metric_only(&self, domain: &Domain, ys: &[u32]) -> bool {
        let k = &self.k;
        if k.patience / 100.0 != 1.0 {
            return false;
        }
        // Not ranged (rr ≤ 0 or NaN): nroc is 0.
        let ranged = k.rr > 0.0;
        if !ranged {
            return true;
        }
        let mut smax = 0.0f64;
        for &j in ys {
            let s = domain.value(1, j).abs();
            if !s.is_finite() {
                return false;
            }
            smax = smax.max(s);
        }
        let bound = 100.0 * ((smax + k.cn_to_os.abs()) + k.rmin.abs()) / k.rr;
        self.engine.abs_os_cn.is_finite() && bound.is_finite()
    }

    pub fn utility(&self, c: f64, s: f64) -> f64 {
        self.utility_at(&self.course(c), s)
    }

    /// What [`Self::utility_at`] needs of course `c`: its unit vector and rate of
    /// closure cosine.
    fn course(&self, c: f64) -> ((f64, f64), f64) {
        (self.engine.unit(c), roc_cosine(self.cosines(), c))
    }

    /// [`Self::utility`] at speed `s` of a course prepared by [`Self::course`].
    #[inline]
    fn utility_at(&self, &(unit, cosine): &((f64, f64), f64), s: f64) -> f64 {
        let cpa = self.engine.cpa_unit(unit, s, self.tol).dist;
        self.k.blend(cpa, cosine, s)
    }
}

/// What [`CutRangeAof`]'s blend reads, plain numbers apart from the AOF (whose cosine
/// table is in a cell): a copy in a row's loop stays in registers, where the AOF's own
/// fields would be read again after every store.
#[derive(Clone, Copy)]
struct Blend {
    dist: f64,
    patience: f64,
    rmin: f64,
    rr: f64,
    /// The engine's.
    cn_to_os: f64,
}

impl Blend {
    /// The CPA part of the blend (as a fraction of the current range), every branch
    /// computed and the answer picked.
    #[inline(always)]
    fn metric(&self, cpa: f64) -> f64 {
        let mid = 100.0 - 100.0 * cpa / self.dist;
        let far = if cpa > self.dist { 0.0 } else { mid };
        if cpa < 0.0 {
            100.0
        } else {
            far
        }
    }

    /// The utility given the CPA distance `cpa` and rate-of-closure cosine `cosine` of a
    /// course at speed `s`; every branch computed and the answer picked (no jumps, so a
    /// row of them runs several at once), with [`Self::utility_at`]'s operations.
    #[inline(always)]
    fn blend(&self, cpa: f64, cosine: f64, s: f64) -> f64 {
        if self.rr > 0.0 {
            self.blend_of::<true>(cpa, cosine, s)
        } else {
            self.blend_of::<false>(cpa, cosine, s)
        }
    }

    /// [`Self::blend`] with `self.rr > 0.0` given as `RANGED` (a row decides it once:
    /// no choice per course).
    #[inline(always)]
    fn blend_of<const RANGED: bool>(&self, cpa: f64, cosine: f64, s: f64) -> f64 {
        let metric = self.metric(cpa);
        let nroc = if RANGED {
            // The engine's roc_of_cosine.
            100.0 * ((s * cosine + self.cn_to_os) - self.rmin) / self.rr
        } else {
            0.0
        };
        let p = self.patience / 100.0;
        (1.0 - p) * nroc + p * metric
    }
}

impl Aof for CutRangeAof {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        self.utility(domain.value(0, index[0]), domain.value(1, index[1]))
    }
    /// The courses' unit vectors and cosines once, then a row of CPAs and the blend per
    /// speed.
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        let [xs, ys] = axes else {
            return eval_grid_pointwise(self, domain, axes, out);
        };
        if xs.is_empty() {
            return;
        }
        let mut c = CourseUnits::of(&self.engine, domain, xs);
        let k = self.k;
        if self.metric_only(domain, ys) {
            // The CPA's metric alone: no cosines, no blend.
            let metric = move |cpa| k.metric(cpa);
            for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
                let at = (domain.value(1, j), self.tol);
                (self.engine).cpa_dists_map((&c.sins, &c.coss), at, row, metric);
            }
            return c.give_back();
        }
        c.cosines.reserve(xs.len());
        // The table read where each course reads it (roc_cosine), the places kept.
        let cos = self.cosines();
        c.cosines
            .extend(c.cos_at.iter().map(|&k| cos[usize::from(k)]));
        for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
            let s = domain.value(1, j);
            // Each CPA blended with its course's cosine as the row is done.
            let units = (&c.sins[..], &c.coss[..]);
            let (e, at) = (&self.engine, (s, self.tol));
            if k.rr > 0.0 {
                let blend = move |cpa, cosine| k.blend_of::<true>(cpa, cosine, s);
                e.cpa_dists_zip(units, at, &c.cosines, row, blend);
            } else {
                let blend = move |cpa, cosine| k.blend_of::<false>(cpa, cosine, s);
                e.cpa_dists_zip(units, at, &c.cosines, row, blend);
            }
        }
        c.give_back();
    }
    /// Every slot of every row is written.
    fn eval_grid_fills(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn avoid_metric_by_hand() {
        let a = AvoidAof {
            engine: CpaEngine::new(0.0, 100.0, 180.0, 2.0, 0.0, 0.0),
            tol: 120.0,
            cd: 8.0,
            acd: 25.0,
        };
        assert_eq!(a.metric(7.9), 0.0);
        assert_eq!(a.metric(8.0), 25.0);
        // Half way between 8 and 25: 25 + 75 / 2.
        assert_eq!(a.metric(16.5), 62.5);
        assert_eq!(a.metric(25.1), 100.0);
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        // Head-on north at 2 m/s: CPA 0 → 0; heading east at 2 m/s the contact passes
        // abeam; it comes within hypot(20·2... ) — simply: far better than head-on.
        assert_eq!(a.eval(&d, &[0, 20]), 0.0);
        assert!(a.eval(&d, &[90, 40]) > 90.0);
    }

    /// The AOFs' row evaluation gives what `eval` gives at every grid point, bit for
    /// bit, over random scenes (a still contact, ownship on or near it, ranges inside
    /// the collision distance) and distance settings (equal, crossed, zero), on the
    /// whole course × speed grid.
    #[test]
    fn rows_equal_pointwise() {
        let mut seed = 9u64;
        let mut rng = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let xs: Vec<u32> = (0..360).collect();
        let ys: Vec<u32> = (0..41).collect();
        let mut grid = vec![0.0; 360 * 41];
        let bits = |v: f64| {
            if v.is_nan() {
                f64::NAN.to_bits()
            } else {
                v.to_bits()
            }
        };
        for case in 0..150 {
            let cn = (
                ((rng() - 0.5) * 300.0).round(),
                ((rng() - 0.5) * 300.0).round(),
                (rng() * 720.0).round() / 2.0,
                if case % 5 == 0 { 0.0 } else { rng() * 4.0 },
            );
            let os = if case % 7 == 0 {
                (cn.0, cn.1)
            } else {
                (0.0, 0.0)
            };
            let (cd, acd) = match case % 4 {
                0 => (10.0, 10.0),
                1 => (0.0, 25.0),
                2 => (30.0, 20.0),
                _ => (rng() * 20.0, 20.0 + rng() * 60.0),
            };
            let avoid = AvoidAof {
                engine: CpaEngine::new(cn.0, cn.1, cn.2, cn.3, os.0, os.1),
                tol: [0.0, 60.0, 120.0][case % 3],
                cd,
                acd,
            };
            let tol = [1.0, 15.0, 200.0][case % 3];
            let patience = [0.0, 50.0, 100.0, rng() * 100.0][case % 4];
            let cut = CutRangeAof::new(cn, os, tol, patience, [0.0, 4.0][case % 2]);
            let aofs: Vec<&dyn Aof> = match &cut {
                Some(c) => vec![&avoid, c],
                None => vec![&avoid],
            };
            for aof in aofs {
                // Said to fill every slot: a slot left alone would keep the sentinel.
                assert!(aof.eval_grid_fills());
                grid.fill(-1234.5678);
                aof.eval_grid(&d, &[&xs, &ys], &mut grid);
                for j in 0..41u32 {
                    for i in 0..360u32 {
                        let got = grid[(i + 360 * j) as usize];
                        let want = aof.eval(&d, &[i, j]);
                        assert_eq!(bits(got), bits(want), "case {case} at ({i}, {j})");
                    }
                }
            }
        }
    }

    /// The metric without jumps ([`AvoidRamp::at`]), as the CPA row's loop runs it (compiled for AVX2 when
    /// the CPU has it, several entries per instruction, and for the baseline), is
    /// [`AvoidAof::metric`] bit for bit, over rows of every length 0..=41 with awkward
    /// distances and settings.
    #[test]
    fn metric_without_jumps_is_the_metric() {
        #[inline(always)]
        fn metric_row(cd: f64, acd: f64, row: &mut [f64]) {
            let ramp = AvoidRamp { cd, acd };
            row.iter_mut().for_each(|d| *d = ramp.at(*d));
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        unsafe fn metric_row_avx2(cd: f64, acd: f64, row: &mut [f64]) {
            metric_row(cd, acd, row);
        }
        let mut seed = 31u64;
        let mut rng = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let odd = [0.0, -0.0, f64::NAN, f64::INFINITY, 10.0, 25.0, 1e-310];
        let pick = move |r: f64, k: f64| {
            if r < 0.15 {
                odd[(k * odd.len() as f64) as usize % odd.len()]
            } else {
                k * 40.0
            }
        };
        for case in 0..3000 {
            let n = case % 42;
            let row: Vec<f64> = (0..n).map(|_| pick(rng(), rng())).collect();
            let (cd, acd) = (pick(rng(), rng()), pick(rng(), rng()));
            let aof = AvoidAof {
                engine: CpaEngine::new(0.0, 100.0, 180.0, 2.0, 0.0, 0.0),
                tol: 120.0,
                cd,
                acd,
            };
            let want: Vec<f64> = row.iter().map(|&d| aof.metric(d)).collect();
            let (mut plain, mut wide) = (row.clone(), row);
            metric_row(cd, acd, &mut plain);
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: AVX2 is present (checked just above).
                unsafe { metric_row_avx2(cd, acd, &mut wide) };
            }
            #[cfg(not(target_arch = "x86_64"))]
            metric_row(cd, acd, &mut wide);
            for ((a, b), w) in plain.iter().zip(&wide).zip(&want) {
                let same = |x: &f64| x.to_bits() == w.to_bits() || (x.is_nan() && w.is_nan());
                assert!(same(a) && same(b), "case {case}: {a} {b} {w}");
            }
        }
    }

    /// The row evaluation keeps its course lists on the thread from one grid to the
    /// next: grids of other sizes and orders, one after the other, and the same grid
    /// again (its unit vectors kept) or on other courses, give what the pointwise
    /// evaluation gives, bit for bit (a kept list longer or shorter than the next grid's
    /// courses, or of other courses, must not show through).
    #[test]
    fn kept_lists_serve_grids_of_any_size() {
        let mut seed = 77u64;
        let mut rng = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let d2 = Domain::parse("course:-90:628:360,speed:0:4:41").unwrap();
        for case in 0..60 {
            let cn = (
                ((rng() - 0.5) * 300.0).round(),
                ((rng() - 0.5) * 300.0).round(),
                (rng() * 720.0).round() / 2.0,
                rng() * 4.0,
            );
            // Some courses and speeds, in any order, as many as the case says.
            let n = [360, 1, 7, 200, 359, 45][case % 6];
            let xs: Vec<u32> = (0..n).map(|_| (rng() * 360.0) as u32 % 360).collect();
            let ys: Vec<u32> = (0..1 + case % 5)
                .map(|_| (rng() * 41.0) as u32 % 41)
                .collect();
            let avoid = AvoidAof {
                engine: CpaEngine::new(cn.0, cn.1, cn.2, cn.3, 0.0, 0.0),
                tol: 120.0,
                cd: rng() * 20.0,
                acd: 20.0 + rng() * 40.0,
            };
            let cut = CutRangeAof::new(cn, (0.0, 0.0), 60.0, rng() * 100.0, 4.0);
            let mut aofs: Vec<&dyn Aof> = vec![&avoid];
            aofs.extend(cut.as_ref().map(|c| c as &dyn Aof));
            // Each grid twice (the second from the kept lists of its courses), on the
            // domain and on one of the same points with other courses.
            for (aof, d) in aofs
                .iter()
                .flat_map(|a| [(a, &d), (a, &d2), (a, &d), (a, &d2)])
            {
                let mut grid = vec![-1234.5678; xs.len() * ys.len()];
                aof.eval_grid(d, &[&xs, &ys], &mut grid);
                for (j, &y) in ys.iter().enumerate() {
                    for (k, &x) in xs.iter().enumerate() {
                        let got = grid[k + xs.len() * j];
                        let want = aof.eval(d, &[x, y]);
                        assert_eq!(got.to_bits(), want.to_bits(), "case {case} at ({x}, {y})");
                    }
                }
            }
        }
    }

    #[test]
    fn cutrange_utility_by_hand() {
        // Contact 100 m north, still; ownship at the origin, vmax 4.
        let a = CutRangeAof::new((0.0, 100.0, 0.0, 0.0), (0.0, 0.0), 15.0, 0.0, 4.0).unwrap();
        // Patience 0: pure normalised rate of closure, 100 heading at it at full speed,
        // 0 heading away at full speed, 50 when stopped (roc 0 in [-4, 4]).
        assert!((a.utility(0.0, 4.0) - 100.0).abs() < 1e-9);
        assert!(a.utility(180.0, 4.0).abs() < 1e-9);
        assert!((a.utility(0.0, 0.0) - 50.0).abs() < 1e-9);
        let p = CutRangeAof::new((0.0, 100.0, 0.0, 0.0), (0.0, 0.0), 15.0, 100.0, 4.0).unwrap();
        // Patience 100: metric only; 15 s at 4 m/s closes 60 m: CPA 40 → 100 − 40.
        assert!((p.utility(0.0, 4.0) - 60.0).abs() < 1e-9);
        assert!(CutRangeAof::new((0.0, 0.0, 0.0, 0.0), (0.0, 0.0), 15.0, 0.0, 4.0).is_none());
        assert!(CutRangeAof::new((0.0, 9.0, 0.0, 0.0), (0.0, 0.0), 0.5, 0.0, 4.0).is_none());
    }
}
