//! uFldObstacleSim for simulators (obstacles.md §3): its obstacle file (§3.2), its
//! configuration (§3.1) and what it publishes (§3.5: the obstacles as `VIEW_POLYGON`,
//! `KNOWN_OBSTACLE` and `GIVEN_OBSTACLE`, at the first report of each vehicle, on
//! `PMV_CONNECT` and every `refresh_interval`). Field resets and point (sensor) mode
//! are random in the reference: point mode draws from the simulator's random numbers;
//! field resets are not modelled (their parameters are accepted).
//!
//! How a simulator drives it with the obstacle manager (one per vehicle) and the
//! collision counter (shoreside), step by step:
//!
//! ```
//! use obstacle_manager::{CollisionConfig, CollisionDetector, Config, MailValue,
//!     ObstacleFile, ObstacleManager, ObstacleSim, SimConfig, SimVehicle};
//! let text = "region = pts={0,-60:0,60:200,60:200,-60}\nmin_range = 2\nmin_size = 6\n\
//!             max_size = 10\npoly = pts={60,-12:60,6:80,6:80,-12},label=ob_0\n";
//! let file = ObstacleFile::parse(text, "obstacles.txt").unwrap();
//! let mut cfg = SimConfig::default();
//! cfg.set("min_duration", "400").unwrap();
//! cfg.set("max_duration", "500").unwrap();
//! let rng = 0.5; // the simulator's random numbers in [0, 1)
//! let mut sim = ObstacleSim::new(cfg, file, || rng);
//! let mut mgr_cfg = Config::default();
//! mgr_cfg.set("given_max_duration", "1000").unwrap();
//! let mut mgr = ObstacleManager::new(mgr_cfg, 0.0);
//! let mut det = CollisionDetector::new(CollisionConfig::default());
//! let mut alerts = Vec::new();
//! for k in 0..100 {
//!     let now = k as f64;
//!     let (x, y) = (k as f64 * 1.0, 0.0); // the vehicle's position this step
//!     let mut mail = vec![("NAV_X", MailValue::Num(x)), ("NAV_Y", MailValue::Num(y))];
//!     if k == 0 {
//!         mail.push(("OBM_ALERT_REQUEST",
//!             MailValue::Str("name=avd_ob_,update_var=OBSTACLE_ALERT,alert_range=15")));
//!     }
//!     // The shoreside sees each vehicle's latest report.
//!     let seen = [SimVehicle { name: "alpha", x, y, color: None }];
//!     let shore = sim.step(now, &seen, &mut || rng).to_vec();
//!     for p in &shore {
//!         let v = p.val.as_str().unwrap_or_default();
//!         match p.var.as_str() {
//!             // Bridged to the vehicle (uFldShoreBroker `bridge = src=GIVEN_OBSTACLE`).
//!             "GIVEN_OBSTACLE" => mail.push(("GIVEN_OBSTACLE", MailValue::Str(v))),
//!             "KNOWN_OBSTACLE" => det.known_obstacle(v, now).unwrap(),
//!             _ => {}
//!         }
//!     }
//!     mgr.handle_mail(now, &mail);
//!     alerts.extend(mgr.iterate(now).iter().filter(|p| p.var == "OBSTACLE_ALERT").cloned());
//!     det.step(now, &[("alpha", x, y)]);
//! }
//! assert_eq!(alerts.len(), 1, "one alert when ob_0 came within 15 m");
//! // alpha drove through ob_0: one encounter, and it was a collision.
//! assert_eq!((det.encounters(), det.collisions()), (1, 1));
//! ```

use std::fmt::Write as _;
use std::path::Path;

use contact_manager::Posting;
use geometry::{fmt_x, pts_spec, Polygon};

mod config;
mod file;
pub mod sensor;

pub use config::{SimConfig, SimConfigError};
pub use file::{LineError, ObstacleFile, ObstacleFileError};

/// A vehicle as the simulator sees it this step (its latest NODE_REPORT).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimVehicle<'a> {
    pub name: &'a str,
    pub x: f64,
    pub y: f64,
    /// The report's `COLOR` field, if any (the colour of its sensor points).
    pub color: Option<&'a str>,
}

