//! The objective function LegRun and ZigZag share (behaviors-more.md): a course
//! ZAIC_PEAK toward a heading coupled with a ZAIC_SPD around a speed. The speed function
//! is kept while its inputs repeat (most iterations) and the course builder is kept and
//! set again, so a build allocates nothing once warm.

use behavior_api::ivp::{coupler, Domain, IvpFunction, ZaicPeak, ZaicSpd};
use behavior_api::kept::Kept;

/// What differs between the behaviors' functions.
#[derive(Clone, Copy, Debug)]
pub struct Shape {
    /// The ZAIC_SPD's utility at the high end of its plateau (LegRun 70, ZigZag 85).
    pub spd_high_util: f64,
    /// The course peak width, when the behavior sets it.
    pub peak_width: Option<f64>,
}

/// The speed function of speed `v`, not normalized.
fn speed(dom: &Domain, v: f64, shape: Shape) -> Option<IvpFunction> {
    let mut zs = ZaicSpd::new(dom, "speed").ok()?;
    zs.set_params5(v, 0.1, v + 0.4, shape.spd_high_util, 20.0);
    zs.extract()
}

/// The course builder's parameters, as a fresh builder gets them; false when a setter
/// failed.
fn set_course(z: &mut ZaicPeak, heading: f64, shape: Shape) -> bool {
    let ok = z.set_summit(heading, 0);
    let ok = z.set_base_width(180.0, 0) && ok;
    match shape.peak_width {
        Some(w) => z.set_peak_width(w, 0) && ok,
        None => ok,
    }
}

/// The function made afresh (the reference for [`Objective::build`]): course weight
/// `w1`, speed weight `100 − w1`.
#[cfg(test)]
pub fn build(dom: &Domain, v: f64, heading: f64, w1: f64, shape: Shape) -> Option<IvpFunction> {
    let spd = speed(dom, v, shape)?;
    let mut zc = ZaicPeak::new(dom, "course").ok()?;
    zc.set_value_wrap(true);
    set_course(&mut zc, heading, shape);
    let crs = zc.extract(false)?;
    coupler::couple(crs, spd, w1, 100.0 - w1, true)
}

/// What one behavior keeps between builds over its one domain.
#[derive(Default)]
pub struct Objective {
    /// The speed function normalized to `[0, 100 − w1]`, by (speed, weight) bits.
    speed: Kept<(u64, u64)>,
    course: Option<ZaicPeak>,
}

impl Objective {
    /// [`build`], bit for bit, without building again what did not change.
    pub fn build(
        &mut self,
        dom: &Domain,
        v: f64,
        heading: f64,
        w1: f64,
        shape: Shape,
    ) -> Option<IvpFunction> {
        let w2 = 100.0 - w1;
        let spd = self
            .speed
            .get((v.to_bits(), w2.to_bits()), || {
                let mut f = speed(dom, v, shape).ok_or(())?;
                f.normalize(0.0, w2);
                Ok::<_, ()>(f)
            })
            .ok()?;
        if self.course.is_none() {
            let mut z = ZaicPeak::new(dom, "course").ok()?;
            z.set_value_wrap(true);
            self.course = Some(z);
        }
        let z = self.course.as_mut()?;
        let ok = set_course(z, heading, shape);
        let crs = z.extract(false);
        if !ok {
            // A failed setter stays in the builder: the next build starts afresh.
            self.course = None;
        }
        coupler::try_couple_normalized(crs?, spd, w1, w2, true).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::function_bits;

    /// Kept builds equal fresh ones for both shapes, over speeds and weights that
    /// change, repeat and come back, headings every iteration, and a failed (NaN)
    /// heading in between.
    #[test]
    fn kept_build_equals_a_fresh_build() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        for shape in [
            Shape {
                spd_high_util: 70.0,
                peak_width: None,
            },
            Shape {
                spd_high_util: 85.0,
                peak_width: Some(0.0),
            },
        ] {
            let mut o = Objective::default();
            let speeds = [1.5, 1.5, 2.0, 1.5, 0.3, 0.3, 4.0];
            for k in 0..120 {
                let v = speeds[k % speeds.len()];
                let w1 = if k % 11 < 6 { 50.0 } else { 80.0 };
                let heading = if k == 40 {
                    f64::NAN
                } else {
                    (k as f64 * 37.3) % 360.0
                };
                let got = o.build(&d, v, heading, w1, shape);
                let want = build(&d, v, heading, w1, shape);
                assert_eq!(got.is_some(), want.is_some(), "iteration {k}");
                if let (Some(g), Some(w)) = (got, want) {
                    assert_eq!(function_bits(&g), function_bits(&w), "iteration {k}");
                }
            }
        }
    }
}
