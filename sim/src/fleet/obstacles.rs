//! Obstacles in a fleet run (issue 22 point 4): uFldObstacleSim on the shoreside, a
//! pObstacleMgr on each vehicle whose mission configures one, and uFldCollObDetect's
//! counting, all from the `obstacle-manager` library.
//!
//! ```toml
//! obstacle_file = "obstacles.txt"   # uFldObstacleSim's format (region, min_range, poly lines)
//!
//! [[obstacle]]                      # more obstacles, each a convex polygon
//! poly = "pts={60,-12:60,6:80,6:80,-12},label=rock"   # no label: ob_<n>
//!
//! [obstacle_sim]                    # uFldObstacleSim's block (obstacles.md §3.1)
//! apptick = 1                       # Hz (its AppTick; default 1, as the missions set it)
//! min_duration = 400
//! max_duration = 500
//! refresh_interval = 200
//!
//! [obstacle_collision]              # uFldCollObDetect's block (§4; defaults 1, 5, 15)
//! collision_dist = 1
//! near_miss_dist = 5
//! encounter_dist = 14
//! ```
//!
//! The simulator ticks at its AppTick with every vehicle's position; what it posts as
//! `GIVEN_OBSTACLE` (or, in point mode, `TRACKED_FEATURE_<VNAME>`) is bridged to each
//! vehicle's bus as uFldShoreBroker does (`GIVEN_OBSTACLE`, `TRACKED_FEATURE`), and its
//! `KNOWN_OBSTACLE`s feed the collision counter. A vehicle whose `.moos` has a
//! `ProcessConfig = pObstacleMgr` block runs the manager at that block's AppTick
//! (default 4); its `OBSTACLE_ALERT`s spawn BHV_AvoidObstacleV24 on that vehicle's helm.
//! The counter looks at every simulator step (finer than uFldCollObDetect's own tick);
//! an encounter still open when the run ends is counted then (as the vehicle pairs
//! are), so a vehicle that ends inside an obstacle is a collision.
//!
//! Bad input stops the run before it starts, with its line: a `poly` that is not a
//! convex polygon, two obstacles with one label, an unknown simulator or collision
//! parameter, a bad obstacle-file line (`file:line`), a bad pObstacleMgr block line.

use std::collections::BTreeMap;
use std::path::Path;

use obstacle_manager::{
    CollisionConfig, CollisionDetector, Config, MailValue, ObstacleFile, ObstacleManager,
    ObstacleSim, SimConfig, SimVehicle,
};
use serde::{Deserialize, Serialize};
use toml::Spanned;

use crate::bus::SimBus;
use crate::run::SimError;
use crate::scenario::ScenarioError;
use helm_engine::posting::Value;
use helm_engine::Mail;

pub const OBM_NAME: &str = "pObstacleMgr";
pub const OBSIM_NAME: &str = "uFldObstacleSim";
/// The source of bridged obstacle mail on a vehicle's bus.
pub const BROKER_NAME: &str = "uFldShoreBroker";

/// One `[[obstacle]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleDoc {
    poly: Spanned<String>,
}

/// The scenario's obstacle entries as read by serde.
pub struct Docs<'a> {
    pub obstacle: &'a [ObstacleDoc],
    pub obstacle_file: Option<&'a Spanned<String>>,
    pub obstacle_sim: Option<&'a BTreeMap<String, Spanned<toml::Value>>>,
    pub obstacle_collision: Option<&'a BTreeMap<String, Spanned<toml::Value>>>,
}

/// The obstacles of a fleet scenario, read and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleSetup {
    pub file: ObstacleFile,
    pub sim: SimConfig,
    /// The simulator's AppTick (Hz).
    pub sim_tick: f64,
    pub collision: CollisionConfig,
}

fn value_text(v: &toml::Value) -> Option<String> {
    match v {
        toml::Value::String(s) => Some(s.clone()),
        toml::Value::Integer(i) => Some(i.to_string()),
        toml::Value::Float(f) if f.is_finite() => Some(f.to_string()),
        toml::Value::Boolean(b) => Some(b.to_string()),
        _ => None,
    }
}