/// One simulated obstacle: its styled polygon and its duration (< 0: none).
#[derive(Clone, Debug, PartialEq)]
pub struct SimObstacle {
    pub poly: Polygon,
    pub duration: f64,
}

impl SimObstacle {
    /// `<pts, 2 decimals>,label=<l>[,vsource=<v>][,duration=<d>]` — what
    /// `KNOWN_OBSTACLE` and `GIVEN_OBSTACLE` carry.
    pub fn given_spec(&self) -> String {
        let a = &self.poly.attrs;
        let mut s = pts_spec(self.poly.vertices(), 2);
        let _ = write!(s, ",label={}", a.label);
        if !a.vsource.is_empty() {
            let _ = write!(s, ",vsource={}", a.vsource);
        }
        if self.duration >= 0.0 {
            let _ = write!(s, ",duration={}", fmt_x(self.duration, 5));
        }
        s
    }
}

/// uFldObstacleSim's publishing side.
#[derive(Clone, Debug)]
pub struct ObstacleSim {
    cfg: SimConfig,
    file: ObstacleFile,
    obstacles: Vec<SimObstacle>,
    region: Option<Polygon>,
    vehicles: Vec<String>,
    refresh_needed: bool,
    last_refresh: Option<f64>,
    refreshes: u64,
    /// Sensor points published per obstacle label (all vehicles together).
    point_counts: std::collections::HashMap<String, u64>,
    postings: Vec<Posting>,
    handed_out: bool,
}

impl ObstacleSim {
    /// The simulator with `file`'s obstacles, styled by `cfg`; with
    /// `max_duration > 0` each obstacle draws a duration uniform in
    /// [max(min_duration, 0), max_duration] from `rand01` (values in [0, 1)).
    pub fn new(cfg: SimConfig, file: ObstacleFile, mut rand01: impl FnMut() -> f64) -> ObstacleSim {
        let mut obstacles: Vec<SimObstacle> = file
            .obstacles
            .iter()
            .map(|p| SimObstacle {
                poly: cfg.style_obstacle(p),
                duration: -1.0,
            })
            .collect();
        if cfg.max_duration > 0.0 {
            let lo = cfg.min_duration.max(0.0);
            for o in &mut obstacles {
                o.duration = lo + rand01().clamp(0.0, 1.0) * (cfg.max_duration - lo);
            }
        }
        let region = file.region.as_ref().map(|r| cfg.style_region(r));
        let mut postings = vec![Posting::str(
            "PLOGGER_CMD",
            format!("COPY_FILE_REQUEST = {}", file.path),
        )];
        if let Some(r) = file.min_range {
            postings.push(Posting::num("UFOS_MIN_RNG", r));
        }
        ObstacleSim {
            cfg,
            file,
            obstacles,
            region,
            vehicles: Vec::new(),
            refresh_needed: false,
            last_refresh: None,
            refreshes: 0,
            point_counts: std::collections::HashMap::new(),
            postings,
            handed_out: false,
        }
    }

    pub fn obstacles(&self) -> &[SimObstacle] {
        &self.obstacles
    }
    pub fn region(&self) -> Option<&Polygon> {
        self.region.as_ref()
    }
    pub fn file(&self) -> &ObstacleFile {
        &self.file
    }
    pub fn refreshes(&self) -> u64 {
        self.refreshes
    }

    /// A `NODE_REPORT` of `vname` arrived: the first one of each vehicle asks for a
    /// refresh.
    pub fn node_report(&mut self, vname: &str) {
        if !self.vehicles.iter().any(|v| v == vname) {
            self.vehicles.push(vname.to_string());
            self.refresh_needed = true;
        }
    }

    /// `PMV_CONNECT` arrived (a viewer connected): refresh.
    pub fn pmv_connect(&mut self) {
        self.refresh_needed = true;
    }

