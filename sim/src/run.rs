//! One simulated run: the helm, the vehicle and the pokes on the in-process bus, on a
//! simulated clock (no sockets, no sleeping).
//!
//! Time steps are the union of the simulator's ticks at `k / sim_AppTick` (k ≥ 0), the
//! helm's at `k / helm_AppTick` (k ≥ 1; its start-up is at 0, as `helm run` iterates
//! one period after start-up), the pokes' times, and the DB's `DB_CLIENTS` once per
//! second; tick times are computed from integer counts, so no rounding accumulates. In a step, pokes are posted, then the simulator steps and posts `NAV_*`,
//! then the helm fetches its mail and iterates; what was posted in the step is
//! delivered at its end (see [`super::bus`]), so the order inside a step only orders
//! the log.
//!
//! The helm is driven by [`helm_cycle::HelmCycle`], the code `helm run` uses.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::bus::{SimBus, HELM};
use super::observe::Observer;
use super::scenario::{Scenario, ScenarioError};
use helm_cycle::HelmCycle;
use helm_engine::posting::Value;
use helm_engine::Mail;
use helm_mission::HelmRecipe;
use vehicle_model::{Drift, Kinematics, SimBlock, VehicleModel, SIM_NAME};

/// MOOS time of the start of every simulated run (fixed: logs are reproducible).
pub const SIM_EPOCH: f64 = 1_700_000_000.0;
/// The helm's app name on the bus.
pub const HELM_NAME: &str = "pHelmIvP";
/// Source of the scenario's pokes.
pub const POKE_NAME: &str = "uPokeDB";

/// Errors before a simulated run starts.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    #[error("{0}")]
    Mission(#[from] helm_mission::MissionLoadError),
    #[error("{0}")]
    Scenario(#[from] ScenarioError),
    #[error("{}: no mission file (.moos) in this folder", .0.display())]
    NoMission(PathBuf),
    #[error("{}: more than one mission file (.moos) in this folder: {}; name one", .0.display(), .1)]
    ManyMissions(PathBuf, String),
    #[error("{problems}")]
    Malconfig { problems: String },
    #[error("{problems}\n{count} problem(s) in the simulator block; nothing run")]
    SimBlock { problems: String, count: usize },
    /// A fleet that cannot run (a vehicle's contact manager block, shards that do not
    /// belong together, ...).
    #[error("{0}")]
    Fleet(String),
    #[error("cannot write {}: {source}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl SimError {
    /// The process exit code (see `helm --help`): 2 a mission file that cannot be read
    /// as one (missing, unreadable, not text, a `.bhv`) or a folder without one mission, 1 a mission or scenario that is wrong, 4 an output
    /// that cannot be written.
    pub fn exit_code(&self) -> u8 {
        match self {
            SimError::Mission(_) => 2,
            SimError::Scenario(ScenarioError::Read { .. }) => 2,
            SimError::NoMission(_) | SimError::ManyMissions(..) => 2,
            SimError::Write { .. } => 4,
            _ => 1,
        }
    }
}

/// The mission file named by `path`: the file itself, or the one `.moos` in a folder.
pub fn find_mission(path: &Path) -> Result<PathBuf, SimError> {
    if !path.is_dir() {
        return Ok(path.to_path_buf());
    }
    let mut found: Vec<PathBuf> = std::fs::read_dir(path)
        .map_err(|source| SimError::Write {
            path: path.to_path_buf(),
            source,
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "moos"))
        .collect();
    found.sort();
    match found.len() {
        0 => Err(SimError::NoMission(path.to_path_buf())),
        1 => Ok(found.remove(0)),
        _ => Err(SimError::ManyMissions(
            path.to_path_buf(),
            found
                .iter()
                .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
                .collect::<Vec<_>>()
                .join(", "),
        )),
    }
}

/// A mission read once, ready to be simulated any number of times.
pub struct Prepared {
    /// The mission's name (file stem).
    pub name: String,
    pub mission_path: PathBuf,
    pub recipe: HelmRecipe,
    pub scenario: Scenario,
    pub helm_tick: f64,
    pub sim_tick: f64,
    /// The vehicle at the start (mission block, then the scenario's overrides).
    pub vehicle: Kinematics,
    pub library_report: Vec<String>,
    /// Unknown names in the simulator block (`file:line: ...`), ignored but shown.
    pub sim_warnings: Vec<String>,
    community: String,
}

/// A change of the start pose, and of how fast the vehicle goes (Monte Carlo).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StartShift {
    pub dx: f64,
    pub dy: f64,
    pub dheading: f64,
    /// Percent added to every commanded speed: 10 makes the vehicle go 10% faster than
    /// its `DESIRED_SPEED` says (as a thrust mismatch would), so that in a fleet each
    /// vessel's speed — what the others see as a contact's speed — varies run to run.
    pub dspeed_pct: f64,
}

