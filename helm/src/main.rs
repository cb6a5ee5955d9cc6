//! `helm`: the IvP Helm. See `helm --help`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use helm::conform;
use helm::factory::BehaviorFactory;

/// The IvP Helm (pHelmIvP) rebuilt in Rust: behavior-based autonomy with plugin behaviors.
#[derive(Parser)]
#[command(name = "helm", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Replay conformance cases recorded from the real C++ helm and compare.
    ///
    /// PATH is a case file (`*.toml`) or a folder of them. Prints one line per
    /// difference (case, step, variable, expected, got) and ends with
    /// `N passed, M failed`; exits 1 if any case failed. Behavior libraries are
    /// loaded from the colon-separated directories in IVP_BEHAVIOR_DIRS.
    Conform {
        /// Replay each case for at least 2 s and print `bench <case> <µs>`: the mean time
        /// of the decision step (modes, behaviors, solve), as the C++ timings measure it.
        #[arg(long)]
        bench: bool,
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
}

fn factory_from_env() -> BehaviorFactory {
    let mut factory = BehaviorFactory::with_builtins();
    let dirs: Vec<PathBuf> = std::env::var("IVP_BEHAVIOR_DIRS")
        .unwrap_or_default()
        .split(':')
        .map(str::trim)
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .collect();
    factory.searched_dirs = dirs.iter().map(|d| d.display().to_string()).collect();
    let builtin = |t: &str| BehaviorFactory::with_builtins().is_builtin(t);
    let (libs, events) = helm::loader::load_dirs(&dirs, &builtin);
    for e in events {
        tracing::info!("{e:?}");
    }
    for l in libs {
        factory.add_library(l);
    }
    factory
}

fn conform_cmd(bench: bool, paths: &[PathBuf]) -> ExitCode {
    let files = match conform::collect(paths) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let factory = factory_from_env();
    if bench {
        let mut failed = false;
        for f in &files {
            match conform::bench_file(f, &factory, 2.0) {
                Ok(r) => {
                    println!("bench {} {:.3}", r.name, r.decision_us);
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
        return if failed {
            ExitCode::FAILURE
        } else {
            ExitCode::SUCCESS
        };
    }
    let (mut passed, mut failed) = (0, 0);
    for f in &files {
        let r = conform::run_file(f, &factory);
        if r.passed() {
            passed += 1;
            continue;
        }
        failed += 1;
        if let Some(e) = &r.error {
            println!("{}: error: {e}", r.name);
        }
        for m in &r.mismatches {
            println!(
                "{} step {} {}: expected {} got {}",
                r.name, m.step, m.var, m.expected, m.got
            );
        }
    }
    println!("{passed} passed, {failed} failed");
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
        .init();
    let cli = Cli::parse();
    match cli.command {
        Command::Conform { bench, paths } => conform_cmd(bench, &paths),
    }
}
