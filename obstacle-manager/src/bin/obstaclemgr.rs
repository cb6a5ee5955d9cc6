//! `obstaclemgr`: the obstacle manager as a MOOS app, in place of pObstacleMgr.
//!
//! `obstaclemgr MISSION.moos [NAME] [--alias=NAME]` reads `ProcessConfig = NAME`
//! (default `pObstacleMgr`), connects to the mission's MOOSDB under NAME, and every
//! AppTick hands the mail to the library's manager and posts what it returns, with an
//! appcast on request. In an Antler block: `Run = obstaclemgr @ NewConsole = false ~
//! pObstacleMgr`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use contact_manager::appcast::{serialize, Caster, BASE_VARS};
use moos::client::{Client, ClientConfig};
use moos::mission::MissionFile;
use moos::Message;
use obstacle_manager::{appcast, Config, MailValue, ObstacleManager, Value};

const DEFAULT_NAME: &str = "pObstacleMgr";
const DEFAULT_TICK: f64 = 4.0;

/// Block lines every MOOS app reads itself (not the manager's business).
const APP_PARAMS: &[&str] = &[
    "apptick",
    "commstick",
    "maxapptick",
    "iteratemode",
    "app_logging",
    "comms_policy",
    "term_report_interval",
];

const USAGE: &str = "\
Usage: obstaclemgr MISSION.moos [NAME] [--alias=NAME] [OPTIONS]