impl StartShift {
    /// A helm's command as the simulated vehicle carries it out: `DESIRED_SPEED` scaled
    /// by the speed change, anything else as it is (a speed change of 0 is exact).
    pub fn command(&self, var: &str, value: f64) -> f64 {
        if var == "DESIRED_SPEED" {
            value * (1.0 + self.dspeed_pct / 100.0)
        } else {
            value
        }
    }
}

/// What to do besides running.
#[derive(Default)]
pub struct RunOptions<'a> {
    /// Write an `.alog` here.
    pub alog: Option<PathBuf>,
    /// Keep every bus message in [`Outcome::log`].
    pub record: bool,
    /// Override the scenario's max time.
    pub max_time: Option<f64>,
    /// Told the simulated seconds done, about once per simulated second.
    pub progress: Option<&'a (dyn Fn(f64) + Sync)>,
}

/// What a run did.
#[derive(Debug)]
pub struct Outcome {
    pub sim_time_s: f64,
    pub wall_time_s: f64,
    pub end_reason: String,
    pub iterations: u64,
    pub observer: Observer,
    pub start: vehicle_model::Nav,
    pub end: vehicle_model::Nav,
    pub log: Vec<Mail>,
    pub helm_state: &'static str,
    /// Whether the helm was in DRIVE at any iteration (else it never steered).
    pub drove: bool,
}

impl Outcome {
    /// What the run did wrong, in plain words, worst first (empty: nothing).
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        let panics = &self.observer.behavior_panics;
        if !panics.is_empty() {
            w.push(format!(
                "{} behavior panic(s): the behavior was disabled and the helm all-stopped \
                 (first: {})",
                panics.len(),
                panics[0]
            ));
        }
        if !self.drove {
            w.push(format!(
                "the helm stayed in {}: MOOS_MANUAL_OVERRIDE was never false; set \
                 start_in_drive = true or poke MOOS_MANUAL_OVERRIDE=false",
                self.helm_state
            ));
        }
        w
    }
}

/// The mission's uSimMarine block with its warnings, or the error listing its errors.
pub(crate) fn sim_block(block: SimBlock) -> Result<(SimBlock, Vec<String>), SimError> {
    let errors = block.error_texts();
    if !errors.is_empty() {
        return Err(SimError::SimBlock {
            problems: errors.join("\n"),
            count: errors.len(),
        });
    }
    let warnings = block.warning_texts().map(str::to_string).collect();
    Ok((block, warnings))
}

/// A new `.alog` at `path`, its header written (log start `t0`).
pub(crate) fn open_alog(path: &Path, t0: f64) -> Result<moos::alog::AlogFile, SimError> {
    moos::alog::AlogFile::create(path, t0).map_err(|source| SimError::Write {
        path: path.to_path_buf(),
        source,
    })
}