type Bad<'a> = &'a dyn Fn(std::ops::Range<usize>, String) -> ScenarioError;

/// Read the obstacle entries (None: the scenario has none).
pub fn read_setup(d: &Docs, dir: &Path, bad: Bad) -> Result<Option<ObstacleSetup>, ScenarioError> {
    if d.obstacle.is_empty() && d.obstacle_file.is_none() {
        for t in [d.obstacle_sim, d.obstacle_collision].into_iter().flatten() {
            if let Some((_, v)) = t.iter().next() {
                return Err(bad(
                    v.span(),
                    "obstacle parameters without obstacles (`[[obstacle]]` or `obstacle_file`)"
                        .into(),
                ));
            }
        }
        return Ok(None);
    }
    let mut file = match d.obstacle_file {
        Some(f) => {
            let p = dir.join(f.get_ref().trim());
            let shown = p.display().to_string();
            let text = std::fs::read_to_string(&p).map_err(|e| {
                bad(
                    f.span(),
                    format!("obstacle file `{}`: {e} ({shown})", f.get_ref()),
                )
            })?;
            // Every bad line is named as file:line (the reference ignores the rest).
            ObstacleFile::parse(&text, &shown)
                .map_err(|e| bad(f.span(), format!("bad obstacle file:\n{e}")))?
        }
        None => ObstacleFile {
            path: "scenario.toml".into(),
            ..ObstacleFile::default()
        },
    };
    for o in d.obstacle {
        let one = ObstacleFile::parse(&format!("poly = {}", o.poly.get_ref().trim()), "").map_err(
            |_| {
                bad(
                    o.poly.span(),
                    format!("`{}` is not a convex polygon", o.poly.get_ref()),
                )
            },
        )?;
        file.obstacles.extend(one.obstacles);
    }
    let mut labels = std::collections::HashSet::new();
    for (i, p) in file.obstacles.iter_mut().enumerate() {
        if p.attrs.label.is_empty() {
            p.attrs.label = format!("ob_{i}");
        }
        if !labels.insert(p.attrs.label.clone()) {
            let span = d.obstacle_file.map_or(0..0, |f| f.span());
            let span = d
                .obstacle
                .iter()
                .find(|o| {
                    o.poly
                        .get_ref()
                        .contains(&format!("label={}", p.attrs.label))
                })
                .map_or(span, |o| o.poly.span());
            return Err(bad(
                span,
                format!("two obstacles labelled `{}`", p.attrs.label),
            ));
        }
    }
    let mut sim = SimConfig::default();
    let mut sim_tick = 1.0;
    for (k, v) in d.obstacle_sim.into_iter().flatten() {
        let text = value_text(v.get_ref())
            .ok_or_else(|| bad(v.span(), format!("`{k}`: not a string, number or boolean")))?;
        if k.eq_ignore_ascii_case("apptick") {
            sim_tick = mbutil::parse_number(&text)
                .filter(|t| t.is_finite() && *t > 0.0)
                .ok_or_else(|| bad(v.span(), format!("`apptick = {text}`: must be > 0")))?;
            continue;
        }
        if k.eq_ignore_ascii_case("obstacle_file") {
            return Err(bad(
                v.span(),
                "give the obstacle file as the top-level `obstacle_file`".into(),
            ));
        }
        sim.set(k, &text)
            .map_err(|e| bad(v.span(), format!("[obstacle_sim] {e}")))?;
    }
    let mut collision = CollisionConfig::default();
    for (k, v) in d.obstacle_collision.into_iter().flatten() {
        let text = value_text(v.get_ref())
            .ok_or_else(|| bad(v.span(), format!("`{k}`: not a string, number or boolean")))?;
        collision
            .set(k, &text)
            .map_err(|e| bad(v.span(), format!("[obstacle_collision] {e}")))?;
    }
    for w in collision.finish() {
        tracing::warn!("[obstacle_collision]: {w}");
    }
    Ok(Some(ObstacleSetup {
        file,
        sim,
        sim_tick,
        collision,
    }))
}

