//! COLREGS in the statistics (issue 22 point 5): for every ordered pair (ownship,
//! contact) of a fleet run, the rule situation and whether ownship did what the rule
//! asks of it.
//!
//! **When.** The geometry is taken once per pair, at the first step at which ownship's
//! contact manager has an alert on the contact (the alert that spawns its avoidance
//! behavior); for a pair never alerted, at the first step within the `[collision]`
//! encounter range. Pairs that never get there have no situation.
//!
//! **The rule** (true positions and headings at that step; `os_cn` = the contact's
//! bearing relative to ownship's heading, `cn_os` = ownship's bearing relative to the
//! contact's heading, both in [0, 360); the sectors of behaviors-contacts.md §5.3), in
//! this order:
//! 1. *head-on*: |angle180(os_cn)| ≤ 12 and |angle180(cn_os)| ≤ 12;
//! 2. *overtaking*: ownship abaft the contact's beam (`cn_os` in [112.5, 247.5]) and
//!    faster than it along the contact's heading;
//! 3. *overtaken*: the contact abaft ownship's beam (`os_cn` in [112.5, 247.5]) and
//!    faster than ownship along ownship's heading;
//! 4. *give-way crossing*: the contact on ownship's starboard bow (`os_cn` < 112.5) and
//!    ownship on the contact's port side (`cn_os` > 247.5);
//! 5. *stand-on crossing*: the mirror (`os_cn` > 247.5 and `cn_os` < 112.5);
//! 6. otherwise *none* (e.g. opening, or both on each other's same side): not judged.
//!
//! **Passed as the rule asks**, judged from the trigger to the run's end:
//! * head-on: at the closest approach the contact is on ownship's port side
//!   (`os_cn` in (180, 360)): port to port;
//! * give-way: ownship never crossed the contact's track line (the line through the
//!   contact along its heading) ahead of the contact while within the trigger range of
//!   it: it passed astern (or did not cross at all);
//! * overtaking: the closest approach stayed at or above the `[collision]` range;
//! * stand-on and overtaken: up to the closest approach ownship's heading stayed within
//!   20° of its heading at the trigger and its speed within max(0.5 m/s, 25%) of its
//!   speed then ("kept course and speed", roughly: the stand-on vessel of V22 may still
//!   act in extremis, which shows as a failure here).

use serde::{Deserialize, Serialize};

/// Heading tolerance of a stand-on vessel (deg).
pub const STANDON_HDG_TOL: f64 = 20.0;
/// Speed tolerance of a stand-on vessel: max(this, 25% of its speed) (m/s).
pub const STANDON_SPD_TOL: f64 = 0.5;

/// The rule situations, as they appear in `summary.json` and `runs.csv`.
pub const SITUATIONS: [&str; 5] = ["headon", "giveway", "standon", "overtaking", "overtaken"];

/// One vessel's position and velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vessel {
    pub x: f64,
    pub y: f64,
    /// Degrees, 0 north, clockwise.
    pub heading: f64,
    pub speed: f64,
}

fn angle180(a: f64) -> f64 {
    let a = a.rem_euclid(360.0);
    if a > 180.0 {
        a - 360.0
    } else {
        a
    }
}

/// The bearing of `b` from `a` (deg, 0 north, clockwise).
fn bearing(a: &Vessel, b: &Vessel) -> f64 {
    (b.x - a.x).atan2(b.y - a.y).to_degrees().rem_euclid(360.0)
}

/// `b`'s bearing relative to `a`'s heading, in [0, 360).
pub fn rel_bearing(a: &Vessel, b: &Vessel) -> f64 {
    (bearing(a, b) - a.heading).rem_euclid(360.0)
}

/// `v`'s speed along `heading`.
fn speed_along(v: &Vessel, heading: f64) -> f64 {
    v.speed * (v.heading - heading).to_radians().cos()
}

