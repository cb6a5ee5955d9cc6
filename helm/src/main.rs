//! `helm`: the IvP Helm. See `helm --help`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use helm_conform as conform;
use helm_engine::factory::BehaviorFactory;

/// The IvP Helm (pHelmIvP) rebuilt in Rust: behavior-based autonomy with plugin behaviors.
#[derive(Parser)]
#[command(
    name = "helm",
    version,
    about = "The IvP Helm of MOOS-IvP (pHelmIvP), rebuilt in Rust, with plugin behaviors",
    long_about = None,
    after_help = "As a drop-in for pHelmIvP (what pAntler runs):\n  \
        helm MISSION.moos [FILE.bhv]... [NAME] [--alias=NAME] [--verbose=verbose|terse|quiet]\n  \
        helm -v | -e | -i | -w | -help    (version, example block, interface, docs, help)\n\n\
        Examples:\n  \
        helm sim missions/alpha                         a mission in fast time: picture, log, summary\n  \
        helm sim missions/alpha --runs 100 --jitter x=5,y=5,heading=20   Monte Carlo\n  \
        helm check missions/alpha                       every configuration problem\n  \
        helm run --embedded missions/alpha              in real time, on this machine alone\n  \
        helm alpha.moos pHelmIvP                        as pAntler starts pHelmIvP\n\n\
        Environment:\n  \
        IVP_BEHAVIOR_DIRS      colon-separated folders of behavior libraries (searched first)\n  \
        IVP_HELM_BUNDLED_DIR   folders of the shipped libraries (default: beside this binary,\n                         \
        then ../lib/ivp-helm from it; empty: none)\n  \
        HELM_VERBOSE           verbose | terse | quiet: terminal output of a running helm\n  \
        RUST_LOG               log filter (e.g. info, helm_engine=debug); default: errors only\n\n\
        Exit codes (check, sim, run, conform alike):\n  \
        0  done, nothing wrong\n  \
        1  the mission is wrong (MALCONFIG, a bad simulator block or scenario; conform: a case failed)\n  \
        2  usage: a bad argument, or a file that cannot be read as what it should be (missing,\n     \
        unreadable, a .bhv given as the mission, a folder without one mission or case)\n  \
        3  the run went wrong: a behavior panicked (sim --strict: also any behavior error,\n     \
        or a helm that never drove)\n  \
        4  the environment failed: the MOOSDB, the network, an output that cannot be written\n  \
        130 interrupted"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the helm on a mission, as pHelmIvP does.
    ///
    /// Connects to the MOOSDB named by ServerHost/ServerPort in MISSION. With
    /// --embedded, starts a MOOSDB and a vehicle simulator in this process first, so the
    /// mission runs on one machine with nothing else installed.
    ///
    /// Example: helm run --embedded missions/alpha/alpha.moos
    Run {
        /// The mission file (`.moos`), or a folder holding one.
        mission: PathBuf,
        /// Extra behavior files (`.bhv`).
        bhv: Vec<PathBuf>,
        /// The app name whose ProcessConfig block is read.
        #[arg(long, default_value = "pHelmIvP")]
        alias: String,
        /// Start an embedded MOOSDB and vehicle simulator.
        #[arg(long)]
        embedded: bool,
        /// Stop after this many seconds.
        #[arg(long)]
        duration: Option<f64>,
        /// No terminal heartbeat or summary.
        #[arg(long)]
        quiet: bool,
        /// Log every posting and every mail from other apps to this `.alog` file.
        #[arg(long)]
        alog: Option<PathBuf>,
    },
    /// Run a mission in deterministic fast time: helm, simulator and bus in one process.
    ///
    /// Writes an .alog, an SVG picture and summary.json to runs/<mission>-<time>/ (or
    /// --out); with --runs N, runs it N times from perturbed starts on all cores and
    /// writes runs.csv. A scenario.toml beside the mission adds pokes, end conditions
    /// and start overrides; with [[vehicle]] entries it runs a fleet (node reports,
    /// contact managers, collision and COLREGS statistics, obstacles); see
    /// missions/README.md.
    ///
    /// A single run logs all the helm posts, BHV_IPF included, as a wildcard pLogger
    /// would: a 10-vehicle fleet hour with avoidance writes about 7 GB, and writing
    /// takes more of the run's time than the helms do. For timing or statistics use
    /// --runs, which writes no logs unless --alogs asks.
    ///
    /// Examples: helm sim missions/alpha; helm sim missions/encounter --runs 1000
    /// --jitter x=10,y=10,heading=15; helm sim missions/fleet --runs 400 --shard 2/4
    /// --out shard2, then helm sim merge shard1 shard2 shard3 shard4 --out all
    Sim(helm_sim_cli::cli::SimArgs),
    /// A map in the browser: live from a MOOSDB, or replaying an .alog or a run folder.
    ///
    /// Serves the page on http://127.0.0.1:8080/ (loopback only; --bind exposes it).
    ///
    /// Example: helm view runs/alpha-<time>/
    View(viewer::cli::ViewArgs),
    /// Read a mission as the helm would and report every configuration problem.
    ///
    /// Reads the `ProcessConfig = <alias>` block of MISSION, the `.bhv` files it names
    /// (`behaviors = ...`) and those given here, and the behavior libraries in
    /// IVP_BEHAVIOR_DIRS, `ivp_behavior_dir` lines and (for types still missing) beside
    /// the helm binary (IVP_HELM_BUNDLED_DIR overrides). Prints each problem with its file
    /// and line, and exits 1 if the helm would be MALCONFIG (it would never drive).
    ///
    /// Example: helm check missions/alpha/alpha.moos
    Check {
        /// The mission file (`.moos`), or a folder holding one.
        mission: PathBuf,
        /// Extra behavior files (`.bhv`), as on the pHelmIvP command line.
        bhv: Vec<PathBuf>,
        /// The app name whose ProcessConfig block is read.
        #[arg(long, default_value = "pHelmIvP")]
        alias: String,
    },
    /// Replay conformance cases recorded from the real C++ helm and compare.
    ///
    /// PATH is a case file (`*.toml`) or a folder of them (searched recursively; none
    /// found: exit 2). Prints one line per failing case (case, step, variable, expected,
    /// got: its first difference) and ends with `N passed, M failed`; exits 1 if any
    /// case failed. A case naming a behavior type this project does not have yet is
    /// listed as `waiting for its behavior types: ...` and neither passes nor fails.
    /// Behavior libraries are loaded from the colon-separated directories in
    /// IVP_BEHAVIOR_DIRS, then beside the helm binary.
    Conform {
        /// Print every difference, not only the first of each failing case.
        #[arg(long)]
        all: bool,
        /// Replay each case for at least 2 s and print `bench <case> <µs>`: the mean time
        /// of the decision step (modes, behaviors, solve), as the C++ timings measure it.
        /// Where the case's `.timing-O2.json` is beside it, the C++ helm's mean and
        /// median-replay times follow with our share of each, and a last line counts the
        /// cases at most 1/10 of it. The C++ times were recorded on another machine.
        #[arg(long)]
        bench: bool,
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
}