/// A vehicle's pObstacleMgr, from its mission's block (None: the mission runs none).
#[derive(Clone, Debug)]
pub struct ObmPlan {
    pub cfg: Config,
    pub tick: f64,
}

/// Read `ProcessConfig = pObstacleMgr` of a vehicle's mission.
pub fn obm_plan(
    file: &moos::mission::MissionFile,
    vname: &str,
) -> Result<Option<ObmPlan>, SimError> {
    let mut cfg = Config::default();
    let Some(bad) = contact_manager::block::read(file, OBM_NAME, |k, v| {
        cfg.set(k, v).map_err(|e| e.to_string())
    }) else {
        return Ok(None);
    };
    if !bad.is_empty() {
        return Err(SimError::Fleet(format!(
            "vehicle {vname}: bad {OBM_NAME} block:\n{}",
            bad.join("\n")
        )));
    }
    Ok(Some(ObmPlan {
        cfg,
        tick: file.app_tick(OBM_NAME, 4.0),
    }))
}

/// A vehicle's manager during a run: its bus client and its tick count.
pub struct ObmLive {
    pub mgr: ObstacleManager,
    client: usize,
    k: u64,
    tick: f64,
    inbox: Vec<Mail>,
    /// Alerts it posted (the spawns' cause).
    pub alerts: u64,
}

impl ObmLive {
    /// Join `bus` (before the helm starts, so the helm's alert request reaches it).
    pub fn new(plan: &ObmPlan, bus: &mut SimBus, t0: f64) -> ObmLive {
        let client = bus.add_client(OBM_NAME);
        let mgr = ObstacleManager::new(plan.cfg.clone(), t0);
        for var in mgr.subscriptions() {
            bus.subscribe(client, &var);
        }
        ObmLive {
            mgr,
            client,
            k: 1,
            tick: plan.tick,
            inbox: Vec::new(),
            alerts: 0,
        }
    }

    pub fn next(&self) -> f64 {
        self.k as f64 / self.tick
    }

