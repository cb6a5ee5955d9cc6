//! `contactmgr`: the contact manager as a MOOS app, in place of pContactMgrV20.
//!
//! `contactmgr MISSION.moos [NAME] [--alias=NAME]` reads `ProcessConfig = NAME`
//! (default `pContactMgrV20`), connects to the mission's MOOSDB under NAME, and every
//! AppTick hands the mail to the library's manager and posts what it returns, with an
//! appcast on request. In an Antler block: `Run = contactmgr @ NewConsole = false ~
//! pContactMgrV20`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use contact_manager::appcast::{self, Caster, BASE_VARS};
use contact_manager::{Config, ContactManager, MailValue, Value, Warnings};
use moos::client::{Client, ClientConfig};
use moos::mission::{config_f64, MissionFile};
use moos::Message;

const DEFAULT_NAME: &str = "pContactMgrV20";
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
Usage: contactmgr MISSION.moos [NAME] [--alias=NAME] [OPTIONS]

The contact manager (pContactMgrV20's behaviour) as a MOOS app: reads NODE_REPORT and
ownship's NAV_*, keeps a contact table, posts alert flags (which make the helm spawn
collision-avoidance behaviors) and the CONTACTS_* status variables.

  MISSION.moos     the mission file (ServerHost, ServerPort, Community, LatOrigin, ...)
  NAME, --alias=N  the MOOS name, and the ProcessConfig block read (default pContactMgrV20)
  -e, --example    print an example configuration block
  -i, --interface  print the subscriptions and publications
  -v, --version    print the version
  -h, --help       print this help

Unknown or bad configuration lines are reported as FILE:LINE: problem (and as appcast
configuration warnings); the app still runs, as pContactMgrV20 does.
";

const EXAMPLE: &str = "\
ProcessConfig = pContactMgrV20
{
  AppTick   = 2
  CommsTick = 2

  // An alert, in one line or several with the same id. The helm's contact
  // templates also send theirs at run time as BCM_ALERT_REQUEST.
  alert = id=avd, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME]
  alert = id=avd, off_flag=CONTACT_DONE=$[VNAME]
  alert = id=avd, alert_range=40, cpa_range=60, match_type=kayak

  contact_max_age      = 60          // s (default 60)
  reject_range         = 2000        // m (default 2000)
  max_contacts         = 500
  decay                = 15,30       // s: extrapolated speed decays to 0
  recap_interval       = 1           // s between CONTACTS_RECAP
  max_retired_history  = 5
  contact_local_coords = verbatim    // or lazy_lat_lon, force_lat_lon
  alert_verbose        = false       // ALERT_VERBOSE lines
  display_radii        = false       // VIEW_CIRCLE of the alert range
  post_closest_range   = false       // CONTACT_CLOSEST_RANGE
  post_closest_relbng  = false       // CONTACT_CLOSEST_RELBNG
  hold_alerts_for_helm = false       // no alerts before IVPHELM_STATE = DRIVE
  ignore_group         = red         // global filter: match_/ignore_ name, group, type, region
  disable_var          = CMGR_DISABLE  // value <contact> -> BHV_ABLE_FILTER
  enable_var           = CMGR_ENABLE
  expunge_var          = CMGR_EXPUNGE
}
";

const INTERFACE: &str = "\
SUBSCRIPTIONS:
  NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED   ownship
  NODE_REPORT                            contacts
  BCM_ALERT_REQUEST                      id=..,on_flag=VAR=VAL,off_flag=..,alert_range=..,cpa_range=..
  BCM_REPORT_REQUEST                     var=VAR,range=M[,group=..][,type=..][,refresh=true]
  BCM_DISPLAY_RADII                      true/false
  IVPHELM_STATE                          with hold_alerts_for_helm
  <disable_var>, <enable_var>, <expunge_var>
  APPCAST_REQ, LOADCAST_REQ, TERM_REPORT_INTERVAL, COMMS_POLICY

PUBLICATIONS:
  alert on/off flags (as configured), ALERT_VERBOSE
  CONTACTS_LIST, CONTACTS_ALERTED, CONTACTS_UNALERTED, CONTACTS_COUNT,
  CONTACTS_RETIRED, CONTACTS_RECAP, CONTACT_CLOSEST, CONTACT_CLOSEST_TIME,
  CONTACT_CLOSEST_RANGE, CONTACT_CLOSEST_RELBNG, CONTACT_RANGES
  <VAR> of each BCM_REPORT_REQUEST, BHV_ABLE_FILTER, VIEW_CIRCLE
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
                    "contactmgr ",
                    env!("CARGO_PKG_VERSION"),
                    " (pContactMgrV20 behaviour)\n"
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

