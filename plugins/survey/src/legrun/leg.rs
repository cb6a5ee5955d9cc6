//! LegRun's leg: the two end points and the turn settings at each end
//! (behaviors-more.md §9.2), and the turn paths they give.

use behavior_api::geometry::{angle360, dist, parse_point, project_point, rel_ang};
use behavior_api::{atof, is_number};

use super::engine::Pt;
use super::turn::Turn;

/// The settings of the turn at one end.
#[derive(Clone, Debug, PartialEq)]
pub struct TurnSet {
    pub rad: f64,
    pub ext: f64,
    pub bias: f64,
    pub port: bool,
}

impl Default for TurnSet {
    fn default() -> Self {
        TurnSet {
            rad: -1.0,
            ext: 0.0,
            bias: 0.0,
            port: true,
        }
    }
}

#[derive(Clone, Debug)]
pub struct Leg {
    pub p1: Option<Pt>,
    pub p2: Option<Pt>,
    pub turns: [TurnSet; 2],
    pub rad_min: f64,
    pub gap: f64,
    pub id: String,
    pub modified: bool,
}

impl Default for Leg {
    fn default() -> Self {
        Leg {
            p1: None,
            p2: None,
            turns: [TurnSet::default(), TurnSet::default()],
            rad_min: 2.0,
            gap: 20.0,
            id: String::new(),
            modified: true,
        }
    }
}

fn num(v: &str) -> Option<f64> {
    is_number(v).then(|| atof(v))
}

impl Leg {
    pub fn valid(&self) -> bool {
        self.p1.is_some() && self.p2.is_some() && self.turns.iter().all(|t| t.rad >= 0.0)
    }