    /// One iteration at `now` (§3.4 steps 3 to 5) with the vehicles' latest reports
    /// (a vehicle seen for the first time asks for a refresh, as its first NODE_REPORT
    /// does): the postings since the last step. The first refresh with
    /// `refresh_interval > 0` comes at the first step (the reference's last-refresh
    /// time starts at 0). In point mode `rand01` draws the sensor points.
    pub fn step(
        &mut self,
        now: f64,
        vehicles: &[SimVehicle<'_>],
        rand01: &mut dyn FnMut() -> f64,
    ) -> &[Posting] {
        if self.handed_out {
            self.postings.clear();
            self.handed_out = false;
        }
        for v in vehicles {
            self.node_report(v.name);
        }
        let ri = self.cfg.refresh_interval;
        if ri > 0.0 && self.last_refresh.is_none_or(|t| now - t > ri) {
            self.refresh_needed = true;
        }
        if self.cfg.post_points {
            self.sensor_points(vehicles, rand01);
        }
        if self.refresh_needed {
            self.refresh(now);
        }
        self.handed_out = true;
        &self.postings
    }

    /// §3.6: `rate_points` boundary points per obstacle within `sensor_range` of each
    /// vehicle, as `TRACKED_FEATURE_<VNAME>` and (with visuals) `VIEW_POINT`.
    fn sensor_points(&mut self, vehicles: &[SimVehicle<'_>], rand01: &mut dyn FnMut() -> f64) {
        for v in vehicles {
            let var = format!("TRACKED_FEATURE_{}", v.name.to_ascii_uppercase());
            for o in &self.obstacles {
                // A NaN distance (a vehicle without a position) is out of range.
                let d = o.poly.dist_to_poly(v.x, v.y);
                if d.is_nan() || d > self.cfg.sensor_range {
                    continue;
                }
                let a = &o.poly.attrs;
                let mut j = 0.0;
                while j < self.cfg.rate_points {
                    j += 1.0;
                    let Some((x, y)) = sensor::sensor_point(&o.poly, v.x, v.y, rand01) else {
                        continue;
                    };
                    let (xs, ys) = (fmt_x(x, 2), fmt_x(y, 2));
                    let mut val = format!("x={xs},y={ys},key={}", a.label);
                    if !a.vsource.is_empty() {
                        let _ = write!(val, ",vsource={}", a.vsource);
                    }
                    self.postings.push(Posting::str(&var, val));
                    let n = self.point_counts.entry(a.label.clone()).or_insert(0);
                    *n += 1;
                    if self.cfg.post_visuals {
                        let mut p = format!(
                            "x={xs},y={ys},label={}:{}:{},label_color=invisible",
                            v.name,
                            a.label,
                            *n % 100
                        );
                        if let Some(c) = v.color {
                            let _ = write!(p, ",vertex_color={c}");
                        }
                        let _ = write!(
                            p,
                            ",duration=10,vertex_size={}",
                            fmt_x(self.cfg.point_size, 1)
                        );
                        self.postings.push(Posting::str("VIEW_POINT", p));
                    }
                }
            }
        }
    }

    fn refresh(&mut self, now: f64) {
        if self.cfg.post_visuals {
            for o in &self.obstacles {
                self.postings
                    .push(Posting::str("VIEW_POLYGON", o.poly.spec(2)));
            }
            if let Some(r) = self.region.as_ref().filter(|_| self.cfg.draw_region) {
                self.postings.push(Posting::str("VIEW_POLYGON", r.spec(1)));
            }
        }
        for o in &self.obstacles {
            let s = o.given_spec();
            if !self.cfg.post_points {
                self.postings
                    .push(Posting::str("GIVEN_OBSTACLE", s.clone()));
            }
            self.postings.push(Posting::str("KNOWN_OBSTACLE", s));
        }
        self.last_refresh = Some(now);
        self.refresh_needed = false;
        self.refreshes += 1;
    }
}

/// Read an obstacle file from disk (at most 16 MB).
pub fn read_file(path: &Path) -> Result<ObstacleFile, ObstacleFileError> {
    file::read(path)
}

#[cfg(test)]
mod tests;
