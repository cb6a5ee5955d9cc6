//! The Loiter objective function: course to the next vertex × the desired speed,
//! coupled with the patience as the course weight.

use ivp::zaic::{ZaicPeak, ZaicSpd};
use ivp::{Domain, IvpFunction};

use crate::kept::{self, Kept};

/// Inputs of one function build.
#[derive(Clone, Copy, Debug)]
pub struct LoiterObjective<'a> {
    /// `zaic` or `zaic_spd`.
    pub ipf_type: &'a str,
    pub speed: f64,
    /// Bearing from ownship to the next vertex.
    pub bearing: f64,
    /// Course weight in the coupler (speed weight = 100 - this).
    pub patience: f64,
}

/// A failed build: `Some(text)` for the BHV_WARNING, `None` for none.
pub type Failure = Option<&'static str>;

const ZAIC_FAIL: Failure = Some("Failure on the ZAIC");

/// Build the coupled function, normalized to [0,100]. Everything made afresh: the
/// reference [`Builder::build`] keeps to.
pub fn build(domain: &Domain, o: &LoiterObjective<'_>) -> Result<IvpFunction, Failure> {
    let spd = speed(domain, o);
    let spd = match spd {
        Err(None) => return Err(None),
        spd => spd.ok(),
    };
    let mut z = ZaicPeak::new(domain, "course").map_err(|_| None)?;
    z.set_value_wrap(true);
    z.set_params(o.bearing, 0.0, 180.0, 0.0, 0.0, 100.0, 0);
    let crs = z.extract(true);
    couple(crs, spd, o)
}

/// The speed function (it depends on the ZAIC type and the speed only); a builder that
/// cannot be made is a failure without warning.
fn speed(domain: &Domain, o: &LoiterObjective<'_>) -> Result<IvpFunction, Failure> {
    let f = if o.ipf_type == "zaic_spd" {
        let mut z = ZaicSpd::new(domain, "speed").map_err(|_| None)?;
        z.set_params(o.speed, 0.1, o.speed + 0.4, 85.0, 20.0, 0.0, 0.0, 100.0);
        z.extract()
    } else {
        let mut z = ZaicPeak::new(domain, "speed").map_err(|_| None)?;
        z.set_params(o.speed, 0.0, 0.3, 0.0, 0.0, 100.0, 0);
        z.extract(true)
    };
    f.ok_or(ZAIC_FAIL)
}

fn couple(
    crs: Option<IvpFunction>,
    spd: Option<IvpFunction>,
    o: &LoiterObjective<'_>,
) -> Result<IvpFunction, Failure> {
    let (Some(crs), Some(spd)) = (crs, spd) else {
        return Err(ZAIC_FAIL);
    };
    let mut f = ivp::coupler::couple(crs, spd, o.patience, 100.0 - o.patience, true).ok_or(None)?;
    f.normalize(0.0, 100.0);
    Ok(f)
}

/// What one Loiter keeps between builds (over its one domain): the speed function,
/// normalized as the coupler normalizes it, while the ZAIC type, the speed and the
/// patience are the same, and the course builder.
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
        o: &LoiterObjective<'_>,
    ) -> Result<IvpFunction, Failure> {
        let w2 = 100.0 - o.patience;
        let key = (o.ipf_type == "zaic_spd", o.speed.to_bits(), w2.to_bits());
        let spd = self.speed.get(key, || {
            let mut f = speed(domain, o)?;
            f.normalize(0.0, w2);
            Ok::<_, Failure>(f)
        });
        let spd = match spd {
            Err(None) => return Err(None),
            spd => spd.ok(),
        };
        let z = kept::peak(&mut self.course, domain, "course", true, 1).ok_or(None)?;
        let ok = z.set_params(o.bearing, 0.0, 180.0, 0.0, 0.0, 100.0, 0);
        // The course pieces coupled as they are, not made a function first.
        let coupled = spd.map(|spd| z.try_extract_coupled(true, spd, (o.patience, w2), true));
        kept::drop_on_failure(&mut self.course, ok);
        let Some(Ok(coupled)) = coupled else {
            return Err(ZAIC_FAIL);
        };
        let mut f = coupled.map_err(|_| None)?;
        f.normalize(0.0, 100.0);
        Ok(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What the kept builder hands out is bit for bit what a fresh build gives, over
    /// random changes of every input (NaN and out-of-domain values included) and of the
    /// ZAIC type, failures and recoveries from them included.
    #[test]
    fn kept_function_equals_a_fresh_build() {
        let d = crate::waypoint::ipf::tests::domain(4.0, 41);
        let mut b = Builder::default();
        let mut next = crate::kept::tests::picker(0x2545_f491_4f6c_dd1d);
        let mut o = LoiterObjective {
            ipf_type: "zaic",
            speed: 1.5,
            bearing: 10.0,
            patience: 50.0,
        };
        let (mut same_speed, mut failed) = (0, 0);
        for round in 0..3000 {
            match next(7) {
                0 => o.speed = [0.0, -0.0, 1.5, 2.0, 3.9, 4.5, f64::NAN][next(7) as usize],
                1 => o.ipf_type = ["zaic", "zaic_spd"][next(2) as usize],
                2 => o.patience = [50.0, 30.0, 99.0, 0.0][next(4) as usize],
                3 => o.bearing = [0.0, -0.0, 359.0, 359.5, f64::NAN][next(5) as usize],
                _ => same_speed += 1,
            }
            if next(3) > 0 {
                o.bearing = (next(36_000) as f64) / 100.0;
            }
            match (b.build(&d, &o), build(&d, &o)) {
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
}
