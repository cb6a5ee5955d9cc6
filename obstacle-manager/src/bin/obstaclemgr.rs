//! `obstaclemgr`: the obstacle manager as a MOOS app, in place of pObstacleMgr.
//!
//! `obstaclemgr MISSION.moos [NAME] [--alias=NAME]` reads `ProcessConfig = NAME`
//! (default `pObstacleMgr`), connects to the mission's MOOSDB under NAME, and every
//! AppTick hands the mail to the library's manager and posts what it returns, with an
//! appcast on request. In an Antler block: `Run = obstaclemgr @ NewConsole = false ~
//! pObstacleMgr`.

use std::process::ExitCode;

use contact_manager::app::{self, AppInfo};
use moos::mission::MissionFile;
use obstacle_manager::{Config, ObstacleManager};

const INFO: AppInfo = AppInfo {
    bin: "obstaclemgr",
    stands_for: "pObstacleMgr",
    default_tick: 4.0,
    version: env!("CARGO_PKG_VERSION"),
    usage: USAGE,
    example: EXAMPLE,
    interface: INTERFACE,
};

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

/// The manager's configuration from the block, and each refused line as
/// `file:line: problem` (also printed on stderr).
fn read_config(mission: &MissionFile, name: &str) -> (Config, Vec<String>) {
    let mut cfg = Config::default();
    let problems = app::block_problems(mission, name, |k, v| {
        cfg.set(k, v).map_err(|e| e.to_string())
    });
    (cfg, problems)
}

fn run(args: app::Args) -> Result<(), String> {
    let mission = MissionFile::read(&args.mission).map_err(|e| e.to_string())?;
    let (cfg, problems) = read_config(&mission, &args.name);
    // Started once connected: the given obstacles are stamped with MOOS time.
    app::run(&INFO, &args, &mission, |client| {
        let mut mgr = ObstacleManager::new(cfg, client.moos_time());
        for p in &problems {
            mgr.warnings_mut().config_warning(p);
        }
        mgr
    })
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
    fn command_line_like_pobstaclemgr() {
        let parse_args = |v: &[String]| app::parse_args(&INFO, v);
        let name = |v: &[&str]| match parse_args(&s(v)) {
            Ok(app::Cmd::Run(a)) => a.name,
            _ => panic!("not a run: {v:?}"),
        };
        assert_eq!(name(&["m.moos"]), "pObstacleMgr");
        assert_eq!(name(&["m.moos", "pObstacleMgr_2"]), "pObstacleMgr_2");
        assert_eq!(name(&["m.moos", "x", "--alias=om"]), "om");
        assert!(matches!(parse_args(&s(&["-e"])), Ok(app::Cmd::Print(t)) if t == EXAMPLE));
        assert!(matches!(parse_args(&s(&["-i"])), Ok(app::Cmd::Print(t)) if t == INTERFACE));
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
