//! The parameters of BHV_AvoidObstacleV24 (obstacles.md §1.2) and their setter rules:
//! the three distances and the two CPA distances drag each other, and complain only when
//! the dragged value had been set explicitly before.

use behavior_api::flag::{parse_flag, FlagParam};
use behavior_api::geometry::{parse_polygon, Polygon};
use behavior_api::params::{no_white, parse_bool};
use behavior_api::{atof, is_color, parse_number};

/// What a setter did: accepted, refused silently, or refused with a BHV_BAD_CONFIG text.
#[derive(Clone, Debug, PartialEq)]
pub enum Set {
    Ok,
    Refused,
    BadConfig(String),
}

/// A range flag: posted while the range is below `below` (always when `below ≤ 0`).
#[derive(Clone, Debug, PartialEq)]
pub struct RngFlag {
    pub below: f64,
    pub flag: String,
}

/// Every type-specific parameter, with the defaults of §1.2.
#[derive(Clone, Debug)]
pub struct Params {
    pub obstacle: Polygon,
    pub allowable_ttc: f64,
    pub min_util_cpa: f64,
    pub max_util_cpa: f64,
    pub pwt_inner: f64,
    pub pwt_outer: f64,
    pub completed: f64,
    /// Which setters were ever called (the "explicitly set" of §1.2.1 and §1.6 step 5).
    pub ttc_set: bool,
    pub min_set: bool,
    pub max_set: bool,
    pub inner_set: bool,
    pub outer_set: bool,
    pub completed_set: bool,
    pub holonomic_ok: bool,
    pub can_disable: bool,
    pub use_refinery: bool,
    pub allstop_on_breach: bool,
    pub rng_flags: Vec<RngFlag>,
    pub cpa_flags: Vec<String>,
    /// The visual hints table (§1.10), in insertion order.
    pub hints: Vec<(String, String)>,
    pub id: String,
}

impl Default for Params {
    fn default() -> Self {
        let hints = [
            ("vertex_size", "0"),
            ("edge_size", "1"),
            ("vertex_color", "gray50"),
            ("edge_color", "gray50"),
            ("fill_color", "off"),
            ("label_color", "white"),
        ];
        Params {
            obstacle: Polygon::default(),
            allowable_ttc: 20.0,
            min_util_cpa: 8.0,
            max_util_cpa: 16.0,
            pwt_inner: 10.0,
            pwt_outer: 50.0,
            completed: 50.0,
            ttc_set: false,
            min_set: false,
            max_set: false,
            inner_set: false,
            outer_set: false,
            completed_set: false,
            holonomic_ok: false,
            can_disable: false,
            use_refinery: false,
            allstop_on_breach: true,
            rng_flags: Vec::new(),
            cpa_flags: Vec::new(),
            hints: hints
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            id: String::new(),
        }
    }
}

fn bool_into(field: &mut bool, v: &str) -> Set {
    match parse_bool(v, *field) {
        Some(b) => {
            *field = b;
            Set::Ok
        }
        None => Set::Refused,
    }
}

fn bad(text: &str) -> Set {
    Set::BadConfig(text.to_string())
}

impl Params {
    /// Apply one parameter (name already lower-cased). `None`: not a parameter of this
    /// type (the helm then reports it as unknown).
    pub fn set(&mut self, param: &str, value: &str) -> Option<Set> {
        let v = value.trim();
        let num = || parse_number(v).filter(|n| *n >= 0.0);
        Some(match param {
            "polygon" | "poly" => match parse_polygon(v) {
                Some(p) if p.is_convex() => {
                    self.obstacle = p;
                    Set::Ok
                }
                _ => bad("obstacle is not convex"),
            },
            "allowable_ttc" => {
                // atof, no number check: `abc` is 0 and accepted.
                let t = atof(v);
                if t < 0.0 {
                    bad("allowable_ttc cannot be a negative number")
                } else {
                    self.allowable_ttc = t;
                    self.ttc_set = true;
                    Set::Ok
                }
            }
            "min_util_cpa_dist" => return num().map(|n| self.set_min_cpa(n)),
            "max_util_cpa_dist" => return num().map(|n| self.set_max_cpa(n)),
            "pwt_inner_dist" => return num().map(|n| self.set_inner(n)),
            "pwt_outer_dist" => return num().map(|n| self.set_outer(n)),
            "completed_dist" => return num().map(|n| self.set_completed(n)),
            "holonomic_ok" => bool_into(&mut self.holonomic_ok, v),
            // Stored by the reference but never used.
            "draw_buff_min_poly" | "draw_buff_max_poly" => {
                if parse_bool(v, true).is_some() {
                    Set::Ok
                } else {
                    Set::Refused
                }
            }
            "can_disable" => bool_into(&mut self.can_disable, v),
            "use_refinery" => bool_into(&mut self.use_refinery, v),
            "allstop_on_breach" => bool_into(&mut self.allstop_on_breach, v),
            "rng_flag" => self.set_rng_flag(v),
            "cpa_flag" => match parse_flag(v) {
                Ok(FlagParam::Flag(_)) => {
                    self.cpa_flags.push(v.to_string());
                    Set::Ok
                }
                _ => Set::Refused,
            },
            "visual_hints" => self.set_hints(v),
            "id" | "obid" => match no_white(v) {
                Some(id) if self.id.is_empty() || self.id == id => {
                    self.id = id.to_string();
                    Set::Ok
                }
                _ => Set::Refused,
            },
            _ => return None,
        })
    }

