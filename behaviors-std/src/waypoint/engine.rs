//! The waypoint engine (behaviors-std.md §2.2): traversal of a point list with capture,
//! slip ("non-monotonic") capture, capture line, cycles and repeats.

use geometry::{angle_from_three_points, dist, Vertex};

/// Result of one [`WaypointEngine::advance`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Advance {
    EmptySeglist,
    Completed,
    Cycled,
    Advanced,
    InTransit,
}

/// State of a traversal.
#[derive(Clone, Debug)]
pub struct WaypointEngine {
    /// Points as given (before reversal).
    raw: Vec<Vertex>,
    /// Points in traversal order.
    pts: Vec<Vertex>,
    reverse: bool,
    ix: usize,
    cycles: u32,
    repeats: u32,
    repeats_sofar: u32,
    repeats_endless: bool,
    perpetual: bool,
    complete: bool,
    cpa: f64,
    capture_hits: u32,
    slip_hits: u32,
    capture_radius: f64,
    slip_radius: f64,
    capture_line: bool,
    prev: Option<(f64, f64)>,
    /// Bumped whenever the points change (views built from them are kept until then).
    version: u64,
}

impl Default for WaypointEngine {
    fn default() -> Self {
        WaypointEngine {
            raw: Vec::new(),
            pts: Vec::new(),
            reverse: false,
            ix: 0,
            cycles: 0,
            repeats: 0,
            repeats_sofar: 0,
            repeats_endless: false,
            perpetual: false,
            complete: true,
            cpa: -1.0,
            capture_hits: 0,
            slip_hits: 0,
            capture_radius: 3.0,
            slip_radius: 15.0,
            capture_line: false,
            prev: None,
            version: 0,
        }
    }
}

impl WaypointEngine {
    pub fn new() -> Self {
        Self::default()
    }

    fn rebuild(&mut self) {
        self.version += 1;
        self.pts = self.raw.clone();
        if self.reverse {
            self.pts.reverse();
        }
    }

    /// Load a new point list: index 0, cycle count 0, not complete.
    pub fn set_points(&mut self, pts: Vec<Vertex>) {
        self.raw = pts;
        self.rebuild();
        self.ix = 0;
        self.cycles = 0;
        self.repeats_sofar = 0;
        self.complete = false;
        self.cpa = -1.0;
        self.prev = None;
    }

    /// Replace the points keeping index, cycle count and completion (`xpoints`).
    pub fn replace_points_keep_state(&mut self, pts: Vec<Vertex>) {
        self.raw = pts;
        self.rebuild();
        if self.ix >= self.pts.len() {
            self.ix = 0;
        }
    }

    /// Append a point (ignored when the order is reversed).
    pub fn add_point(&mut self, v: Vertex) {
        if self.reverse {
            return;
        }
        self.raw.push(v);
        self.rebuild();
        self.complete = false;
    }

    /// Traversal order; a change resets the index and clears completion.
    pub fn set_reverse(&mut self, reverse: bool) {
        if reverse == self.reverse {
            return;
        }
        self.reverse = reverse;
        self.rebuild();
        self.ix = 0;
        self.cpa = -1.0;
        self.complete = false;
    }

    pub fn reverse(&self) -> bool {
        self.reverse
    }
    pub fn points(&self) -> &[Vertex] {
        &self.pts
    }
    /// Changes whenever [`WaypointEngine::points`] may have changed.
    pub fn points_version(&self) -> u64 {
        self.version
    }
    pub fn size(&self) -> usize {
        self.pts.len()
    }
    pub fn index(&self) -> usize {
        self.ix
    }
    /// Set the current index (ignored when out of range).
    pub fn set_index(&mut self, ix: usize) {
        if ix < self.pts.len() {
            self.ix = ix;
        }
    }
    pub fn point(&self, i: usize) -> Option<Vertex> {
        self.pts.get(i).copied()
    }
    pub fn current(&self) -> Option<Vertex> {
        self.point(self.ix)
    }
    pub fn cycles(&self) -> u32 {
        self.cycles
    }
    pub fn repeats(&self) -> u32 {
        self.repeats
    }
    pub fn repeats_sofar(&self) -> u32 {
        self.repeats_sofar
    }
    pub fn repeats_endless(&self) -> bool {
        self.repeats_endless
    }
    pub fn set_repeats(&mut self, n: u32) {
        self.repeats = n;
    }
    pub fn set_repeats_endless(&mut self, v: bool) {
        self.repeats_endless = v;
    }
    pub fn set_perpetual(&mut self, v: bool) {
        self.perpetual = v;
    }
    pub fn complete(&self) -> bool {
        self.complete
    }
    pub fn capture_hits(&self) -> u32 {
        self.capture_hits
    }
    pub fn slip_hits(&self) -> u32 {
        self.slip_hits
    }
    pub fn capture_radius(&self) -> f64 {
        self.capture_radius
    }
    pub fn slip_radius(&self) -> f64 {
        self.slip_radius
    }
    pub fn set_capture_radius(&mut self, r: f64) {
        self.capture_radius = r;
    }
    pub fn set_slip_radius(&mut self, r: f64) {
        self.slip_radius = r;
    }
    pub fn capture_line(&self) -> bool {
        self.capture_line
    }
    pub fn set_capture_line(&mut self, v: bool) {
        self.capture_line = v;
    }
    pub fn set_prev_point(&mut self, p: Option<(f64, f64)>) {
        self.prev = p;
    }
    pub fn prev_point(&self) -> Option<(f64, f64)> {
        self.prev
    }
    /// Forget the closest-approach distance.
    pub fn reset_cpa(&mut self) {
        self.cpa = -1.0;
    }

