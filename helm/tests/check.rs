//! `helm check`: every reader error names its file and line and shows the line.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

const MISSION: &str = "ServerHost = localhost\nServerPort = 9000\nCommunity = alpha\nLatOrigin = 43.8\nLongOrigin = -70.3\n\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = m.bhv\n  domain = course:0:359:360\n  domain = speed:0:4:41\n}\n";

const GOOD_BHV: &str = "initialize DEPLOY = true\n\nBehavior = BHV_Waypoint\n{\n  name = go\n  condition = DEPLOY = true\n  speed = 2\n  points = 0,0 : 10,10\n}\n";

/// Write a mission and its .bhv, run `helm check`, return (exit code, stdout+stderr).
fn check(name: &str, mission: &str, bhv: &str) -> (i32, String, PathBuf) {
    let d = common::scratch(Path::new("check").join(name));
    std::fs::write(d.join("m.moos"), mission).expect("write mission");
    std::fs::write(d.join("m.bhv"), bhv).expect("write bhv");
    let out = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("check")
        .arg(d.join("m.moos"))
        .env_remove("IVP_BEHAVIOR_DIRS")
        .output()
        .expect("run helm");
    (out.status.code().unwrap_or(-1), common::text(&out), d)
}

fn bhv_path(d: &Path) -> String {
    d.join("m.bhv").display().to_string()
}

#[test]
fn a_good_mission_checks_ok() {
    let (code, text, _) = check("good", MISSION, GOOD_BHV);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("ok: 1 behavior(s): go"), "{text}");
}

#[test]
fn unexpected_brace_names_file_line_and_shows_it() {
    let bhv = "Behavior = BHV_Waypoint\n{\n  name = a\n}\n}\n";
    let (code, text, d) = check("brace", MISSION, bhv);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains(&format!("{}:5:", bhv_path(&d))), "{text}");
    assert!(text.contains("Unexpected close brace"), "{text}");
    assert!(text.contains("MALCONFIG"), "{text}");
}

#[test]
fn a_hash_line_is_not_a_comment() {
    let bhv = "# a comment?\nBehavior = BHV_Waypoint\n{\n  name = a\n}\n";
    let (code, text, d) = check("hash", MISSION, bhv);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains(&format!("{}:1:", bhv_path(&d))), "{text}");
    assert!(text.contains("# a comment?"), "{text}");
}

#[test]
fn bad_parameter_lines_are_all_reported() {
    let bhv = "Behavior = BHV_Waypoint\n{\n  name = a\n  speeed = 2\n  condition = (A=1) and (B=2) and (C=3)\n  pwt = -3\n}\n";
    let (code, text, d) = check("params", MISSION, bhv);
    assert_eq!(code, 1, "{text}");
    let p = bhv_path(&d);
    assert!(
        text.contains(&format!(
            "{p}:4: unknown parameter of BHV_Waypoint: speeed = 2"
        )),
        "{text}"
    );
    assert!(
        text.contains(&format!("{p}:5: bad value: condition = ")) && text.contains("(C=3)"),
        "{text}"
    );
    assert!(
        text.contains(&format!("{p}:6: bad value: pwt = -3")),
        "{text}"
    );
}

#[test]
fn unknown_type_names_the_type_and_where() {
    let bhv = "Behavior = BHV_Nope\n{\n  name = a\n}\n";
    let (code, text, d) = check("type", MISSION, bhv);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains(&format!("{}:1:", bhv_path(&d))), "{text}");
    assert!(text.contains("unknown behavior type BHV_Nope"), "{text}");
}

#[test]
fn duplicate_and_prefix_names_conflict() {
    let bhv = "Behavior = BHV_Timer\n{\n  name = loiter\n}\nBehavior = BHV_Timer\n{\n  name = loiter_east\n}\n";
    let (code, text, _) = check("names", MISSION, bhv);
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains("Duplicate behavior name found: loiter_east"),
        "{text}"
    );
}

