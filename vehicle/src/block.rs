//! Reading the simulator's `ProcessConfig` block strictly: every line is either used,
//! known to uSimMarine but not modelled here (a note), unknown (a warning, with a
//! did-you-mean), or a value that cannot be read (an error). Nothing is dropped silently.

use moos_mission::mission::{ConfigLine, MissionFile};

/// The block names read, in this order: the first present is used.
pub const SIM_BLOCKS: [&str; 2] = ["uSimMarine", "uSimMarineV22"];

/// How bad a block line is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    /// A uSimMarine parameter this model does not implement; ignored.
    Note,
    /// A name neither uSimMarine nor this model knows; ignored.
    Warning,
    /// A value that cannot be read: the run must not start on a guess.
    Error,
}

/// One problem of the simulator block, with its line.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockProblem {
    pub severity: Severity,
    /// `file:line: text`.
    pub text: String,
}

/// The start pose and parameters read from the block; `None` where the block is silent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimBlock {
    /// The block's name (`uSimMarine` or `uSimMarineV22`), if there is one.
    pub block: Option<&'static str>,
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub heading: Option<f64>,
    pub speed: Option<f64>,
    pub depth: Option<f64>,
    pub speed_lag: Option<f64>,
    pub turn_rate: Option<f64>,
    pub depth_rate: Option<f64>,
    /// `max_depth_rate_speed`: the speed at which the full depth rate is reached (the
    /// rate scales with speed below it).
    pub depth_rate_speed: Option<f64>,
    /// `buoyancy_rate`: how fast (m/s) a stopped vehicle rises toward the surface.
    pub buoyancy_rate: Option<f64>,
    /// `default_water_depth` (or `water_depth`): the bottom; the vehicle goes no deeper.
    pub water_depth: Option<f64>,
    pub problems: Vec<BlockProblem>,
}

/// Parameters uSimMarine / uSimMarineV22 (and every MOOS app) accept that this
/// kinematic model does not implement: accepted with a note, never an error.
const NOT_MODELLED: &[&str] = &[
    "maxapptick",
    "iteratemode",
    "term_reporting",
    "prefix",
    "drift_x",
    "drift_y",
    "drift_vector",
    "rotate_speed",
    "max_acceleration",
    "max_deceleration",
    "max_rudder_degs_per_sec",
    "sim_pause",
    "dual_state",
    "thrust_factor",
    "thrust_reflect",
    "thrust_map",
    "turn_loss",
    "trim_tolerance",
    "max_trim_delay",
    "post_des_thrust",
    "post_des_rudder",
    "depth_control",
    "wormhole",
    "obstacle_hit",
    "maxrudder",
    "maxthrust",
    "maxpitch",
    "maxelevator",
    "speed_factor",
    "sim_instability",
];

/// Prefixes of uSimMarineV22's controller parameters (`yaw_pid_kp`, ...).
const NOT_MODELLED_PREFIXES: &[&str] = &[
    "yaw_pid_",
    "speed_pid_",
    "z_to_pitch_pid_",
    "pitch_pid_",
    "depth_pid_",
];

/// What this model reads.
const MODELLED: &[&str] = &[
    "start_x",
    "start_y",
    "start_heading",
    "start_speed",
    "start_depth",
    "start_pos",
    "speed_lag",
    "turn_rate",
    "depth_rate",
    "max_depth_rate",
    "max_depth_rate_speed",
    "buoyancy_rate",
    "default_water_depth",
    "water_depth",
];