    /// Reset for a new traversal (repeats, CPA, index, completion).
    pub fn reset_for_new_traversal(&mut self) {
        self.repeats_sofar = 0;
        self.cpa = -1.0;
        self.ix = 0;
        self.complete = false;
    }

    /// Total length of one cycle including the closing gap last → first.
    pub fn cycle_length(&self) -> f64 {
        let n = self.pts.len();
        if n < 2 {
            return 0.0;
        }
        (0..n)
            .map(|i| {
                let a = self.pts[i];
                let b = self.pts[(i + 1) % n];
                dist(a.x, a.y, b.x, b.y)
            })
            .sum()
    }

    /// Distance from (x, y) through the rest of the current cycle.
    pub fn dist_to_go_cycle(&self, x: f64, y: f64) -> f64 {
        let Some(cur) = self.current() else {
            return 0.0;
        };
        let mut d = dist(x, y, cur.x, cur.y);
        for i in self.ix + 1..self.pts.len() {
            let a = self.pts[i - 1];
            let b = self.pts[i];
            d += dist(a.x, a.y, b.x, b.y);
        }
        d
    }

    /// Distance to the end of all remaining cycles; -1 when repeats are endless.
    pub fn dist_to_go_all(&self, x: f64, y: f64) -> f64 {
        if self.repeats_endless {
            return -1.0;
        }
        let mut d = self.dist_to_go_cycle(x, y);
        let remaining = self.repeats.saturating_sub(self.repeats_sofar);
        if self.perpetual && remaining > 0 {
            d += f64::from(remaining) * self.cycle_length();
        }
        d
    }