    fn set_min_cpa(&mut self, n: f64) -> Set {
        self.min_util_cpa = n;
        let explicit = self.max_set;
        self.min_set = true;
        if self.max_util_cpa < n {
            self.max_util_cpa = n;
            if explicit {
                return bad("min_util_cpa must be <= max_util_cpa");
            }
        }
        Set::Ok
    }

    fn set_max_cpa(&mut self, n: f64) -> Set {
        self.max_util_cpa = n;
        let explicit = self.min_set;
        self.max_set = true;
        if self.min_util_cpa > n {
            self.min_util_cpa = n;
            if explicit {
                return bad("max_util_cpa must be >= min_util_cpa");
            }
        }
        Set::Ok
    }

    fn set_inner(&mut self, n: f64) -> Set {
        self.pwt_inner = n;
        self.inner_set = true;
        if self.pwt_outer < n {
            self.pwt_outer = n;
            if self.outer_set {
                return bad("pwt_inner_dist must be <= pwt_outer_dist");
            }
        }
        if self.completed < n {
            self.completed = n;
            if self.completed_set {
                return bad("pwt_inner_dist must be <= completed_dist");
            }
        }
        Set::Ok
    }

    fn set_outer(&mut self, n: f64) -> Set {
        self.pwt_outer = n;
        self.outer_set = true;
        if self.pwt_inner > n {
            self.pwt_inner = n;
            if self.inner_set {
                return bad("pwt_outer_dist must be >= pwt_inner_dist");
            }
        }
        if self.completed < n {
            self.completed = n;
            if self.completed_set {
                return bad("pwt_outer_dist must be <= completed_dist");
            }
        }
        Set::Ok
    }

    fn set_completed(&mut self, n: f64) -> Set {
        self.completed = n;
        self.completed_set = true;
        if self.pwt_inner > n {
            self.pwt_inner = n;
            if self.inner_set {
                return bad("completed_dist must be >= pwt_inner_dist");
            }
        }
        if self.pwt_outer > n {
            self.pwt_outer = n;
            if self.outer_set {
                return bad("completed_dist must be >= pwt_outer_dist");
            }
        }
        Set::Ok
    }

    /// `[<D ]VAR = VALUE`: D must be a number; a malformed flag part is dropped, the
    /// line still accepted (§1.2).
    fn set_rng_flag(&mut self, v: &str) -> Set {
        let (below, rest) = match v.strip_prefix('<') {
            Some(r) => {
                let r = r.trim_start();
                let (word, rest) = r.split_once(char::is_whitespace).unwrap_or((r, ""));
                match parse_number(word) {
                    Some(d) => (d, rest.trim()),
                    None => return Set::Refused,
                }
            }
            None => (-1.0, v),
        };
        if let Ok(FlagParam::Flag(_)) = parse_flag(rest) {
            self.rng_flags.push(RngFlag {
                below,
                flag: rest.to_string(),
            });
        }
        Set::Ok
    }

    /// `key=value, ...`: colour keys need a colour, the others a number (negative ones
    /// accepted but not stored). The first bad element refuses the line; earlier ones stay.
    fn set_hints(&mut self, v: &str) -> Set {
        for elem in v.split(',') {
            let Some((k, val)) = elem.split_once('=') else {
                return Set::Refused;
            };
            let key = k
                .trim()
                .to_ascii_lowercase()
                .replace("lcolor", "label_color");
            let val = val.trim();
            if key.contains("color") {
                if !is_color(val) {
                    return Set::Refused;
                }
            } else {
                match parse_number(val) {
                    Some(n) if n < 0.0 => continue,
                    Some(_) => {}
                    None => return Set::Refused,
                }
            }
            self.set_hint(&key, val);
        }
        Set::Ok
    }

    pub fn set_hint(&mut self, key: &str, val: &str) {
        match self.hints.iter_mut().find(|(k, _)| k == key) {
            // In place: the behavior sets its fill hints every iteration.
            Some(e) => {
                if e.1 != val {
                    e.1.clear();
                    e.1.push_str(val);
                }
            }
            None => self.hints.push((key.to_string(), val.to_string())),
        }
    }