impl Prepared {
    /// Read `mission` (plus extra `.bhv` files) and `scenario` (default: the
    /// `scenario.toml` beside the mission, if any). A MALCONFIG helm is an error: it
    /// would never drive.
    pub fn load(
        mission: &Path,
        bhv: &[PathBuf],
        scenario: Option<&Path>,
    ) -> Result<Prepared, SimError> {
        let mission = find_mission(mission)?;
        let dir = mission.parent().unwrap_or(Path::new(".")).to_path_buf();
        let scenario = match scenario {
            Some(p) => Scenario::read(p)?,
            None => Scenario::beside(&dir)?,
        };
        let loaded = helm_mission::load(&mission, bhv, HELM_NAME)?;
        let library_report = loaded.library_report.clone();
        let (recipe, file) = loaded.into_recipe();
        // Problems found while reading and while building the behavior set.
        let problems = recipe.build().config_warnings().to_vec();
        if !problems.is_empty() {
            let mut text = problems.join("\n");
            text.push_str(&format!(
                "\nMALCONFIG: {} configuration problem(s); the helm would never drive, nothing run",
                problems.len()
            ));
            return Err(SimError::Malconfig { problems: text });
        }
        let helm_tick = file.app_tick(HELM_NAME, 5.0);
        let sim_tick = file.app_tick(SIM_NAME, 10.0);
        let (block, sim_warnings) = sim_block(SimBlock::read(&file))?;
        let mut vehicle = Kinematics::from_block(&block);
        let v = &scenario.vehicle;
        vehicle.x = v.x.unwrap_or(vehicle.x);
        vehicle.y = v.y.unwrap_or(vehicle.y);
        vehicle.heading = v.heading.unwrap_or(vehicle.heading).rem_euclid(360.0);
        vehicle.speed = v.speed.unwrap_or(vehicle.speed);
        vehicle.depth = v.depth.unwrap_or(vehicle.depth);
        let name = mission.file_stem().map_or_else(
            || "mission".to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
        Ok(Prepared {
            name,
            mission_path: mission,
            community: file.global("Community").unwrap_or_default(),
            recipe,
            scenario,
            helm_tick,
            sim_tick,
            vehicle,
            library_report,
            sim_warnings,
        })
    }

    /// Run once from the start pose moved by `shift`.
    pub fn run(&self, shift: StartShift, opts: &RunOptions) -> Result<Outcome, SimError> {
        let wall = Instant::now();
        let t0 = SIM_EPOCH;
        let max_time = opts.max_time.unwrap_or(self.scenario.max_time);
        let mut kin = self.vehicle.clone();
        kin.x += shift.dx;
        kin.y += shift.dy;
        kin.heading = (kin.heading + shift.dheading).rem_euclid(360.0);
        let mut model = Drift {
            model: kin,
            current: self.scenario.vehicle.current,
        };
        let start_nav = model.nav();

        let mut bus = SimBus::new(
            &[HELM_NAME, SIM_NAME],
            Observer::new(t0, self.scenario.when.clone()),
        );
        if let Some(path) = &opts.alog {
            bus.alog = Some(open_alog(path, t0)?);
        }
        if opts.record {
            bus.record = Some(Vec::new());
        }
        const SIM: usize = 1;
        for var in ["DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH"] {
            bus.subscribe(SIM, var);
        }
        let db_name = format!("MOOSDB_{}", self.community);
        let clients = Value::Str(format!("{SIM_NAME},{HELM_NAME},"));

        let mut helm = self.recipe.build();
        let mut cycle = HelmCycle::startup(&mut helm, &mut bus, t0);
        // Functions are serialised only for a reader (a log, a record, a subscriber).
        helm.set_ipf_posting(bus.is_read("BHV_IPF"));
        bus.deliver();

        let (mut kh, mut ks, mut kd, mut kp) = (1u64, 0u64, 0u64, 0usize);
        let mut last_sim = 0.0f64;
        let mut sim_in: Vec<Mail> = Vec::new();
        let mut helm_in: Vec<Mail> = Vec::new();
        let mut next_progress = 1.0;
        let mut off;
        let mut drove = helm.state() == helm_engine::HelmState::Drive;
        let reason = loop {
            let th = kh as f64 / self.helm_tick;
            let ts = ks as f64 / self.sim_tick;
            let td = kd as f64;
            let tp = self.scenario.pokes.get(kp).map_or(f64::INFINITY, |p| p.at);
            off = th.min(ts).min(td).min(tp);
            if off > max_time {
                off = max_time;
                break "max-time".to_string();
            }
            let now = t0 + off;
            if let Some(p) = opts.progress {
                if off >= next_progress {
                    next_progress = off.floor() + 1.0;
                    p(off);
                }
            }
            while kp < self.scenario.pokes.len() && self.scenario.pokes[kp].at == off {
                let p = &self.scenario.pokes[kp];
                bus.post(POKE_NAME, &p.var, &p.value, "", now);
                kp += 1;
            }
            if td == off {
                bus.post(&db_name, "DB_CLIENTS", &clients, "", now);
                kd += 1;
            }
            if ts == off {
                bus.fetch(SIM, &mut sim_in);
                // A parked helm's all-stop (DESIRED_HEADING = 0) does not steer: under
                // manual override the controller does not actuate the rudder.
                let parked = helm.state() != helm_engine::HelmState::Drive;
                for m in &sim_in {
                    if let Value::Num(v) = m.value {
                        if !(parked && m.var == "DESIRED_HEADING") {
                            model.on_mail(&m.var, shift.command(&m.var, v));
                        }
                    }
                }
                model.step(off - last_sim);
                last_sim = off;
                let nav = model.nav();
                bus.observer.track.push(nav.x, nav.y);
                bus.observer.depth.push(off, nav.depth);
                for (var, value) in nav.vars() {
                    bus.post(SIM_NAME, var, &Value::Num(value), "", now);
                }
                ks += 1;
            }
            if th == off {
                if self.scenario.mission_over && cycle.status.end.is_over(now) {
                    break "mission-over".to_string();
                }
                bus.fetch(HELM, &mut helm_in);
                cycle.mail(&mut helm, now, &helm_in);
                cycle.iterate(&mut helm, &mut bus, now);
                drove |= helm.state() == helm_engine::HelmState::Drive;
                kh += 1;
            }
            bus.deliver();
            if let Some(r) = &bus.observer.fired {
                break r.clone();
            }
        };
        if let Some(w) = &mut bus.alog {
            if let Err(e) = w.flush() {
                bus.alog_error = Some(e);
            }
        }
        if let (Some(e), Some(path)) = (bus.alog_error.take(), &opts.alog) {
            return Err(SimError::Write {
                path: path.clone(),
                source: e,
            });
        }
        bus.observer.headings = Some((start_nav.heading, model.nav().heading));
        Ok(Outcome {
            sim_time_s: off,
            wall_time_s: wall.elapsed().as_secs_f64(),
            end_reason: reason,
            iterations: cycle.status.iterations,
            start: start_nav,
            end: model.nav(),
            log: bus.record.take().unwrap_or_default(),
            observer: std::mem::take(&mut bus.observer),
            helm_state: helm.state().as_str(),
            drove,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_speed_change_scales_only_the_speed_command() {
        let s = StartShift {
            dspeed_pct: 20.0,
            ..StartShift::default()
        };
        assert_eq!(s.command("DESIRED_SPEED", 2.0), 2.4);
        assert_eq!(s.command("DESIRED_HEADING", 90.0), 90.0);
        // No change is exact, so unperturbed runs keep their bytes.
        assert_eq!(StartShift::default().command("DESIRED_SPEED", 1.7), 1.7);
    }

    #[test]
    fn a_faster_vehicle_covers_more_ground_in_the_same_time() {
        let mission = Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/alpha");
        let prep = Prepared::load(&mission, &[], None).expect("alpha loads");
        let opts = RunOptions {
            max_time: Some(60.0),
            ..RunOptions::default()
        };
        let nominal = prep.run(StartShift::default(), &opts).expect("runs");
        let fast = prep
            .run(
                StartShift {
                    dspeed_pct: 20.0,
                    ..StartShift::default()
                },
                &opts,
            )
            .expect("runs");
        let ratio = fast.observer.track.distance / nominal.observer.track.distance;
        assert!((1.1..1.3).contains(&ratio), "distance ratio {ratio}");
        let speeds = fast.end.speed / nominal.end.speed;
        assert!((1.15..1.25).contains(&speeds), "end speed ratio {speeds}");
    }
}