    /// Its tick, if due at `off`.
    pub fn step(&mut self, bus: &mut SimBus, off: f64, now: f64) {
        if self.next() != off {
            return;
        }
        self.k += 1;
        bus.fetch(self.client, &mut self.inbox);
        let batch: Vec<(&str, MailValue<'_>)> = self
            .inbox
            .iter()
            .map(|m| {
                let v = match &m.value {
                    Value::Num(n) => MailValue::Num(*n),
                    Value::Str(s) => MailValue::Str(s),
                };
                (m.var.as_str(), v)
            })
            .collect();
        self.mgr.handle_mail(now, &batch);
        drop(batch);
        let alert_var = self.mgr.request().map(|r| r.update_var.clone());
        for p in self.mgr.iterate(now) {
            let v = match &p.val {
                obstacle_manager::Value::Str(s) => Value::Str(s.clone()),
                obstacle_manager::Value::Num(n) => Value::Num(*n),
            };
            if alert_var.as_deref() == Some(p.var.as_str()) {
                self.alerts += 1;
            }
            bus.post(OBM_NAME, &p.var, &v, "", now);
        }
    }
}

/// Per run: the shoreside simulator and the counter.
pub struct World {
    sim: ObstacleSim,
    det: CollisionDetector,
    det_cfg: CollisionConfig,
    tick: f64,
    k: u64,
    rng: u64,
}

/// splitmix64: the simulator's random numbers (durations, sensor points), seeded by
/// the run so a run is the same every time.
fn next01(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

impl World {
    pub fn new(s: &ObstacleSetup, seed: u64) -> World {
        let mut rng = seed ^ 0x0b57_ac1e;
        let sim = ObstacleSim::new(s.sim.clone(), s.file.clone(), || next01(&mut rng));
        World {
            sim,
            det: CollisionDetector::new(s.collision.clone()),
            det_cfg: s.collision.clone(),
            tick: s.sim_tick,
            k: 0,
            rng,
        }
    }

    /// The simulator's next tick (s from the start).
    pub fn next(&self) -> f64 {
        self.k as f64 / self.tick
    }

    /// The simulator's tick, if due at `off`: its postings bridged to every vehicle.
    pub fn step(
        &mut self,
        off: f64,
        now: f64,
        names: &[String],
        buses: &mut [&mut SimBus],
        pos: &[(f64, f64)],
    ) {
        if self.next() != off {
            return;
        }
        self.k += 1;
        let seen: Vec<SimVehicle> = names
            .iter()
            .zip(pos)
            .map(|(n, p)| SimVehicle {
                name: n,
                x: p.0,
                y: p.1,
                color: None,
            })
            .collect();
        let rng = &mut self.rng;
        let posts = self.sim.step(now, &seen, &mut || next01(rng)).to_vec();
        for p in &posts {
            let Some(v) = p.val.as_str() else { continue };
            match p.var.as_str() {
                "KNOWN_OBSTACLE" => {
                    if let Err(e) = self.det.known_obstacle(v, off) {
                        tracing::warn!("{OBSIM_NAME}: {e}");
                    }
                }
                "GIVEN_OBSTACLE" => {
                    for b in buses.iter_mut() {
                        b.post(
                            BROKER_NAME,
                            "GIVEN_OBSTACLE",
                            &Value::Str(v.into()),
                            "",
                            now,
                        );
                    }
                }
                var => {
                    // Point mode: each vehicle's own sensor points.
                    if let Some(who) = var.strip_prefix("TRACKED_FEATURE_") {
                        for (b, n) in buses.iter_mut().zip(names) {
                            if n.eq_ignore_ascii_case(who) {
                                b.post(
                                    BROKER_NAME,
                                    "TRACKED_FEATURE",
                                    &Value::Str(v.into()),
                                    "",
                                    now,
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// The vehicles are at `pos` (in `names` order).
    pub fn collide(&mut self, off: f64, names: &[String], pos: &[(f64, f64)]) {
        let v: Vec<(&str, f64, f64)> = names
            .iter()
            .zip(pos)
            .map(|(n, p)| (n.as_str(), p.0, p.1))
            .collect();
        self.det.step(off, &v);
    }

    /// What the run did, `alerts[i]` the alerts vehicle i's manager posted.
    pub fn finish(self, alerts: &[(String, u64)]) -> ObstacleOutcome {
        let cfg = self.det_cfg.clone();
        let mut pairs = Vec::new();
        let (mut enc, mut near, mut coll) = (
            self.det.encounters(),
            self.det.near_misses(),
            self.det.collisions(),
        );
        for ((v, o), s) in self.det.pairs() {
            let (mut e, mut n, mut c) = (s.encounters, s.near_misses, s.collisions);
            // An encounter still open at the end counts, by its closest approach so far.
            if s.encounter_min >= 0.0 && s.dist >= 0.0 && s.dist <= cfg.encounter_dist {
                e += 1;
                enc += 1;
                if s.encounter_min < cfg.collision_dist {
                    c += 1;
                    coll += 1;
                } else if s.encounter_min < cfg.near_miss_dist {
                    n += 1;
                    near += 1;
                }
            }
            pairs.push(ObstaclePair {
                vehicle: v.to_string(),
                obstacle: o.to_string(),
                closest_m: s.closest,
                encounters: e,
                near_misses: n,
                collisions: c,
            });
        }
        let polygons: Vec<geometry::Polygon> = self
            .sim
            .obstacles()
            .iter()
            .map(|o| o.poly.clone())
            .collect();
        let obstacles = polygons
            .iter()
            .map(|p| {
                let best = pairs
                    .iter()
                    .filter(|q| q.obstacle == p.attrs.label)
                    .min_by(|a, b| a.closest_m.total_cmp(&b.closest_m));
                ObstacleRecord {
                    label: p.attrs.label.clone(),
                    closest_m: best.map_or(-1.0, |b| b.closest_m),
                    closest_vehicle: best.map(|b| b.vehicle.clone()),
                }
            })
            .collect();
        ObstacleOutcome {
            collision_dist: cfg.collision_dist,
            near_miss_dist: cfg.near_miss_dist,
            encounter_dist: cfg.encounter_dist,
            encounters: enc,
            near_misses: near,
            collisions: coll,
            closest_m: self.det.global_min().unwrap_or(-1.0),
            alerts: alerts.to_vec(),
            obstacles,
            pairs,
            polygons,
            region: self.sim.region().cloned(),
        }
    }
}

/// One obstacle over the run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObstacleRecord {
    pub label: String,
    /// Closest any vehicle came (m; 0 inside; −1: never measured).
    pub closest_m: f64,
    pub closest_vehicle: Option<String>,
}

/// One vehicle and obstacle over the run, as uFldCollObDetect counts them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObstaclePair {
    pub vehicle: String,
    pub obstacle: String,
    pub closest_m: f64,
    pub encounters: u32,
    pub near_misses: u32,
    pub collisions: u32,
}

/// The obstacles of a run (in `summary.json` as `obstacles`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObstacleOutcome {
    pub collision_dist: f64,
    pub near_miss_dist: f64,
    pub encounter_dist: f64,
    pub encounters: u32,
    pub near_misses: u32,
    pub collisions: u32,
    /// The closest any vehicle came to any obstacle (m; −1: none measured).
    pub closest_m: f64,
    /// (vehicle, OBSTACLE_ALERTs its pObstacleMgr posted), for vehicles that run one.
    pub alerts: Vec<(String, u64)>,
    pub obstacles: Vec<ObstacleRecord>,
    pub pairs: Vec<ObstaclePair>,
    #[serde(skip)]
    pub polygons: Vec<geometry::Polygon>,
    #[serde(skip)]
    pub region: Option<geometry::Polygon>,
}

impl ObstacleOutcome {
    /// The terminal lines.
    pub fn terminal(&self) -> String {
        let mut s = format!(
            "  obstacles: {}; encounters (< {} m) {}, near misses (< {} m) {}, collisions (< {} m) {}; closest {:.1} m",
            self.obstacles.len(),
            self.encounter_dist,
            self.encounters,
            self.near_miss_dist,
            self.near_misses,
            self.collision_dist,
            self.collisions,
            self.closest_m
        );
        for (v, n) in &self.alerts {
            s.push_str(&format!(
                "\n  {v}: {n} obstacle alert(s) from its {OBM_NAME}"
            ));
        }
        s
    }
}

/// The obstacles' vertices (so the picture's view takes them in).
pub fn picture_points(o: &ObstacleOutcome) -> Vec<(f64, f64)> {
    o.polygons
        .iter()
        .flat_map(|p| p.vertices().iter().map(|v| (v.x, v.y)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::spec::FleetScenario;
    use std::path::PathBuf;

    /// A folder per test: tests run in parallel and each writes the files.
    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("fleet-obstacles-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("temp dir");
        std::fs::write(d.join("m.moos"), "Community = x\n").expect("write");
        std::fs::write(
            d.join("good.txt"),
            "// rocks\nregion = pts={0,-60:0,60:200,60:200,-60}\nmin_range = 2\n\
             poly = pts={60,-12:60,6:80,6:80,-12},label=ob_0\n",
        )
        .expect("write");
        std::fs::write(
            d.join("bad.txt"),
            "poly = pts={60,-12:60,6:80,6:80,-12},label=ob_0\n\
             poly = pts={0,0:10,0:5,1:10,10:0,10},label=dent\nmin_range = far\n",
        )
        .expect("write");
        d
    }

    const V: &str = "[[vehicle]]\nname = \"abe\"\nmission = \"m.moos\"\n";

    fn parse(tag: &str, t: &str) -> Result<FleetScenario, crate::scenario::ScenarioError> {
        FleetScenario::parse(t, &dir(tag).join("scenario.toml"))
    }

    #[test]
    fn obstacles_from_the_file_and_the_scenario_with_their_blocks() {
        let s = parse("good", &format!(
            "obstacle_file = \"good.txt\"\n{V}[[obstacle]]\npoly = \"pts={{100,0:110,0:110,10:100,10}}\"\n\
             [[obstacle]]\npoly = \"pts={{120,0:130,0:130,10}},label=pier\"\n\
             [obstacle_sim]\napptick = 2\nmin_duration = 400\nmax_duration = 500\n\
             [obstacle_collision]\nencounter_dist = 14\n"
        ))
        .expect("parses");
        let o = s.obstacles.expect("obstacles");
        let labels: Vec<&str> = o
            .file
            .obstacles
            .iter()
            .map(|p| p.attrs.label.as_str())
            .collect();
        // An unlabelled [[obstacle]] is named by its place in the list.
        assert_eq!(labels, ["ob_0", "ob_1", "pier"]);
        assert!(o.file.region.is_some());
        assert_eq!((o.sim_tick, o.sim.max_duration), (2.0, 500.0));
        assert_eq!(o.collision.encounter_dist, 14.0);
        assert_eq!(
            o.collision.collision_dist, 1.0,
            "uFldCollObDetect's default"
        );
        // No obstacle entries: none, and the fleet is as before.
        assert!(parse("good", V).expect("parses").obstacles.is_none());
    }

    #[test]
    fn bad_obstacle_lines_are_refused_with_their_line() {
        let cases = [
            // Not convex (a dent at 5,1): the [[obstacle]]'s line.
            (
                format!("{V}\n[[obstacle]]\npoly = \"pts={{0,0:10,0:5,1:10,10:0,10}}\"\n"),
                6,
                "not a convex polygon",
            ),
            (format!("{V}[[obstacle]]\npoly = \"rock\"\n"), 5, "not a convex polygon"),
            (format!("{V}[[obstacle]]\npolygon = \"x\"\n"), 5, "unknown field"),
            (
                format!(
                    "{V}[[obstacle]]\npoly = \"pts={{0,0:9,0:9,9}},label=a\"\n\
                     [[obstacle]]\npoly = \"pts={{20,0:29,0:29,9}},label=a\"\n"
                ),
                5,
                "two obstacles labelled `a`",
            ),
            (
                format!("obstacle_file = \"nope.txt\"\n{V}"),
                1,
                "obstacle file `nope.txt`",
            ),
            (
                format!("{V}[[obstacle]]\npoly = \"pts={{0,0:9,0:9,9}}\"\n[obstacle_sim]\nrefresh_intervall = 5\n"),
                7,
                "[obstacle_sim]",
            ),
            (
                format!("{V}[[obstacle]]\npoly = \"pts={{0,0:9,0:9,9}}\"\n[obstacle_sim]\napptick = 0\n"),
                7,
                "apptick",
            ),
            (
                format!("{V}[[obstacle]]\npoly = \"pts={{0,0:9,0:9,9}}\"\n[obstacle_collision]\nnear_miss_dist = -1\n"),
                7,
                "[obstacle_collision]",
            ),
            (
                format!("{V}[obstacle_collision]\nnear_miss_dist = 3\n"),
                5,
                "without obstacles",
            ),
        ];
        for (text, line, has) in cases {
            let e = parse("bad", &text).expect_err(&text).to_string();
            assert!(
                e.contains(&format!("scenario.toml:{line}: ")),
                "{text:?} -> {e}"
            );
            assert!(e.contains(has), "{text:?} -> {e}");
        }
        // The obstacle file's bad lines, each as file:line.
        let e = parse("bad", &format!("obstacle_file = \"bad.txt\"\n{V}"))
            .expect_err("bad file")
            .to_string();
        assert!(e.contains("scenario.toml:1: bad obstacle file"), "{e}");
        assert!(e.contains("bad.txt:2: Poorly specified obstacle"), "{e}");
        assert!(
            e.contains("bad.txt:3: Poorly specified min_range: far"),
            "{e}"
        );
    }
}
