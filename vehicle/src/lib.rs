//! `vehicle-model`: what closes the loop between the helm's `DESIRED_*` and its `NAV_*`.
//!
//! [`VehicleModel`] is the small interface both simulators use (`helm run --embedded`'s
//! uSimMarine thread and `helm sim`); [`Kinematics`] is today's uSimMarine-like model and
//! [`Drift`] adds a constant water current to any model. A better model (thrust, drag,
//! currents varying in space) plugs in behind the same trait.
//!
//! It depends on `moos-mission` only (to read the uSimMarine block) and must not depend
//! on the helm, MOOS sockets or the simulator that drives it.
//!
//! ```
//! use moos_mission::mission::MissionFile;
//! use vehicle_model::{Kinematics, VehicleModel};
//! let text = "ProcessConfig = uSimMarine\n{\n  start_pos = x=0, y=0, heading=90, speed=0\n}\n";
//! let mission = MissionFile::parse(text, std::path::Path::new("doc.moos")).unwrap();
//! let mut boat = Kinematics::from_mission(&mission);
//! boat.on_mail("DESIRED_SPEED", 2.0);
//! for _ in 0..100 {
//!     boat.step(0.1);
//! }
//! assert!(boat.nav().x > 5.0, "it heads east");
//! ```

use moos_mission::mission::MissionFile;

mod block;
pub use block::{BlockProblem, Severity, SimBlock, SIM_BLOCKS};

/// The simulator's MOOS name and config block.
pub const SIM_NAME: &str = "uSimMarine";

/// What a model reports each step (posted as `NAV_X`, `NAV_Y`, `NAV_HEADING`,
/// `NAV_SPEED`, `NAV_DEPTH`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Nav {
    pub x: f64,
    pub y: f64,
    /// Compass degrees in [0, 360): 0 north (+y), 90 east (+x).
    pub heading: f64,
    pub speed: f64,
    pub depth: f64,
}

impl Nav {
    /// The `NAV_*` variables and values, in posting order.
    pub fn vars(&self) -> [(&'static str, f64); 5] {
        [
            ("NAV_X", self.x),
            ("NAV_Y", self.y),
            ("NAV_HEADING", self.heading),
            ("NAV_SPEED", self.speed),
            ("NAV_DEPTH", self.depth),
        ]
    }
}

/// A vehicle model driven by the helm's desired values.
pub trait VehicleModel: Send {
    /// A mail value (`DESIRED_HEADING`, `DESIRED_SPEED`, `DESIRED_DEPTH`; others ignored).
    fn on_mail(&mut self, var: &str, value: f64);
    /// Advance by `dt` seconds of MOOS time.
    fn step(&mut self, dt: f64);
    /// The current navigation state.
    fn nav(&self) -> Nav;
    /// Move by `(dx, dy)` metres without changing anything else (a current, a drift).
    fn displace(&mut self, dx: f64, dy: f64);
}

/// Vehicle state and model parameters of the uSimMarine-like kinematic model:
///
/// - speed follows `DESIRED_SPEED` with a first-order lag:
///   `v += (v_des − v)·(1 − e^(−dt/speed_lag))`;
/// - heading turns toward `DESIRED_HEADING` the short way round, at most
///   `turn_rate·dt` degrees per step;
/// - `x += sin(h)·v·dt`, `y += cos(h)·v·dt` (compass heading);
/// - depth moves toward `DESIRED_DEPTH` at most `depth_rate·dt`, the rate scaled by
///   `speed / depth_rate_speed` below that speed (a UUV dives with its planes, so it
///   needs way on); a vehicle below 0.1 m/s rises at `buoyancy_rate` instead; depth
///   stays within the surface (0) and the bottom (`water_depth`).
///
/// Until a desired value arrives the vehicle keeps its start value.
#[derive(Clone, Debug, PartialEq)]
pub struct Kinematics {
    pub x: f64,
    pub y: f64,
    /// Compass degrees in [0, 360).
    pub heading: f64,
    pub speed: f64,
    pub depth: f64,
    pub desired_heading: Option<f64>,
    pub desired_speed: Option<f64>,
    pub desired_depth: Option<f64>,
    /// Time constant of the speed lag (s).
    pub speed_lag: f64,
    /// Largest turn rate (deg/s).
    pub turn_rate: f64,
    /// Largest depth change rate (m/s).
    pub depth_rate: f64,
    /// Speed at which `depth_rate` is reached (`None`: at any speed).
    pub depth_rate_speed: Option<f64>,
    /// Rise rate of a stopped vehicle (m/s; 0: it stays).
    pub buoyancy_rate: f64,
    /// The bottom (`None`: no bottom).
    pub water_depth: Option<f64>,
}

impl Kinematics {
    /// Start state and parameters from the simulator block (`uSimMarine`, else
    /// `uSimMarineV22`; see [`SimBlock::read`] for the forms read). Defaults: start pose
    /// 0, `speed_lag` 1 s, `turn_rate` 20 deg/s, `depth_rate` 0.5 m/s. The block's
    /// problems are dropped here: read them with [`SimBlock::read`] and
    /// [`Kinematics::from_block`].
    pub fn from_mission(mission: &MissionFile) -> Kinematics {
        Kinematics::from_block(&SimBlock::read(mission))
    }

