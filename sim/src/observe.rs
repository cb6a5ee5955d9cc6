//! What `helm sim` watches on the bus for its summary, its picture and its end rule:
//! the track, the `VIEW_*` objects, the all-stops, behavior errors, waypoints reached,
//! and the scenario's `[[end.when]]` conditions. Memory stays bounded on long runs
//! (the track is thinned, lists are capped).

use std::collections::BTreeMap;

use super::scenario::When;
use helm_engine::posting::Value;

/// Most points kept of a track; past it every other point is dropped.
const TRACK_CAP: usize = 20_000;
/// Most entries kept of the all-stop and error lists.
const LIST_CAP: usize = 1_000;

/// The vehicle's track, thinned to at most [`TRACK_CAP`] points (start and latest kept).
#[derive(Clone, Debug, Default)]
pub struct Track {
    pts: Vec<(f64, f64)>,
    /// Keep one point in `stride`.
    stride: u64,
    seen: u64,
    last: Option<(f64, f64)>,
    pub distance: f64,
}

impl Track {
    pub fn push(&mut self, x: f64, y: f64) {
        if let Some((lx, ly)) = self.last {
            self.distance += (x - lx).hypot(y - ly);
        }
        self.last = Some((x, y));
        if self.stride == 0 {
            self.stride = 1;
        }
        if self.seen.is_multiple_of(self.stride) {
            if self.pts.len() >= TRACK_CAP {
                let mut i = 0;
                self.pts.retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
                self.stride *= 2;
            }
            self.pts.push((x, y));
        }
        self.seen += 1;
    }

    /// The kept points, the latest position last.
    pub fn points(&self) -> Vec<(f64, f64)> {
        let mut v = self.pts.clone();
        if let Some(l) = self.last {
            if v.last() != Some(&l) {
                v.push(l);
            }
        }
        v
    }

    pub fn first(&self) -> Option<(f64, f64)> {
        self.pts.first().copied()
    }

    pub fn last(&self) -> Option<(f64, f64)> {
        self.last
    }
}

/// The kind of a `VIEW_*` object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum ViewKind {
    Seglist,
    Polygon,
    Point,
    Circle,
}

impl ViewKind {
    fn of(var: &str) -> Option<ViewKind> {
        Some(match var {
            "VIEW_SEGLIST" => ViewKind::Seglist,
            "VIEW_POLYGON" => ViewKind::Polygon,
            "VIEW_POINT" => ViewKind::Point,
            "VIEW_CIRCLE" => ViewKind::Circle,
            _ => return None,
        })
    }
}

/// The `label=` field of a spec (empty if none).
pub fn spec_label(spec: &str) -> &str {
    for field in spec.split(',') {
        if let Some((k, v)) = field.split_once('=') {
            if k.trim().eq_ignore_ascii_case("label") {
                return v.trim();
            }
        }
    }
    ""
}

fn is_erase(spec: &str) -> bool {
    spec.split(',')
        .any(|f| f.trim().eq_ignore_ascii_case("active=false"))
}

/// Whether an all-stop reason is a problem. `NothingToDo` is not: the helm all-stops
/// with it whenever no behavior is active, which is how a mission normally ends (and
/// how it waits between phases), so it is listed apart, never as a failure.
pub fn is_problem_allstop(reason: &str) -> bool {
    reason != "NothingToDo"
}

/// One all-stop: when the helm's `IVPHELM_ALLSTOP` became non-clear, and why.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AllStop {
    /// Seconds from the start of the run.
    pub time: f64,
    pub reason: String,
}

/// Watches every posting on the bus.
#[derive(Clone, Debug, Default)]
pub struct Observer {
    pub start: f64,
    pub track: Track,
    /// Last drawn version of each object, by kind and label (erasures keep the last
    /// drawn one, so the picture shows everything the run showed).
    pub views: BTreeMap<(ViewKind, String), String>,
    /// Labels of objects that moved (were redrawn different) during the run.
    pub moved: std::collections::BTreeSet<(ViewKind, String)>,
    /// Objects whose last posting erased them (`active=false`): not drawn.
    pub erased: std::collections::BTreeSet<(ViewKind, String)>,
    /// The vehicle's heading at the start and at the end (set when the run ends).
    pub headings: Option<(f64, f64)>,
    pub allstops: Vec<AllStop>,
    last_allstop: String,
    pub behavior_errors: Vec<String>,
    /// The behavior errors that were panics (also in `behavior_errors`).
    pub behavior_panics: Vec<String>,
    pub waypoints_reached: u64,
    /// Behaviors the helm spawned from a template (`IVPHELM_LIFE_EVENT`, `event=spawn`,
    /// not those made at start-up).
    pub spawns: u64,
    pub when: Vec<When>,
    /// The first `[[end.when]]` condition that fired (its reason).
    pub fired: Option<String>,
    /// Depth over time (drawn when the helm's domain has depth).
    pub depth: crate::depth_strip::DepthTrace,
}

impl Observer {
    pub fn new(start: f64, when: Vec<When>) -> Observer {
        Observer {
            start,
            when,
            ..Observer::default()
        }
    }

