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
//! The model itself is [`vehicle_model::Kinematics`] behind [`VehicleModel`] (shared
//! with `helm sim`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use moos::client::Client;
use moos::mission::MissionFile;
use moos::wire::Message;

use crate::moos_io::AppSettings;
use vehicle_model::VehicleModel;
pub use vehicle_model::{Kinematics, SIM_NAME};

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

fn sim_loop(
    client: Client,
    mut model: impl VehicleModel,
    settings: AppSettings,
    stop: &AtomicBool,
) {
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
        for (var, value) in model.nav().vars() {
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
