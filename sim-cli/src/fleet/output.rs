//! What a fleet run leaves behind: `summary.json` and the terminal summary.

use std::fmt::Write as _;

use serde::Serialize;

use crate::output::Pose;
use helm_sim::fleet::collide::{Detector, PairRecord};
use helm_sim::fleet::comms::CommsStats;
use helm_sim::fleet::run::{FleetOutcome, VehicleOutcome};
use helm_sim::fleet::spec::Ranges;

/// One vehicle in `summary.json`.
#[derive(Debug, Serialize)]
pub struct VehicleSummary<'a> {
    pub name: &'a str,
    pub color: &'a str,
    pub distance_m: f64,
    pub iterations: u64,
    pub helm_state: &'a str,
    pub drove: bool,
    pub waypoints_reached: u64,
    /// Behaviors the helm spawned (e.g. one avoidance behavior per alerted contact).
    pub spawned_behaviors: u64,
    pub node_reports_received: u64,
    /// NODE_REPORTs in its mail without a name, a time or a position.
    pub malformed_node_reports: u64,
    pub allstops: usize,
    pub behavior_errors: &'a [String],
    pub behavior_panics: &'a [String],
    pub start: Pose,
    pub end: Pose,
}

/// An all-stop of one vehicle (the fleet summary's `allstops`).
#[derive(Debug, Serialize)]
pub struct VehicleAllStop<'a> {
    pub vehicle: &'a str,
    /// Seconds from the start of the run.
    pub time: f64,
    pub reason: &'a str,
}

/// `summary.json` of a fleet run.
#[derive(Debug, Serialize)]
pub struct FleetSummary<'a> {
    pub mission: &'a str,
    pub vehicles: Vec<VehicleSummary<'a>>,
    /// Every vehicle's all-stops, vehicle after vehicle (as the one-vehicle summary has).
    pub allstops: Vec<VehicleAllStop<'a>>,
    /// Every vehicle's behavior errors, each `<vehicle>: <error>`.
    pub behavior_errors: Vec<String>,
    pub sim_time_s: f64,
    pub wall_time_s: f64,
    pub end_reason: &'a str,
    pub collision_ranges: Ranges,
    pub encounters: u32,
    pub near_misses: u32,
    pub collisions: u32,
    /// The closest approach over all pairs (m).
    pub closest_m: f64,
    pub pairs: &'a [PairRecord],
    pub comms: CommsStats,
    /// What went wrong, in plain words, worst first.
    pub warnings: Vec<String>,
    /// Vehicle-obstacle encounters, as uFldCollObDetect counts them (issue 22).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub obstacles: Option<&'a helm_sim::fleet::obstacles::ObstacleOutcome>,
    /// Each ordered pair's COLREGS situation and verdict (see `helm_sim::fleet::colregs`).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub colregs: &'a [helm_sim::fleet::colregs::RuleRecord],
}

fn vehicle(v: &VehicleOutcome) -> VehicleSummary<'_> {
    VehicleSummary {
        name: &v.name,
        color: &v.color,
        distance_m: v.observer.track.distance,
        iterations: v.iterations,
        helm_state: v.helm_state,
        drove: v.drove,
        waypoints_reached: v.observer.waypoints_reached,
        spawned_behaviors: v.observer.spawns,
        node_reports_received: v.node_reports,
        malformed_node_reports: v.malformed_reports,
        allstops: v.observer.allstops.len(),
        behavior_errors: &v.observer.behavior_errors,
        behavior_panics: &v.observer.behavior_panics,
        start: v.start.into(),
        end: v.end.into(),
    }
}

/// "1 vehicle", "8 vehicles".
pub fn vehicles(n: usize) -> String {
    format!("{n} vehicle{}", if n == 1 { "" } else { "s" })
}

/// The collision line of a picture's subtitle: nothing between pairs with one vehicle.
pub fn pair_line(pairs: &[PairRecord]) -> String {
    if pairs.is_empty() {
        return "one vehicle: no pairs".into();
    }
    let (e, n, c) = Detector::totals(pairs);
    format!(
        "{e} encounter(s), {n} near miss(es), {c} collision(s); closest approach {:.1} m",
        closest(pairs)
    )
}

/// The closest approach over all pairs (infinite with one vehicle).
pub fn closest(pairs: &[PairRecord]) -> f64 {
    pairs
        .iter()
        .map(|p| p.closest_m)
        .fold(f64::INFINITY, f64::min)
}

