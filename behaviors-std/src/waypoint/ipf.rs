//! The Waypoint objective function (behaviors-std.md §2.4).

use ivp::zaic::{ZaicPeak, ZaicSpd};
use ivp::{Domain, IvpFunction};

use crate::kept::{self, Kept};

/// Inputs of one function build.
#[derive(Clone, Copy, Debug)]
pub struct WptObjective<'a> {
    /// `zaic`, `zaic_spd`, `roc`, `rate_of_closure` (`roc` falls back to `zaic`).
    pub ipf_type: &'a str,
    pub cruise: f64,
    /// Bearing from ownship to the track point.
    pub bearing: f64,
    /// Ownship heading (angle360).
    pub heading: f64,
    /// Course weight in the coupler (speed weight = 100 - this).
    pub crs_pct: f64,
}

/// Build the coupled course × speed function, normalized to [0,100]; on failure the
/// BHV_WARNING text. Everything made afresh: the reference [`Builder::build`] keeps to.
pub fn build(domain: &Domain, o: &WptObjective<'_>) -> Result<IvpFunction, &'static str> {
    let spd = speed(domain, o)?;
    let mut z = ZaicPeak::new(domain, "course").map_err(|_| CRS_FAIL)?;
    z.set_value_wrap(true);
    z.set_params(o.bearing, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
    let k = z.add_component();
    z.set_params(o.heading, 30.0, 180.0, 5.0, 0.0, 20.0, k);
    let crs = z.extract(false).ok_or(CRS_FAIL)?;
    ivp::coupler::couple(crs, spd, o.crs_pct, 100.0 - o.crs_pct, true).ok_or(COUPLE_FAIL)
}

const CRS_FAIL: &str = "Failure on the CRS ZAIC";
const COUPLE_FAIL: &str = "Failure on the CRS_SPD COUPLER";

/// The speed function: it depends on the ZAIC type and the cruise speed only.
fn speed(domain: &Domain, o: &WptObjective<'_>) -> Result<IvpFunction, &'static str> {
    if o.ipf_type == "zaic_spd" {
        let mut z = ZaicSpd::new(domain, "speed")
            .map_err(|_| "Failure on the SPD ZAIC via ZAIC_SPD utility")?;
        z.set_params(o.cruise, 0.1, o.cruise + 0.4, 70.0, 20.0, 0.0, 0.0, 100.0);
        z.extract()
            .ok_or("Failure on the SPD ZAIC via ZAIC_SPD utility")
    } else {
        let mut z = ZaicPeak::new(domain, "speed")
            .map_err(|_| "Failure on the SPD ZAIC via ZAIC_PEAK utility")?;
        z.set_params(o.cruise, o.cruise / 2.0, 1.6, 20.0, 0.0, 100.0, 0);
        z.extract(true)
            .ok_or("Failure on the SPD ZAIC via ZAIC_PEAK utility")
    }
}

/// The course builder's two components (track bearing, ownship heading), as [`build`]
/// sets them; false when a setter failed.
fn set_course(z: &mut ZaicPeak, o: &WptObjective<'_>) -> bool {
    let ok = z.set_params(o.bearing, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
    z.set_params(o.heading, 30.0, 180.0, 5.0, 0.0, 20.0, 1) && ok
}

/// [`set_course`] on a builder it set before without a failure: only the summits
/// change (the other parameters are constants, and setting one again to the value it
/// holds changes nothing), so only they are set.
fn set_summits(z: &mut ZaicPeak, o: &WptObjective<'_>) -> bool {
    let ok = z.set_summit(o.bearing, 0);
    z.set_summit(o.heading, 1) && ok
}

/// What one Waypoint keeps between builds (over its one domain): the speed function,
/// normalized as the coupler normalizes it, while the ZAIC type, the cruise speed and
/// the speed weight are the same (they seldom change, the bearing and heading change
/// every iteration), and the course builder.
#[derive(Default)]
pub struct Builder {
    speed: Kept<(bool, u64, u64)>,
    course: Option<ZaicPeak>,
}

impl Builder {
    /// [`build`], bit for bit, without building again what did not change.
    pub fn build(
        &mut self,
        domain: &Domain,
        o: &WptObjective<'_>,
    ) -> Result<IvpFunction, &'static str> {
        let w2 = 100.0 - o.crs_pct;
        let key = (o.ipf_type == "zaic_spd", o.cruise.to_bits(), w2.to_bits());
        let spd = self.speed.get(key, || {
            let mut f = speed(domain, o)?;
            f.normalize(0.0, w2);
            Ok::<_, &str>(f)
        })?;
        // A kept builder was set by `set_course` without a failure (one that failed is
        // dropped): its summits are all that change.
        let fresh = self.course.is_none();
        let z = kept::peak(&mut self.course, domain, "course", true, 2).ok_or(CRS_FAIL)?;
        let ok = if fresh {
            set_course(z, o)
        } else {
            set_summits(z, o)
        };
        let f = z.try_extract_coupled(false, spd, (o.crs_pct, w2), true);
        kept::drop_on_failure(&mut self.course, ok);
        f.map_err(|_| CRS_FAIL)?.map_err(|_| COUPLE_FAIL)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub fn domain(speed_high: f64, speed_pts: u32) -> Domain {
        let mut d = Domain::new();
        d.add_var("course", 0.0, 359.0, 360).unwrap();
        d.add_var("speed", 0.0, speed_high, speed_pts).unwrap();
        d
    }

    /// First grid point with the highest value (course-major order).
    pub fn argmax(f: &IvpFunction) -> (u32, u32, f64) {
        let d = f.domain();
        let (nc, ns) = (d.var(0).points, d.var(1).points);
        let mut best = (0, 0, f64::NEG_INFINITY);
        for c in 0..nc {
            for s in 0..ns {
                let v = f.eval(&[c, s]).unwrap();
                if v > best.2 {
                    best = (c, s, v);
                }
            }
        }
        best
    }

    fn obj(cruise: f64, bearing: f64, heading: f64) -> WptObjective<'static> {
        WptObjective {
            ipf_type: "zaic",
            cruise,
            bearing,
            heading,
            crs_pct: 50.0,
        }
    }

    #[test]
    fn worked_example_a() {
        let d = domain(2.0, 21);
        let bearing = geometry::rel_ang(0.0, 0.0, 100.0, 50.0);
        let f = build(&d, &obj(2.0, bearing, 90.0)).unwrap();
        assert_eq!(f.piece_count(), 14);
        let p = f.piece(0);
        assert_eq!((p.lo(0), p.hi(0), p.lo(1), p.hi(1)), (0, 60, 0, 10));
        let w = p.weights();
        assert!((w[0] - 0.289425).abs() < 1e-6, "{w:?}");
        assert!((w[1] - 3.571429).abs() < 1e-6);
        assert!((w[2] - 31.610224).abs() < 1e-6);
        let (c, s, v) = argmax(&f);
        assert_eq!((c, s), (64, 20));
        assert!((v - 100.0).abs() < 1e-9);
    }

    #[test]
    fn other_worked_cases() {
        // (heading, track pt, cruise, speed high, speed pts, pieces, course, speed idx)
        let cases = [
            (90.0, (100.0, 50.0), 1.2, 2.0, 21, 28, 64, 12),
            (10.0, (-50.0, 80.0), 1.5, 4.0, 41, 35, 328, 15),
            (200.0, (30.0, -70.0), 0.5, 2.0, 21, 28, 157, 5),
            (45.5, (100.0, 100.0), 2.0, 2.0, 21, 10, 45, 20),
            (0.0, (0.0, 100.0), 1.0, 2.0, 21, 16, 0, 10),
        ];
        for (h, (tx, ty), cruise, hi, pts, pcs, crs, spd) in cases {
            let d = domain(hi, pts);
            let f = build(&d, &obj(cruise, geometry::rel_ang(0.0, 0.0, tx, ty), h)).unwrap();
            assert_eq!(f.piece_count(), pcs, "case hdg {h}");
            let (c, s, _) = argmax(&f);
            assert_eq!((c, s), (crs, spd), "case hdg {h}");
        }
    }

    /// What the kept builder hands out is bit for bit what a fresh build gives, over
    /// random changes of every input (some repeated, -0.0, NaN and out-of-domain values
    /// included) and of the ZAIC type, failures and recoveries from them included.
    #[test]
    fn kept_function_equals_a_fresh_build() {
        let d = domain(4.0, 41);
        let mut b = Builder::default();
        let mut next = crate::kept::tests::picker(0x9e37_79b9_7f4a_7c15);
        let mut o = obj(1.5, 45.0, 90.0);
        let (mut same_speed, mut failed) = (0, 0);
        for round in 0..3000 {
            let angle = |r: u64| [0.0, -0.0, 359.0, 359.5, 180.0, 12.25, f64::NAN][r as usize];
            match next(8) {
                0 => o.cruise = [0.0, -0.0, 1.5, 2.0, 3.9, 4.5, f64::NAN][next(7) as usize],
                1 => o.ipf_type = ["zaic", "zaic_spd", "roc"][next(3) as usize],
                2 => o.crs_pct = [50.0, 30.0, 99.0, 0.0][next(4) as usize],
                3 => o.bearing = angle(next(7)),
                4 => o.heading = angle(next(7)),
                _ => same_speed += 1,
            }
            // Most rounds turn the vehicle a little, as the iterations do.
            if next(3) > 0 {
                o.bearing = (next(36_000) as f64) / 100.0;
                o.heading = (next(3600) as f64) / 10.0;
            }
            let kept = b.build(&d, &o);
            let fresh = build(&d, &o);
            match (kept, fresh) {
                (Ok(k), Ok(f)) => {
                    let p = crate::kept::tests::parts;
                    assert_eq!(p(&k), p(&f), "round {round} {o:?}");
                    k.recycle();
                    f.recycle();
                }
                (k, f) => {
                    assert_eq!(k.err(), f.err(), "round {round} {o:?}");
                    failed += 1;
                }
            }
        }
        assert!(same_speed > 1000 && failed > 100, "{same_speed} {failed}");
    }

    #[test]
    fn zaic_spd_and_weights() {
        let d = domain(2.0, 21);
        let mut o = obj(1.5, 45.0, 45.0);
        o.ipf_type = "zaic_spd";
        let f = build(&d, &o).unwrap();
        let (c, s, _) = argmax(&f);
        assert_eq!((c, s), (45, 15));
        o.ipf_type = "roc"; // falls back to zaic
        assert!(build(&d, &o).is_ok());
        let mut sd = Domain::new();
        sd.add_var("speed", 0.0, 2.0, 21).unwrap();
        assert_eq!(
            build(&sd, &obj(1.0, 0.0, 0.0)).unwrap_err(),
            "Failure on the CRS ZAIC"
        );
    }
}