    /// The model a read block describes.
    pub fn from_block(b: &SimBlock) -> Kinematics {
        Kinematics {
            x: b.x.unwrap_or(0.0),
            y: b.y.unwrap_or(0.0),
            heading: b.heading.unwrap_or(0.0).rem_euclid(360.0),
            speed: b.speed.unwrap_or(0.0).max(0.0),
            depth: b.depth.unwrap_or(0.0),
            desired_heading: None,
            desired_speed: None,
            desired_depth: None,
            speed_lag: b.speed_lag.unwrap_or(1.0),
            turn_rate: b.turn_rate.unwrap_or(20.0),
            depth_rate: b.depth_rate.unwrap_or(0.5),
            depth_rate_speed: b.depth_rate_speed,
            buoyancy_rate: b.buoyancy_rate.unwrap_or(0.0),
            water_depth: b.water_depth,
        }
    }
}

impl Kinematics {
    /// The depth part of a step (see the type's docs).
    fn step_depth(&mut self, dt: f64) {
        if self.speed < 0.1 && self.buoyancy_rate > 0.0 {
            self.depth -= self.buoyancy_rate * dt;
        } else if let Some(d) = self.desired_depth {
            let scale = self
                .depth_rate_speed
                .map_or(1.0, |s| (self.speed / s).clamp(0.0, 1.0));
            let max = self.depth_rate * scale * dt;
            self.depth += (d - self.depth).clamp(-max, max);
        }
        let bottom = self.water_depth.unwrap_or(f64::INFINITY);
        self.depth = self.depth.clamp(0.0, bottom);
    }

    /// Height above the bottom (`None` without a `water_depth`).
    pub fn altitude(&self) -> Option<f64> {
        self.water_depth.map(|w| w - self.depth)
    }
}

impl VehicleModel for Kinematics {
    fn on_mail(&mut self, var: &str, value: f64) {
        if !value.is_finite() {
            return;
        }
        match var {
            "DESIRED_HEADING" => self.desired_heading = Some(value.rem_euclid(360.0)),
            "DESIRED_SPEED" => self.desired_speed = Some(value.max(0.0)),
            "DESIRED_DEPTH" => self.desired_depth = Some(value),
            _ => {}
        }
    }

    fn step(&mut self, dt: f64) {
        if dt <= 0.0 || !dt.is_finite() {
            return;
        }
        if let Some(v) = self.desired_speed {
            self.speed += (v - self.speed) * (1.0 - (-dt / self.speed_lag).exp());
        }
        if let Some(h) = self.desired_heading {
            let err = (h - self.heading + 540.0).rem_euclid(360.0) - 180.0;
            let max = self.turn_rate * dt;
            self.heading = (self.heading + err.clamp(-max, max)).rem_euclid(360.0);
        }
        self.step_depth(dt);
        let rad = self.heading.to_radians();
        self.x += rad.sin() * self.speed * dt;
        self.y += rad.cos() * self.speed * dt;
    }

    fn nav(&self) -> Nav {
        Nav {
            x: self.x,
            y: self.y,
            heading: self.heading,
            speed: self.speed,
            depth: self.depth,
        }
    }

    fn displace(&mut self, dx: f64, dy: f64) {
        self.x += dx;
        self.y += dy;
    }
}

/// A model carried by a constant current of `(east, north)` m/s: after each step the
/// vehicle moves by `current·dt` (NAV_SPEED and NAV_HEADING stay through the water, as
/// uSimMarine reports them).
#[derive(Clone, Debug, PartialEq)]
pub struct Drift<M> {
    pub model: M,
    pub current: (f64, f64),
}

impl<M: VehicleModel> VehicleModel for Drift<M> {
    fn on_mail(&mut self, var: &str, value: f64) {
        self.model.on_mail(var, value);
    }

    fn step(&mut self, dt: f64) {
        if dt <= 0.0 || !dt.is_finite() {
            return;
        }
        self.model.step(dt);
        self.model
            .displace(self.current.0 * dt, self.current.1 * dt);
    }

