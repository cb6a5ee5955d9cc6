//! The COLREGS mode machine (behaviors-contacts.md §5.3): which rule situation this
//! contact is in, from this iteration's contact geometry. Pure: no helm, no postings
//! (the debug texts are returned for the behavior to post).

use behavior_api::contacts::ContactRelation;
use behavior_api::geometry::{angle180, project_point};

/// The rule situation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    None,
    HeadOn,
    Overtaking,
    GiveWay,
    StandOn,
    /// Stand-on while being overtaken.
    StandOnOt,
    Cpa,
    Complete,
}

impl Mode {
    pub fn as_str(self) -> &'static str {
        match self {
            Mode::None => "none",
            Mode::HeadOn => "headon",
            Mode::Overtaking => "overtaking",
            Mode::GiveWay => "giveway",
            Mode::StandOn => "standon",
            Mode::StandOnOt => "standon_ot",
            Mode::Cpa => "cpa",
            Mode::Complete => "complete",
        }
    }

    /// `avoid_mode` (testing): the modes a user may force.
    pub fn parse_forced(s: &str) -> Option<Mode> {
        Some(match s {
            "headon" => Mode::HeadOn,
            "giveway" => Mode::GiveWay,
            "none" => Mode::None,
            "overtaking" => Mode::Overtaking,
            "standon" => Mode::StandOn,
            "cpa" => Mode::Cpa,
            _ => return None,
        })
    }

    fn is_standon(self) -> bool {
        matches!(self, Mode::StandOn | Mode::StandOnOt)
    }
}

/// The refinement of a mode (side to pass, how sure a stand-on call is).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Submode {
    None,
    Stern,
    Bow,
    Neither,
    Port,
    Starboard,
    Unsure,
    UnsureBow,
    UnsureStern,
    Inextremis,
    /// Set on leaving overtaking by the release rule (the reference's `cpa` submode).
    Cpa,
}

impl Submode {
    pub fn as_str(self) -> &'static str {
        match self {
            Submode::None => "none",
            Submode::Stern => "stern",
            Submode::Bow => "bow",
            Submode::Neither => "neither",
            Submode::Port => "port",
            Submode::Starboard => "starboard",
            Submode::Unsure => "unsure",
            Submode::UnsureBow => "unsure_bow",
            Submode::UnsureStern => "unsure_stern",
            Submode::Inextremis => "inextremis",
            Submode::Cpa => "cpa",
        }
    }

    /// `avoid_submode`: valid only for the mode it refines (any for the others).
    pub fn parse_for(mode: Mode, s: &str) -> Option<Submode> {
        let sub = match s {
            "none" => Submode::None,
            "stern" => Submode::Stern,
            "bow" => Submode::Bow,
            "neither" => Submode::Neither,
            "port" => Submode::Port,
            "starboard" => Submode::Starboard,
            "unsure" => Submode::Unsure,
            "inextremis" => Submode::Inextremis,
            _ => return None,
        };
        let ok = match mode {
            Mode::GiveWay => matches!(
                sub,
                Submode::Stern | Submode::Bow | Submode::Neither | Submode::None
            ),
            Mode::Overtaking => matches!(sub, Submode::Port | Submode::Starboard | Submode::None),
            Mode::StandOn => matches!(
                sub,
                Submode::Bow
                    | Submode::Stern
                    | Submode::Unsure
                    | Submode::Neither
                    | Submode::None
                    | Submode::Inextremis
            ),
            _ => true,
        };
        ok.then_some(sub)
    }
}

/// The mode index (`COLREGS_AVOID_IX_*`, `$[MODE_ID]`).
pub fn mode_index(mode: Mode, sub: Submode) -> u32 {
    match mode {
        Mode::Complete => 3,
        Mode::HeadOn => 10,
        Mode::GiveWay => match sub {
            Submode::Stern => 20,
            Submode::Bow => 22,
            _ => 0,
        },
        Mode::StandOn => match sub {
            Submode::Stern => 30,
            Submode::Inextremis => 31,
            Submode::Bow => 32,
            Submode::UnsureStern => 34,
            Submode::UnsureBow => 36,
            Submode::Unsure => 38,
            Submode::Neither => 39,
            _ => 0,
        },
        Mode::Overtaking => {
            if sub == Submode::Port {
                43
            } else {
                47
            }
        }
        Mode::Cpa => 50,
        Mode::None | Mode::StandOnOt => 0,
    }
}