/// The situation of `os` with respect to `cn` (module doc), or "none".
pub fn classify(os: &Vessel, cn: &Vessel) -> &'static str {
    let os_cn = rel_bearing(os, cn);
    let cn_os = rel_bearing(cn, os);
    let abaft = |b: f64| (112.5..=247.5).contains(&b);
    if angle180(os_cn).abs() <= 12.0 && angle180(cn_os).abs() <= 12.0 {
        "headon"
    } else if abaft(cn_os) && speed_along(os, cn.heading) > cn.speed {
        "overtaking"
    } else if abaft(os_cn) && speed_along(cn, os.heading) > os.speed {
        "overtaken"
    } else if os_cn < 112.5 && cn_os > 247.5 {
        "giveway"
    } else if os_cn > 247.5 && cn_os < 112.5 {
        "standon"
    } else {
        "none"
    }
}

/// One ordered pair's verdict (in `summary.json` as `colregs`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RuleRecord {
    pub ownship: String,
    pub contact: String,
    pub situation: String,
    /// "alert" or "range": what fixed the geometry.
    pub trigger: String,
    pub at_s: f64,
    pub range_m: f64,
    pub os_cn_rel_bng: f64,
    pub cn_os_rel_bng: f64,
    /// None for situation "none".
    pub passed: Option<bool>,
    /// How the verdict was reached, in words.
    pub detail: String,
}

#[derive(Clone, Debug)]
struct Pair {
    situation: &'static str,
    trigger: &'static str,
    at: f64,
    range0: f64,
    rel0: (f64, f64),
    hdg0: f64,
    spd0: f64,
    min_d: f64,
    os_cn_at_min: f64,
    dev_so_far: (f64, f64),
    dev_at_min: (f64, f64),
    /// Side of the contact's track line ownship was on at the last step.
    side: f64,
    bow_crossings: u32,
    stern_crossings: u32,
}

/// Watches every ordered pair.
pub struct Tracker {
    n: usize,
    pairs: Vec<Option<Pair>>,
    encounter: f64,
    collision: f64,
    /// Per vessel, the sine and cosine of its heading in this update, worked out on
    /// first use: every pair with it as contact needs them (n − 1 pairs, one each).
    trig: Vec<Option<(f64, f64)>>,
}

impl Tracker {
    pub fn new(n: usize, encounter: f64, collision: f64) -> Tracker {
        Tracker {
            n,
            pairs: vec![None; n * n],
            trig: vec![None; n],
            encounter,
            collision,
        }
    }

    /// The vessels at `t` (s from the start); `alerted(i, j)`: vessel i's contact
    /// manager has an alert on vessel j.
    pub fn update(
        &mut self,
        t: f64,
        v: &[Vessel],
        dist: &super::collide::Distances,
        alerted: &dyn Fn(usize, usize) -> bool,
    ) {
        self.trig.clear();
        self.trig.resize(self.n, None);
        for i in 0..self.n {
            for j in 0..self.n {
                if i == j {
                    continue;
                }
                let (os, cn) = (&v[i], &v[j]);
                let d = dist.get(i, j);
                let slot = &mut self.pairs[i * self.n + j];
                let p = match slot {
                    Some(p) => p,
                    None => {
                        let trigger = if alerted(i, j) {
                            "alert"
                        } else if d <= self.encounter {
                            "range"
                        } else {
                            continue;
                        };
                        slot.insert(Pair {
                            situation: classify(os, cn),
                            trigger,
                            at: t,
                            range0: d,
                            rel0: (rel_bearing(os, cn), rel_bearing(cn, os)),
                            hdg0: os.heading,
                            spd0: os.speed,
                            min_d: f64::INFINITY,
                            os_cn_at_min: 0.0,
                            dev_so_far: (0.0, 0.0),
                            dev_at_min: (0.0, 0.0),
                            side: side(os, cn, trig_of(&mut self.trig[j], cn)),
                            bow_crossings: 0,
                            stern_crossings: 0,
                        })
                    }
                };
                let dh = angle180(os.heading - p.hdg0).abs();
                let ds = (os.speed - p.spd0).abs();
                p.dev_so_far = (p.dev_so_far.0.max(dh), p.dev_so_far.1.max(ds));
                if d < p.min_d {
                    p.min_d = d;
                    p.os_cn_at_min = rel_bearing(os, cn);
                    p.dev_at_min = p.dev_so_far;
                }
                let (hs, hc) = trig_of(&mut self.trig[j], cn);
                let s = side(os, cn, (hs, hc));
                if s != 0.0 && p.side != 0.0 && s != p.side && d <= p.range0.max(self.encounter) {
                    // (`sin_cos` is `(sin, cos)`: the same bits as each alone.)
                    let along = (os.x - cn.x) * hs + (os.y - cn.y) * hc;
                    if along > 0.0 {
                        p.bow_crossings += 1;
                    } else {
                        p.stern_crossings += 1;
                    }
                }
                if s != 0.0 {
                    p.side = s;
                }
            }
        }
    }

