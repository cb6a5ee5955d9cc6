//! LegRun's simplified waypoint engine (behaviors-more.md §9.3), one for the leg and one
//! for the turn path: capture radius, slip radius, capture line, lead point.

use behavior_api::geometry::{
    angle_from_three_points, dist, perp_seg_int_pt, project_point, rel_ang,
};

pub type Pt = (f64, f64);

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EngineState {
    Transit,
    Advanced,
    Cycled,
    Completed,
    Empty,
}

#[derive(Clone, Debug)]
pub struct WptEngine {
    pub pts: Vec<Pt>,
    pub ix: usize,
    pub state: EngineState,
    pub cpa: f64,
    pub prev: Option<Pt>,
    pub repeats: u64,
    /// Negative: endless.
    pub max_repeats: i64,
    pub capture_radius: f64,
    pub slip_radius: f64,
    pub capture_line: bool,
    pub lead: f64,
    pub lead_damper: f64,
    pub hits: u64,
    pub track: Pt,
}

impl Default for WptEngine {
    fn default() -> Self {
        WptEngine {
            pts: Vec::new(),
            ix: 0,
            state: EngineState::Transit,
            cpa: -1.0,
            prev: None,
            repeats: 0,
            max_repeats: 0,
            capture_radius: 3.0,
            slip_radius: 15.0,
            capture_line: false,
            lead: 0.0,
            lead_damper: 0.0,
            hits: 0,
            track: (0.0, 0.0),
        }
    }
}

impl WptEngine {
    pub fn set_seglist(&mut self, pts: Vec<Pt>, retain: bool) {
        self.pts = pts;
        self.state = EngineState::Transit;
        self.cpa = -1.0;
        self.repeats = 0;
        if retain && !self.pts.is_empty() {
            if self.ix >= self.pts.len() {
                self.ix = 0;
            }
            let p = if self.ix == 0 {
                self.pts.len() - 1
            } else {
                self.ix - 1
            };
            self.prev = Some(self.pts[p]);
        } else {
            self.ix = 0;
        }
    }

    pub fn set_curr_index(&mut self, i: usize) {
        if i < self.pts.len() {
            self.ix = i;
            self.cpa = -1.0;
        }
    }

    pub fn reset_state(&mut self) {
        self.pts.clear();
        self.prev = None;
        self.ix = 0;
        self.state = EngineState::Transit;
        self.cpa = -1.0;
        self.hits = 0;
        self.repeats = 0;
    }

    pub fn reset_for_new_traversal(&mut self) {
        self.ix = 0;
        self.state = EngineState::Transit;
        self.cpa = -1.0;
        self.prev = None;
        self.repeats = 0;
    }

    pub fn advanced(&self) -> bool {
        matches!(
            self.state,
            EngineState::Advanced | EngineState::Cycled | EngineState::Completed
        )
    }

    pub fn completed(&self) -> bool {
        self.state == EngineState::Completed
    }

    pub fn current(&self) -> Option<Pt> {
        self.pts.get(self.ix).copied()
    }

    pub fn step(&mut self, os: Pt) {
        if self.prev.is_none() {
            self.prev = Some(os);
        }
        if self.pts.is_empty() {
            self.state = EngineState::Empty;
            return;
        }
        if self.state == EngineState::Completed {
            return;
        }
        let c = self.pts[self.ix];
        let d = dist(os.0, os.1, c.0, c.1);
        if self.cpa == -1.0 || d < self.cpa {
            self.cpa = d;
        }
        let advance = d < self.capture_radius
            || (self.slip_radius > self.capture_radius
                && d > self.cpa
                && self.cpa <= self.slip_radius)
            || (self.capture_line
                && self.prev.is_some_and(|p| {
                    angle_from_three_points(c.0, c.1, p.0, p.1, os.0, os.1) >= 90.0
                }));
        if advance {
            self.hits += 1;
            self.ix += 1;
            self.prev = Some(self.pts[self.ix - 1]);
            if self.ix >= self.pts.len() {
                self.ix = 0;
                self.cpa = -1.0;
                self.repeats += 1;
                if self.max_repeats >= 0 && self.repeats as i64 > self.max_repeats {
                    self.prev = None;
                    self.state = EngineState::Completed;
                } else {
                    self.state = EngineState::Cycled;
                }
            } else {
                let n = self.pts[self.ix];
                self.cpa = dist(os.0, os.1, n.0, n.1);
                self.state = EngineState::Advanced;
            }
        } else {
            self.state = EngineState::Transit;
        }
        let c = self.pts[self.ix];
        self.track = c;
        if self.completed() {
            return;
        }
        if let (true, Some(p)) = (self.lead > 0.0 && self.lead_damper > 0.0, self.prev) {
            let n = perp_seg_int_pt(p.0, p.1, c.0, c.1, os.0, os.1);
            let dn = dist(n.0, n.1, os.0, os.1);
            let mut f = 1.0;
            if dn < self.lead_damper {
                f += 2.0 * (1.0 - dn / self.lead_damper);
            }
            if dist(n.0, n.1, c.0, c.1) > self.lead * f {
                self.track = project_point(rel_ang(p.0, p.1, c.0, c.1), self.lead * f, n.0, n.1);
            }
        }
    }

