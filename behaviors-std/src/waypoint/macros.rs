//! BHV_Waypoint's own macros (behaviors-std.md §2.6).

use geometry::{fmt_x, pts_spec};

use super::BhvWaypoint;
use crate::common::subst;

impl BhvWaypoint {
    /// Expand this type's macros (§2.6) in `text`.
    pub fn expand_type_macros(&self, text: &str) -> String {
        let mut s = text.to_string();
        if !s.contains("$[") && !s.contains("$(") {
            return s;
        }
        let n = self.engine.size();
        let ix = self.engine.index();
        let f3 = |v: f64| fmt_x(v, 3);
        let b = |v: bool| if v { "1" } else { "0" };
        let (nx, ny) = self
            .nextpt
            .or_else(|| self.engine.current().map(|p| (p.x, p.y)))
            .unwrap_or((0.0, 0.0));
        let (px, py) = self.prev_pt.unwrap_or((0.0, 0.0));
        let cycrem = if self.engine.repeats_endless() {
            "forever".to_string()
        } else {
            self.engine
                .repeats()
                .saturating_sub(self.engine.repeats_sofar())
                .to_string()
        };
        let hits = self.engine.capture_hits() + self.engine.slip_hits();
        let (ox, oy) = (self.plat.x, self.plat.y);
        let subs: Vec<(&str, String)> = vec![
            ("POINTS", pts_spec(self.engine.points(), 1)),
            ("SPEED", f3(self.cruise_speed)),
            ("SPEED_ALT", f3(self.speed_alt)),
            ("USE_SPEED_ALT", b(self.use_alt_speed).into()),
            ("IPF_TYPE", self.ipf_type.clone()),
            ("WPT_FLAG_ON_START", b(self.wptflag_on_start).into()),
            ("LEAD_TO_START", b(self.lead_to_start).into()),
            ("LEAD_DAMPER", f3(self.lead_damper)),
            (
                "ORDER",
                if self.engine.reverse() {
                    "reverse"
                } else {
                    "normal"
                }
                .into(),
            ),
            ("NI", ix.to_string()),
            ("IX", ix.to_string()),
            ("NX", f3(nx)),
            ("NY", f3(ny)),
            ("PI", self.prev_waypt_index.to_string()),
            ("PX", f3(px)),
            ("PY", f3(py)),
            ("X", f3(px)),
            ("Y", f3(py)),
            ("CYCLES", self.engine.cycles().to_string()),
            ("CYCREM", cycrem),
            ("WPTS_HIT", hits.to_string()),
            ("WPTS_REM", n.saturating_sub(ix).to_string()),
            ("WPTS", n.to_string()),
            ("CYC_DIST_TOGO", f3(self.engine.dist_to_go_cycle(ox, oy))),
            ("ALL_DIST_TOGO", f3(self.engine.dist_to_go_all(ox, oy))),
        ];
        for (k, v) in subs {
            subst(&mut s, k, &v);
        }
        s
    }
}
