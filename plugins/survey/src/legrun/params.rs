//! LegRun's own parameters (behaviors-more.md §9.1) and its leg-speed schedule (§9.6).

use behavior_api::params::parse_bool;
use behavior_api::{atof, is_color, is_number, parse_number};

use super::{InitMode, LegRun};

impl LegRun {
    pub(super) fn set_legrun_param(&mut self, param: &str, value: &str) -> bool {
        let v = value.trim();
        let both = |s: &mut Self, f: &dyn Fn(&mut super::engine::WptEngine)| {
            f(&mut s.leg_engine);
            f(&mut s.turn_engine);
        };
        match param {
            "speed" => {
                let Some(x) = parse_number(v) else {
                    return false;
                };
                self.speed = x.clamp(0.0, self.max_spd.max(0.0));
                self.speed == x
            }
            "patience" => parse_number(v)
                .map(|x| self.patience = x.clamp(1.0, 99.0))
                .is_some(),
            "capture_radius" | "radius" | "slip_radius" => {
                // atof: text reads as 0 and is accepted; negative is refused.
                let x = atof(v);
                if x < 0.0 {
                    return false;
                }
                if param == "slip_radius" {
                    both(self, &|e| e.slip_radius = x);
                } else {
                    both(self, &|e| e.capture_radius = x);
                }
                true
            }
            "capture_line" => match v.to_ascii_lowercase().as_str() {
                "true" => {
                    both(self, &|e| e.capture_line = true);
                    true
                }
                "false" => {
                    both(self, &|e| e.capture_line = false);
                    true
                }
                "absolute" => {
                    both(self, &|e| {
                        e.capture_line = true;
                        e.capture_radius = 0.0;
                        e.slip_radius = 0.0;
                    });
                    true
                }
                _ => false,
            },
            "lead" | "lead_damper" => match parse_number(v).filter(|x| *x >= 0.0) {
                Some(x) if param == "lead" => {
                    both(self, &|e| e.lead = x);
                    true
                }
                Some(x) => {
                    both(self, &|e| e.lead_damper = x);
                    true
                }
                None => false,
            },
            "repeat" => {
                if v.eq_ignore_ascii_case("forever") {
                    self.leg_engine.max_repeats = -1;
                    return true;
                }
                if !is_number(v) {
                    // Neither a number nor `forever`: accepted and ignored.
                    return true;
                }
                let x = atof(v).trunc();
                if x < 0.0 {
                    return false;
                }
                self.leg_engine.max_repeats = x.min(i64::MAX as f64) as i64;
                true
            }
            "init_leg_mode" => {
                self.init_mode = match v {
                    "fixed" => InitMode::Fixed,
                    "close_turn" => InitMode::CloseTurn,
                    "far_turn" => InitMode::FarTurn,
                    "resume" => InitMode::Resume,
                    _ => return false,
                };
                true
            }
            "leg_spds" => self.set_leg_spds(v),
            "leg_spds_onturn" => parse_bool(v, self.spds_onturn)
                .map(|b| self.spds_onturn = b)
                .is_some(),
            "leg_spds_repeat" => parse_bool(v, self.spds_repeat)
                .map(|b| self.spds_repeat = b)
                .is_some(),
            "mid_leg_pct" | "mid_turn_pct" => {
                match parse_number(v).filter(|x| (0.0..=100.0).contains(x)) {
                    Some(x) if param == "mid_leg_pct" => {
                        self.mid_leg_pct = x;
                        true
                    }
                    Some(x) => {
                        self.mid_turn_pct = x;
                        true
                    }
                    None => false,
                }
            }
            "leg_endflag" | "leg_end_flag" => self.flags.leg_end.set(v),
            "leg1_endflag" | "leg1_end_flag" => self.flags.leg1_end.set(v),
            "leg2_endflag" | "leg2_end_flag" => self.flags.leg2_end.set(v),
            "turn_endflag" | "turn_end_flag" => self.flags.turn_end.set(v),
            "turn1_endflag" | "turn1_end_flag" => self.flags.turn1_end.set(v),
            "turn2_endflag" | "turn2_end_flag" => self.flags.turn2_end.set(v),
            "midlegflag" | "mid_leg_flag" => self.flags.mid_leg.set(v),
            "midturnflag" | "mid_turn_flag" => self.flags.mid_turn.set(v),
            "visual_hints" => self.set_visual_hints(v),
            _ => {
                self.preview_pending = true;
                self.leg.set_param(param, v)
            }
        }
    }

    fn set_visual_hints(&mut self, value: &str) -> bool {
        // The kept VIEW_* attributes are built again from the new hints.
        self.texts.ready = false;
        for item in value.split(',') {
            let Some((k, val)) = item.split_once('=') else {
                return false;
            };
            let key = k
                .trim()
                .to_ascii_lowercase()
                .replace("lcolor", "label_color");
            let val = val.trim();
            if key.contains("color") {
                if !(is_color(val) || val.eq_ignore_ascii_case("off")) {
                    return false;
                }
                self.hints.insert(key, val.to_string());
            } else {
                let Some(x) = parse_number(val) else {
                    return false;
                };
                if x >= 0.0 {
                    self.hints.insert(key, val.to_string());
                }
            }
        }
        true
    }

    /// `clear`, `reset`, `replace,<list>` or a list of `S` / `N:S` to append.
    pub(super) fn set_leg_spds(&mut self, value: &str) -> bool {
        let s: String = value
            .to_ascii_lowercase()
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect();
        match s.as_str() {
            "clear" => {
                self.spds.clear();
                self.spd_pos = 0;
                return true;
            }
            "reset" => {
                self.spd_pos = 0;
                return true;
            }
            _ => {}
        }
        let list = match s.strip_prefix("replace,") {
            Some(rest) => {
                self.spds.clear();
                self.spd_pos = 0;
                rest
            }
            None => s.as_str(),
        };
        let mut add = Vec::new();
        for elem in list.split(',') {
            let (n, spd) = match elem.split_once(':') {
                Some((n, spd)) => {
                    if !is_number(n) {
                        return false;
                    }
                    let n = atof(n);
                    if n <= 0.0 || n.fract() != 0.0 || n > 10_000.0 {
                        return false;
                    }
                    (n as usize, spd)
                }
                None => (1, elem),
            };
            let Some(x) = parse_number(spd).filter(|x| *x >= 0.0 && *x <= self.max_spd) else {
                return false;
            };
            add.extend(std::iter::repeat_n(x, n));
        }
        self.spds.extend(add);
        true
    }
}