/// What the machine needs besides the contact geometry.
#[derive(Clone, Copy, Debug)]
pub struct Inputs<'a> {
    pub rel: &'a ContactRelation,
    /// Ownship x, y, heading, speed.
    pub os: (f64, f64, f64, f64),
    /// Contact x, y, heading.
    pub cn: (f64, f64, f64),
    pub outer: f64,
    pub min_util: f64,
    pub max_util: f64,
    pub giveway_bow_dist: f64,
    pub turn_radius: f64,
    pub crossed: bool,
    /// The contact's turn rate (deg/s), when its heading history makes one.
    pub turn_rate: Option<f64>,
}

/// A debug posting of the machine (the behavior decides whether to post it).
#[derive(Clone, Debug, PartialEq)]
pub enum Debug {
    /// `HEADON_DEBUG_<OWNSHIP>` reason.
    HeadOn(&'static str),
    /// `XCN_BOW_DIST_<CN>`.
    BowDist(f64),
    /// `XCN_BOW_TURN_GAP_<CN>`.
    BowTurnGap(f64),
}

/// The machine's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Machine {
    pub mode: Mode,
    pub submode: Submode,
}

impl Default for Machine {
    fn default() -> Self {
        Machine {
            mode: Mode::None,
            submode: Submode::None,
        }
    }
}

impl Machine {
    fn reset(&mut self, mode: Mode, sub: Submode) {
        self.mode = mode;
        self.submode = sub;
    }

    fn clear(&mut self) {
        self.reset(Mode::None, Submode::None);
    }

    /// One update: the six checks in order, each only when the mode (as the previous
    /// check left it) is one it looks at. Debug postings are appended to `dbg`.
    pub fn update(&mut self, i: &Inputs<'_>, dbg: &mut Vec<Debug>) {
        if matches!(self.mode, Mode::None | Mode::Overtaking | Mode::Cpa) {
            self.check_overtaking(i);
        }
        if matches!(self.mode, Mode::None | Mode::HeadOn | Mode::Cpa) {
            self.check_headon(i, dbg);
        }
        if matches!(self.mode, Mode::None | Mode::StandOnOt | Mode::Cpa) {
            self.check_standon_ot(i);
        }
        if matches!(self.mode, Mode::None | Mode::GiveWay | Mode::Cpa) {
            self.check_giveway(i, dbg);
        }
        if matches!(self.mode, Mode::None | Mode::StandOn | Mode::Cpa) {
            self.check_standon(i);
        }
        if matches!(self.mode, Mode::None | Mode::Cpa) {
            if i.rel.range > i.outer {
                self.clear();
            } else {
                self.reset(Mode::Cpa, Submode::None);
            }
        }
    }

    /// Whether this update entered a stand-on mode from another (ownship's heading and
    /// speed are then remembered as the stand-on reference).
    pub fn entered_standon(before: Mode, after: Mode) -> bool {
        after.is_standon() && !before.is_standon()
    }

    fn check_overtaking(&mut self, i: &Inputs<'_>) {
        let r = i.rel;
        if r.range >= i.outer || r.rate_of_closure < 0.0 {
            self.clear();
            return;
        }
        if self.mode == Mode::Overtaking {
            if r.cn_os_rel_bng > 337.5 || r.cn_os_rel_bng < 22.5 {
                self.reset(Mode::Cpa, Submode::Cpa);
            }
            let b = r.os_cn_rel_bng;
            if self.submode == Submode::Port {
                if b > 180.0 && b < 355.0 {
                    self.submode = Submode::Starboard;
                }
            } else if b < 5.0 {
                self.submode = Submode::Port;
            }
            return;
        }
        if r.cn_os_rel_bng < 112.5 || r.cn_os_rel_bng > 247.5 || !r.os_passes_cn {
            self.clear();
            return;
        }
        let side = if r.cn_port_of_os {
            Submode::Starboard
        } else {
            Submode::Port
        };
        self.reset(Mode::Overtaking, side);
    }

