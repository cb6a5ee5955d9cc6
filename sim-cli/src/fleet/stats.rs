//! The obstacle and COLREGS figures in a fleet's tables (issue 22 points 4 and 5):
//! `runs.csv` columns, the Monte Carlo lines, the terminal lines of one run.
//!
//! Columns after the fleet's own: with obstacles `ob_encounters`, `ob_near_misses`,
//! `ob_collisions`, `ob_closest_m`; with two vehicles or more, for each ordered pair
//! (ownship `a`, contact `b`) `rule_a_b` (the situation, `none`, or empty when they
//! never met) and `rule_ok_a_b` (1 passed as the rule asks, 0 not, empty not judged).

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use helm_sim::fleet::colregs::{asks, label, tally};
use helm_sim::fleet::obstacles::ObstacleOutcome;
use helm_sim::fleet::run::FleetOutcome;

/// A run's obstacle counts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObstacleCells {
    pub encounters: u32,
    pub near_misses: u32,
    pub collisions: u32,
    pub closest_m: f64,
}

impl ObstacleCells {
    pub fn of(o: &ObstacleOutcome) -> ObstacleCells {
        ObstacleCells {
            encounters: o.encounters,
            near_misses: o.near_misses,
            collisions: o.collisions,
            closest_m: o.closest_m,
        }
    }
}

/// One ordered pair's situation ("" never met) and verdict.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RuleCell {
    pub situation: String,
    pub passed: Option<bool>,
}

fn column(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// The ordered pairs (i, j), i ≠ j, row by row.
fn ordered(n: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..n).flat_map(move |i| (0..n).filter(move |j| *j != i).map(move |j| (i, j)))
}

/// The names `a_b` of the ordered pairs (none with one vehicle).
pub fn rule_columns(vehicles: &[String]) -> Vec<String> {
    ordered(vehicles.len())
        .map(|(i, j)| format!("{}_{}", column(&vehicles[i]), column(&vehicles[j])))
        .collect()
}

/// A run's cells, in [`rule_columns`]' order.
pub fn rule_cells(o: &FleetOutcome) -> Vec<RuleCell> {
    let names: Vec<&str> = o.vehicles.iter().map(|v| v.name.as_str()).collect();
    ordered(names.len())
        .map(|(i, j)| {
            o.colregs
                .iter()
                .find(|r| r.ownship == names[i] && r.contact == names[j])
                .map_or(
                    RuleCell {
                        situation: String::new(),
                        passed: None,
                    },
                    |r| RuleCell {
                        situation: r.situation.clone(),
                        passed: r.passed,
                    },
                )
        })
        .collect()
}

pub fn header(s: &mut String, vehicles: &[String], obstacles: bool) {
    if obstacles {
        s.push_str(",ob_encounters,ob_near_misses,ob_collisions,ob_closest_m");
    }
    for p in rule_columns(vehicles) {
        let _ = write!(s, ",rule_{p},rule_ok_{p}");
    }
}

/// A row's cells (`ob`, `rules`: the row's obstacle counts and rule cells).
pub fn cells(
    s: &mut String,
    vehicles: usize,
    obstacles: bool,
    ob: Option<&ObstacleCells>,
    rules: &[RuleCell],
) {
    if obstacles {
        match ob {
            Some(o) => {
                let _ = write!(
                    s,
                    ",{},{},{},{:.2}",
                    o.encounters, o.near_misses, o.collisions, o.closest_m
                );
            }
            None => s.push_str(",,,,"),
        }
    }
    let n = ordered(vehicles).count();
    for k in 0..n {
        match rules.get(k) {
            Some(c) => {
                let ok = match c.passed {
                    Some(true) => "1",
                    Some(false) => "0",
                    None => "",
                };
                let _ = write!(s, ",{},{ok}", c.situation);
            }
            None => s.push_str(",,"),
        }
    }
}

/// "give-way crossings: 998 of 1000 passed astern (99.8%, 95% interval a–b)" lines.
fn rule_lines(s: &mut String, t: &[(&'static str, usize, usize)], wilson: Wilson) {
    for &(sit, n, k) in t {
        if n == 0 {
            continue;
        }
        let (lo, hi) = wilson(k, n);
        let _ = writeln!(
            s,
            "  {}: {k} of {n} {} ({:.1}%, 95% interval {:.1}%–{:.1}%)",
            label(sit),
            asks(sit),
            100.0 * k as f64 / n as f64,
            100.0 * lo,
            100.0 * hi
        );
    }
}

/// The 95% interval of k successes in n trials (the Monte Carlo's own).
pub type Wilson = fn(usize, usize) -> (f64, f64);

/// The Monte Carlo lines (each ending in a newline), from the rows' obstacle counts and
/// rule cells.
pub fn distribution<'a>(
    s: &mut String,
    obs: &[&ObstacleCells],
    rules: impl Iterator<Item = &'a RuleCell>,
    wilson: Wilson,
) {
    if !obs.is_empty() {
        let n = obs.len();
        let hit = obs.iter().filter(|o| o.collisions > 0).count();
        let near = obs
            .iter()
            .filter(|o| o.collisions > 0 || o.near_misses > 0)
            .count();
        let closest = obs
            .iter()
            .map(|o| o.closest_m)
            .filter(|d| *d >= 0.0)
            .fold(f64::INFINITY, f64::min);
        for (what, k) in [("obstacle hit", hit), ("obstacle near miss", near)] {
            let (lo, hi) = wilson(k, n);
            let _ = writeln!(
                s,
                "  {what} rate {k}/{n} runs = {:.2}% (95% interval {:.2}% to {:.2}%)",
                100.0 * k as f64 / n as f64,
                100.0 * lo,
                100.0 * hi
            );
        }
        if closest.is_finite() {
            let _ = writeln!(s, "  closest to an obstacle over all runs {closest:.2} m");
        }
    }
    let t = tally(rules.map(|c| (c.situation.as_str(), c.passed)));
    rule_lines(s, &t, wilson);
}
