//! A fleet run: every vehicle's apps on one simulated clock, node reports through the
//! comms model, collision statistics over every pair.
//!
//! A step is the earliest next tick of any app of any vehicle, of a poke or of the
//! once-a-second `DB_CLIENTS`. In a step: pokes, then the reports the comms model has
//! due, then each vehicle in scenario order (see [`Live::step`]); then the collision
//! detector sees the positions, every bus delivers, and the shoreside picks up the
//! `NODE_REPORT_LOCAL`s posted in the step and hands them to the comms model. Nothing
//! depends on the wall clock, threads or hash order: same inputs, same logs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::collide::{Detector, Distances, PairRecord};
use super::comms::{CommsModel, CommsStats};
use super::relay::Relayed;
use super::spec::{FleetScenario, Ranges};
use super::vehicle::{Live, VehiclePlan, COMMS_NAME};
use crate::observe::Observer;
use crate::run::{SimError, StartShift, POKE_NAME, SIM_EPOCH};
use helm_engine::posting::Value;
use helm_engine::Mail;

/// A fleet read once, ready to run any number of times.
pub struct FleetPlan {
    /// The scenario's folder name.
    pub name: String,
    pub scenario: FleetScenario,
    pub vehicles: Vec<VehiclePlan>,
}

/// What to do besides running.
#[derive(Default)]
pub struct FleetOptions<'a> {
    /// Write each vehicle's `.alog` here (`<name>.alog`), as the run goes.
    pub alog_dir: Option<PathBuf>,
    pub max_time: Option<f64>,
    /// Seed of the run (the comms drops); 0 for a single run.
    pub seed: u64,
    pub progress: Option<&'a (dyn Fn(f64) + Sync)>,
}

/// What one vehicle did.
#[derive(Debug)]
pub struct VehicleOutcome {
    pub name: String,
    pub color: String,
    pub observer: Observer,
    pub start: vehicle_model::Nav,
    pub end: vehicle_model::Nav,
    pub iterations: u64,
    pub helm_state: &'static str,
    pub drove: bool,
    /// NODE_REPORTs the contact manager received.
    pub node_reports: u64,
    pub malformed_reports: u64,
    /// Where it was at each picture tick: (s from the start, x, y).
    pub ticks: Vec<(f64, f64, f64)>,
}

/// What a fleet run did.
#[derive(Debug)]
pub struct FleetOutcome {
    pub sim_time_s: f64,
    pub wall_time_s: f64,
    pub end_reason: String,
    pub vehicles: Vec<VehicleOutcome>,
    pub pairs: Vec<PairRecord>,
    pub comms: CommsStats,
    pub ranges: Ranges,
    /// s between the picture's time ticks.
    pub tick: f64,
    /// Obstacles, when the scenario has some.
    pub obstacles: Option<super::obstacles::ObstacleOutcome>,
    /// The COLREGS verdict of every ordered pair that met.
    pub colregs: Vec<super::colregs::RuleRecord>,
}