    pub fn on_posting(&mut self, var: &str, value: &Value, now: f64) {
        if self.fired.is_none() {
            if let Some(w) = self.when.iter().find(|w| w.matches(var, value)) {
                self.fired = Some(w.reason());
            }
        }
        // Only a few variables matter; a first-byte test keeps the rest cheap.
        if !matches!(var.as_bytes().first(), Some(b'V' | b'I' | b'B' | b'W')) {
            return;
        }
        if let Some(kind) = ViewKind::of(var) {
            if let Value::Str(spec) = value {
                self.on_view(kind, spec);
            }
            return;
        }
        match (var, value) {
            ("IVPHELM_DOMAIN", Value::Str(s)) => {
                self.depth.enabled = s.split(':').any(|v| v.starts_with("depth,"));
            }
            ("IVPHELM_ALLSTOP", Value::Str(s)) if *s != self.last_allstop => {
                self.last_allstop.clone_from(s);
                if !s.eq_ignore_ascii_case("clear") && self.allstops.len() < LIST_CAP {
                    self.allstops.push(AllStop {
                        time: now - self.start,
                        reason: s.clone(),
                    });
                }
            }
            ("BHV_ERROR", v) if self.behavior_errors.len() < LIST_CAP => {
                let text = match v {
                    Value::Str(s) => s.clone(),
                    Value::Num(n) => format!("{n}"),
                };
                // The helm's wording for a caught panic (runtime::fault callers).
                if text.contains("behavior panicked") {
                    self.behavior_panics.push(text.clone());
                }
                self.behavior_errors.push(text);
            }
            ("IVPHELM_LIFE_EVENT", Value::Str(s))
                if s.contains("event=spawn") && !s.contains("seed=helm_startup") =>
            {
                self.spawns += 1;
            }
            ("WPT_INDEX", v) => {
                let n = match v {
                    Value::Num(n) => *n,
                    Value::Str(s) => s.trim().parse().unwrap_or(0.0),
                };
                if n > 0.0 {
                    self.waypoints_reached += 1;
                }
            }
            ("WPT_STAT", Value::Str(s)) if s.ends_with(",completed") || s.ends_with(",cycled") => {
                self.waypoints_reached += 1;
            }
            _ => {}
        }
    }

    fn on_view(&mut self, kind: ViewKind, spec: &str) {
        let label = spec_label(spec);
        if is_erase(spec) {
            // Kept in `views` (the Monte-Carlo distances use it), but not drawn.
            if self.views.contains_key(&(kind, label.to_string())) {
                self.erased.insert((kind, label.to_string()));
            }
            return;
        }
        if !self.erased.is_empty() {
            self.erased.remove(&(kind, label.to_string()));
        }
        match self.views.get_mut(&(kind, label.to_string())) {
            Some(old) if old == spec => {}
            Some(old) => {
                old.clear();
                old.push_str(spec);
                if !self.moved.contains(&(kind, label.to_string())) {
                    self.moved.insert((kind, label.to_string()));
                }
            }
            None => {
                self.views
                    .insert((kind, label.to_string()), spec.to_string());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn track_is_thinned_not_grown() {
        let mut t = Track::default();
        for i in 0..100_000 {
            t.push(i as f64, 0.0);
        }
        assert!(t.points().len() <= TRACK_CAP + 1);
        assert_eq!(t.first(), Some((0.0, 0.0)));
        assert_eq!(t.last(), Some((99_999.0, 0.0)));
        assert!((t.distance - 99_999.0).abs() < 1e-9);
    }

    #[test]
    fn views_allstops_waypoints() {
        let mut o = Observer::new(100.0, Vec::new());
        let s = |v: &str| Value::Str(v.into());
        o.on_posting("VIEW_POINT", &s("x=1,y=2,label=a"), 101.0);
        o.on_posting("VIEW_POINT", &s("x=3,y=2,label=a"), 101.0);
        o.on_posting("VIEW_POINT", &s("x=3,y=2,active=false,label=a"), 101.0);
        o.on_posting("IVPHELM_ALLSTOP", &s("NothingToDo"), 101.0);
        o.on_posting("IVPHELM_ALLSTOP", &s("NothingToDo"), 102.0);
        o.on_posting("IVPHELM_ALLSTOP", &s("clear"), 103.0);
        o.on_posting("WPT_INDEX", &Value::Num(0.0), 103.0);
        o.on_posting("WPT_INDEX", &Value::Num(1.0), 104.0);
        o.on_posting("WPT_STAT", &s("behavior-name=w,completed"), 105.0);
        assert_eq!(o.views.len(), 1);
        assert_eq!(o.views.values().next().unwrap(), "x=3,y=2,label=a");
        assert!(o.erased.contains(&(ViewKind::Point, "a".to_string())));
        o.on_posting("VIEW_POINT", &s("x=4,y=2,label=a"), 106.0);
        assert!(o.erased.is_empty(), "drawn again");
        assert_eq!(
            o.allstops,
            vec![AllStop {
                time: 1.0,
                reason: "NothingToDo".into()
            }]
        );
        assert_eq!(o.waypoints_reached, 2);
    }
}