/// A number as uSimMarine reads one: the whole trimmed text, finite.
fn number(text: &str) -> Option<f64> {
    let t = text.trim();
    if t.is_empty() || !t.chars().all(|c| c.is_ascii_digit() || "+-.eE".contains(c)) {
        return None;
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

impl SimBlock {
    /// Read the first of [`SIM_BLOCKS`] present in `mission`.
    pub fn read(mission: &MissionFile) -> SimBlock {
        let mut out = SimBlock::default();
        let Some((name, lines)) = SIM_BLOCKS
            .iter()
            .find_map(|b| mission.process_config(b).map(|l| (*b, l)))
        else {
            return out;
        };
        out.block = Some(name);
        let file = mission.path().display().to_string();
        for l in &lines {
            out.line(&file, l);
        }
        out
    }

    fn problem(&mut self, severity: Severity, file: &str, l: &ConfigLine, text: String) {
        self.problems.push(BlockProblem {
            severity,
            text: format!("{file}:{}: {text}", l.line),
        });
    }

    fn line(&mut self, file: &str, l: &ConfigLine) {
        let key = l.name.to_ascii_lowercase();
        let value = l.value.trim();
        let block = self.block.unwrap_or("uSimMarine");
        if l.value.is_empty() && l.raw == l.name {
            self.problem(
                Severity::Warning,
                file,
                l,
                format!("{block}: line `{}` is not `name = value`; ignored", l.raw),
            );
            return;
        }
        let bad = |what: &str| format!("{block}: {} = {value}: expected {what}", l.name);
        match key.as_str() {
            "start_pos" => match start_pos(value) {
                Ok(p) => {
                    self.x = p.x.or(self.x);
                    self.y = p.y.or(self.y);
                    self.heading = p.heading.or(self.heading);
                    self.speed = p.speed.or(self.speed);
                    self.depth = p.depth.or(self.depth);
                }
                Err(why) => self.problem(
                    Severity::Error,
                    file,
                    l,
                    format!(
                        "{block}: start_pos = {value}: {why} (expected `x=0, y=-20, heading=180, \
                         speed=0, depth=0` or `0,-20,180,0`)"
                    ),
                ),
            },
            "start_x" | "start_y" | "start_heading" | "start_depth" => match number(value) {
                Some(v) => {
                    let slot = match key.as_str() {
                        "start_x" => &mut self.x,
                        "start_y" => &mut self.y,
                        "start_heading" => &mut self.heading,
                        _ => &mut self.depth,
                    };
                    *slot = Some(v);
                }
                None => self.problem(Severity::Error, file, l, bad("a number")),
            },
            "start_speed" => match number(value).filter(|v| *v >= 0.0) {
                Some(v) => self.speed = Some(v),
                None => self.problem(Severity::Error, file, l, bad("a number >= 0")),
            },
            "speed_lag" | "turn_rate" | "depth_rate" | "max_depth_rate" => {
                match number(value).filter(|v| *v > 0.0) {
                    Some(v) => {
                        let slot = match key.as_str() {
                            "speed_lag" => &mut self.speed_lag,
                            "turn_rate" => &mut self.turn_rate,
                            _ => &mut self.depth_rate,
                        };
                        *slot = Some(v);
                    }
                    None => self.problem(Severity::Error, file, l, bad("a number > 0")),
                }
            }
            "max_depth_rate_speed" | "default_water_depth" | "water_depth" => {
                match number(value).filter(|v| *v > 0.0) {
                    Some(v) => {
                        if key == "max_depth_rate_speed" {
                            self.depth_rate_speed = Some(v);
                        } else {
                            self.water_depth = Some(v);
                        }
                    }
                    None => self.problem(Severity::Error, file, l, bad("a number > 0")),
                }
            }
            "buoyancy_rate" => match number(value).filter(|v| *v >= 0.0) {
                Some(v) => self.buoyancy_rate = Some(v),
                None => self.problem(Severity::Error, file, l, bad("a number >= 0")),
            },
            // The simulator's tick: read by whoever drives the model.
            "apptick" | "commstick" => {}
            k if NOT_MODELLED.contains(&k)
                || NOT_MODELLED_PREFIXES.iter().any(|p| k.starts_with(p)) =>
            {
                self.problem(
                    Severity::Note,
                    file,
                    l,
                    format!(
                        "{block}: {} is not modelled by this simulator; ignored",
                        l.name
                    ),
                );
            }
            _ => {
                let hint = nearest(&key)
                    .map(|n| format!(" (did you mean `{n}`?)"))
                    .unwrap_or_default();
                self.problem(
                    Severity::Warning,
                    file,
                    l,
                    format!(
                        "{block}: unknown parameter `{}`{hint}; ignored. Read: {}",
                        l.name,
                        MODELLED.join(", ")
                    ),
                );
            }
        }
    }

    /// The problems at least as bad as `min`.
    pub fn problems_at_least(&self, min: Severity) -> impl Iterator<Item = &BlockProblem> {
        self.problems.iter().filter(move |p| p.severity >= min)
    }

    /// Its errors' texts, in file order: values that cannot be read (a run must not
    /// start).
    pub fn error_texts(&self) -> Vec<&str> {
        self.problems_at_least(Severity::Error)
            .map(|p| p.text.as_str())
            .collect()
    }

    /// Its warnings' texts, in file order: names it ignores.
    pub fn warning_texts(&self) -> impl Iterator<Item = &str> {
        self.problems
            .iter()
            .filter(|p| p.severity == Severity::Warning)
            .map(|p| p.text.as_str())
    }
}

/// The pieces of a `start_pos` value.
#[derive(Default)]
struct StartPos {
    x: Option<f64>,
    y: Option<f64>,
    heading: Option<f64>,
    speed: Option<f64>,
    depth: Option<f64>,
}

/// `start_pos` in either of the forms the distribution's missions write: keyed
/// (`x=100, y=-100, heading=90, speed=0[, depth=0]`, any order) or positional
/// (`100,-100[,90[,0[,0]]]`: x, y, heading, speed, depth).
fn start_pos(value: &str) -> Result<StartPos, String> {
    let mut p = StartPos::default();
    let parts: Vec<&str> = value.split(',').map(str::trim).collect();
    if parts.iter().any(|s| s.contains('=')) {
        for part in parts {
            let Some((k, v)) = part.split_once('=') else {
                return Err(format!("`{part}` is not `name=value`"));
            };
            let n = number(v).ok_or_else(|| format!("`{}` is not a number", v.trim()))?;
            let slot = match k.trim().to_ascii_lowercase().as_str() {
                "x" => &mut p.x,
                "y" => &mut p.y,
                "heading" => &mut p.heading,
                "speed" => &mut p.speed,
                "depth" => &mut p.depth,
                other => return Err(format!("unknown field `{other}`")),
            };
            *slot = Some(n);
        }
    } else {
        if parts.len() < 2 || parts.len() > 5 {
            return Err(format!("{} fields", parts.len()));
        }
        let slots = [
            &mut p.x,
            &mut p.y,
            &mut p.heading,
            &mut p.speed,
            &mut p.depth,
        ];
        for (slot, part) in slots.into_iter().zip(parts) {
            *slot = Some(number(part).ok_or_else(|| format!("`{part}` is not a number"))?);
        }
    }
    if p.speed.is_some_and(|s| s < 0.0) {
        return Err("speed must be >= 0".into());
    }
    Ok(p)
}

/// The known name closest to `key` (edit distance at most 3), for a did-you-mean.
fn nearest(key: &str) -> Option<&'static str> {
    MODELLED
        .iter()
        .chain(NOT_MODELLED)
        .map(|n| (edit_distance(key, n), *n))
        .filter(|(d, _)| *d <= 3)
        .min()
        .map(|(_, n)| n)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn read(body: &str) -> SimBlock {
        let text = format!("ProcessConfig = uSimMarine\n{{\n{body}\n}}\n");
        SimBlock::read(&MissionFile::parse(&text, Path::new("m.moos")).expect("parses"))
    }

    #[test]
    fn keyed_start_pos() {
        let b = read("  start_pos = x=100, y=-100, heading=90, speed=0");
        assert_eq!(
            (b.x, b.y, b.heading, b.speed),
            (Some(100.0), Some(-100.0), Some(90.0), Some(0.0))
        );
        assert!(b.problems.is_empty(), "{:?}", b.problems);
    }

    #[test]
    fn positional_start_pos_and_upper_case_keys() {
        let b = read("  START_POS = 5,-7, 180, 1\n  TURN_RATE = 40");
        assert_eq!(
            (b.x, b.y, b.heading, b.speed, b.turn_rate),
            (Some(5.0), Some(-7.0), Some(180.0), Some(1.0), Some(40.0))
        );
    }

    #[test]
    fn bad_values_are_errors_with_their_line() {
        let b = read("  turn_rate = banana\n  start_heading = north\n  start_pos = x=1, q=2");
        let errs = b.error_texts();
        assert_eq!(errs.len(), 3, "{errs:?}");
        assert!(errs[0].starts_with("m.moos:3: ") && errs[0].contains("a number > 0"));
        assert!(errs[1].starts_with("m.moos:4: ") && errs[1].contains("north"));
        assert!(errs[2].contains("unknown field `q`"));
    }

    #[test]
    fn unknown_names_warn_with_a_suggestion_and_known_ones_note() {
        let b = read("  strat_x = 3\n  thrust_map = 0:0, 100:5\n  yaw_pid_kp = 1\n  AppTick = 4");
        assert_eq!(b.problems[0].severity, Severity::Warning);
        assert!(b.problems[0].text.contains("did you mean `start_x`"));
        assert_eq!(b.problems[1].severity, Severity::Note);
        assert_eq!(b.problems[2].severity, Severity::Note);
        assert_eq!(b.problems.len(), 3, "AppTick is used: {:?}", b.problems);
        assert_eq!(b.x, None);
    }

    #[test]
    fn v22_block_is_read_when_there_is_no_usimmarine() {
        let text = "ProcessConfig = uSimMarineV22\n{\n start_pos = x=1, y=2\n}\n";
        let b = SimBlock::read(&MissionFile::parse(text, Path::new("m.moos")).expect("parses"));
        assert_eq!(
            (b.block, b.x, b.y),
            (Some("uSimMarineV22"), Some(1.0), Some(2.0))
        );
    }
}