    fn check_headon(&mut self, i: &Inputs<'_>, dbg: &mut Vec<Debug>) {
        let r = i.rel;
        if self.mode == Mode::HeadOn {
            if r.range > i.min_util && r.rate_of_closure < 0.0 {
                self.clear();
                dbg.push(Debug::HeadOn("release due to opening range"));
            } else if r.os_aft_of_cn {
                self.clear();
                dbg.push(Debug::HeadOn("release due to os aft of cn"));
            } else if r.os_star_of_cn && r.cn_star_of_os {
                let e1 = r.os_cn_rel_bng - 12.0;
                let e2 = r.cn_os_rel_bng - 12.0;
                if e1 > 5.0 || e2 > 5.0 || e1 + e2 > 7.5 {
                    self.clear();
                    dbg.push(Debug::HeadOn("release due to passing to port"));
                }
            }
            return;
        }
        if r.range >= 2.0 * i.outer {
            self.clear();
            dbg.push(Debug::HeadOn("not entered due to range"));
        } else if angle180(r.os_cn_rel_bng).abs() > 12.0 || angle180(r.cn_os_rel_bng).abs() > 12.0 {
            self.clear();
            dbg.push(Debug::HeadOn("not entered due to rel bearing"));
        } else {
            self.reset(Mode::HeadOn, Submode::None);
            dbg.push(Debug::HeadOn("entered head-on mode"));
        }
    }

    fn check_standon_ot(&mut self, i: &Inputs<'_>) {
        let r = i.rel;
        if r.range >= i.outer {
            self.clear();
            return;
        }
        if self.mode == Mode::StandOnOt {
            if i.crossed || r.rate_of_closure < 0.0 {
                self.clear();
                return;
            }
        } else if r.os_cn_rel_bng < 112.5
            || r.os_cn_rel_bng > 247.5
            || !r.cn_passes_os
            || r.os_curr_cpa_dist > i.max_util
        {
            self.clear();
            return;
        }
        let sub = if r.range <= i.max_util && r.os_curr_cpa_dist <= i.min_util {
            Submode::Inextremis
        } else if r.cn_port_of_os {
            Submode::Port
        } else {
            Submode::Starboard
        };
        self.reset(Mode::StandOnOt, sub);
    }

    fn check_giveway(&mut self, i: &Inputs<'_>, dbg: &mut Vec<Debug>) {
        let r = i.rel;
        if r.range >= i.outer {
            self.clear();
            return;
        }
        if self.mode == Mode::GiveWay {
            if (r.range > i.min_util && r.rate_of_closure < 0.0) || r.os_star_of_cn {
                self.reset(Mode::Cpa, Submode::None);
            }
            return;
        }
        if r.cn_os_rel_bng < 247.5 || r.os_cn_rel_bng > 112.5 {
            self.clear();
            return;
        }
        self.reset(Mode::GiveWay, Submode::Stern);
        dbg.push(Debug::BowDist(r.os_crosses_cn_bow_dist));
        if r.os_crosses_cn_bow {
            let acc = if i.giveway_bow_dist > 0.0 {
                i.giveway_bow_dist
            } else {
                (2.0 * i.max_util + i.min_util) / 3.0
            };
            if r.os_crosses_cn_bow_dist > acc {
                self.submode = Submode::Bow;
            }
            let (osx, osy, osh, _) = i.os;
            let (px, py) = project_point(osh + 90.0, i.turn_radius, osx, osy);
            let gap = (dist_to_line(px, py, i.cn) - i.turn_radius).max(0.0);
            if gap < acc {
                self.submode = Submode::Bow;
            }
            dbg.push(Debug::BowTurnGap(gap));
        }
        let (_, _, osh, osv) = i.os;
        if !r.os_crosses_cn && speed_in_heading(osh, osv, i.cn.2) > 0.0 {
            self.submode = Submode::Bow;
        }
    }