    /// The verdicts, ordered by (ownship, contact) index.
    pub fn finish(&self, names: &[String]) -> Vec<RuleRecord> {
        let mut out = Vec::new();
        for i in 0..self.n {
            for j in 0..self.n {
                let Some(p) = &self.pairs[i * self.n + j] else {
                    continue;
                };
                let (passed, detail) = self.judge(p);
                out.push(RuleRecord {
                    ownship: names[i].clone(),
                    contact: names[j].clone(),
                    situation: p.situation.to_string(),
                    trigger: p.trigger.to_string(),
                    at_s: p.at,
                    range_m: p.range0,
                    os_cn_rel_bng: p.rel0.0,
                    cn_os_rel_bng: p.rel0.1,
                    passed,
                    detail,
                });
            }
        }
        out
    }

    fn judge(&self, p: &Pair) -> (Option<bool>, String) {
        match p.situation {
            "headon" => {
                let port = p.os_cn_at_min > 180.0 && p.os_cn_at_min < 360.0;
                (
                    Some(port),
                    format!(
                        "contact at {:.0} deg relative at the closest approach ({:.1} m): {}",
                        p.os_cn_at_min,
                        p.min_d,
                        if port {
                            "port to port"
                        } else {
                            "starboard to starboard"
                        }
                    ),
                )
            }
            "giveway" => (
                Some(p.bow_crossings == 0),
                format!(
                    "crossed the contact's track {} time(s) ahead, {} time(s) astern",
                    p.bow_crossings, p.stern_crossings
                ),
            ),
            "overtaking" => (
                Some(p.min_d >= self.collision),
                format!("closest approach {:.1} m", p.min_d),
            ),
            "standon" | "overtaken" => {
                let (dh, ds) = p.dev_at_min;
                let ok = dh <= STANDON_HDG_TOL && ds <= STANDON_SPD_TOL.max(0.25 * p.spd0);
                (
                    Some(ok),
                    format!(
                        "up to the closest approach heading changed up to {dh:.0} deg, speed up to {ds:.2} m/s"
                    ),
                )
            }
            _ => (None, "no rule situation".into()),
        }
    }
}

/// `cn`'s heading's (sine, cosine), kept in `slot` once worked out.
fn trig_of(slot: &mut Option<(f64, f64)>, cn: &Vessel) -> (f64, f64) {
    *slot.get_or_insert_with(|| cn.heading.to_radians().sin_cos())
}

/// Which side of `cn`'s track line `os` is on: 1 starboard, −1 port, 0 on it; `(s, c)`
/// the sine and cosine of `cn`'s heading.
fn side(os: &Vessel, cn: &Vessel, (s, c): (f64, f64)) -> f64 {
    // Cross product of the contact's heading (s, c) with the offset to ownship.
    let cross = s * (os.y - cn.y) - c * (os.x - cn.x);
    if cross > 0.0 {
        -1.0
    } else if cross < 0.0 {
        1.0
    } else {
        0.0
    }
}

/// Per situation: (situation, judged, passed) over `records`.
pub fn tally<'a>(
    records: impl Iterator<Item = (&'a str, Option<bool>)>,
) -> Vec<(&'static str, usize, usize)> {
    let mut t: Vec<(&'static str, usize, usize)> = SITUATIONS.iter().map(|s| (*s, 0, 0)).collect();
    for (s, p) in records {
        if let (Some(e), Some(ok)) = (t.iter_mut().find(|e| e.0 == s), p) {
            e.1 += 1;
            e.2 += usize::from(ok);
        }
    }
    t
}

/// What the rule asks, in words (for the summaries).
pub fn asks(situation: &str) -> &'static str {
    match situation {
        "headon" => "passed port to port",
        "giveway" => "passed astern",
        "standon" => "kept course and speed",
        "overtaking" => "passed clear",
        "overtaken" => "kept course and speed",
        _ => "",
    }
}