    fn length_from(&self, i: usize) -> f64 {
        self.pts
            .windows(2)
            .skip(i)
            .map(|w| dist(w[0].0, w[0].1, w[1].0, w[1].1))
            .sum()
    }

    /// Fraction of the path left behind (0 when the path has no length).
    pub fn pct_to_end(&self, os: Pt) -> f64 {
        let len = self.length_from(0);
        let Some(c) = self.current() else { return 0.0 };
        if len <= 0.0 {
            return 0.0;
        }
        let rest = dist(os.0, os.1, c.0, c.1) + self.length_from(self.ix);
        (len - rest).max(0.0) / len
    }

    /// Progress from the previous vertex to the next one (-1 when undefined).
    pub fn pct_to_next(&self, os: Pt) -> f64 {
        let Some(c) = self.current() else { return -1.0 };
        let p = self.pts[if self.ix == 0 {
            self.pts.len() - 1
        } else {
            self.ix - 1
        }];
        let dn = dist(os.0, os.1, c.0, c.1);
        let dp = dist(os.0, os.1, p.0, p.1);
        if dn + dp <= 0.0 {
            return -1.0;
        }
        dp / (dn + dp)
    }

    pub fn dist_to_next(&self, os: Pt) -> f64 {
        self.current().map_or(-1.0, |c| dist(os.0, os.1, c.0, c.1))
    }

    pub fn dist_to_prev(&self, os: Pt) -> f64 {
        self.prev.map_or(-1.0, |p| dist(os.0, os.1, p.0, p.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capture_advance_cycle_and_complete() {
        let mut e = WptEngine::default();
        e.set_seglist(vec![(0.0, 10.0), (0.0, 20.0)], false);
        e.step((0.0, 0.0));
        assert_eq!((e.state, e.track), (EngineState::Transit, (0.0, 10.0)));
        e.step((0.0, 8.0));
        assert_eq!((e.state, e.ix), (EngineState::Advanced, 1));
        e.step((0.0, 18.0));
        assert_eq!((e.state, e.ix, e.repeats), (EngineState::Completed, 0, 1));
        e.step((0.0, 18.0));
        assert!(e.completed());
        e.reset_for_new_traversal();
        e.max_repeats = 1;
        e.step((0.0, 8.0));
        e.step((0.0, 18.0));
        assert_eq!(e.state, EngineState::Cycled);
    }

    #[test]
    fn slip_and_lead() {
        let mut e = WptEngine {
            lead: 5.0,
            lead_damper: 1.0,
            ..WptEngine::default()
        };
        e.set_seglist(vec![(0.0, 0.0), (0.0, 100.0)], true);
        assert_eq!(e.prev, Some((0.0, 100.0)));
        // Heading to (0,0) from the far end: the track point leads 5 m (tripled on the line).
        e.step((0.0, 50.0));
        assert_eq!(e.track, (0.0, 35.0));
        e.step((3.0, 50.0));
        assert_eq!(e.track, (0.0, 45.0));
        assert!((e.pct_to_next((0.0, 50.0)) - 0.5).abs() < 1e-12);
        // Slip: closest approach 10 m, then moving away.
        let mut s = WptEngine::default();
        s.set_seglist(vec![(10.0, 0.0), (50.0, 0.0)], false);
        s.step((0.0, 0.0));
        s.step((0.0, 1.0));
        assert_eq!((s.state, s.ix), (EngineState::Advanced, 1));
    }
}
