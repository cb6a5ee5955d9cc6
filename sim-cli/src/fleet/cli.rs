//! `helm sim` on a fleet scenario: one run (logs, picture, summary) or a Monte Carlo.

use std::path::Path;

use crate::args::{progress, verdict, SimArgs};
use crate::output;
use helm_sim::fleet::run::{FleetOptions, FleetPlan};
use helm_sim::run::SimError;

/// Run the fleet of the scenario at `path` as `args` ask.
pub fn run(args: &SimArgs, path: &Path) -> Result<u8, SimError> {
    if !args.bhv.is_empty() {
        return Err(SimError::Fleet(format!(
            "{}: a fleet scenario names each vehicle's behavior files (`bhv = [...]`); \
             none may be given on the command line",
            path.display()
        )));
    }
    let plan = FleetPlan::load(path)?;
    for v in &plan.vehicles {
        for line in &v.library_report {
            tracing::info!("{}: {line}", v.spec.name);
        }
        for w in &v.warnings {
            eprintln!("warning: {}: {w}", v.spec.name);
        }
    }
    if args.runs > 1 || args.shard.is_some() {
        return super::montecarlo::cli(args, &plan);
    }
    single(args, &plan)
}

fn single(args: &SimArgs, plan: &FleetPlan) -> Result<u8, SimError> {
    let dir = output::out_dir(args.out.as_deref(), &plan.name)?;
    let max = args.max_time.unwrap_or(plan.scenario.max_time);
    let bar = progress(
        max.ceil() as u64,
        "{spinner} simulated {pos}/{len} s [{bar:40}] {elapsed_precise}",
    );
    let tick = |t: f64| bar.set_position(t as u64);
    let shifts = match args.jitter {
        Some(j) => super::montecarlo::shifts(&j, args.seed, plan.vehicles.len()),
        None => Vec::new(),
    };
    let o = plan.run(
        &shifts,
        &FleetOptions {
            alog_dir: Some(dir.clone()),
            max_time: args.max_time,
            seed: 0,
            progress: Some(&tick),
        },
    )?;
    bar.finish_and_clear();
    let summary = super::output::summary(&o, &plan.name);
    let json = serde_json::to_string_pretty(&summary).unwrap_or_default();
    let summary_path = dir.join("summary.json");
    output::write(&summary_path, &(json + "\n"))?;
    let title = format!(
        "{}: {}, {} after {:.1} s",
        plan.name,
        super::output::vehicles(o.vehicles.len()),
        o.end_reason,
        o.sim_time_s
    );
    let sub = format!(
        "{}; ticks every {} s",
        super::output::pair_line(&o.pairs),
        o.tick
    );
    let picture = dir.join(format!("{}.svg", plan.name));
    output::write(&picture, &super::picture::svg(&o, &title, &sub))?;
    println!("{}", super::output::terminal(&o, &plan.name));
    println!("picture: {}", picture.display());
    println!("logs:    {}/<vehicle>.alog", dir.display());
    println!("summary: {}", summary_path.display());
    let panics: usize = o
        .vehicles
        .iter()
        .map(|v| v.observer.behavior_panics.len())
        .sum();
    let errors: usize = o
        .vehicles
        .iter()
        .map(|v| v.observer.behavior_errors.len())
        .sum();
    Ok(verdict(
        args.strict,
        panics,
        errors,
        o.vehicles.iter().any(|v| !v.drove),
    ))
}