    /// One step of the traversal with ownship at (osx, osy).
    pub fn advance(&mut self, osx: f64, osy: f64) -> Advance {
        let n = self.pts.len();
        if n == 0 {
            return Advance::EmptySeglist;
        }
        if self.complete {
            return Advance::Completed;
        }
        if self.ix >= n {
            self.ix = 0;
        }
        let pt = self.pts[self.ix];
        let d = dist(osx, osy, pt.x, pt.y);
        if self.cpa < 0.0 || d < self.cpa {
            self.cpa = d;
        }
        let mut captured = false;
        if d < self.capture_radius {
            captured = true;
            self.capture_hits += 1;
        } else if self.slip_radius > self.capture_radius
            && d > self.cpa
            && self.cpa <= self.slip_radius
        {
            captured = true;
            self.slip_hits += 1;
        }
        if !captured && self.capture_line {
            if let Some((px, py)) = self.prev {
                if angle_from_three_points(pt.x, pt.y, px, py, osx, osy) >= 90.0 {
                    captured = true;
                    self.capture_hits += 1;
                }
            }
        }
        if !captured {
            return Advance::InTransit;
        }
        self.ix += 1;
        if self.ix >= n {
            self.cycles += 1;
            self.ix = 0;
            self.cpa = -1.0;
            if self.perpetual {
                self.repeats_sofar += 1;
                if !self.repeats_endless && self.repeats_sofar > self.repeats {
                    self.complete = true;
                }
            } else {
                self.complete = true;
            }
            return if self.complete {
                Advance::Completed
            } else {
                Advance::Cycled
            };
        }
        self.prev = None;
        let np = self.pts[self.ix];
        self.cpa = dist(osx, osy, np.x, np.y);
        Advance::Advanced
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eng(pts: &[(f64, f64)]) -> WaypointEngine {
        let mut e = WaypointEngine::new();
        e.set_points(pts.iter().map(|&(x, y)| Vertex::new(x, y)).collect());
        e
    }

    #[test]
    fn empty_and_capture() {
        let mut e = WaypointEngine::new();
        assert_eq!(e.advance(0.0, 0.0), Advance::EmptySeglist);
        let mut e = eng(&[(0.0, -40.0), (60.0, -40.0)]);
        assert_eq!(e.advance(0.0, 0.0), Advance::InTransit);
        assert_eq!(e.advance(0.0, -37.5), Advance::Advanced);
        assert_eq!(e.index(), 1);
        assert_eq!(e.capture_hits(), 1);
        assert_eq!(e.advance(58.0, -40.0), Advance::Completed);
        assert!(e.complete());
        assert_eq!(e.cycles(), 1);
        assert_eq!(e.index(), 0);
        assert_eq!(e.advance(58.0, -40.0), Advance::Completed);
    }

    #[test]
    fn slip_capture() {
        let mut e = eng(&[(0.0, 10.0), (0.0, 50.0)]);
        e.set_capture_radius(3.0);
        e.set_slip_radius(15.0);
        assert_eq!(e.advance(5.0, 0.0), Advance::InTransit); // cpa 11.18
        assert_eq!(e.advance(6.0, 10.0), Advance::InTransit); // cpa 6
        assert_eq!(e.advance(8.0, 12.0), Advance::Advanced); // moving away: slip
        assert_eq!(e.slip_hits(), 1);
        // Slip radius not larger than capture radius: no slip capture.
        let mut e = eng(&[(0.0, 10.0)]);
        e.set_capture_radius(5.0);
        e.set_slip_radius(5.0);
        assert_eq!(e.advance(6.0, 10.0), Advance::InTransit);
        assert_eq!(e.advance(7.0, 10.0), Advance::InTransit);
    }

    #[test]
    fn capture_line() {
        let mut e = eng(&[(0.0, 10.0), (0.0, 100.0)]);
        e.set_capture_line(true);
        e.set_slip_radius(0.0);
        e.set_prev_point(Some((0.0, 0.0)));
        assert_eq!(e.advance(20.0, 9.0), Advance::InTransit);
        assert_eq!(e.advance(20.0, 11.0), Advance::Advanced);
        assert_eq!(e.prev_point(), None);
    }

    #[test]
    fn repeats_and_perpetual() {
        let mut e = eng(&[(0.0, 0.0), (10.0, 0.0)]);
        e.set_perpetual(true);
        e.set_repeats(1);
        assert_eq!(e.advance(0.0, 0.0), Advance::Advanced);
        assert_eq!(e.advance(10.0, 0.0), Advance::Cycled);
        assert_eq!(e.cycles(), 1);
        assert_eq!(e.advance(0.0, 0.0), Advance::Advanced);
        assert_eq!(e.advance(10.0, 0.0), Advance::Completed);
        assert_eq!(e.cycles(), 2);
        e.reset_for_new_traversal();
        assert!(!e.complete());
        assert_eq!(e.advance(0.0, 0.0), Advance::Advanced);
        // endless
        let mut e = eng(&[(0.0, 0.0)]);
        e.set_perpetual(true);
        e.set_repeats_endless(true);
        for _ in 0..5 {
            assert_eq!(e.advance(0.0, 0.0), Advance::Cycled);
        }
        assert_eq!(e.dist_to_go_all(0.0, 0.0), -1.0);
    }

    #[test]
    fn reverse_order_and_distances() {
        let mut e = eng(&[(20.0, -20.0), (50.0, -20.0), (50.0, -50.0), (20.0, -50.0)]);
        e.set_reverse(true);
        assert_eq!(e.current(), Some(Vertex::new(20.0, -50.0)));
        e.add_point(Vertex::new(0.0, 0.0)); // ignored when reversed
        assert_eq!(e.size(), 4);
        assert_eq!(e.cycle_length(), 120.0);
        assert_eq!(e.dist_to_go_cycle(20.0, -40.0), 10.0 + 90.0);
        e.set_perpetual(true);
        e.set_repeats(1);
        assert_eq!(e.dist_to_go_all(20.0, -40.0), 100.0 + 120.0);
        e.set_reverse(false);
        assert_eq!(e.current(), Some(Vertex::new(20.0, -20.0)));
        e.set_index(2);
        assert_eq!(e.index(), 2);
        e.set_index(9);
        assert_eq!(e.index(), 2);
    }
}
