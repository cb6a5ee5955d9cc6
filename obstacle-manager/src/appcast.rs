//! The manager's appcast report body (the `APPCAST` framing and the request table are
//! contact-manager's `appcast`, shared).

use std::fmt::Write as _;

use crate::manager::ObstacleManager;
use crate::obstacle::Source;

/// Ownship, the alert request, the counters and one line per obstacle.
pub fn body(m: &ObstacleManager) -> String {
    let mut s = String::new();
    let (x, y) = m.nav();
    let c = m.counts();
    let _ = writeln!(s, "Ownship: x={x:.1} y={y:.1}");
    match m.request() {
        Some(r) => {
            let _ = writeln!(
                s,
                "Alert request: name={} update_var={} alert_range={}",
                r.name,
                r.update_var,
                mbutil::compact(r.range, 1)
            );
        }
        None => {
            let _ = writeln!(s, "Alert request: none yet");
        }
    }
    if let Some(g) = &m.config().general_alert {
        let _ = writeln!(
            s,
            "General alert: name={} update_var={} alert_range={}",
            g.name,
            g.update_var,
            mbutil::compact(g.range, 1)
        );
    }
    let _ = writeln!(
        s,
        "Points: {} valid, {} invalid, {} ignored   Alert requests: {}",
        c.points_valid, c.points_invalid, c.points_ignored, c.alert_requests
    );
    let _ = writeln!(
        s,
        "Obstacles: {} now, {} ever, {} resolved, {} updates",
        m.obstacles().count(),
        c.obstacles_ever,
        c.resolved,
        c.updates
    );
    let _ = writeln!(s, "\n  Key  Source  Points  Vertices  Range  Vsource");
    for (k, o) in m.obstacles() {
        let src = match o.source {
            Source::Given => "given",
            Source::Points => "points",
        };
        let _ = writeln!(
            s,
            "  {k}  {src}  {}  {}  {:.1}  {}",
            o.points.len(),
            o.poly.size(),
            o.range,
            o.vsource
        );
    }
    s
}

impl contact_manager::app::Manager for ObstacleManager {
    fn subscriptions(&self) -> Vec<String> {
        ObstacleManager::subscriptions(self)
    }
    fn handle_mail(&mut self, now: f64, mail: &[(&str, crate::MailValue<'_>)]) {
        ObstacleManager::handle_mail(self, now, mail)
    }
    fn iterate(&mut self, now: f64) -> &[crate::Posting] {
        ObstacleManager::iterate(self, now)
    }
    fn iterations(&self) -> u64 {
        ObstacleManager::iterations(self)
    }
    fn warnings(&self) -> &crate::Warnings {
        ObstacleManager::warnings(self)
    }
    fn warnings_mut(&mut self) -> &mut crate::Warnings {
        ObstacleManager::warnings_mut(self)
    }
    fn appcast_body(&self, _now: f64) -> String {
        body(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Config, MailValue};

    #[test]
    fn report_lists_obstacles() {
        let mut m = ObstacleManager::new(Config::default(), 0.0);
        m.handle_mail(
            0.0,
            &[(
                "TRACKED_FEATURE",
                MailValue::Str("x=3,y=4,key=k1,vsource=lidar"),
            )],
        );
        m.iterate(0.0);
        let b = body(&m);
        assert!(b.contains("  k1  points  1  3  4.9  lidar"), "{b}");
        assert!(b.contains("Alert request: none yet"));
    }
}