/// The mission file a MISSION argument names: the file, or the one `.moos` in a folder
/// (as `helm sim` takes it).
fn mission_arg(path: &std::path::Path) -> Result<PathBuf, ExitCode> {
    helm_sim::find_mission(path).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(e.exit_code())
    })
}

fn check_cmd(mission: &std::path::Path, bhv: &[PathBuf], alias: &str) -> ExitCode {
    let mission = match mission_arg(mission) {
        Ok(m) => m,
        Err(code) => return code,
    };
    let mission = mission.as_path();
    let loaded = match helm_mission::load(mission, bhv, alias) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    for line in &loaded.library_report {
        println!("{line}");
    }
    let files = loaded.bhv_files.clone();
    let (helm, file) = loaded.into_helm();
    for f in &files {
        println!("Behavior file: {}", f.display());
    }
    // The simulator block, read as `helm sim` and `run --embedded` read it.
    let block = vehicle_model::SimBlock::read(&file);
    for p in &block.problems {
        let kind = match p.severity {
            vehicle_model::Severity::Note => "note",
            vehicle_model::Severity::Warning => "warning",
            vehicle_model::Severity::Error => "error",
        };
        println!("{kind}: {}", p.text);
    }
    let sim_errors = block
        .problems_at_least(vehicle_model::Severity::Error)
        .count();
    if sim_errors > 0 && helm.config_warnings().is_empty() {
        println!(
            "{sim_errors} problem(s) in the simulator block: `helm sim` and `helm run --embedded` \
             would not start"
        );
        return ExitCode::FAILURE;
    }
    if helm.config_warnings().is_empty() {
        println!(
            "ok: {} behavior(s): {}",
            helm.behavior_names().len(),
            helm.behavior_names().join(", ")
        );
        ExitCode::SUCCESS
    } else {
        for w in helm.config_warnings() {
            println!("{w}");
        }
        println!(
            "MALCONFIG: {} configuration problem(s); the helm would not drive",
            helm.config_warnings().len()
        );
        ExitCode::FAILURE
    }
}

