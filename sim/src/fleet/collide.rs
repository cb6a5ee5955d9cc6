//! Collision statistics as uFldCollisionDetect keeps them: for every pair of vehicles
//! the closest approach and its time, and events. An event starts when the pair comes
//! within the encounter range and ends when it leaves it (or the run ends); each event
//! is an encounter, and also a near miss when its closest approach was under the near
//! miss range, or a collision when under the collision range (a collision is not also
//! counted as a near miss).

use super::spec::Ranges;

/// One pair of vehicles over the run. Fields are added as the simulator learns more
/// about encounters (e.g. the geometry at the first alert).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PairRecord {
    pub a: String,
    pub b: String,
    /// Closest distance of the two over the run (m).
    pub closest_m: f64,
    /// When (s from the start).
    pub closest_time_s: f64,
    /// Where each was then (for the picture).
    pub closest_a: (f64, f64),
    pub closest_b: (f64, f64),
    pub encounters: u32,
    pub near_misses: u32,
    pub collisions: u32,
    #[serde(skip)]
    event_min: Option<f64>,
}

impl PairRecord {
    fn close_event(&mut self, r: &Ranges) {
        if let Some(m) = self.event_min.take() {
            self.encounters += 1;
            if m < r.collision {
                self.collisions += 1;
            } else if m < r.near_miss {
                self.near_misses += 1;
            }
        }
    }
}

/// The distance between every two vehicles (the `hypot` of their offset), worked out
/// once a step for the detector, the COLREGS tracker and the comms model. `hypot`
/// ignores the signs of the offset, so (i, j) and (j, i) are the same number.
#[derive(Debug, Default)]
pub struct Distances {
    n: usize,
    d: Vec<f64>,
}

impl Distances {
    pub fn of(pos: &[(f64, f64)]) -> Distances {
        let mut d = Distances::default();
        d.update(pos);
        d
    }

    pub fn update(&mut self, pos: &[(f64, f64)]) {
        let n = pos.len();
        self.n = n;
        self.d.clear();
        self.d.resize(n * n, 0.0);
        for i in 0..n {
            for j in i + 1..n {
                let d = (pos[i].0 - pos[j].0).hypot(pos[i].1 - pos[j].1);
                self.d[i * n + j] = d;
                self.d[j * n + i] = d;
            }
        }
    }

    /// From vehicle `i` to each vehicle (0 to itself).
    pub fn row(&self, i: usize) -> &[f64] {
        &self.d[i * self.n..(i + 1) * self.n]
    }

    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.d[i * self.n + j]
    }
}

/// Watches every pair.
pub struct Detector {
    pub ranges: Ranges,
    /// Pairs (i, j), i < j, in order (0,1), (0,2), ..., (1,2), ...
    pub pairs: Vec<PairRecord>,
}

impl Detector {
    pub fn new(names: &[String], ranges: Ranges) -> Detector {
        let mut pairs = Vec::new();
        for i in 0..names.len() {
            for j in i + 1..names.len() {
                pairs.push(PairRecord {
                    a: names[i].clone(),
                    b: names[j].clone(),
                    closest_m: f64::INFINITY,
                    closest_time_s: 0.0,
                    closest_a: (0.0, 0.0),
                    closest_b: (0.0, 0.0),
                    encounters: 0,
                    near_misses: 0,
                    collisions: 0,
                    event_min: None,
                });
            }
        }
        Detector { ranges, pairs }
    }

    /// The vehicles are at `pos` at `t` (s from the start), `dist` apart.
    pub fn update(&mut self, t: f64, pos: &[(f64, f64)], dist: &Distances) {
        let mut k = 0;
        for i in 0..pos.len() {
            for j in i + 1..pos.len() {
                let p = &mut self.pairs[k];
                k += 1;
                let d = dist.get(i, j);
                if d < p.closest_m {
                    p.closest_m = d;
                    p.closest_time_s = t;
                    p.closest_a = pos[i];
                    p.closest_b = pos[j];
                }
                if d <= self.ranges.encounter {
                    p.event_min = Some(p.event_min.map_or(d, |m| m.min(d)));
                } else {
                    p.close_event(&self.ranges);
                }
            }
        }
    }

    /// The run ended: events still open are counted.
    pub fn finish(&mut self) {
        let r = self.ranges;
        for p in &mut self.pairs {
            p.close_event(&r);
        }
    }

    /// (encounters, near misses, collisions) over all pairs.
    pub fn totals(pairs: &[PairRecord]) -> (u32, u32, u32) {
        pairs.iter().fold((0, 0, 0), |(e, n, c), p| {
            (e + p.encounters, n + p.near_misses, c + p.collisions)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_are_counted_once_each_by_their_closest_approach() {
        let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
        let mut d = Detector::new(&names, Ranges::default());
        // b passes a at 5 m (near miss), leaves, comes back to 2 m (collision); c stays far.
        let path = [30.0, 15.0, 5.0, 12.0, 40.0, 10.0, 2.0, 8.0];
        for (k, dist) in path.iter().enumerate() {
            let pos = [(0.0, 0.0), (*dist, 0.0), (0.0, 500.0)];
            d.update(k as f64, &pos, &Distances::of(&pos));
        }
        d.finish();
        let ab = &d.pairs[0];
        assert_eq!((ab.encounters, ab.near_misses, ab.collisions), (2, 1, 1));
        assert_eq!((ab.closest_m, ab.closest_time_s), (2.0, 6.0));
        assert_eq!(d.pairs[1].encounters, 0);
        assert_eq!((d.pairs[1].a.as_str(), d.pairs[2].a.as_str()), ("a", "b"));
        assert_eq!(Detector::totals(&d.pairs), (2, 1, 1));
    }
}