impl FleetPlan {
    /// Read the scenario at `path` and every vehicle's mission.
    pub fn load(path: &Path) -> Result<FleetPlan, SimError> {
        let scenario = FleetScenario::read(path)?;
        let vehicles = scenario
            .vehicles
            .iter()
            .map(VehiclePlan::load)
            .collect::<Result<Vec<_>, _>>()?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let name = std::fs::canonicalize(dir)
            .ok()
            .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| "fleet".into());
        Ok(FleetPlan {
            name,
            scenario,
            vehicles,
        })
    }

    /// Run once, vehicle i moved by `shifts[i]` (missing: no shift).
    pub fn run(
        &self,
        shifts: &[StartShift],
        opts: &FleetOptions,
    ) -> Result<FleetOutcome, SimError> {
        let wall = Instant::now();
        let t0 = SIM_EPOCH;
        let sc = &self.scenario;
        let max_time = opts.max_time.unwrap_or(sc.max_time);
        let mut live = Vec::with_capacity(self.vehicles.len());
        for (i, p) in self.vehicles.iter().enumerate() {
            let alog = opts
                .alog_dir
                .as_ref()
                .map(|d| d.join(format!("{}.alog", p.spec.name)));
            let shift = shifts.get(i).copied().unwrap_or_default();
            live.push(Live::new(p, shift, t0, sc.when.clone(), alog)?);
        }
        let names: Vec<String> = self.vehicles.iter().map(|p| p.spec.name.clone()).collect();
        let mut detector = Detector::new(&names, sc.ranges);
        let mut comms = CommsModel::new(sc.comms, opts.seed);
        let mut pos: Vec<(f64, f64)> = live.iter().map(|l| (l.nav().x, l.nav().y)).collect();
        let mut dist = Distances::of(&pos);
        detector.update(0.0, &pos, &dist);
        let mut rules =
            super::colregs::Tracker::new(live.len(), sc.ranges.encounter, sc.ranges.collision);
        let mut world = sc
            .obstacles
            .as_ref()
            .map(|o| super::obstacles::World::new(o, opts.seed));
        let clients: Vec<Value> = self
            .vehicles
            .iter()
            .map(|p| {
                // A vehicle running pObstacleMgr lists it too (the others as before).
                let obm = if p.obm.is_some() { "pObstacleMgr," } else { "" };
                Value::Str(format!(
                    "uSimMarine,pHelmIvP,pContactMgrV20,pNodeReporter,{obm}{COMMS_NAME},"
                ))
            })
            .collect();
        let db_names: Vec<String> = self
            .vehicles
            .iter()
            .map(|p| format!("MOOSDB_{}", p.spec.name))
            .collect();
        let (mut kd, mut kp) = (0u64, 0usize);
        let mut ticks: Vec<Vec<(f64, f64, f64)>> = vec![Vec::new(); live.len()];
        let mut ktick = 1u64;
        let mut reports: Vec<Mail> = Vec::new();
        let mut next_progress = 1.0;
        let mut off;
        let reason = loop {
            let td = kd as f64;
            let tp = sc.pokes.get(kp).map_or(f64::INFINITY, |p| p.poke.at);
            off = live
                .iter()
                .zip(&self.vehicles)
                .map(|(l, p)| l.next(p))
                .fold(td.min(tp), f64::min)
                .min(world.as_ref().map_or(f64::INFINITY, |w| w.next()));
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
            while kp < sc.pokes.len() && sc.pokes[kp].poke.at == off {
                let fp = &sc.pokes[kp];
                for (i, l) in live.iter_mut().enumerate() {
                    if fp.vehicle.is_none_or(|v| v == i) {
                        l.bus.post(POKE_NAME, &fp.poke.var, &fp.poke.value, "", now);
                    }
                }
                kp += 1;
            }
            while let Some((to, r)) = comms.due(off) {
                live[to].receive_report(r, now);
            }
            if td == off {
                for (i, l) in live.iter_mut().enumerate() {
                    l.bus.post(&db_names[i], "DB_CLIENTS", &clients[i], "", now);
                }
                kd += 1;
            }
            if let Some(w) = &mut world {
                let mut buses: Vec<&mut crate::bus::SimBus> =
                    live.iter_mut().map(|l| &mut l.bus).collect();
                w.step(off, now, &names, &mut buses, &pos);
            }
            let mut moved = false;
            for (l, p) in live.iter_mut().zip(&self.vehicles) {
                moved |= l.step(p, off, now, sc.mission_over);
            }
            if moved {
                for (p, l) in pos.iter_mut().zip(&live) {
                    let n = l.nav();
                    *p = (n.x, n.y);
                }
                dist.update(&pos);
                detector.update(off, &pos, &dist);
                if let Some(w) = &mut world {
                    w.collide(off, &names, &pos);
                }
                if live.len() > 1 {
                    let vs: Vec<super::colregs::Vessel> = live
                        .iter()
                        .map(|l| {
                            let n = l.nav();
                            super::colregs::Vessel {
                                x: n.x,
                                y: n.y,
                                heading: n.heading,
                                speed: n.speed,
                            }
                        })
                        .collect();
                    let alerted = |i: usize, j: usize| {
                        live[i]
                            .mgr
                            .alerted()
                            .any(|(c, _)| c.eq_ignore_ascii_case(&names[j]))
                    };
                    rules.update(off, &vs, &dist, &alerted);
                }
                let due = ktick as f64 * sc.tick;
                if off >= due {
                    for (t, p) in ticks.iter_mut().zip(&pos) {
                        t.push((due, p.0, p.1));
                    }
                    ktick += 1;
                }
            }
            for (i, l) in live.iter_mut().enumerate() {
                l.bus.deliver();
                l.take_reports(&mut reports);
                for m in &reports {
                    if let Value::Str(s) = &m.value {
                        let r = l.written(s).unwrap_or_else(|| Relayed::new(s.clone()));
                        comms.send(off, i, r, dist.row(i));
                    }
                }
            }
            if let Some(r) = live.iter().find_map(|l| l.bus.observer.fired.clone()) {
                break r;
            }
            if sc.mission_over && live.iter().all(|l| l.over) {
                break "mission-over".to_string();
            }
        };
        detector.finish();
        let obm_alerts: Vec<(String, u64)> = live
            .iter()
            .zip(&names)
            .filter_map(|(l, n)| l.obm.as_ref().map(|o| (n.clone(), o.alerts)))
            .collect();
        let obstacles = world.map(|w| w.finish(&obm_alerts));
        let mut vehicles = Vec::with_capacity(live.len());
        for ((mut l, p), ticks) in live.into_iter().zip(&self.vehicles).zip(ticks) {
            l.finish();
            if let Some(e) = l.bus.alog_error.take() {
                let dir = opts.alog_dir.clone().unwrap_or_default();
                return Err(SimError::Write {
                    path: dir.join(format!("{}.alog", p.spec.name)),
                    source: e,
                });
            }
            vehicles.push(VehicleOutcome {
                name: p.spec.name.clone(),
                color: p.spec.color.clone(),
                start: l.start,
                end: l.nav(),
                iterations: l.iterations(),
                helm_state: l.helm_state(),
                drove: l.drove,
                node_reports: l.mgr.received().1,
                malformed_reports: l.mgr.malformed_reports(),
                ticks,
                observer: std::mem::take(&mut l.bus.observer),
            });
        }
        Ok(FleetOutcome {
            sim_time_s: off,
            wall_time_s: wall.elapsed().as_secs_f64(),
            end_reason: reason,
            vehicles,
            pairs: detector.pairs,
            comms: comms.stats,
            ranges: sc.ranges,
            tick: sc.tick,
            obstacles,
            colregs: rules.finish(&names),
        })
    }
}