fn factory_from_env() -> BehaviorFactory {
    let dirs = helm_mission::behavior_dirs_from_env();
    let (factory, report) = helm_mission::factory_with_bundled(&dirs);
    for line in report {
        tracing::info!("{line}");
    }
    factory
}

/// `helm conform --bench`: each case's decision step beside the C++ helm's time for it.
fn bench_cmd(files: &[PathBuf], factory: &BehaviorFactory) -> ExitCode {
    let mut failed = false;
    // Cases with a C++ timing, and how many of them are at most 1/10 of it (mean, median).
    let (mut compared, mut by_mean, mut by_median) = (0, 0, 0);
    let mut cpp_cpu = String::new();
    for f in files {
        match conform::bench_file(f, factory, 2.0) {
            Ok(conform::BenchOutcome::Waiting(types)) => {
                println!(
                    "bench {}: waiting for its behavior types: {}",
                    f.display(),
                    types.join(", ")
                );
            }
            Ok(conform::BenchOutcome::Timed(r)) => {
                match conform::CppTiming::beside(f) {
                    Ok(Some(cpp)) => {
                        let (mean, median) = against_cpp(&r, &cpp);
                        compared += 1;
                        by_mean += usize::from(mean <= 0.1);
                        by_median += usize::from(median <= 0.1);
                        if cpp_cpu.is_empty() {
                            cpp_cpu = cpp.cpu;
                        }
                    }
                    Ok(None) => println!("bench {} {:.3}", r.name, r.decision_us),
                    Err(e) => {
                        failed = true;
                        println!("bench {} {:.3}", r.name, r.decision_us);
                        eprintln!("bench {}: {e}", f.display());
                    }
                }
                // After the case's line, in order when both go to one file.
                let _ = std::io::Write::flush(&mut std::io::stdout());
                eprintln!(
                    "  (whole step incl. mail, publication and replay: {:.3} µs)",
                    r.whole_us
                );
            }
            Err(e) => {
                failed = true;
                eprintln!("bench {}: {e}", f.display());
            }
        }
    }
    if compared > 0 {
        if cpp_cpu.is_empty() {
            cpp_cpu = "an unnamed CPU".into();
        }
        println!(
            "at most 1/10 of the C++ time: {by_mean} of {compared} cases by the mean, \
             {by_median} by the median replay (C++ timed on {cpp_cpu}; this machine: {})",
            this_cpu()
        );
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// Prints a case's line with the C++ times; returns our mean and median over theirs.
fn against_cpp(r: &conform::BenchResult, cpp: &conform::CppTiming) -> (f64, f64) {
    let mean = r.decision_us / cpp.mean_us;
    let median = r.median_rep_us / cpp.median_rep_us;
    println!(
        "bench {} {:.3}  (C++ {:.3}: {mean:.3}; median of {} replays {:.3} vs {:.3}: {median:.3})",
        r.name, r.decision_us, cpp.mean_us, r.reps, r.median_rep_us, cpp.median_rep_us
    );
    (mean, median)
}

/// The CPU model, as Linux names it (timings differ between machines).
fn this_cpu() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("model name").and_then(|r| r.split_once(':')))
                .map(|(_, m)| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

fn conform_cmd(bench: bool, all: bool, paths: &[PathBuf]) -> ExitCode {
    let files = match conform::collect(paths) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let factory = factory_from_env();
    if bench {
        return bench_cmd(&files, &factory);
    }
    let (mut passed, mut failed, mut waiting) = (0, 0, 0);
    for f in &files {
        let r = conform::run_file(f, &factory);
        match r.outcome() {
            conform::Outcome::Passed => {
                passed += 1;
                continue;
            }
            conform::Outcome::Waiting => {
                waiting += 1;
                println!(
                    "{}: waiting for its behavior types: {}",
                    r.name,
                    r.waiting_for.join(", ")
                );
                continue;
            }
            conform::Outcome::Failed => failed += 1,
        }
        if let Some(e) = &r.error {
            println!("{}: error: {e}", r.name);
        }
        // One line per failing case (its first difference); --all lists every one.
        let shown = if all { r.mismatches.len() } else { 1 };
        for m in r.mismatches.iter().take(shown) {
            let more = r.mismatches.len() - shown;
            let tail = if more > 0 {
                format!(" (+{more} more differences; --all lists them)")
            } else {
                String::new()
            };
            println!(
                "{} step {} {}: expected {} got {}{tail}",
                r.name, m.step, m.var, m.expected, m.got
            );
        }
    }
    // Waiting cases neither pass nor fail: they name types the project does not have yet.
    let waiting = if waiting > 0 {
        format!(", {waiting} waiting for their behavior types")
    } else {
        String::new()
    };
    println!("{passed} passed, {failed} failed{waiting}");
    if failed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("error")),
        )
        .with_writer(std::io::stderr)
        // Colours only on a terminal: a log file gets plain text.
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .init();
    let mut args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let called_phelm = args
        .first()
        .and_then(|p| std::path::Path::new(p).file_name())
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("pHelmIvP"));
    let first = args.get(1).and_then(|a| a.to_str()).unwrap_or_default();
    const SUBCOMMANDS: [&str; 5] = ["run", "sim", "check", "conform", "view"];
    if called_phelm && SUBCOMMANDS.contains(&first) {
        // A pHelmIvP link takes pHelmIvP's command line only: starting a helm on a
        // mission named "sim" would be a surprise.
        eprintln!(
            "error: pHelmIvP takes pHelmIvP's command line (MISSION.moos [FILE.bhv]... [NAME]); \
             `{first}` is a command of `helm`: run it as `helm {first} ...`"
        );
        return ExitCode::from(2);
    }
    if !called_phelm && first == "-help" {
        // One help text for `helm -help` and `helm --help`.
        args[1] = "--help".into();
    }
    if helm_app::phelmivp::is_phelmivp_form(&args) {
        return phelmivp_main(&args[1..]);
    }
    if args.get(1).is_none_or(|a| a != "run") {
        end_quietly_when_output_closes();
    }
    let cli = Cli::parse_from(&args);
    match cli.command {
        Command::Conform { bench, all, paths } => conform_cmd(bench, all, &paths),
        Command::Sim(args) => helm_sim_cli::cli::main(&args),
        Command::View(args) => viewer::cli::main(&args),
        Command::Check {
            mission,
            bhv,
            alias,
        } => check_cmd(&mission, &bhv, &alias),
        Command::Run {
            mission,
            bhv,
            alias,
            embedded,
            duration,
            quiet,
            alog,
        } => {
            let mission = match mission_arg(&mission) {
                Ok(m) => m,
                Err(code) => return code,
            };
            let opts = helm_app::RunOptions {
                mission,
                bhv,
                alias,
                embedded,
                duration,
                quiet,
            };
            let run_verbose = match std::env::var("HELM_VERBOSE") {
                Ok(v) => match helm_engine::config::parse_verbose(&v) {
                    Some(v) => Some(v),
                    None => {
                        eprintln!("error: HELM_VERBOSE={v:?}: use verbose, terse or quiet");
                        return ExitCode::from(2);
                    }
                },
                Err(_) => None,
            };
            let extras = helm_app::RunExtras {
                alog,
                run_verbose,
                ..Default::default()
            };
            run_app(&opts, extras)
        }
    }
}

