//! The ob-ship model (obstacles.md §1.4.1, §1.7, §1.8): ownship against one convex
//! obstacle: range, the mid and rim buffer polygons, the passing side, the relevance with
//! its bearing discount and side lock, and the objective function over courses.

use behavior_api::geometry::obstacle::{bearing_min_max, buffer_polygon, poly_ray_cpa};
use behavior_api::geometry::{angle360, angle_diff, rel_ang, Polygon};
use behavior_api::ivp::reflector::eval_grid_pointwise;
use behavior_api::ivp::{Aof, Domain};

/// Corner rounding step of the mid and rim polygons (fixed, degrees).
pub const CORNER_STEP: f64 = 30.0;

/// Ownship pose as the helm's platform model gives it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub heading: f64,
}

/// Which side of ownship the obstacle's centre lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Star,
    Port,
    NotApplicable,
}

impl Side {
    pub fn as_str(self) -> &'static str {
        match self {
            Side::Star => "star",
            Side::Port => "port",
            Side::NotApplicable => "n/a",
        }
    }
}

/// Values derived from the obstacle and ownship each iteration (§1.4.1).
#[derive(Clone, Debug)]
pub struct Derived {
    pub range: f64,
    pub mid: Polygon,
    pub rim: Polygon,
    pub centre: (f64, f64),
    pub obcent_bng: f64,
    pub passing_side: Side,
    /// `Bad Expand: ...` / `Bad expand: ...` when a buffer failed.
    pub failed_expand: Option<String>,
    /// What `mid` and `rim` were made from when both expansions went well: the obstacle
    /// and the two flexed distances' bits. The next derive keeps them while these hold
    /// (they are rebuilt every iteration otherwise, though they seldom change).
    made_from: Option<(Polygon, [u64; 2])>,
}

/// Compute the derived values; `prev` (the last ones) keeps the old mid/rim when an
/// expansion fails, and gives them again when they were made from the same inputs.
pub fn derive(
    gut: &Polygon,
    os: Pose,
    min_cpa: f64,
    max_cpa: f64,
    prev: Option<Derived>,
) -> Derived {
    let range = if gut.contains(os.x, os.y) {
        0.0
    } else {
        gut.dist_to_poly(os.x, os.y)
    };
    let flex = |d: f64| {
        if range < d + 1.0 {
            (range - 1.0).max(0.0)
        } else {
            d
        }
    };
    let (dmid, drim) = (flex(min_cpa), flex(max_cpa));
    let bits = [dmid.to_bits(), drim.to_bits()];
    let mut failed_expand = None;
    let (mid, rim, made_from) = match prev {
        Some(Derived {
            mid,
            rim,
            made_from: Some((from, b)),
            ..
        }) if b == bits && from == *gut => (mid, rim, Some((from, b))),
        prev => {
            let mid = buffer_polygon(gut, dmid, CORNER_STEP);
            let rim = buffer_polygon(gut, drim, CORNER_STEP);
            let (mut mid, mut rim) = if !mid.is_convex() || !rim.is_convex() {
                failed_expand = Some(format!("Bad Expand: {}", gut.spec(1)));
                match prev {
                    Some(p) => (p.mid, p.rim),
                    None => (Polygon::default(), Polygon::default()),
                }
            } else {
                let holds = |b: &Polygon| gut.vertices().iter().all(|v| b.contains(v.x, v.y));
                if !holds(&mid) || !holds(&rim) {
                    failed_expand = Some(format!("Bad expand: {}", gut.spec(1)));
                }
                (mid, rim)
            };
            let label = &gut.attrs.label;
            mid.attrs.label = format!("{label}_mid_poly");
            rim.attrs.label = format!("{label}_rim_poly");
            let made_from = failed_expand.is_none().then(|| (gut.clone(), bits));
            (mid, rim, made_from)
        }
    };
    let centre = gut.center();
    let obcent_bng = rel_ang(os.x, os.y, centre.0, centre.1);
    let rel = angle360(obcent_bng - os.heading);
    let passing_side = if rel > 0.0 && rel < 180.0 {
        Side::Star
    } else if rel > 180.0 {
        Side::Port
    } else {
        Side::NotApplicable
    };
    Derived {
        range,
        mid,
        rim,
        centre,
        obcent_bng,
        passing_side,
        failed_expand,
        made_from,
    }
}

