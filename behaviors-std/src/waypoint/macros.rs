//! BHV_Waypoint's own macros (behaviors-std.md §2.6).

use geometry::{fmt_x, pts_spec};

use super::BhvWaypoint;
use crate::common::{macro_at, subst};

impl BhvWaypoint {
    /// Expand this type's macros (§2.6) in `text`.
    pub fn expand_type_macros(&self, text: &str) -> String {
        let mut s = text.to_string();
        // Only the macros the text names are worked out (this runs for every flag
        // posted at a waypoint), in the order of KEYS; the names are looked for again
        // after each substitution, as a value put in may name a later macro.
        let mut named = if s.contains('$') { named_in(&s) } else { 0 };
        for (k, key) in KEYS.iter().enumerate() {
            if named & (1 << k) != 0 {
                subst(&mut s, key, &self.macro_value(key));
                named = named_in(&s);
            }
        }
        s
    }

    /// The value of one of this type's macros.
    fn macro_value(&self, key: &str) -> String {
        let n = self.engine.size();
        let ix = self.engine.index();
        let f3 = |v: f64| fmt_x(v, 3);
        let b = |v: bool| if v { "1" } else { "0" }.to_string();
        let (px, py) = self.prev_pt.unwrap_or((0.0, 0.0));
        let (ox, oy) = (self.plat.x, self.plat.y);
        match key {
            "POINTS" => pts_spec(self.engine.points(), 1),
            "SPEED" => f3(self.cruise_speed),
            "SPEED_ALT" => f3(self.speed_alt),
            "USE_SPEED_ALT" => b(self.use_alt_speed),
            "IPF_TYPE" => self.ipf_type.clone(),
            "WPT_FLAG_ON_START" => b(self.wptflag_on_start),
            "LEAD_TO_START" => b(self.lead_to_start),
            "LEAD_DAMPER" => f3(self.lead_damper),
            "ORDER" if self.engine.reverse() => "reverse".into(),
            "ORDER" => "normal".into(),
            "NI" | "IX" => ix.to_string(),
            "NX" | "NY" => {
                let (nx, ny) = self
                    .nextpt
                    .or_else(|| self.engine.current().map(|p| (p.x, p.y)))
                    .unwrap_or((0.0, 0.0));
                f3(if key == "NX" { nx } else { ny })
            }
            "PI" => self.prev_waypt_index.to_string(),
            "PX" | "X" => f3(px),
            "PY" | "Y" => f3(py),
            "CYCLES" => self.engine.cycles().to_string(),
            "CYCREM" if self.engine.repeats_endless() => "forever".into(),
            "CYCREM" => (self.engine.repeats())
                .saturating_sub(self.engine.repeats_sofar())
                .to_string(),
            "WPTS_HIT" => (self.engine.capture_hits() + self.engine.slip_hits()).to_string(),
            "WPTS_REM" => n.saturating_sub(ix).to_string(),
            "WPTS" => n.to_string(),
            "CYC_DIST_TOGO" => f3(self.engine.dist_to_go_cycle(ox, oy)),
            "ALL_DIST_TOGO" => f3(self.engine.dist_to_go_all(ox, oy)),
            _ => String::new(),
        }
    }
}

/// The [`KEYS`] that `s` names as `$[KEY]` or `$(KEY)`, as bits: one pass over the text.
fn named_in(s: &str) -> u32 {
    let b = s.as_bytes();
    let mut named = 0;
    for at in 0..b.len().saturating_sub(1) {
        let close = match (b[at], b[at + 1]) {
            (b'$', b'[') => b']',
            (b'$', b'(') => b')',
            _ => continue,
        };
        for (k, key) in KEYS.iter().enumerate() {
            if macro_at(s, at, key, close) {
                named |= 1 << k;
            }
        }
    }
    named
}

/// The macros of §2.6, in the order they are expanded.
const KEYS: [&str; 25] = [
    "POINTS",
    "SPEED",
    "SPEED_ALT",
    "USE_SPEED_ALT",
    "IPF_TYPE",
    "WPT_FLAG_ON_START",
    "LEAD_TO_START",
    "LEAD_DAMPER",
    "ORDER",
    "NI",
    "IX",
    "NX",
    "NY",
    "PI",
    "PX",
    "PY",
    "X",
    "Y",
    "CYCLES",
    "CYCREM",
    "WPTS_HIT",
    "WPTS_REM",
    "WPTS",
    "CYC_DIST_TOGO",
    "ALL_DIST_TOGO",
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::common::has_macro_named;
    use behavior_api::sdk::{HelmDomain, IvpBehavior};
    use behavior_api::testing::MockHelm;

    /// The one-pass scan expands as the search per macro name it replaced.
    #[test]
    fn named_scan_expands_as_the_search_per_name() {
        let mut b = BhvWaypoint::new(&HelmDomain::new("course,0,359,360:speed,0,2,21"));
        let mut h = MockHelm::new("wpt");
        for (p, v) in [
            ("points", "0,0:10,-5:10,10"),
            ("speed", "1.5"),
            ("lead", "4"),
        ] {
            assert!(h.with(|c| b.set_param(c, p, v)));
        }
        let atoms = [
            "$[", "$(", "]", ")", "$", "[", "NI", "NX", "X", "Y", "PX", "WPTS", "_HIT", "ORDER",
            "SPEED", "_ALT", "POINTS", "é", " ",
        ];
        let mut seed = 3u64;
        let mut next = |n: usize| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as usize % n
        };
        for _ in 0..5000 {
            let len = next(10);
            let text: String = (0..len).map(|_| atoms[next(atoms.len())]).collect();
            let mut plain = text.clone();
            for key in KEYS {
                if has_macro_named(&plain, key) {
                    subst(&mut plain, key, &b.macro_value(key));
                }
            }
            assert_eq!(b.expand_type_macros(&text), plain, "{text:?}");
        }
    }
}