/// Run the helm until the mission, the duration or a signal ends it.
fn run_app(opts: &helm_app::RunOptions, mut extras: helm_app::RunExtras) -> ExitCode {
    // The first SIGINT/SIGTERM ends the run cleanly (final line, alog flushed); a
    // second one ends the process at once.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = stop.clone();
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, std::sync::atomic::Ordering::Relaxed) {
            std::process::exit(130);
        }
    });
    extras.stop = Some(stop);
    match helm_app::run_with(opts, &extras) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// `helm MISSION.moos [FILE.bhv]... [NAME] [--alias=NAME] [--verbose=...]`: pHelmIvP.
/// Offline commands (`check`, `sim`, `conform`, help texts) end quietly when their
/// reader goes away (`helm sim ... | head`), as `cat` does: the default SIGPIPE action.
/// Never for a running helm: its sockets must see a closed peer as an error to handle,
/// not as the end of the process.
fn end_quietly_when_output_closes() {
    #[cfg(unix)]
    // SAFETY: sets a signal's disposition to the default, before any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn phelmivp_main(args: &[std::ffi::OsString]) -> ExitCode {
    use helm_app::phelmivp::{self, Action, ArgError};
    let parsed = phelmivp::parse(args);
    if !matches!(parsed, Ok(Action::Run(_))) {
        end_quietly_when_output_closes();
    }
    let run = match parsed {
        Ok(Action::Run(r)) => r,
        Ok(Action::Version) => {
            println!("{}", phelmivp::version_text());
            return ExitCode::SUCCESS;
        }
        Ok(Action::Example) => {
            print!("{}", phelmivp::EXAMPLE);
            return ExitCode::SUCCESS;
        }
        Ok(Action::Help) => {
            print!("{}", phelmivp::help_text());
            return ExitCode::SUCCESS;
        }
        Ok(Action::Interface) => {
            print!("{}", phelmivp::interface_text());
            return ExitCode::SUCCESS;
        }
        Ok(Action::Web) => {
            println!("{}", phelmivp::WEB);
            return ExitCode::SUCCESS;
        }
        Err(e @ ArgError::IllegalVerbose(_)) => {
            println!("{e}");
            return ExitCode::FAILURE;
        }
        Err(ArgError::NoMission) => {
            // pHelmIvP prints its help when no mission file is given.
            print!("{}", phelmivp::help_text());
            return ExitCode::FAILURE;
        }
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    for a in &run.ignored {
        eprintln!("pHelmIvP: ignoring argument {a:?} (not a pHelmIvP option)");
    }
    let env = match std::env::var("HELM_VERBOSE") {
        Ok(v) => match helm_engine::config::parse_verbose(&v) {
            Some(v) => Some(v),
            None => {
                println!("Illegal verbose setting. Exiting now.");
                eprintln!("(HELM_VERBOSE={v:?}: use verbose, terse or quiet)");
                return ExitCode::FAILURE;
            }
        },
        Err(_) => None,
    };
    let opts = helm_app::RunOptions {
        mission: run.mission,
        bhv: run.bhv,
        alias: run.name,
        embedded: false,
        duration: None,
        quiet: false,
    };
    let extras = helm_app::RunExtras {
        phelmivp_verbose: Some((run.verbose, env)),
        ..Default::default()
    };
    run_app(&opts, extras)
}
