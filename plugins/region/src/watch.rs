//! The containment watch both op-region behaviors keep: a polygon is "entered" once
//! ownship has been inside it for `trigger_entry_time` seconds in a row, and once
//! entered it is "breached" when ownship has been outside for `trigger_exit_time`
//! seconds in a row (a short excursion is forgiven).

/// Entry/exit debouncing for one polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct Watch {
    pub entry_time: f64,
    pub exit_time: f64,
    /// Whether the polygon counts before ownship has entered it (false: a vehicle that
    /// starts outside is not in breach until it has been inside once).
    pub armed_from_start: bool,
    entered: bool,
    inside_since: Option<f64>,
    outside_since: Option<f64>,
}

impl Watch {
    pub fn new(entry_time: f64, exit_time: f64) -> Self {
        Watch {
            entry_time,
            exit_time,
            armed_from_start: false,
            entered: false,
            inside_since: None,
            outside_since: None,
        }
    }

    /// Forget everything seen (the `reset` of both behaviors).
    pub fn reset(&mut self) {
        self.entered = false;
        self.inside_since = None;
        self.outside_since = None;
    }

    /// Record one observation at `now`; true when this observation is a breach.
    pub fn observe(&mut self, now: f64, inside: bool) -> bool {
        if inside {
            self.outside_since = None;
            let since = *self.inside_since.get_or_insert(now);
            if now - since >= self.entry_time {
                self.entered = true;
            }
            return false;
        }
        self.inside_since = None;
        if !self.entered && !self.armed_from_start {
            return false;
        }
        let since = *self.outside_since.get_or_insert(now);
        now - since >= self.exit_time
    }

    /// Seconds ownship has been inside without a break (0 outside).
    pub fn secs_inside(&self, now: f64) -> f64 {
        self.inside_since.map_or(0.0, |s| now - s)
    }

    pub fn entered(&self) -> bool {
        self.entered
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entry_then_debounced_exit() {
        let mut w = Watch::new(1.0, 1.0);
        assert!(!w.observe(0.0, true));
        assert!(!w.entered());
        assert!(
            !w.observe(0.5, false),
            "not yet entered: leaving is no breach"
        );
        assert!(!w.observe(1.0, true));
        assert!(!w.observe(2.0, true));
        assert!(w.entered());
        assert_eq!(w.secs_inside(2.5), 1.5);
        assert!(!w.observe(3.0, false));
        assert!(!w.observe(3.75, false));
        assert!(!w.observe(3.9, true), "back in time: forgiven");
        assert!(!w.observe(4.0, false));
        assert!(w.observe(5.0, false));
        w.reset();
        assert!(!w.observe(6.0, false));
    }

    #[test]
    fn armed_from_start_counts_a_start_outside() {
        let mut w = Watch::new(1.0, 0.0);
        w.armed_from_start = true;
        assert!(w.observe(0.0, false));
    }
}