#[test]
fn a_missing_behavior_file_is_named() {
    let mission = MISSION.replace("behaviors = m.bhv", "behaviors = nothere.bhv");
    let (code, text, _) = check("missing", &mission, GOOD_BHV);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("nothere.bhv"), "{text}");
    assert!(text.contains("Could not find File"), "{text}");
}

#[test]
fn unhandled_block_lines_name_the_mission_line() {
    let mission = MISSION.replace("  AppTick = 4\n", "  AppTick = 4\n  comms_policy = lean\n");
    let (code, text, d) = check("block", &mission, GOOD_BHV);
    assert_eq!(code, 1, "{text}");
    let m = d.join("m.moos").display().to_string();
    assert!(
        text.contains(&format!(
            "{m}:10: Unhandled config line: comms_policy = lean"
        )),
        "{text}"
    );
}

#[test]
fn a_mission_without_the_block_or_community_is_malconfig() {
    let mission = "ServerPort = 9000\nLatOrigin = 1\nLongOrigin = 2\n";
    let (code, text, _) = check("noblock", mission, GOOD_BHV);
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains("No mission config block found for pHelmIvP"),
        "{text}"
    );
    assert!(text.contains("Community/Vehicle name not found"), "{text}");
}

#[test]
fn a_missing_mission_file_is_an_error_naming_it() {
    let out = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(["check", "/nonexistent/dir/x.moos"])
        .output()
        .expect("run helm");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/dir/x.moos"));
}

#[test]
fn a_missing_behavior_directory_is_a_problem_unless_allowed() {
    // helm.md §2.1: a configured ivp_behavior_dir that does not exist is a config warning
    // (MALCONFIG); `bhv_dir_not_found_ok = true` lets it pass without a word.
    let with_dir = MISSION.replace(
        "  AppTick = 4\n",
        "  AppTick = 4\n  ivp_behavior_dir = /no/such/dir\n",
    );
    let (code, text, d) = check("missing-dir", &with_dir, GOOD_BHV);
    assert_eq!(code, 1, "{text}");
    let m = d.join("m.moos").display().to_string();
    assert!(
        text.contains(&format!(
            "{m}:10: behavior directory not found: /no/such/dir"
        )),
        "{text}"
    );
    let allowed = with_dir.replace(
        "  AppTick = 4\n",
        "  AppTick = 4\n  bhv_dir_not_found_ok = true\n",
    );
    let (code, text, _) = check("missing-dir-ok", &allowed, GOOD_BHV);
    assert_eq!(code, 0, "{text}");
    assert!(!text.contains("/no/such/dir"), "{text}");
    // An existing one is loaded (and named in the report).
    let here = MISSION.replace(
        "  AppTick = 4\n",
        &format!("  AppTick = 4\n  ivp_behavior_dir = {}\n", d.display()),
    );
    let (code, text, _) = check("existing-dir", &here, GOOD_BHV);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("Loading directory:"), "{text}");
}

#[test]
fn bad_term_reporting_and_time_warp_are_problems() {
    // helm.md §2.2: an invalid TERM_REPORTING and a MOOSTimeWarp <= 0 are config
    // warnings, not values quietly replaced by defaults.
    let bad = MISSION.replace(
        "Community = alpha\n",
        "Community = alpha\nTERM_REPORTING = maybe\nMOOSTimeWarp = -2\n",
    );
    let (code, text, d) = check("bad-globals", &bad, GOOD_BHV);
    assert_eq!(code, 1, "{text}");
    let m = d.join("m.moos").display().to_string();
    assert!(
        text.contains(&format!("{m}: TERM_REPORTING = maybe: not a boolean")),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "{m}: MOOSTimeWarp = -2: not a time warp (above 0, at most 400)"
        )),
        "{text}"
    );
    let good = MISSION.replace(
        "Community = alpha\n",
        "Community = alpha\nTERM_REPORTING = false\nMOOSTimeWarp = 10\n",
    );
    let (code, text, _) = check("good-globals", &good, GOOD_BHV);
    assert_eq!(code, 0, "{text}");
}
