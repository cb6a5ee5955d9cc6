//! `contactmgr`: the contact manager as a MOOS app, in place of pContactMgrV20.
//!
//! `contactmgr MISSION.moos [NAME] [--alias=NAME]` reads `ProcessConfig = NAME`
//! (default `pContactMgrV20`), connects to the mission's MOOSDB under NAME, and every
//! AppTick hands the mail to the library's manager and posts what it returns, with an
//! appcast on request. In an Antler block: `Run = contactmgr @ NewConsole = false ~
//! pContactMgrV20`.

use std::process::ExitCode;

use contact_manager::app::{self, AppInfo};
use contact_manager::{block, Config, ContactManager, Warnings};
use moos::mission::MissionFile;

const INFO: AppInfo = AppInfo {
    bin: "contactmgr",
    stands_for: "pContactMgrV20",
    default_tick: 4.0,
    version: env!("CARGO_PKG_VERSION"),
    usage: USAGE,
    example: EXAMPLE,
    interface: INTERFACE,
};

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

/// The manager's configuration from the block; each refused line is reported as
/// `file:line: problem` on stderr and kept as a configuration warning.
fn read_config(mission: &MissionFile, name: &str, w: &mut Warnings) -> Config {
    let mut cfg = Config::default();
    for p in app::block_problems(mission, name, |k, v| {
        cfg.set(k, v).map_err(|e| e.to_string())
    }) {
        w.config_warning(&p);
    }
    cfg
}

fn run(args: app::Args) -> Result<(), String> {
    let mission = MissionFile::read(&args.mission).map_err(|e| e.to_string())?;
    let mut warnings = Warnings::default();
    let cfg = read_config(&mission, &args.name, &mut warnings);
    let community = mission.global("Community").unwrap_or_default();
    let mut mgr = ContactManager::new(&community, cfg, block::origin(&mission));
    *mgr.warnings_mut() = warnings;
    app::run(&INFO, &args, &mission, |_| mgr)
}

fn main() -> ExitCode {
    app::main(&INFO, run)
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
        let parse_args = |v: &[String]| app::parse_args(&INFO, v);
        let name = |v: &[&str]| match parse_args(&s(v)) {
            Ok(app::Cmd::Run(a)) => a.name,
            _ => panic!("not a run: {v:?}"),
        };
        assert_eq!(name(&["m.moos"]), "pContactMgrV20");
        assert_eq!(name(&["m.moos", "pContactMgrV20_2"]), "pContactMgrV20_2");
        assert_eq!(name(&["m.moos", "x", "--alias=cm"]), "cm");
        assert!(matches!(parse_args(&s(&["-e"])), Ok(app::Cmd::Print(t)) if t == EXAMPLE));
        assert!(matches!(parse_args(&s(&["-i"])), Ok(app::Cmd::Print(t)) if t == INTERFACE));
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