/// Raw range relevance with the bearing discount (§1.7 steps 1–3).
pub fn range_relevance(gut: &Polygon, os: Pose, range: f64, inner: f64, outer: f64) -> f64 {
    if range >= outer {
        return 0.0;
    }
    let pct = if range <= inner {
        1.0
    } else if outer - inner <= 0.0 {
        0.0
    } else {
        (outer - range) / (outer - inner)
    };
    let Some((bmin, bmax)) = bearing_min_max(gut, os.x, os.y) else {
        return pct;
    };
    if bmin > bmax {
        return pct;
    }
    let theta = angle_diff(os.heading, bmin).min(angle_diff(os.heading, bmax));
    let c = (theta * std::f64::consts::PI / 180.0).cos().max(0.0);
    let rr = c * pct;
    if pct > 0.0 && rr == 0.0 {
        0.01
    } else {
        rr
    }
}

/// The side lock (§1.7): `None` = no lock; the side named is where ownship should pass.
pub fn update_side_lock(lock: Option<Side>, rr: f64, passing: Side) -> Option<Side> {
    if rr <= 0.0 {
        return lock;
    }
    if rr > 0.6 && lock.is_none() {
        return match passing {
            Side::Star => Some(Side::Port),
            Side::Port => Some(Side::Star),
            Side::NotApplicable => None,
        };
    }
    if rr < 0.1 {
        return None;
    }
    lock
}

/// Whether every vertex lies more than `margin` degrees off ownship's stern arc
/// centre, i.e. strictly within (90+margin, 270−margin) relative bearing (§1.6 step 3).
pub fn all_aft(gut: &Polygon, os: Pose, margin: f64) -> bool {
    !gut.is_empty()
        && gut.vertices().iter().all(|v| {
            let r = angle360(rel_ang(os.x, os.y, v.x, v.y) - os.heading);
            r > 90.0 + margin && r < 270.0 - margin
        })
}

/// `cpa(c)` of §1.8 with the holonomic platform model (the turn path is ownship's
/// position alone): 0 from inside the polygon, else the ray's closest approach (never
/// more than the distance from ownship, so the path part does not matter).
pub fn seglr_cpa(poly: &Polygon, os: Pose, c: f64) -> f64 {
    if poly.contains(os.x, os.y) {
        0.0
    } else {
        poly_ray_cpa(poly, os.x, os.y, c)
    }
}

/// AOF_AvoidObstacleV24 (§1.8) with the helm's holonomic platform model: the utility of a
/// course is that of the ray's closest approach to the obstacle.
pub struct ObstacleAof<'a> {
    pub gut: &'a Polygon,
    pub os: Pose,
    pub min_cpa: f64,
    pub max_cpa: f64,
    /// The side lock flag and the side the obstacle centre must stay on.
    pub locked: bool,
    pub passing_side: Side,
    pub centre: (f64, f64),
    pub course_ix: usize,
}

impl ObstacleAof<'_> {
    /// Utility of course `c` (speed plays no part).
    pub fn utility(&self, c: f64) -> f64 {
        if self.locked {
            let r = angle360(rel_ang(self.os.x, self.os.y, self.centre.0, self.centre.1) - c);
            let side = if r > 0.0 && r < 180.0 {
                Side::Star
            } else {
                Side::Port
            };
            if side != self.passing_side {
                return 0.0;
            }
        }
        let d = seglr_cpa(self.gut, self.os, c);
        if d >= self.max_cpa {
            100.0
        } else if d <= self.min_cpa {
            0.0
        } else {
            100.0 * (d - self.min_cpa) / (self.max_cpa - self.min_cpa)
        }
    }
}