    fn center_ang_len(&self) -> Option<(Pt, f64, f64)> {
        let (a, b) = (self.p1?, self.p2?);
        Some((
            ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0),
            rel_ang(a.0, a.1, b.0, b.1),
            dist(a.0, a.1, b.0, b.1),
        ))
    }

    fn set_by_center(&mut self, c: Pt, ang: f64, len: f64) -> bool {
        if len <= 0.0 {
            return false;
        }
        self.p1 = Some(project_point(ang - 180.0, len / 2.0, c.0, c.1));
        self.p2 = Some(project_point(ang, len / 2.0, c.0, c.1));
        true
    }

    /// A leg parameter; false when refused. Every call marks the leg modified.
    pub fn set_param(&mut self, param: &str, value: &str) -> bool {
        self.modified = true;
        let v = value.trim();
        let which: &[usize] = if param.starts_with("turn1_") {
            &[0]
        } else if param.starts_with("turn2_") {
            &[1]
        } else {
            &[0, 1]
        };
        let base = param
            .trim_start_matches("turn1_")
            .trim_start_matches("turn2_")
            .trim_start_matches("turn_");
        let is_turn = param.starts_with("turn");
        match param {
            "p1" | "vx1" | "p2" | "vx2" => {
                let Some(p) = parse_point(v) else {
                    return false;
                };
                if param.ends_with('1') {
                    self.p1 = Some((p.x, p.y));
                } else {
                    self.p2 = Some((p.x, p.y));
                }
                return true;
            }
            "leg" => return self.set_leg(v),
            "leg_len" | "leg_len_mod" | "leg_ang" | "leg_ang_mod" => {
                let (Some(x), Some((c, ang, len))) = (num(v), self.center_ang_len()) else {
                    return false;
                };
                let modify = param.ends_with("_mod");
                return if param.starts_with("leg_len") {
                    self.set_by_center(c, ang, if modify { len + x } else { x })
                } else {
                    self.set_by_center(c, angle360(if modify { ang + x } else { x }), len)
                };
            }
            "shift_pt" => {
                let f: Vec<&str> = if v.contains('=') {
                    v.split(',')
                        .map(|kv| kv.split_once('=').map_or("", |p| p.1))
                        .collect()
                } else if v.contains(',') {
                    v.split(',').collect()
                } else {
                    v.split(':').collect()
                };
                let (Some((_, ang, len)), 2) = (self.center_ang_len(), f.len()) else {
                    return false;
                };
                let (Some(x), Some(y)) = (num(f[0]), num(f[1])) else {
                    return false;
                };
                return self.set_by_center((x, y), ang, len);
            }
            "turn_rad_min" => {
                return num(v)
                    .filter(|r| *r > 0.0)
                    .map(|r| self.rad_min = r)
                    .is_some();
            }
            "turn_pt_gap" => return num(v).map(|g| self.gap = g.max(0.5)).is_some(),
            "id" => {
                self.id = v.to_string();
                return true;
            }
            _ if !is_turn => return false,
            _ => {}
        }
        if matches!(base, "dir") {
            let lower = v.to_ascii_lowercase();
            let new = match lower.as_str() {
                "port" => Some(true),
                "star" | "starboard" => Some(false),
                "toggle" => None,
                _ => return false,
            };
            for &i in which {
                // `toggle` makes port starboard and anything else port.
                self.turns[i].port = new.unwrap_or(!self.turns[i].port);
            }
            return true;
        }
        let Some(x) = num(v) else { return false };
        let rad_min = self.rad_min;
        for &i in which {
            let t = &mut self.turns[i];
            match base {
                "rad" if x > 0.0 => t.rad = x.max(rad_min),
                "rad_mod" => t.rad = (t.rad + x).max(rad_min),
                "ext" if x >= 0.0 => t.ext = x,
                "ext_mod" => t.ext = (t.ext + x).max(0.0),
                "bias" => t.bias = x.clamp(-100.0, 100.0),
                "bias_mod" => t.bias = (t.bias + x).clamp(-100.0, 100.0),
                _ => return false,
            }
        }
        true
    }

    /// `x:y:ang:len` or `x=..,y=..,ang=..,len=..`.
    fn set_leg(&mut self, v: &str) -> bool {
        let lower = v.to_ascii_lowercase();
        let vals: Vec<Option<f64>> = if lower.contains('=') {
            let mut out = [None; 4];
            for kv in lower.split(',') {
                let Some((k, x)) = kv.split_once('=') else {
                    return false;
                };
                let i = match k.trim() {
                    "x" => 0,
                    "y" => 1,
                    "ang" => 2,
                    "len" => 3,
                    _ => return false,
                };
                out[i] = num(x);
            }
            out.to_vec()
        } else {
            lower.split(':').map(num).collect()
        };
        match vals.as_slice() {
            [Some(x), Some(y), Some(a), Some(l)] => self.set_by_center((*x, *y), *a, *l),
            _ => false,
        }
    }

    /// The turn path at P1 (`which` 0) or P2 (1).
    pub fn turn_path(&self, which: usize) -> Vec<Pt> {
        let (Some(a), Some(b)) = (self.p1, self.p2) else {
            return Vec::new();
        };
        let (end, other) = if which == 0 { (a, b) } else { (b, a) };
        let t = &self.turns[which];
        let th = rel_ang(end.0, end.1, other.0, other.1);
        let mut out = Vec::new();
        let mut start = end;
        if t.ext > 0.0 {
            out.push(end);
            start = project_point(th - 180.0, t.ext, end.0, end.1);
        }
        let turn = Turn {
            start,
            heading: angle360(th + 180.0),
            end,
            radius: t.rad,
            gap: self.gap,
            bias: t.bias,
            port: t.port,
        };
        out.extend(turn.generate());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_by_centre_and_turn_settings() {
        let mut l = Leg::default();
        assert!(!l.valid());
        assert!(l.set_param("leg", "x=0,y=0,ang=90,len=100"));
        assert_eq!((l.p1, l.p2), (Some((-50.0, 0.0)), Some((50.0, 0.0))));
        assert!(l.set_param("leg", "10:0:0:20"));
        assert_eq!((l.p1, l.p2), (Some((10.0, -10.0)), Some((10.0, 10.0))));
        assert!(!l.set_param("leg", "10:0:0:-20"));
        assert!(l.set_param("leg_len_mod", "20"));
        assert_eq!(l.p2, Some((10.0, 20.0)));
        assert!(l.set_param("shift_pt", "x=0,y=0"));
        assert_eq!(l.p1, Some((0.0, -20.0)));
        assert!(!l.valid());
        assert!(l.set_param("turn_rad", "1"));
        assert_eq!(l.turns[0].rad, 2.0);
        assert!(l.valid());
        assert!(l.set_param("turn2_bias", "150"));
        assert_eq!((l.turns[0].bias, l.turns[1].bias), (0.0, 100.0));
        assert!(l.set_param("turn1_dir", "toggle"));
        assert!(!l.turns[0].port && l.turns[1].port);
        for (p, v) in [
            ("turn_rad", "0"),
            ("turn1_ext", "-1"),
            ("turn2_dir", "up"),
            ("vx1", "x"),
            ("bogus", "1"),
        ] {
            assert!(!l.set_param(p, v), "{p}");
        }
        assert!(!l.turn_path(0).is_empty());
    }
}