    pub fn hint(&self, key: &str) -> Option<&str> {
        self.hints
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// inner ≤ outer ≤ completed and min ≤ max CPA (part of the model's validity).
    pub fn distances_ordered(&self) -> bool {
        self.pwt_inner <= self.pwt_outer
            && self.pwt_outer <= self.completed
            && self.min_util_cpa <= self.max_util_cpa
    }

    /// `BHV_SETTINGS` (§1.4 step 2).
    pub fn settings(&self, name: &str) -> String {
        format!(
            "type=BHV_AvoidObstacleV24,name={name},allowable_ttc={:.2},min_util_cpa={:.2},max_util_cpa={:.2},pwt_outer_dist={:.2},pwt_inner_dist={:.2},completed_dist={:.2}",
            self.allowable_ttc,
            self.min_util_cpa,
            self.max_util_cpa,
            self.pwt_outer,
            self.pwt_inner,
            self.completed
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(p: &mut Params, k: &str, v: &str) -> Option<Set> {
        p.set(k, v)
    }

    #[test]
    fn defaults_and_settings_string() {
        let p = Params::default();
        assert_eq!(
            p.settings("a"),
            "type=BHV_AvoidObstacleV24,name=a,allowable_ttc=20.00,min_util_cpa=8.00,max_util_cpa=16.00,pwt_outer_dist=50.00,pwt_inner_dist=10.00,completed_dist=50.00"
        );
    }

    #[test]
    fn distances_drag_and_complain_only_when_explicit() {
        let mut p = Params::default();
        // Outer alone: inner stays 10, completed 50.
        assert_eq!(set(&mut p, "pwt_outer_dist", "20"), Some(Set::Ok));
        assert_eq!((p.pwt_inner, p.completed), (10.0, 50.0));
        // §1.2.1: completed 20 then outer 30 → completed dragged to 30, line refused.
        let mut p = Params::default();
        assert_eq!(set(&mut p, "completed_dist", "20"), Some(Set::Ok));
        assert_eq!(
            set(&mut p, "pwt_outer_dist", "30"),
            Some(Set::BadConfig(
                "pwt_outer_dist must be <= completed_dist".into()
            ))
        );
        assert_eq!(p.completed, 30.0);
        // The reverse order: outer dragged down to 20.
        let mut p = Params::default();
        assert_eq!(set(&mut p, "pwt_outer_dist", "30"), Some(Set::Ok));
        assert_eq!(
            set(&mut p, "completed_dist", "20"),
            Some(Set::BadConfig(
                "completed_dist must be >= pwt_outer_dist".into()
            ))
        );
        assert_eq!(p.pwt_outer, 20.0);
        // CPA pair: min above a default max drags it silently.
        let mut p = Params::default();
        assert_eq!(set(&mut p, "min_util_cpa_dist", "20"), Some(Set::Ok));
        assert_eq!(p.max_util_cpa, 20.0);
        assert_eq!(
            set(&mut p, "max_util_cpa_dist", "5"),
            Some(Set::BadConfig(
                "max_util_cpa must be >= min_util_cpa".into()
            ))
        );
        // Negative or non-numbers fall through to "unknown".
        assert_eq!(set(&mut p, "min_util_cpa_dist", "-1"), None);
        assert_eq!(set(&mut p, "pwt_inner_dist", "x"), None);
    }

    #[test]
    fn other_setters() {
        let mut p = Params::default();
        assert_eq!(set(&mut p, "allowable_ttc", "abc"), Some(Set::Ok));
        assert_eq!(p.allowable_ttc, 0.0);
        assert_eq!(
            set(&mut p, "allowable_ttc", "-2"),
            Some(Set::BadConfig(
                "allowable_ttc cannot be a negative number".into()
            ))
        );
        assert_eq!(
            set(&mut p, "poly", "pts={0,0:5,2:10,0:5,10}"),
            Some(Set::BadConfig("obstacle is not convex".into()))
        );
        assert_eq!(
            set(&mut p, "poly", "pts={60,-12:60,6:80,6:80,-12},label=oba"),
            Some(Set::Ok)
        );
        assert_eq!(p.obstacle.attrs.label, "oba");
        assert_eq!(set(&mut p, "id", "oba"), Some(Set::Ok));
        assert_eq!(set(&mut p, "obid", "oba"), Some(Set::Ok));
        assert_eq!(set(&mut p, "id", "obb"), Some(Set::Refused));
        assert_eq!(set(&mut p, "rng_flag", "<x RNG=1"), Some(Set::Refused));
        assert_eq!(set(&mut p, "rng_flag", "<20 RNG = $[RNG]"), Some(Set::Ok));
        assert_eq!(set(&mut p, "rng_flag", "<20 RNG ="), Some(Set::Ok));
        assert_eq!(p.rng_flags.len(), 1);
        assert_eq!(p.rng_flags[0].below, 20.0);
        assert_eq!(set(&mut p, "cpa_flag", "CPA ="), Some(Set::Refused));
        assert_eq!(set(&mut p, "use_refinery", "maybe"), Some(Set::Refused));
        assert_eq!(set(&mut p, "buffer_dist", "3"), None);
        assert_eq!(
            set(&mut p, "visual_hints", "gut_lcolor=red, edge_size=-1"),
            Some(Set::Ok)
        );
        assert_eq!(p.hint("gut_label_color"), Some("red"));
        assert_eq!(p.hint("edge_size"), Some("1"));
        assert_eq!(
            set(&mut p, "visual_hints", "vertex_size=2, edge_color=nocolor"),
            Some(Set::Refused)
        );
        assert_eq!(p.hint("vertex_size"), Some("2"));
    }
}
