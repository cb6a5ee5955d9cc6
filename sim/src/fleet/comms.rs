//! The comms model between vehicles, after uFldNodeComms: a node report posted by one
//! vehicle (`NODE_REPORT_LOCAL`) reaches each other vehicle as `NODE_REPORT` when the two
//! are within the comms range at the time it was sent, unless the seeded draw drops it;
//! it arrives `latency` seconds later (at the first step at or after that time, and
//! never in the step that sent it).

use std::collections::VecDeque;

use super::spec::Comms;
use crate::seed::splitmix64;

/// What the comms model did, for the summary.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct CommsStats {
    /// Reports posted by the vehicles.
    pub reports: u64,
    /// Copies delivered to another vehicle.
    pub delivered: u64,
    /// Copies not sent: the receiver was out of range.
    pub out_of_range: u64,
    /// Copies lost to the drop percentage.
    pub dropped: u64,
}

/// Reports (`T`: what carries one) on their way.
pub struct CommsModel<T> {
    cfg: Comms,
    rng: u64,
    queue: VecDeque<(f64, usize, T)>,
    pub stats: CommsStats,
}

impl<T: Clone> CommsModel<T> {
    /// `seed` is mixed into the scenario's comms seed (Monte Carlo runs differ).
    pub fn new(cfg: Comms, seed: u64) -> CommsModel<T> {
        let mut rng = cfg.seed ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        splitmix64(&mut rng);
        CommsModel {
            cfg,
            rng,
            queue: VecDeque::new(),
            stats: CommsStats::default(),
        }
    }

    /// Vehicle `from` posted `report` at `t` (s from the start); `range[to]` is how far
    /// each vehicle is from it now.
    pub fn send(&mut self, t: f64, from: usize, report: T, range: &[f64]) {
        self.stats.reports += 1;
        for (to, &d) in range.iter().enumerate() {
            if to == from {
                continue;
            }
            if d > self.cfg.range {
                self.stats.out_of_range += 1;
                continue;
            }
            if self.cfg.drop_pct > 0.0 {
                let u = (splitmix64(&mut self.rng) >> 11) as f64 / (1u64 << 53) as f64;
                if u * 100.0 < self.cfg.drop_pct {
                    self.stats.dropped += 1;
                    continue;
                }
            }
            self.stats.delivered += 1;
            self.queue
                .push_back((t + self.cfg.latency, to, report.clone()));
        }
    }

    /// The next report due at or before `t`, with its receiver.
    pub fn due(&mut self, t: f64) -> Option<(usize, T)> {
        // One latency for all: the queue is in due-time order.
        if self.queue.front().is_some_and(|(at, _, _)| *at <= t) {
            self.queue.pop_front().map(|(_, to, r)| (to, r))
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_drop_and_latency() {
        let cfg = Comms {
            range: 100.0,
            drop_pct: 0.0,
            latency: 2.0,
            seed: 1,
        };
        let mut c = CommsModel::new(cfg, 0);
        let pos = [(0.0, 0.0), (50.0, 0.0), (150.0, 0.0)];
        let dist = crate::fleet::collide::Distances::of(&pos);
        let (all, two) = (dist.row(0), &dist.row(0)[..2]);
        c.send(1.0, 0, "NAME=a", all);
        assert_eq!((c.stats.delivered, c.stats.out_of_range), (1, 1));
        assert!(c.due(2.9).is_none(), "latency 2 s");
        assert_eq!(c.due(3.0), Some((1, "NAME=a")));
        assert!(c.due(10.0).is_none());

        let mut lossy = CommsModel::new(
            Comms {
                drop_pct: 30.0,
                ..cfg
            },
            7,
        );
        for i in 0..1000 {
            lossy.send(i as f64, 0, "r", two);
        }
        let d = lossy.stats.dropped;
        assert!((200..400).contains(&d), "dropped {d} of 1000 at 30%");
        let mut again = CommsModel::new(
            Comms {
                drop_pct: 30.0,
                ..cfg
            },
            7,
        );
        for i in 0..1000 {
            again.send(i as f64, 0, "r", two);
        }
        assert_eq!(again.stats, lossy.stats, "seeded");
    }
}
