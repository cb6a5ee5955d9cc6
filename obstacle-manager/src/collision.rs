//! uFldCollObDetect's counting (obstacles.md §4), for a simulator: per vehicle and
//! obstacle the closest approach of each encounter; encounters, near misses and
//! collisions counted when an encounter ends, with the configured flags.

use std::collections::BTreeMap;

use contact_manager::{Posting, Value};
use geometry::{fmt_x, parse_polygon, Polygon};

/// A refused configuration line or `KNOWN_OBSTACLE`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CollisionError {
    #[error("unknown parameter: {0}")]
    Unknown(String),
    #[error("{param}: not a number {rule}: {value}")]
    BadNumber {
        param: String,
        value: String,
        rule: &'static str,
    },
    #[error("flag is not VAR=VALUE: {0}")]
    BadFlag(String),
    #[error("not a convex polygon: {0}")]
    BadObstacle(String),
}

/// The configuration; defaults are uFldCollObDetect's.
#[derive(Clone, Debug, PartialEq)]
pub struct CollisionConfig {
    pub collision_dist: f64,
    pub near_miss_dist: f64,
    pub encounter_dist: f64,
    pub collision_flags: Vec<(String, String)>,
    pub near_miss_flags: Vec<(String, String)>,
    pub encounter_flags: Vec<(String, String)>,
    /// The appcast histogram (not computed here).
    pub bin_min_val: f64,
    pub bin_delta: f64,
}

impl Default for CollisionConfig {
    fn default() -> Self {
        CollisionConfig {
            collision_dist: 1.0,
            near_miss_dist: 5.0,
            encounter_dist: 15.0,
            collision_flags: Vec::new(),
            near_miss_flags: Vec::new(),
            encounter_flags: Vec::new(),
            bin_min_val: -1.0,
            bin_delta: -1.0,
        }
    }
}

impl CollisionConfig {
    /// Apply one block line (names in any case).
    pub fn set(&mut self, param: &str, value: &str) -> Result<(), CollisionError> {
        let p = param.trim().to_ascii_lowercase();
        let v = value.trim();
        let num = |positive: bool| {
            mbutil::parse_number(v)
                .filter(|n| n.is_finite() && (*n > 0.0 || (!positive && *n == 0.0)))
                .ok_or_else(|| CollisionError::BadNumber {
                    param: p.clone(),
                    value: v.into(),
                    rule: if positive { "> 0" } else { ">= 0" },
                })
        };
        let flag = || {
            let (var, val) = v
                .split_once('=')
                .filter(|(var, _)| !var.trim().is_empty())
                .ok_or_else(|| CollisionError::BadFlag(v.into()))?;
            Ok::<_, CollisionError>((var.trim().to_string(), val.trim().to_string()))
        };
        match p.as_str() {
            "collision_dist" => self.collision_dist = num(false)?,
            "near_miss_dist" => self.near_miss_dist = num(false)?,
            "encounter_dist" => self.encounter_dist = num(false)?,
            "bin_min_val" => self.bin_min_val = num(false)?,
            "bin_delta" => self.bin_delta = num(true)?,
            "collision_flag" => self.collision_flags.push(flag()?),
            "near_miss_flag" => self.near_miss_flags.push(flag()?),
            "encounter_flag" => self.encounter_flags.push(flag()?),
            _ => return Err(CollisionError::Unknown(p)),
        }
        Ok(())
    }

    /// The reference's adjustments after reading, with their warnings.
    pub fn finish(&mut self) -> Vec<String> {
        let mut w = Vec::new();
        if self.collision_dist > self.near_miss_dist {
            self.near_miss_dist = self.collision_dist;
            w.push("near_miss_dist cannot be < collision_dist".to_string());
        }
        if self.near_miss_dist > self.encounter_dist {
            self.encounter_dist = self.near_miss_dist;
            w.push("encounter_dist cannot be < near_miss_dist".to_string());
        }
        w
    }
}

/// One vehicle-obstacle pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairStats {
    prev: f64,
    /// Distance at the last step (0 inside), −1 before the first.
    pub dist: f64,
    /// Closest approach of the encounter under way (−1 when none).
    pub encounter_min: f64,
    /// Closest approach ever.
    pub closest: f64,
    pub encounters: u32,
    pub near_misses: u32,
    pub collisions: u32,
}

impl PairStats {
    fn new() -> PairStats {
        PairStats {
            prev: -1.0,
            dist: -1.0,
            encounter_min: -1.0,
            closest: f64::INFINITY,
            encounters: 0,
            near_misses: 0,
            collisions: 0,
        }
    }
}

/// uFldCollObDetect's state: the known obstacles and the pair table.
#[derive(Clone, Debug)]
pub struct CollisionDetector {
    cfg: CollisionConfig,
    /// label → (polygon, arrival time).
    obstacles: BTreeMap<String, (Polygon, f64)>,
    /// vehicle → obstacle label → stats (nested, so a step looks pairs up without
    /// building keys).
    pairs: BTreeMap<String, BTreeMap<String, PairStats>>,
    global_min: Option<f64>,
    encounters: u32,
    near_misses: u32,
    collisions: u32,
    postings: Vec<Posting>,
}

impl CollisionDetector {
    pub fn new(cfg: CollisionConfig) -> CollisionDetector {
        CollisionDetector {
            cfg,
            obstacles: BTreeMap::new(),
            pairs: BTreeMap::new(),
            global_min: None,
            encounters: 0,
            near_misses: 0,
            collisions: 0,
            postings: Vec::new(),
        }
    }