/// What went wrong, worst first (empty: nothing).
pub fn warnings(o: &FleetOutcome) -> Vec<String> {
    let mut w = Vec::new();
    for v in &o.vehicles {
        if let Some(p) = v.observer.behavior_panics.first() {
            w.push(format!(
                "{}: {} behavior panic(s) (first: {p})",
                v.name,
                v.observer.behavior_panics.len()
            ));
        }
    }
    for v in &o.vehicles {
        if !v.drove {
            w.push(format!(
                "{}: the helm stayed in {}: MOOS_MANUAL_OVERRIDE was never false",
                v.name, v.helm_state
            ));
        }
        if v.malformed_reports > 0 {
            w.push(format!(
                "{}: {} malformed NODE_REPORT(s) in its mail",
                v.name, v.malformed_reports
            ));
        }
    }
    w
}

pub fn summary<'a>(o: &'a FleetOutcome, mission: &'a str) -> FleetSummary<'a> {
    let (encounters, near_misses, collisions) = Detector::totals(&o.pairs);
    let c = closest(&o.pairs);
    FleetSummary {
        mission,
        vehicles: o.vehicles.iter().map(vehicle).collect(),
        allstops: o
            .vehicles
            .iter()
            .flat_map(|v| {
                v.observer.allstops.iter().map(|a| VehicleAllStop {
                    vehicle: &v.name,
                    time: a.time,
                    reason: &a.reason,
                })
            })
            .collect(),
        behavior_errors: o
            .vehicles
            .iter()
            .flat_map(|v| {
                v.observer
                    .behavior_errors
                    .iter()
                    .map(move |e| format!("{}: {e}", v.name))
            })
            .collect(),
        sim_time_s: o.sim_time_s,
        wall_time_s: o.wall_time_s,
        end_reason: &o.end_reason,
        collision_ranges: o.ranges,
        encounters,
        near_misses,
        collisions,
        // JSON has no infinity: a lone vehicle has no closest approach.
        closest_m: if c.is_finite() { c } else { -1.0 },
        pairs: &o.pairs,
        comms: o.comms,
        warnings: warnings(o),
        obstacles: o.obstacles.as_ref(),
        colregs: &o.colregs,
    }
}

/// The terminal summary (lines).
pub fn terminal(o: &FleetOutcome, mission: &str) -> String {
    let mut s = String::new();
    for w in warnings(o) {
        let _ = writeln!(s, "PROBLEM: {w}");
    }
    let speedup = if o.wall_time_s > 0.0 {
        format!("{:.0}x real time", o.sim_time_s / o.wall_time_s)
    } else {
        "-".into()
    };
    let _ = writeln!(
        s,
        "{mission}: {}, {} after {:.1} s simulated, {:.3} s wall ({speedup})",
        vehicles(o.vehicles.len()),
        o.end_reason,
        o.sim_time_s,
        o.wall_time_s
    );
    for v in &o.vehicles {
        let _ = writeln!(
            s,
            "  {:<10} {:>8.1} m, {} iterations, helm {}, {} behavior(s) spawned, {} node reports, end x={:.1} y={:.1}",
            v.name,
            v.observer.track.distance,
            v.iterations,
            v.helm_state,
            v.observer.spawns,
            v.node_reports,
            v.end.x,
            v.end.y
        );
    }
    // One vehicle has no pairs: no vessel-to-vessel line to print.
    if !o.pairs.is_empty() {
        let (e, n, c) = Detector::totals(&o.pairs);
        let r = &o.ranges;
        let _ = writeln!(
            s,
            "  encounters (< {} m) {e}, near misses (< {} m) {n}, collisions (< {} m) {c}",
            r.encounter, r.near_miss, r.collision
        );
    }
    let mut pairs: Vec<&PairRecord> = o.pairs.iter().collect();
    pairs.sort_by(|a, b| a.closest_m.total_cmp(&b.closest_m));
    for p in pairs.iter().take(5) {
        let _ = writeln!(
            s,
            "  closest {}-{}: {:.1} m at {:.1} s",
            p.a, p.b, p.closest_m, p.closest_time_s
        );
    }
    helm_sim::fleet::colregs::terminal(&mut s, o.obstacles.as_ref(), &o.colregs);
    let cm = &o.comms;
    let _ = write!(
        s,
        "  node reports: {} posted, {} delivered, {} out of range, {} dropped",
        cm.reports, cm.delivered, cm.out_of_range, cm.dropped
    );
    s
}