impl Aof for ObstacleAof<'_> {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        self.utility(domain.value(self.course_ix, index[self.course_ix]))
    }
}

/// The same utilities, one per course index, computed once: the reflector asks for
/// every piece corner (about 4200 points for 840 pieces) but only the course matters.
/// The list is the caller's, kept from build to build ([`CourseTable::into_list`]).
pub struct CourseTable {
    course_ix: usize,
    table: Vec<f64>,
}

impl CourseTable {
    /// The table in `list` (emptied first).
    pub fn new(aof: &ObstacleAof<'_>, domain: &Domain, mut list: Vec<f64>) -> Self {
        let points = domain.var(aof.course_ix).points;
        list.clear();
        list.extend((0..points).map(|j| aof.utility(domain.value(aof.course_ix, j))));
        CourseTable {
            course_ix: aof.course_ix,
            table: list,
        }
    }

    /// The list back, for the next table.
    pub fn into_list(self) -> Vec<f64> {
        self.table
    }

    fn at(&self, j: u32) -> f64 {
        self.table.get(j as usize).copied().unwrap_or(0.0)
    }
}

// Speed is ignored but not declared so (`Aof::ignores`): the reflector would then fit
// tile by tile in new lists each build. Its grid fit gives the same pieces bit for bit
// (the speed slope is exactly 0 either way) in kept storage.
impl Aof for CourseTable {
    fn eval(&self, _domain: &Domain, index: &[u32]) -> f64 {
        self.at(index[self.course_ix])
    }
    /// Rows of table entries (course first) or rows of one entry (course second).
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        let [xs, ys] = axes else {
            return eval_grid_pointwise(self, domain, axes, out);
        };
        if xs.is_empty() {
            return;
        }
        for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
            if self.course_ix == 0 {
                for (o, &i) in row.iter_mut().zip(xs.iter()) {
                    *o = self.at(i);
                }
            } else {
                row.fill(self.at(j));
            }
        }
    }
    fn eval_grid_fills(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> Polygon {
        Polygon::from_xy(&[(60.0, -12.0), (60.0, 6.0), (80.0, 6.0), (80.0, -12.0)])
    }

    #[test]
    fn relevance_at_the_recorded_spawn_point() {
        // os (46.23959, 0) heading 90, outer 15, inner 5 (obstacle_v24_transit, t=1025).
        // range = 60 − 46.23959 = 13.76041 (to the west edge x = 60);
        // pct = (15 − 13.76041)/(15 − 5) = 0.123959;
        // tangent bearings: to (60,6) 90 − atan(6/13.76041) = 66.4441°, to (60,−12)
        // 90 + atan(12/13.76041) = 131.0910°; θ = 90 − 66.4441 = 23.5559°,
        // cos θ = 0.916668; rr = 0.113629, × pwt 500 = 56.8137 (BHV_STATUS pwt=56.81371).
        let os = Pose {
            x: 46.23959416797254,
            y: 0.0,
            heading: 90.0,
        };
        let d = derive(&rect(), os, 3.0, 7.0, None);
        assert!((d.range - 13.76040583202746).abs() < 1e-9);
        let rr = range_relevance(&rect(), os, d.range, 5.0, 15.0);
        assert!((rr * 500.0 - 56.81371).abs() < 1e-4, "{}", rr * 500.0);
        // Centre (70, −3) is right of the bow: passing side star.
        assert_eq!(d.passing_side, Side::Star);
    }

    /// Derived values with kept polygons equal those derived afresh (the previous ones
    /// given only for a failed expansion) over poses and distances that change, repeat
    /// and come back, and an obstacle that changes.
    #[test]
    fn kept_polygons_are_the_fresh_ones() {
        let tri = Polygon::from_xy(&[(60.0, -12.0), (70.0, 6.0), (80.0, -12.0)]);
        let (mut kept, mut fresh): (Option<Derived>, Option<Derived>) = (None, None);
        let mut reused = 0;
        for k in 0..120 {
            // Range 10 (no flex), 6 and 3.5 (flexed), steps of 0.25 in y; back and forth.
            let x = [50.0, 50.0, 54.0, 50.0, 56.5, 56.5, 50.0][k % 7];
            let os = Pose {
                x,
                y: -8.0 + 0.25 * (k % 11) as f64,
                heading: (k * 37 % 360) as f64,
            };
            let (min, max) = if (40..60).contains(&k) {
                (2.0, 9.5)
            } else {
                (3.0, 7.0)
            };
            let gut = if (80..90).contains(&k) {
                tri.clone()
            } else {
                rect()
            };
            let had = kept.as_ref().and_then(|d| d.made_from.clone());
            let d = derive(&gut, os, min, max, kept.take());
            if had.is_some() && had == d.made_from {
                reused += 1;
            }
            // The reference: the previous values without what they were made from.
            let prev = fresh.take().map(|p| Derived {
                made_from: None,
                ..p
            });
            let f = derive(&gut, os, min, max, prev);
            assert_eq!(d.mid, f.mid, "step {k}");
            assert_eq!(d.rim, f.rim, "step {k}");
            assert_eq!(d.failed_expand, f.failed_expand, "step {k}");
            assert_eq!(
                (d.range.to_bits(), d.obcent_bng.to_bits(), d.passing_side),
                (f.range.to_bits(), f.obcent_bng.to_bits(), f.passing_side),
                "step {k}"
            );
            assert_eq!(d.centre, f.centre, "step {k}");
            (kept, fresh) = (Some(d), Some(f));
        }
        assert!(reused > 30, "polygons kept {reused} times");
    }

    /// The table as it was declared before: ignoring every dimension but the course, so
    /// the reflector fitted it tile by tile with shared fits.
    struct Sharing<'a>(&'a CourseTable);

    impl Aof for Sharing<'_> {
        fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
            self.0.eval(domain, index)
        }
        fn ignores(&self, dim: usize) -> bool {
            dim != self.0.course_ix
        }
    }

    /// The table's grid fit gives the functions of the shared tile-by-tile fit bit for
    /// bit, course first or second in the domain, with and without the side lock.
    #[test]
    fn grid_fit_is_the_shared_fit() {
        use behavior_api::ivp::Reflector;
        use behavior_api::testing::function_bits;
        let gut = rect();
        let build = |domain: &Domain, aof: &dyn Aof| {
            let mut refl = Reflector::new(domain, aof);
            refl.set_param("uniform_piece", "discrete@course:3,speed:3");
            refl.set_param("uniform_grid", "discrete@course:9,speed:9");
            refl.create(None, None);
            function_bits(&refl.into_function(true).expect("function"))
        };
        for course_first in [true, false] {
            let mut domain = Domain::new();
            let vars = [("course", 0.0, 359.0, 360), ("speed", 0.0, 4.0, 21)];
            for k in [0, 1] {
                let (name, lo, hi, n) = vars[if course_first { k } else { 1 - k }];
                domain.add_var(name, lo, hi, n).expect("var");
            }
            let course_ix = domain.index_of("course").expect("course");
            for k in 0..12 {
                let os = Pose {
                    x: 40.0 + 1.5 * k as f64,
                    y: -20.0 + 3.0 * k as f64,
                    heading: (k * 29 % 360) as f64,
                };
                let aof = ObstacleAof {
                    gut: &gut,
                    os,
                    min_cpa: 3.0,
                    max_cpa: 7.0,
                    locked: k % 3 == 0,
                    passing_side: if k % 2 == 0 { Side::Star } else { Side::Port },
                    centre: gut.center(),
                    course_ix,
                };
                let table = CourseTable::new(&aof, &domain, Vec::new());
                let want = build(&domain, &Sharing(&table));
                assert_eq!(build(&domain, &table), want, "pose {k}");
            }
        }
    }

    #[test]
    fn relevance_edges() {
        let os = Pose {
            x: 50.0,
            y: 0.0,
            heading: 90.0,
        };
        // Range 10 ≥ outer 10: 0.
        assert_eq!(range_relevance(&rect(), os, 10.0, 5.0, 10.0), 0.0);
        // Heading 270 (away): θ to the nearer tangent > 90 → cos clipped to 0, floor 0.01.
        let away = Pose {
            heading: 270.0,
            ..os
        };
        assert_eq!(range_relevance(&rect(), away, 10.0, 5.0, 20.0), 0.01);
        // Inside inner: pct 1, and straight at it θ = 90 − 59.04 = 30.96 (tangent to
        // (60,6): atan(10/6) = 59.04° from north) → cos 30.96° = 0.857493.
        let rr = range_relevance(&rect(), os, 4.0, 5.0, 20.0);
        assert!((rr - 0.857493).abs() < 1e-6, "{rr}");
    }

    #[test]
    fn side_lock_engages_and_releases() {
        assert_eq!(update_side_lock(None, 0.7, Side::Star), Some(Side::Port));
        assert_eq!(
            update_side_lock(Some(Side::Port), 0.3, Side::Port),
            Some(Side::Port)
        );
        assert_eq!(update_side_lock(Some(Side::Port), 0.05, Side::Port), None);
        assert_eq!(
            update_side_lock(Some(Side::Port), 0.0, Side::Port),
            Some(Side::Port)
        );
    }

    #[test]
    fn utility_at_chosen_courses() {
        // os (31.57, 0.005) as in run R1, min 5 / max 10.
        let os = Pose {
            x: 31.57,
            y: 0.005,
            heading: 88.88,
        };
        let gut = rect();
        let aof = ObstacleAof {
            gut: &gut,
            os,
            min_cpa: 5.0,
            max_cpa: 10.0,
            locked: false,
            passing_side: Side::Star,
            centre: (70.0, -3.0),
            course_ix: 0,
        };
        // Course 90 runs into the west edge: cpa 0 → utility 0.
        assert_eq!(aof.utility(90.0), 0.0);
        // Course 0 (north): the nearest vertex (60,6) lies behind-abeam, its foot on the
        // ray is ahead (y 6 > 0.005), distance |60 − 31.57| = 28.43 ≥ 10 → 100.
        assert_eq!(aof.utility(0.0), 100.0);
        // Course 59 (R1): perpendicular distance of (60,6) to the ray:
        // |(28.43, 5.995) × (sin 59°, cos 59°)| = |28.43·0.515038 − 5.995·0.857167|
        // = |14.64254 − 5.13872| = 9.50382 → 100·(9.50382 − 5)/5 = 90.076.
        assert!(
            (aof.utility(59.0) - 90.076).abs() < 1e-3,
            "{}",
            aof.utility(59.0)
        );
        // With the lock (pass with the centre to starboard), course 120 puts the centre
        // (bearing ≈ 94.4) to port of the course: 0 whatever the CPA.
        let locked = ObstacleAof {
            locked: true,
            ..aof
        };
        assert_eq!(locked.utility(120.0), 0.0);
        assert!((locked.utility(59.0) - 90.076).abs() < 1e-3);
    }

    #[test]
    fn aft_test() {
        let os = Pose {
            x: 100.0,
            y: 0.0,
            heading: 90.0,
        };
        assert!(all_aft(&rect(), os, 20.0));
        assert!(!all_aft(
            &rect(),
            Pose {
                heading: 270.0,
                ..os
            },
            20.0
        ));
    }
}
