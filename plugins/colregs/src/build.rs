//! The objective function of the current mode (behaviors-contacts.md §5.4): the mode's
//! AOF through the reflector on the behavior's uniform tiling, or the stand-on ZAICs.

use behavior_api::contact::ContactBase;
use behavior_api::ivp::{Aof, Domain, IvpFunction, Reflector};

use crate::aof::{CpaAof, Pass, R13Aof, R14Aof, R16Aof, Scene, Side};
use crate::modes::{Machine, Mode, Submode};
use crate::params::{Params, Version};
use crate::standon;

/// The CPA horizon of the CPA mode and of V17's head-on function.
const FIXED_TOL: f64 = 120.0;

/// What a build gave.
pub enum Built {
    /// The mode's function, normalized to [0, 100] (the reflector's functions twice, as
    /// the reference normalizes them once more after the reflector).
    Function(IvpFunction),
    /// A BHV_ERROR text (an AOF that failed to initialise): no function.
    Error(String),
    /// A BHV_WARNING text (a stand-on builder failed): no function.
    Warning(&'static str),
    /// Mode `none`: no function.
    Nothing,
}

/// The native `uniform_grid = course:9,speed:6` as box sizes: per variable the value
/// clipped into the domain, index `int(value/delta + 0.5) − 1`, size index + 1.
pub fn grid_box(domain: &Domain) -> String {
    let mut parts = Vec::new();
    for (name, native) in [("course", 9.0), ("speed", 6.0)] {
        let Some(ix) = domain.index_of(name) else {
            continue;
        };
        let var = domain.var(ix);
        let v = f64::max(var.low, f64::min(native, var.high));
        let delta = var.delta();
        let index = if delta > 0.0 {
            (v / delta + 0.5) as i64 - 1
        } else {
            0
        };
        parts.push(format!("{name}:{}", index.max(0) + 1));
    }
    format!("discrete@{}", parts.join(","))
}

fn reflect(domain: &Domain, grid: &str, aof: &dyn Aof) -> Option<IvpFunction> {
    let mut refl = Reflector::new(domain, aof);
    refl.set_param("uniform_piece", "discrete@course:3,speed:3");
    refl.set_param("uniform_grid", grid);
    refl.create(None, None);
    refl.into_function_normalized_twice()
}

/// Build the function of `m.mode`; `factor` scales both util distances (velocity
/// filter) for this build only.
pub fn build_function(
    domain: &Domain,
    grid: &str,
    base: &ContactBase,
    p: &Params,
    m: Machine,
    held: (f64, f64),
    factor: f64,
) -> Built {
    let range = base.range();
    let min_u = p.min_util_cpa_dist * factor;
    let max_u = p.max_util_cpa_dist * factor;
    let mu = if range <= min_u { range / 2.0 } else { min_u };
    let scene = Scene {
        cnx: base.cn.x,
        cny: base.cn.y,
        cnh: base.cn.hdg,
        cnv: base.cn.spd,
        osx: base.os.x,
        osy: base.os.y,
        osh: base.os.heading,
    };
    let done = |f: Option<IvpFunction>| f.map_or(Built::Nothing, Built::Function);
    let inextremis = m.submode == Submode::Inextremis;
    match m.mode {
        Mode::None | Mode::Complete => Built::Nothing,
        Mode::Overtaking => {
            let side = match m.submode {
                Submode::Port => Some(Side::Port),
                Submode::Starboard => Some(Side::Starboard),
                _ => None,
            };
            match R13Aof::new(&scene, base.time_on_leg, mu, max_u, side) {
                Some(a) => done(reflect(domain, grid, &a)),
                None => Built::Error("Unable to init AOF_R13.".into()),
            }
        }
        Mode::HeadOn => {
            let tol = if p.version == Version::V17 {
                FIXED_TOL
            } else {
                base.time_on_leg
            };
            match R14Aof::new(&scene, tol, mu, max_u) {
                Some(a) => done(reflect(domain, grid, &a)),
                None => Built::Error("Unable to init AOF_R14.".into()),
            }
        }
        Mode::GiveWay => {
            if p.version == Version::V17 {
                // V17 hands the give-way AOF a parameter it no longer takes.
                return Built::Error(format!(
                    "Unable to init AOF_R16:bad param[osh], value[{}]",
                    behavior_api::compact(scene.osh, 6)
                ));
            }
            let pass = match m.submode {
                Submode::Stern => Some(Pass::Stern),
                Submode::Bow => Some(Pass::Bow),
                _ => None,
            };
            match R16Aof::new(&scene, mu, max_u, pass, p.pts_port_turns_ok) {
                Ok(a) => done(reflect(domain, grid, &a)),
                Err(why) => Built::Error(format!("Unable to init AOF_R16:{}", why.join(" # "))),
            }
        }
        Mode::StandOn | Mode::StandOnOt if !inextremis => {
            match standon::build(domain, held.0, held.1) {
                Ok(mut f) => {
                    f.normalize(0.0, 100.0);
                    Built::Function(f)
                }
                Err(e) => Built::Warning(e.message()),
            }
        }
        Mode::StandOn | Mode::StandOnOt | Mode::Cpa => {
            match CpaAof::new(&scene, FIXED_TOL, mu, max_u) {
                Some(a) => done(reflect(domain, grid, &a)),
                None => Built::Error("Unable to init AOF_CPA.".into()),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn native_grid_of_the_usual_domain() {
        // course 9 → index 8 (size 9); speed 6 clipped to 4 → int(40.5) − 1 = 39.
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        assert_eq!(grid_box(&d), "discrete@course:9,speed:40");
        let d = Domain::parse("course:0:358:180,speed:0:5:11").unwrap();
        // course delta 2: int(9/2 + 0.5) − 1 = 4; speed delta 0.5: 6 → 5,
        // int(10.5) − 1 = 9.
        assert_eq!(grid_box(&d), "discrete@course:5,speed:10");
    }
}
