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
//! let text = "ProcessConfig = uSimMarine\n{\n  start_heading = 90\n}\n";
//! let mission = MissionFile::parse(text, std::path::Path::new("doc.moos")).unwrap();
//! let mut boat = Kinematics::from_mission(&mission);
//! boat.on_mail("DESIRED_SPEED", 2.0);
//! for _ in 0..100 {
//!     boat.step(0.1);
//! }
//! assert!(boat.nav().x > 5.0, "it heads east");
//! ```

use moos_mission::mission::MissionFile;

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
/// - depth moves toward `DESIRED_DEPTH` at most `depth_rate·dt`.
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
}

fn block_f64(mission: &MissionFile, name: &str) -> Option<f64> {
    mission
        .config_value(SIM_NAME, name)
        .and_then(|v| moos_mission::mission::config_f64(&v))
        .filter(|v| v.is_finite())
}

impl Kinematics {
    /// Start state and parameters from the `uSimMarine` block (`start_x`, `start_y`,
    /// `start_heading`, `start_speed`, `start_depth`: default 0; `speed_lag` 1 s,
    /// `turn_rate` 20 deg/s, `depth_rate` 0.5 m/s).
    pub fn from_mission(mission: &MissionFile) -> Kinematics {
        let get = |n: &str, d: f64| block_f64(mission, n).unwrap_or(d);
        let positive = |n: &str, d: f64| block_f64(mission, n).filter(|v| *v > 0.0).unwrap_or(d);
        Kinematics {
            x: get("start_x", 0.0),
            y: get("start_y", 0.0),
            heading: get("start_heading", 0.0).rem_euclid(360.0),
            speed: get("start_speed", 0.0).max(0.0),
            depth: get("start_depth", 0.0),
            desired_heading: None,
            desired_speed: None,
            desired_depth: None,
            speed_lag: positive("speed_lag", 1.0),
            turn_rate: positive("turn_rate", 20.0),
            depth_rate: positive("depth_rate", 0.5),
        }
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
        if let Some(d) = self.desired_depth {
            let max = self.depth_rate * dt;
            self.depth += (d - self.depth).clamp(-max, max);
        }
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
