//! The wrap detector of LegRun (behaviors-more.md §9.8): counts how often ownship's
//! track crosses its own earlier track.

use behavior_api::geometry::{dist, segments_cross};

use super::engine::Pt;

const MIN_LEG: f64 = 1.0;
const MAX_LEGS: usize = 5000;

#[derive(Clone, Debug, Default)]
pub struct WrapDetector {
    last: Option<Pt>,
    segs: std::collections::VecDeque<(Pt, Pt)>,
    pub wraps: u64,
}

impl WrapDetector {
    pub fn update(&mut self, p: Pt) {
        let Some(l) = self.last else {
            self.last = Some(p);
            return;
        };
        if dist(l.0, l.1, p.0, p.1) < MIN_LEG {
            return;
        }
        let n = self.segs.len();
        let crossed = self
            .segs
            .iter()
            .take(n.saturating_sub(1))
            .any(|(a, b)| segments_cross(a.0, a.1, b.0, b.1, l.0, l.1, p.0, p.1));
        if crossed {
            self.wraps += 1;
            self.segs.clear();
            self.last = None;
            return;
        }
        self.segs.push_back((l, p));
        if self.segs.len() > MAX_LEGS {
            self.segs.pop_front();
        }
        self.last = Some(p);
    }

    pub fn reset(&mut self) {
        self.last = None;
        self.segs.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_loop_is_one_wrap() {
        let mut w = WrapDetector::default();
        for p in [
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (5.0, 10.0),
            (5.0, -5.0),
        ] {
            w.update(p);
        }
        assert_eq!(w.wraps, 1);
        w.update((5.0, -5.5));
        assert_eq!(w.wraps, 1);
    }
}