The obstacle manager (pObstacleMgr's behaviour) as a MOOS app: reads tracked points
(TRACKED_FEATURE) and given obstacles (GIVEN_OBSTACLE), keeps one convex polygon per
obstacle, answers the helm's OBM_ALERT_REQUEST with alerts that make it spawn
obstacle-avoidance behaviors, and posts OBM_RESOLVED when an obstacle goes away.

  MISSION.moos     the mission file (ServerHost, ServerPort, Community, ...)
  NAME, --alias=N  the MOOS name, and the ProcessConfig block read (default pObstacleMgr)
  -e, --example    print an example configuration block
  -i, --interface  print the subscriptions and publications
  -v, --version    print the version
  -h, --help       print this help

Unknown or bad configuration lines are reported as FILE:LINE: problem (and as appcast
configuration warnings); the app still runs, as pObstacleMgr does.
";

const EXAMPLE: &str = "\
ProcessConfig = pObstacleMgr
{
  AppTick   = 4
  CommsTick = 4

  point_var           = TRACKED_FEATURE  // tracked points: x=..,y=..,key=..[,vsource=..]
  given_obstacle      = pts={50,-100:50,-120:80,-120:80,-100},label=one
  alert_range         = 20          // m, until a helm's OBM_ALERT_REQUEST replaces it
  ignore_range        = 40          // m, points farther away are dropped (default off)
  max_pts_per_cluster = 20
  max_age_per_point   = 20          // s
  given_max_duration  = 60          // s, or off
  post_dist_to_polys  = close       // true, false or close: OBM_DIST_TO_OBJ
  post_view_polys     = true        // VIEW_POLYGON of each hull
  obstacles_color     = blue
  poly_label_thresh   = 25
  poly_shade_thresh   = 100
  poly_vertex_thresh  = 150
  lasso               = false       // a radial pseudo hull instead of the convex hull
  lasso_points        = 6
  lasso_radius        = 5
  general_alert       = update_var=GEN_ALERT, alert_range=40000
  new_obs_flag        = NEWOBS=now:$[OBS_NOW],ever:$[OBS_EVER]
  disable_var         = OBM_DISABLE   // value <id> -> BHV_ABLE_FILTER
  enable_var          = OBM_ENABLE
  expunge_var         = OBM_EXPUNGE
}
";

const INTERFACE: &str = "\
SUBSCRIPTIONS:
  NAV_X, NAV_Y                           ownship
  <point_var> (TRACKED_FEATURE)          x=..,y=..,key=..|label=..[,vsource=..]
  GIVEN_OBSTACLE                         a convex polygon with label= and duration=
  OBM_ALERT_REQUEST                      name=..,update_var=..,alert_range=..
  <disable_var>, <enable_var>, <expunge_var>, mailflag keys
  APPCAST_REQ, LOADCAST_REQ, TERM_REPORT_INTERVAL, COMMS_POLICY

PUBLICATIONS:
  <update_var> of the alert request      name=<name><key>#poly=<pts>,label=<key>#id=<key>
  <update_var> of general_alert
  OBM_RESOLVED, OBM_CONNECT, OBM_DIST_TO_OBJ, OBM_MIN_DIST_EVER
  VIEW_POLYGON, BHV_ABLE_FILTER, new_obs_flag and mailflag postings
  <NAME>_PID, APPCAST
";

struct Args {
    mission: PathBuf,
    name: String,
}

enum Cmd {
    Run(Args),
    Print(&'static str),
}

fn parse_args(args: &[String]) -> Result<Cmd, String> {
    let (mut mission, mut name, mut alias) = (None, None, None);
    for a in args {
        match a.as_str() {
            "-h" | "--help" | "-help" => return Ok(Cmd::Print(USAGE)),
            "-e" | "--example" => return Ok(Cmd::Print(EXAMPLE)),
            "-i" | "--interface" => return Ok(Cmd::Print(INTERFACE)),
            "-v" | "--version" => {
                return Ok(Cmd::Print(concat!(
                    "obstaclemgr ",
                    env!("CARGO_PKG_VERSION"),
                    " (pObstacleMgr behaviour)\n"
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
                    // pAntler passes the MOOS name after the mission (the run alias).
                    name = Some(a.clone());
                } else {
                    return Err(format!("unexpected argument {a}"));
                }
            }
        }
    }
    let mission = mission.ok_or("no mission file (MISSION.moos) given")?;
    let name = alias.or(name).unwrap_or_else(|| DEFAULT_NAME.to_string());
    if name.is_empty() {
        return Err("empty app name".into());
    }
    Ok(Cmd::Run(Args { mission, name }))
}

/// The manager's configuration from the block, and each refused line as
/// `file:line: problem` (also printed on stderr).
fn read_config(mission: &MissionFile, name: &str) -> (Config, Vec<String>) {
    let mut cfg = Config::default();
    let mut problems = Vec::new();
    let file = mission.path().display();
    let Some(lines) = mission.process_config(name) else {
        let msg = format!("{file}: no ProcessConfig = {name} block; running with defaults");
        eprintln!("{msg}");
        return (cfg, vec![msg]);
    };
    for l in lines {
        if APP_PARAMS.iter().any(|p| l.name_is(p)) {
            continue;
        }
        let res = if l.value.is_empty() && l.raw == l.name {
            Err(format!("not a parameter line: {}", l.raw))
        } else {
            cfg.set(&l.name, &l.value).map_err(|e| e.to_string())
        };
        if let Err(e) = res {
            let msg = format!("{file}:{}: {e}", l.line);
            eprintln!("{msg}");
            problems.push(msg);
        }
    }
    (cfg, problems)
}

fn client_config(mission: &MissionFile, name: &str) -> (ClientConfig, f64) {
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
    let tick = mission.app_tick(name, DEFAULT_TICK);
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

fn run(args: Args) -> Result<(), String> {
    let mission = MissionFile::read(&args.mission).map_err(|e| e.to_string())?;
    let (cfg, problems) = read_config(&mission, &args.name);
    let (ccfg, tick) = client_config(&mission, &args.name);
    let warp = ccfg.time_warp;
    let client = Client::start(ccfg).map_err(|e| e.to_string())?;
    while let Err(e) = client.wait_connected(Duration::from_secs(5)) {
        if matches!(e, moos::ClientError::Poisoned(_)) {
            return Err(e.to_string());
        }
        tracing::info!("waiting for the MOOSDB");
    }
    // Started once connected: the given obstacles are stamped with MOOS time.
    let mut mgr = ObstacleManager::new(cfg, client.moos_time());
    for p in &problems {
        mgr.warnings_mut().config_warning(p);
    }
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
    tracing::info!(app = %args.name, community = %community, tick, "obstaclemgr running");
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
            let body = appcast::body(&mgr);
            let cast = serialize(
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

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .init();
    let args: Vec<String> = std::env::args().skip(1).collect();
    match parse_args(&args) {
        Ok(Cmd::Print(text)) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Ok(Cmd::Run(a)) => match run(a) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("obstaclemgr: {e}");
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            eprintln!("obstaclemgr: {e}\n\n{USAGE}");
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn s(v: &[&str]) -> Vec<String> {
        v.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn command_line_like_pobstaclemgr() {
        let name = |v: &[&str]| match parse_args(&s(v)) {
            Ok(Cmd::Run(a)) => a.name,
            _ => panic!("not a run: {v:?}"),
        };
        assert_eq!(name(&["m.moos"]), "pObstacleMgr");
        assert_eq!(name(&["m.moos", "pObstacleMgr_2"]), "pObstacleMgr_2");
        assert_eq!(name(&["m.moos", "x", "--alias=om"]), "om");
        assert!(matches!(parse_args(&s(&["-e"])), Ok(Cmd::Print(EXAMPLE))));
        assert!(matches!(parse_args(&s(&["-i"])), Ok(Cmd::Print(INTERFACE))));
        assert!(parse_args(&s(&[])).is_err());
        assert!(parse_args(&s(&["m.moos", "--bogus"])).is_err());
    }

    #[test]
    fn config_problems_name_file_and_line() {
        let text = "Community = alpha\nProcessConfig = pObstacleMgr\n{\n  AppTick = 4\n  alert_range = 35\n  colour = red\n  given_obstacle = pts={0,0:10,0:5,1:10,10:0,10},label=c\n}\n";
        let m = MissionFile::parse(text, Path::new("t.moos")).unwrap();
        let (cfg, problems) = read_config(&m, "pObstacleMgr");
        assert_eq!(cfg.alert_range, 35.0);
        assert_eq!(
            problems,
            [
                "t.moos:6: unknown parameter: colour",
                "t.moos:7: given_obstacle: not a convex polygon: pts={0,0:10,0:5,1:10,10:0,10},label=c"
            ]
        );
        // The example block is accepted as it stands.
        let m = MissionFile::parse(EXAMPLE, Path::new("e.moos")).unwrap();
        let (_, problems) = read_config(&m, "pObstacleMgr");
        assert!(problems.is_empty(), "{problems:?}");
    }
}
