//! The MOOS-app frame the `contactmgr` and `obstaclemgr` binaries share: pAntler's
//! command line (`MISSION.moos [NAME] [--alias=NAME]`, `-h -e -i -v`), the client set
//! up from the mission's globals, the AppTick loop (mail in time order to the manager,
//! its postings out, the PID posted and re-posted on reconnect) and APPCAST on request.
//! The only part of this crate that touches a socket; the managers stay pure.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientConfig};
use moos::mission::MissionFile;
use moos::Message;

use crate::appcast::{self, Caster, BASE_VARS};
use crate::{MailValue, Posting, Value, Warnings};

/// What a manager gives the frame.
pub trait Manager {
    fn subscriptions(&self) -> Vec<String>;
    fn handle_mail(&mut self, now: f64, mail: &[(&str, MailValue<'_>)]);
    fn iterate(&mut self, now: f64) -> &[Posting];
    fn iterations(&self) -> u64;
    fn warnings(&self) -> &Warnings;
    fn warnings_mut(&mut self) -> &mut Warnings;
    /// The APPCAST report's body (the lines after the header).
    fn appcast_body(&self, now: f64) -> String;
}

/// One binary's identity and texts.
pub struct AppInfo {
    /// The binary's name (`contactmgr`).
    pub bin: &'static str,
    /// The MOOS app it stands in for, also its default name (`pContactMgrV20`).
    pub stands_for: &'static str,
    pub default_tick: f64,
    /// The binary's own package version (`env!("CARGO_PKG_VERSION")` in the binary).
    pub version: &'static str,
    pub usage: &'static str,
    pub example: &'static str,
    pub interface: &'static str,
}

/// A run: the mission file and the MOOS name.
pub struct Args {
    pub mission: PathBuf,
    pub name: String,
}

/// What the command line asks for.
pub enum Cmd {
    Run(Args),
    Print(String),
}

/// pAntler's form: the mission, then the MOOS name (the run alias); `--alias=` wins.
pub fn parse_args(info: &AppInfo, args: &[String]) -> Result<Cmd, String> {
    let (mut mission, mut name, mut alias) = (None, None, None);
    for a in args {
        match a.as_str() {
            "-h" | "--help" | "-help" => return Ok(Cmd::Print(info.usage.into())),
            "-e" | "--example" => return Ok(Cmd::Print(info.example.into())),
            "-i" | "--interface" => return Ok(Cmd::Print(info.interface.into())),
            "-v" | "--version" => {
                return Ok(Cmd::Print(format!(
                    "{} {} ({} behaviour)\n",
                    info.bin, info.version, info.stands_for
                )))
            }
            _ => {
                if let Some(n) = a.strip_prefix("--alias=") {
                    alias = Some(n.to_string());
                } else if a.starts_with('-') {
                    return Err(format!("unknown option {a}"));
                } else if mission.is_none() && a.ends_with(".moos") {
                    mission = Some(PathBuf::from(a));
                } else if name.is_none() {
                    name = Some(a.clone());
                } else {
                    return Err(format!("unexpected argument {a}"));
                }
            }
        }
    }
    let mission = mission.ok_or("no mission file (MISSION.moos) given")?;
    let name = alias
        .or(name)
        .unwrap_or_else(|| info.stands_for.to_string());
    if name.is_empty() {
        return Err("empty app name".into());
    }
    Ok(Cmd::Run(Args { mission, name }))
}

/// The block's problems, each printed on stderr (`file:line: problem`); a missing
/// block is one problem too (the manager runs with its defaults).
pub fn block_problems(
    mission: &MissionFile,
    name: &str,
    set: impl FnMut(&str, &str) -> Result<(), String>,
) -> Vec<String> {
    let problems = crate::block::read(mission, name, set).unwrap_or_else(|| {
        vec![format!(
            "{}: no ProcessConfig = {name} block; running with defaults",
            mission.path().display()
        )]
    });
    for p in &problems {
        eprintln!("{p}");
    }
    problems
}

fn client_config(mission: &MissionFile, name: &str, default_tick: f64) -> (ClientConfig, f64) {
    let host = mission
        .global("ServerHost")
        .filter(|h| !h.is_empty() && !h.eq_ignore_ascii_case("localhost"))
        .unwrap_or_else(|| "127.0.0.1".into());
    let port = mission
        .global_f64("ServerPort")
        .filter(|p| (1.0..=65535.0).contains(p))
        .map_or(9000, |p| p as u16);
    let mut cfg = ClientConfig::new(&host, port, name);
    cfg.time_warp = mission
        .global_f64("MOOSTimeWarp")
        .filter(|w| moos::time::warp_ok(*w))
        .unwrap_or(1.0);
    let tick = mission.app_tick(name, default_tick);
    (cfg, tick)
}

fn publish(c: &Client, var: &str, val: &Value, now: f64) {
    let m = match val {
        Value::Num(v) => Message::notify_double(var, *v, now),
        Value::Str(s) => Message::notify_string(var, s, now),
    };
    if let Err(e) = c.post(m) {
        tracing::warn!(var, error = %e, "posting lost");
    }
}

/// Connect, then run the manager `make` builds (given the client, once connected: a
/// manager may stamp its start with MOOS time) until the process is stopped.
pub fn run<M: Manager>(
    info: &AppInfo,
    args: &Args,
    mission: &MissionFile,
    make: impl FnOnce(&Client) -> M,
) -> Result<(), String> {
    let (ccfg, tick) = client_config(mission, &args.name, info.default_tick);
    let warp = ccfg.time_warp;
    let client = Client::start(ccfg).map_err(|e| e.to_string())?;
    while let Err(e) = client.wait_connected(Duration::from_secs(5)) {
        if matches!(e, moos::ClientError::Poisoned(_)) {
            return Err(e.to_string());
        }
        tracing::info!("waiting for the MOOSDB");
    }
    let mut mgr = make(&client);
    let mut subs = mgr.subscriptions();
    subs.extend(BASE_VARS.iter().map(|s| s.to_string()));
    for s in &subs {
        client.register(s, 0.0).map_err(|e| e.to_string())?;
    }
    let pid_var = format!("{}_PID", args.name.to_ascii_uppercase());
    client
        .notify_double(&pid_var, f64::from(std::process::id()), None)
        .map_err(|e| e.to_string())?;
    let community = client.community();
    let community = if community.is_empty() {
        mission.global("Community").unwrap_or_default()
    } else {
        community
    };
    tracing::info!(app = %args.name, community = %community, tick, "{} running", info.bin);
    let period = Duration::from_secs_f64(1.0 / (tick * warp));
    let mut caster = Caster::new(warp);
    let mut inbox = Vec::new();
    let mut next = Instant::now();
    let mut connects = client.connection_count();
    loop {
        next += period;
        let now_i = Instant::now();
        if next > now_i {
            std::thread::sleep(next - now_i);
        } else {
            next = now_i;
        }
        // Subscriptions are renewed by the client on reconnect; the PID is re-posted.
        if client.connection_count() != connects && client.is_connected() {
            connects = client.connection_count();
            let _ = client.notify_double(&pid_var, f64::from(std::process::id()), None);
        }
        let now = client.moos_time();
        inbox.clear();
        client.fetch(&mut inbox);
        inbox.sort_by(|a, b| a.time.total_cmp(&b.time));
        let texts: Vec<std::borrow::Cow<'_, str>> = inbox.iter().map(|m| m.string()).collect();
        let mut mail = Vec::with_capacity(inbox.len());
        for (m, text) in inbox.iter().zip(&texts) {
            if caster.handle(&m.key, text, &community, &args.name, now) {
                continue;
            }
            let v = if m.is_double() {
                MailValue::Num(m.dval)
            } else {
                MailValue::Str(text)
            };
            mail.push((m.key.as_str(), v));
        }
        mgr.handle_mail(now, &mail);
        for p in mgr.iterate(now) {
            publish(&client, &p.var, &p.val, now);
        }
        if caster.due(now, mgr.iterations(), mgr.warnings()) {
            let body = mgr.appcast_body(now);
            let cast = appcast::serialize(
                &args.name,
                &community,
                mgr.iterations(),
                &body,
                mgr.warnings(),
            );
            publish(&client, "APPCAST", &Value::Str(cast), now);
            mgr.warnings_mut().clear_new();
        }
    }
}

/// A binary's `main`: logs to stderr, the command line, then `start` with the parsed
/// run; exit 0, 1 (the run failed) or 2 (usage).
pub fn main(info: &AppInfo, start: impl FnOnce(Args) -> Result<(), String>) -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .init();
    let args: Vec<String> = std::env::args().skip(1).collect();
    match parse_args(info, &args) {
        Ok(Cmd::Print(text)) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Ok(Cmd::Run(a)) => match start(a) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("{}: {e}", info.bin);
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            eprintln!("{}: {e}\n\n{}", info.bin, info.usage);
            ExitCode::from(2)
        }
    }
}

impl Manager for crate::ContactManager {
    fn subscriptions(&self) -> Vec<String> {
        crate::ContactManager::subscriptions(self)
    }
    fn handle_mail(&mut self, now: f64, mail: &[(&str, MailValue<'_>)]) {
        crate::ContactManager::handle_mail(self, now, mail)
    }
    fn iterate(&mut self, now: f64) -> &[Posting] {
        crate::ContactManager::iterate(self, now)
    }
    fn iterations(&self) -> u64 {
        crate::ContactManager::iterations(self)
    }
    fn warnings(&self) -> &Warnings {
        crate::ContactManager::warnings(self)
    }
    fn warnings_mut(&mut self) -> &mut Warnings {
        crate::ContactManager::warnings_mut(self)
    }
    fn appcast_body(&self, now: f64) -> String {
        appcast::body(self, now)
    }
}
