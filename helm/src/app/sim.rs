//! `uSimMarine`: a small vehicle simulator, a second MOOS client of `helm run --embedded`.
//!
//! It reads `ProcessConfig = uSimMarine` (`start_x`, `start_y`, `start_heading`,
//! `start_speed`, `start_depth`, all default 0; `speed_lag` s default 1.0;
//! `turn_rate` deg/s default 20; `depth_rate` m/s default 0.5; `AppTick` default 10),
//! subscribes to `DESIRED_HEADING`, `DESIRED_SPEED`, `DESIRED_DEPTH`, and each tick
//! integrates this kinematic model over the MOOS time `dt` since the last tick:
//!
//! - speed follows `DESIRED_SPEED` with a first-order lag:
//!   `v += (v_des − v)·(1 − e^(−dt/speed_lag))`;
//! - heading turns toward `DESIRED_HEADING` the short way round, at most
//!   `turn_rate·dt` degrees per tick;
//! - compass heading (0 = north = +y, 90 = east = +x):
//!   `x += sin(h)·v·dt`, `y += cos(h)·v·dt`;
//! - depth moves toward `DESIRED_DEPTH` at most `depth_rate·dt`.
//!
//! Until a desired value arrives the vehicle keeps its start value. Then it posts
//! `NAV_X`, `NAV_Y`, `NAV_HEADING`, `NAV_SPEED`, `NAV_DEPTH`. No currents, no drag.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use moos::client::Client;
use moos::mission::MissionFile;
use moos::wire::Message;

use super::moos_io::AppSettings;

/// The simulator's MOOS name and config block.
pub const SIM_NAME: &str = "uSimMarine";

/// Vehicle state and model parameters.
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
        .and_then(|v| moos::mission::config_f64(&v))
        .filter(|v| v.is_finite())
}

impl Kinematics {
    /// Start state and parameters from the `uSimMarine` block (defaults if absent).
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

    /// Take a desired value from mail (`DESIRED_HEADING`, `_SPEED`, `_DEPTH`).
    pub fn on_mail(&mut self, var: &str, value: f64) {
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

    /// Advance the model by `dt` seconds (MOOS time).
    pub fn step(&mut self, dt: f64) {
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

    fn nav(&self) -> [(&'static str, f64); 5] {
        [
            ("NAV_X", self.x),
            ("NAV_Y", self.y),
            ("NAV_HEADING", self.heading),
            ("NAV_SPEED", self.speed),
            ("NAV_DEPTH", self.depth),
        ]
    }
}

/// A running simulator thread; stopped (and joined) on [`Sim::stop`] or drop.
pub struct Sim {
    stop: Arc<AtomicBool>,
    handle: Option<JoinHandle<()>>,
}

impl Sim {
    /// Connect `uSimMarine` to the DB named in the mission and start its thread.
    pub fn start(mission: &MissionFile) -> Result<Sim, moos::client::ClientError> {
        let settings = AppSettings::read(mission, SIM_NAME, 10.0);
        let client = Client::connect(settings.client_config(SIM_NAME))?;
        for var in ["DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH"] {
            client.register(var, 0.0)?;
        }
        let model = Kinematics::from_mission(mission);
        tracing::info!(
            x = model.x,
            y = model.y,
            heading = model.heading,
            "uSimMarine started"
        );
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let handle = std::thread::Builder::new()
            .name("uSimMarine".into())
            .spawn(move || sim_loop(client, model, settings, &flag))
            .map_err(|e| moos::client::ClientError::BadArgument(format!("cannot spawn: {e}")))?;
        Ok(Sim {
            stop,
            handle: Some(handle),
        })
    }

    pub fn stop(mut self) {
        self.halt();
    }

    fn halt(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

impl Drop for Sim {
    fn drop(&mut self) {
        self.halt();
    }
}

fn sim_loop(client: Client, mut model: Kinematics, settings: AppSettings, stop: &AtomicBool) {
    let period = settings.period();
    let mut last = client.moos_time();
    let mut inbox: Vec<Message> = Vec::new();
    let mut next = Instant::now();
    while !stop.load(Ordering::SeqCst) {
        inbox.clear();
        client.fetch(&mut inbox);
        inbox.sort_by(|a, b| a.time.total_cmp(&b.time));
        for m in inbox.iter().filter(|m| m.is_double()) {
            model.on_mail(&m.key, m.dval);
        }
        let now = client.moos_time();
        // A stall (e.g. a suspended process) must not teleport the vehicle.
        model.step((now - last).min(1.0));
        last = now;
        for (var, value) in model.nav() {
            if let Err(e) = client.notify_double(var, value, Some(now)) {
                tracing::debug!("uSimMarine: {var} not posted: {e}");
            }
        }
        next += period;
        let now_real = Instant::now();
        match next.checked_duration_since(now_real) {
            Some(wait) => std::thread::sleep(wait),
            None => next = now_real,
        }
    }
    client.close();
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
}