    /// `KNOWN_OBSTACLE`: a convex polygon stored by label (the same label replaces).
    pub fn known_obstacle(&mut self, spec: &str, now: f64) -> Result<(), CollisionError> {
        let p = parse_polygon(spec)
            .filter(Polygon::is_convex)
            .ok_or_else(|| CollisionError::BadObstacle(spec.into()))?;
        self.obstacles.insert(p.attrs.label.clone(), (p, now));
        Ok(())
    }

    /// `KNOWN_OBSTACLE_CLEAR`: `all` or a label; only obstacles older than 4 s go.
    pub fn clear(&mut self, what: &str, now: f64) {
        let what = what.trim();
        self.obstacles
            .retain(|label, (_, t)| !((what == "all" || what == label) && now - *t > 4.0));
    }

    pub fn encounters(&self) -> u32 {
        self.encounters
    }
    pub fn near_misses(&self) -> u32 {
        self.near_misses
    }
    pub fn collisions(&self) -> u32 {
        self.collisions
    }
    /// The smallest vehicle-obstacle distance seen (`OB_GLOBAL_MIN`).
    pub fn global_min(&self) -> Option<f64> {
        self.global_min
    }
    /// ((vehicle, obstacle label), stats), sorted.
    pub fn pairs(&self) -> impl Iterator<Item = ((&str, &str), &PairStats)> {
        self.pairs.iter().flat_map(|(v, m)| {
            m.iter()
                .map(move |(label, s)| ((v.as_str(), label.as_str()), s))
        })
    }
    pub fn obstacles(&self) -> impl Iterator<Item = (&str, &Polygon)> {
        self.obstacles.iter().map(|(k, (p, _))| (k.as_str(), p))
    }

    /// One iteration at `now` with the vehicles' positions `(name, x, y)`; returns the
    /// postings (`OB_GLOBAL_MIN` and the flags).
    pub fn step(&mut self, _now: f64, vehicles: &[(&str, f64, f64)]) -> &[Posting] {
        self.postings.clear();
        for &(vname, x, y) in vehicles {
            if !(x.is_finite() && y.is_finite()) {
                continue;
            }
            for (label, (poly, _)) in &self.obstacles {
                let d = if poly.contains(x, y) {
                    0.0
                } else {
                    poly.dist_to_poly(x, y)
                };
                if self.global_min.is_none_or(|m| d < m) {
                    self.global_min = Some(d);
                    self.postings.push(Posting::num("OB_GLOBAL_MIN", d));
                }
                if !self.pairs.contains_key(vname) {
                    self.pairs.insert(vname.to_string(), BTreeMap::new());
                }
                let Some(per_vehicle) = self.pairs.get_mut(vname) else {
                    continue;
                };
                if !per_vehicle.contains_key(label) {
                    per_vehicle.insert(label.clone(), PairStats::new());
                }
                let Some(s) = per_vehicle.get_mut(label) else {
                    continue;
                };
                s.prev = s.dist;
                s.dist = d;
                s.closest = s.closest.min(d);
                if s.encounter_min < 0.0 || d < s.encounter_min {
                    s.encounter_min = d;
                }
                let enc = self.cfg.encounter_dist;
                if !(s.prev > 0.0 && s.prev <= enc && d > enc) {
                    continue;
                }
                let cpa = s.encounter_min;
                let flags = if cpa < self.cfg.collision_dist {
                    self.collisions += 1;
                    s.collisions += 1;
                    Some(&self.cfg.collision_flags)
                } else if cpa < self.cfg.near_miss_dist {
                    self.near_misses += 1;
                    s.near_misses += 1;
                    Some(&self.cfg.near_miss_flags)
                } else {
                    None
                };
                let counts = (self.encounters, self.collisions, self.near_misses);
                if let Some(f) = flags {
                    post_flags(&mut self.postings, f, vname, label, cpa, counts);
                }
                self.encounters += 1;
                s.encounters += 1;
                let counts = (self.encounters, self.collisions, self.near_misses);
                post_flags(
                    &mut self.postings,
                    &self.cfg.encounter_flags,
                    vname,
                    label,
                    cpa,
                    counts,
                );
                s.encounter_min = -1.0;
            }
        }
        &self.postings
    }
}

/// The flags with `$VNAME`, `$UP_VNAME`, `$ID`, `$DIST`, `$ENC_CNT`, `$COLL_CNT`,
/// `$MISS_CNT` (counts = (encounters, collisions, near misses)).
fn post_flags(
    out: &mut Vec<Posting>,
    flags: &[(String, String)],
    vname: &str,
    id: &str,
    dist: f64,
    (enc, coll, miss): (u32, u32, u32),
) {
    let up = vname.to_ascii_uppercase();
    for (var, val) in flags {
        let var = var
            .replace("$UP_VNAME", &up)
            .replace("$VNAME", vname)
            .replace("$ID", id);
        let v = match val.as_str() {
            "$DIST" => Value::Num(dist),
            "$ENC_CNT" => Value::Num(f64::from(enc)),
            "$COLL_CNT" => Value::Num(f64::from(coll)),
            "$MISS_CNT" => Value::Num(f64::from(miss)),
            s => match mbutil::parse_number(s) {
                Some(n) => Value::Num(n),
                None => Value::Str(
                    s.replace("$UP_VNAME", &up)
                        .replace("$VNAME", vname)
                        .replace("$DIST", &fmt_x(dist, 2))
                        .replace("$ID", id)
                        .replace("$ENC_CNT", &enc.to_string())
                        .replace("$COLL_CNT", &coll.to_string())
                        .replace("$MISS_CNT", &miss.to_string()),
                ),
            },
        };
        out.push(Posting { var, val: v });
    }
}

#[cfg(test)]
#[path = "collision_tests.rs"]
mod tests;
