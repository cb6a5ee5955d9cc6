//! `helm view`: its arguments (a `clap::Args` the helm binary embeds) and its main.

use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use thiserror::Error;

use crate::buttons::{mission_buttons, Button};
use crate::feed::Feed;
use crate::live::{self, Hub};
use crate::server::{self, App, Mode};

/// `helm view` arguments.
#[derive(clap::Args, Debug, Clone)]
#[command(after_help = "Examples:\n  \
    helm view missions/alpha/alpha.moos        live, from the mission's MOOSDB\n  \
    helm view --moos_port 9000                 live, from the MOOSDB on localhost:9000\n  \
    helm view runs/alpha-20260101-120000/      replay a helm sim run (or any .alog)\n  \
    helm view runs/alpha-mc100/                a folder of runs: all tracks and the run table\n\n\
    The page is served on 127.0.0.1 only: nobody else on the network can open it.\n\
    --bind 0.0.0.0 exposes it, and the mission's buttons with it, to every machine\n\
    that can reach this one.")]
pub struct ViewArgs {
    /// A mission (`.moos`) to watch live, an `.alog` to replay, or a folder of runs.
    pub target: Option<PathBuf>,
    /// Live: the MOOSDB's host (default: the mission's ServerHost, else localhost).
    #[arg(long)]
    pub host: Option<String>,
    /// Live: the MOOSDB's port (default: the mission's ServerPort).
    #[arg(long = "moos_port")]
    pub moos_port: Option<u16>,
    /// Address to serve the page on. The default, 127.0.0.1, keeps it to this machine;
    /// 0.0.0.0 (or an interface's address) EXPOSES the page and its buttons to the
    /// network.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    pub bind: IpAddr,
    /// Port of the page (0: any free port; the address is printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Live: the name this viewer uses with the MOOSDB.
    #[arg(long, default_value = "uHelmView")]
    pub name: String,
}

#[derive(Debug, Error)]
pub enum ViewError {
    #[error("{0}")]
    Runs(#[from] crate::runs::RunsError),
    #[error("{0}")]
    Mission(#[from] moos::MissionError),
    #[error("{0}")]
    Server(#[from] server::ServerError),
    #[error("no MOOSDB at {host}:{port}: {why}")]
    Db {
        host: String,
        port: u16,
        why: String,
    },
    #[error("nothing to view: give a mission (.moos), an .alog, a folder of runs, or --moos_port")]
    Nothing,
}

/// Run `helm view`: serve until the process is ended.
pub fn main(args: &ViewArgs) -> ExitCode {
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn is_mission(p: &Path) -> bool {
    p.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("moos"))
}

fn run(args: &ViewArgs) -> Result<(), ViewError> {
    let app = match &args.target {
        Some(p) if !is_mission(p) => replay(p)?,
        Some(m) => {
            let mission = moos::MissionFile::read(m)?;
            let host = args
                .host
                .clone()
                .or_else(|| mission.global("ServerHost"))
                .unwrap_or_else(|| "localhost".into());
            let port = args
                .moos_port
                .or_else(|| {
                    mission
                        .global("ServerPort")
                        .and_then(|p| p.trim().parse().ok())
                })
                .unwrap_or(9000);
            let warp = mission.global_f64("MOOSTimeWarp").unwrap_or(1.0);
            let community = mission.global("Community").unwrap_or_default();
            live(
                args,
                &host,
                port,
                warp,
                &community,
                mission_buttons(&mission),
            )?
        }
        None => {
            let port = args.moos_port.ok_or(ViewError::Nothing)?;
            let host = args.host.clone().unwrap_or_else(|| "localhost".into());
            live(args, &host, port, 1.0, "", Vec::new())?
        }
    };
    let serving = server::start(Arc::new(app), SocketAddr::new(args.bind, args.port))?;
    // Scripts and tests read this line for the address.
    println!("helm view: http://{}/", serving.addr);
    let _ = std::io::stdout().flush();
    if !args.bind.is_loopback() {
        eprintln!(
            "helm view: serving on {} — the page and the mission's buttons are open to the network",
            args.bind
        );
    }
    serving.join();
    Ok(())
}

fn replay(path: &Path) -> Result<App, ViewError> {
    let runs = crate::runs::open(path)?;
    for l in runs.runs.iter().flat_map(|r| &r.logs) {
        let s = l.index.skipped_summary();
        if !s.is_empty() {
            eprintln!("helm view: {}: {} lines read, {s}", l.name, l.index.lines);
        }
    }
    Ok(App {
        title: runs.title.clone(),
        mode: Mode::Replay(runs),
        buttons: Vec::new(),
    })
}

fn live(
    args: &ViewArgs,
    host: &str,
    port: u16,
    warp: f64,
    community: &str,
    buttons: Vec<Button>,
) -> Result<App, ViewError> {
    let mut cfg = moos::ClientConfig::new(host, port, &args.name);
    cfg.time_warp = warp;
    let client = Arc::new(moos::Client::connect(cfg).map_err(|e| ViewError::Db {
        host: host.to_owned(),
        port,
        why: e.to_string(),
    })?);
    let community = if community.is_empty() {
        client.community()
    } else {
        community.to_owned()
    };
    let hub = Arc::new(Hub::default());
    let extra: Vec<String> = buttons
        .iter()
        .flat_map(|b| b.postings.iter().map(|p| p.var.clone()))
        .collect();
    let feed = Feed::new(
        if community.is_empty() {
            "ownship"
        } else {
            &community
        },
        extra.clone(),
    );
    let (c, h) = (client.clone(), hub.clone());
    let stop = Arc::new(AtomicBool::new(false));
    std::thread::Builder::new()
        .name("view-moos".into())
        .spawn(move || live::pump_warped(&c, &h, feed, &extra, &stop, warp))
        .map_err(|e| ViewError::Db {
            host: host.to_owned(),
            port,
            why: e.to_string(),
        })?;
    let h = hub.clone();
    let _ = std::thread::Builder::new()
        .name("view-flush".into())
        .spawn(move || h.run_flusher(live::MIN_GAP));
    Ok(App {
        title: format!("{community} (MOOSDB {host}:{port})"),
        mode: Mode::Live {
            hub,
            client,
            db: format!("{host}:{port}"),
        },
        buttons,
    })
}