/// The summary label of a situation.
pub fn label(situation: &str) -> &'static str {
    match situation {
        "headon" => "head-on encounters",
        "giveway" => "give-way crossings",
        "standon" => "stand-on crossings",
        "overtaking" => "overtakings",
        "overtaken" => "overtaken",
        _ => "other",
    }
}

/// More rule judgments than this are summed up in the terminal, not listed.
pub const LISTED_AT_MOST: usize = 6;

/// The terminal lines of one run (each ending in a newline).
pub fn terminal(
    s: &mut String,
    obstacles: Option<&super::obstacles::ObstacleOutcome>,
    rules: &[RuleRecord],
) {
    use std::fmt::Write as _;
    if let Some(ob) = obstacles {
        let _ = writeln!(s, "{}", ob.terminal());
    }
    // A fleet has a judgment per ordered pair (56 for eight vessels): past a few, the
    // terminal gets the tally and `summary.json` keeps each one.
    if rules.len() > LISTED_AT_MOST {
        let _ = writeln!(
            s,
            "  COLREGS by the geometry at first alert, {} ordered pairs (each in summary.json `colregs`):",
            rules.len()
        );
        let mut judged = 0;
        for (situation, n, passed) in tally(rules.iter().map(|r| (r.situation.as_str(), r.passed)))
        {
            judged += n;
            if n > 0 {
                let _ = writeln!(
                    s,
                    "    {} {n}: {} {passed} of {n}",
                    label(situation),
                    asks(situation)
                );
            }
        }
        if judged < rules.len() {
            let _ = writeln!(
                s,
                "    not judged (no rule situation): {}",
                rules.len() - judged
            );
        }
        return;
    }
    for r in rules {
        let verdict = match r.passed {
            Some(true) => format!("{}: yes", asks(&r.situation)),
            Some(false) => format!("{}: NO", asks(&r.situation)),
            None => "not judged".into(),
        };
        let _ = writeln!(
            s,
            "  COLREGS {} vs {}: {} ({} at {:.1} s, {:.0} m) — {verdict} ({})",
            r.ownship, r.contact, r.situation, r.trigger, r.at_s, r.range_m, r.detail
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dists(vs: &[Vessel]) -> super::super::collide::Distances {
        let pos: Vec<(f64, f64)> = vs.iter().map(|v| (v.x, v.y)).collect();
        super::super::collide::Distances::of(&pos)
    }

    fn v(x: f64, y: f64, heading: f64, speed: f64) -> Vessel {
        Vessel {
            x,
            y,
            heading,
            speed,
        }
    }

    #[test]
    fn situations_by_the_sectors() {
        // Head-on: each dead ahead of the other.
        assert_eq!(
            classify(&v(0., 0., 0., 2.), &v(5., 100., 180., 2.)),
            "headon"
        );
        // 30 deg off the bow each: not head-on; contact on starboard, os on its port.
        let os = v(0., 0., 0., 2.);
        let cn = v(60., 60., 270., 2.);
        assert_eq!(classify(&os, &cn), "giveway");
        assert_eq!(classify(&cn, &os), "standon");
        // Overtaking from astern, faster; the other is overtaken.
        let a = v(0., 0., 0., 3.);
        let b = v(2., 40., 0., 1.);
        assert_eq!(classify(&a, &b), "overtaking");
        assert_eq!(classify(&b, &a), "overtaken");
        // Same place astern but slower: no rule.
        assert_eq!(classify(&v(0., 0., 0., 0.5), &b), "none");
        // Relative bearings: due east of a north-heading ship is 90.
        assert!((rel_bearing(&os, &v(10., 0., 0., 0.)) - 90.0).abs() < 1e-9);
    }

    #[test]
    fn headon_side_and_giveway_crossings_are_judged() {
        let names = vec!["a".to_string(), "b".to_string()];
        // a heads north, b south, offset 10 m east: they pass port to port
        // (b on a's starboard side? b is east = starboard of a: starboard to starboard).
        let mut t = Tracker::new(2, 20.0, 3.0);
        for k in 0..=40 {
            let y = k as f64 * 5.0;
            let vs = [v(0., y, 0., 2.), v(10., 200. - y, 180., 2.)];
            t.update(k as f64, &vs, &dists(&vs), &|_, _| k >= 10);
        }
        let r = t.finish(&names);
        assert_eq!(r[0].situation, "headon");
        assert_eq!(r[0].passed, Some(false), "{}", r[0].detail);
        // Mirror: b 10 m west passes port to port.
        let mut t = Tracker::new(2, 20.0, 3.0);
        for k in 0..=40 {
            let y = k as f64 * 5.0;
            let vs = [v(0., y, 0., 2.), v(-10., 200. - y, 180., 2.)];
            t.update(k as f64, &vs, &dists(&vs), &|_, _| k >= 10);
        }
        assert_eq!(t.finish(&names)[0].passed, Some(true));

        // Give-way a (north) crosses b (west-bound from the east): ahead of b, then a
        // run where a waits and crosses astern.
        for (a_speed, ahead) in [(3.0, true), (1.0, false)] {
            let mut t = Tracker::new(2, 20.0, 3.0);
            for k in 0..=120 {
                let tt = k as f64;
                let vs = [
                    v(0., -60. + a_speed * tt, 0., a_speed),
                    v(60. - 2. * tt, 0., 270., 2.),
                ];
                t.update(tt, &vs, &dists(&vs), &|_, _| k >= 5);
            }
            let r = t.finish(&names);
            assert_eq!(r[0].situation, "giveway", "{r:?}");
            assert_eq!(r[0].passed, Some(!ahead), "{}", r[0].detail);
            assert_eq!(r[1].situation, "standon");
            assert_eq!(r[1].passed, Some(true), "kept course: {}", r[1].detail);
        }
    }

    #[test]
    fn tally_counts_judged_pairs() {
        let t = tally(
            [
                ("giveway", Some(true)),
                ("giveway", Some(false)),
                ("none", None),
                ("headon", Some(true)),
            ]
            .into_iter(),
        );
        assert_eq!(t[0], ("headon", 1, 1));
        assert_eq!(t[1], ("giveway", 2, 1));
    }

    #[test]
    fn the_terminal_lists_a_few_judgments_and_sums_up_many() {
        let rule = |k: usize, situation: &str, passed: Option<bool>| RuleRecord {
            ownship: format!("v{k}"),
            contact: "w".into(),
            situation: situation.into(),
            trigger: "alert".into(),
            at_s: 10.0,
            range_m: 70.0,
            os_cn_rel_bng: 0.0,
            cn_os_rel_bng: 0.0,
            passed,
            detail: "d".into(),
        };
        let few = [rule(0, "giveway", Some(true)), rule(1, "none", None)];
        let mut s = String::new();
        terminal(&mut s, None, &few);
        assert_eq!(s.lines().count(), 2, "{s}");
        assert!(s.contains("COLREGS v0 vs w: giveway"), "{s}");

        let mut many: Vec<RuleRecord> = (0..5).map(|k| rule(k, "giveway", Some(k < 2))).collect();
        many.extend((5..7).map(|k| rule(k, "headon", Some(true))));
        many.push(rule(7, "none", None));
        let mut s = String::new();
        terminal(&mut s, None, &many);
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines.len(), 4, "{s}");
        assert!(lines[0].contains("8 ordered pairs"), "{s}");
        assert_eq!(
            lines[1].trim(),
            "head-on encounters 2: passed port to port 2 of 2"
        );
        assert_eq!(
            lines[2].trim(),
            "give-way crossings 5: passed astern 2 of 5"
        );
        assert_eq!(lines[3].trim(), "not judged (no rule situation): 1");
    }
}