/// The manager's configuration from the block; each refused line is reported as
/// `file:line: problem` on stderr and kept as a configuration warning.
fn read_config(mission: &MissionFile, name: &str, w: &mut Warnings) -> Config {
    let mut cfg = Config::default();
    let file = mission.path().display();
    let Some(lines) = mission.process_config(name) else {
        let msg = format!("{file}: no ProcessConfig = {name} block; running with defaults");
        eprintln!("{msg}");
        w.config_warning(&msg);
        return cfg;
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
            w.config_warning(&msg);
        }
    }
    cfg
}

/// The mission's LatOrigin/LongOrigin, when both are numbers.
fn origin(mission: &MissionFile) -> Option<(f64, f64)> {
    let lat = mission.global("LatOrigin").and_then(|v| config_f64(&v))?;
    let lon = mission.global("LongOrigin").and_then(|v| config_f64(&v))?;
    Some((lat, lon))
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
    let mut warnings = Warnings::default();
    let cfg = read_config(&mission, &args.name, &mut warnings);
    let community = mission.global("Community").unwrap_or_default();
    let (ccfg, tick) = client_config(&mission, &args.name);
    let warp = ccfg.time_warp;
    let mut mgr = ContactManager::new(&community, cfg, origin(&mission));
    *mgr.warnings_mut() = warnings;
    let client = Client::start(ccfg).map_err(|e| e.to_string())?;
    while let Err(e) = client.wait_connected(Duration::from_secs(5)) {
        if matches!(e, moos::ClientError::Poisoned(_)) {
            return Err(e.to_string());
        }
        tracing::info!("waiting for the MOOSDB");
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
    tracing::info!(app = %args.name, community = %community, tick, "contactmgr running");
    let community = client.community();
    let community = if community.is_empty() {
        mission.global("Community").unwrap_or_default()
    } else {
        community
    };
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
            let body = appcast::body(&mgr, now);
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
                eprintln!("contactmgr: {e}");
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            eprintln!("contactmgr: {e}\n\n{USAGE}");
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
    fn command_line_like_pcontactmgrv20() {
        let name = |v: &[&str]| match parse_args(&s(v)) {
            Ok(Cmd::Run(a)) => a.name,
            _ => panic!("not a run: {v:?}"),
        };
        assert_eq!(name(&["m.moos"]), "pContactMgrV20");
        assert_eq!(name(&["m.moos", "pContactMgrV20_2"]), "pContactMgrV20_2");
        assert_eq!(name(&["m.moos", "x", "--alias=cm"]), "cm");
        assert!(matches!(parse_args(&s(&["-e"])), Ok(Cmd::Print(EXAMPLE))));
        assert!(matches!(parse_args(&s(&["-i"])), Ok(Cmd::Print(INTERFACE))));
        assert!(parse_args(&s(&[])).is_err());
        assert!(parse_args(&s(&["m.moos", "--bogus"])).is_err());
    }

    #[test]
    fn config_problems_name_file_and_line() {
        let text = "Community = alpha\nProcessConfig = pContactMgrV20\n{\n  AppTick = 2\n  decay = 30,60\n  colour = red\n  alert = id=a, bogus=1\n}\n";
        let m = MissionFile::parse(text, Path::new("t.moos")).unwrap();
        let mut w = Warnings::default();
        let cfg = read_config(&m, "pContactMgrV20", &mut w);
        assert_eq!(cfg.decay.start, 30.0);
        assert_eq!(
            w.config_warnings(),
            [
                "t.moos:6: unknown parameter: colour",
                "t.moos:7: alert: unhandled alert config component: bogus"
            ]
        );
        // The example block is accepted as it stands.
        let m = MissionFile::parse(EXAMPLE, Path::new("e.moos")).unwrap();
        let mut w = Warnings::default();
        read_config(&m, "pContactMgrV20", &mut w);
        assert!(w.config_warnings().is_empty(), "{:?}", w.config_warnings());
    }
}