    fn check_standon(&mut self, i: &Inputs<'_>) {
        let r = i.rel;
        if r.range >= i.outer {
            self.clear();
            return;
        }
        if self.mode == Mode::StandOn
            && (i.crossed || (r.range > i.min_util && r.rate_of_closure < 0.0))
        {
            self.clear();
            return;
        }
        // A failed entry test leaves the mode as it is (no reset).
        if r.os_cn_rel_bng < 247.5
            || r.cn_os_rel_bng > 112.5
            || !r.cn_crosses_os
            || r.rate_of_closure < 0.0
        {
            return;
        }
        self.reset(Mode::StandOn, Submode::Unsure);
        if r.range <= i.max_util && r.os_curr_cpa_dist <= i.min_util {
            self.submode = Submode::Inextremis;
            return;
        }
        if r.os_port_of_cn {
            self.submode = Submode::Neither;
            return;
        }
        self.submode = standon_submode(
            r.os_cn_rel_bng,
            r.cn_crosses_os_bow_dist,
            i.min_util,
            i.max_util,
            i.turn_rate,
        );
    }
}

/// The stand-on classification table (§5.3 check 5) from the relative bearing `b` of
/// the contact, its bow-crossing distance `x` (−1: none) and its turn rate.
pub fn standon_submode(b: f64, x: f64, min_u: f64, max_u: f64, rate: Option<f64>) -> Submode {
    let half = (max_u + min_u) / 2.0;
    let ok = |f: fn(f64) -> bool| rate.is_some_and(f);
    let pick = |c: bool, yes: Submode, no: Submode| if c { yes } else { no };
    use Submode::*;
    if b > 350.0 {
        if x >= min_u {
            pick(ok(|r| r < 0.0), Bow, UnsureBow)
        } else if x > 0.0 {
            pick(ok(|r| r < 0.0), UnsureBow, Unsure)
        } else {
            UnsureStern
        }
    } else if b > 315.0 {
        if x >= half {
            pick(ok(|r| r < 3.0), Bow, UnsureBow)
        } else if x >= min_u {
            pick(ok(|r| r < 0.1), Bow, UnsureBow)
        } else if x > 0.0 {
            pick(ok(|r| r < 0.0), UnsureBow, Unsure)
        } else {
            Stern
        }
    } else if b >= 270.0 {
        if x >= max_u {
            Bow
        } else if x >= half {
            pick(ok(|r| r < 0.1), Bow, UnsureBow)
        } else if x > 0.0 {
            pick(ok(|r| r < 0.0), UnsureBow, Unsure)
        } else {
            Stern
        }
    } else if x >= half {
        pick(ok(|r| r < 0.1), UnsureBow, Unsure)
    } else if x > 0.0 {
        Unsure
    } else {
        Stern
    }
}

/// Distance from (px, py) to the infinite line through the contact along its heading.
fn dist_to_line(px: f64, py: f64, cn: (f64, f64, f64)) -> f64 {
    let (cx, cy, ch) = cn;
    let (dx, dy) = (ch.to_radians().sin(), ch.to_radians().cos());
    ((px - cx) * dy - (py - cy) * dx).abs()
}

/// Ownship's speed along heading `h` (§5.3 give-way): exact at 0, 90 and 180 degrees.
pub fn speed_in_heading(osh: f64, osv: f64, h: f64) -> f64 {
    if osv == 0.0 {
        return 0.0;
    }
    let d = angle180(osh - h).abs();
    if d == 0.0 {
        osv
    } else if d == 180.0 {
        -osv
    } else if d == 90.0 {
        0.0
    } else {
        d.to_radians().cos() * osv
    }
}

#[cfg(test)]
#[path = "modes_tests.rs"]
mod tests;