    fn nav(&self) -> Nav {
        self.model.nav()
    }

    fn displace(&mut self, dx: f64, dy: f64) {
        self.model.displace(dx, dy);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn model() -> Kinematics {
        let m = MissionFile::parse(
            "ProcessConfig = uSimMarine\n{\n start_x = 10\n start_y = -20\n start_heading = 90\n}\n",
            Path::new("t.moos"),
        )
        .expect("parses");
        Kinematics::from_mission(&m)
    }

    #[test]
    fn reads_start_state() {
        let k = model();
        assert_eq!((k.x, k.y, k.heading, k.speed), (10.0, -20.0, 90.0, 0.0));
        assert_eq!((k.speed_lag, k.turn_rate), (1.0, 20.0));
    }

    #[test]
    fn heading_90_moves_east() {
        let mut k = model();
        k.speed = 2.0;
        k.desired_speed = Some(2.0);
        k.step(1.0);
        assert!((k.x - 12.0).abs() < 1e-9 && (k.y + 20.0).abs() < 1e-9);
    }

    #[test]
    fn speed_lags_and_turn_is_bounded() {
        let mut k = model();
        k.on_mail("DESIRED_SPEED", 2.0);
        k.on_mail("DESIRED_HEADING", 350.0);
        k.step(1.0);
        let expect = 2.0 * (1.0 - (-1.0f64).exp());
        assert!((k.speed - expect).abs() < 1e-9);
        // 90 -> 350 is a 100° turn to port: 20° in one second.
        assert!((k.heading - 70.0).abs() < 1e-9);
        for _ in 0..10 {
            k.step(1.0);
        }
        assert!((k.heading - 350.0).abs() < 1e-9);
    }

    fn uuv(block: &str) -> Kinematics {
        let text = format!("ProcessConfig = uSimMarine\n{{\n{block}\n}}\n");
        let m = MissionFile::parse(&text, Path::new("t.moos")).expect("parses");
        let b = SimBlock::read(&m);
        assert!(b.problems.is_empty(), "{:?}", b.problems);
        Kinematics::from_block(&b)
    }

    #[test]
    fn depth_rate_scales_with_speed_and_stays_between_surface_and_bottom() {
        let mut k = uuv(
            "max_depth_rate = 1\nmax_depth_rate_speed = 2\ndefault_water_depth = 30\nbuoyancy_rate = 0.2",
        );
        assert_eq!(k.altitude(), Some(30.0));
        k.on_mail("DESIRED_DEPTH", 50.0);
        k.speed = 1.0;
        k.desired_speed = Some(1.0);
        k.step(1.0);
        // Half the top speed: half the depth rate.
        assert!((k.depth - 0.5).abs() < 1e-9, "{}", k.depth);
        k.speed = 2.0;
        k.desired_speed = Some(2.0);
        for _ in 0..100 {
            k.step(1.0);
        }
        assert_eq!(k.depth, 30.0, "the bottom stops it");
        assert_eq!(k.altitude(), Some(0.0));
        // Stopped: it floats up at the buoyancy rate, and no higher than the surface.
        k.speed = 0.0;
        k.desired_speed = Some(0.0);
        k.step(1.0);
        assert!((k.depth - 29.8).abs() < 1e-9, "{}", k.depth);
        for _ in 0..1000 {
            k.step(1.0);
        }
        assert_eq!(k.depth, 0.0);
    }

    #[test]
    fn bad_depth_values_are_errors() {
        let text =
            "ProcessConfig = uSimMarine\n{\n buoyancy_rate = -1\n default_water_depth = deep\n}\n";
        let m = MissionFile::parse(text, Path::new("t.moos")).expect("parses");
        let b = SimBlock::read(&m);
        assert_eq!(
            b.problems_at_least(Severity::Error).count(),
            2,
            "{:?}",
            b.problems
        );
    }

    #[test]
    fn crossing_north_wraps() {
        let mut k = model();
        k.heading = 350.0;
        k.on_mail("DESIRED_HEADING", 10.0);
        k.step(0.5);
        assert!((k.heading - 0.0).abs() < 1e-9);
    }

    #[test]
    fn drift_adds_the_current_and_keeps_the_water_track() {
        let mut d = Drift {
            model: model(),
            current: (0.5, -1.0),
        };
        d.step(2.0);
        let n = d.nav();
        assert!((n.x - 11.0).abs() < 1e-12 && (n.y + 22.0).abs() < 1e-12);
        assert_eq!(n.speed, 0.0);
    }
}
