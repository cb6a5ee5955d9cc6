//! What a MOOS-IvP user writes for our behavior types (BHV_Waypoint, BHV_Loiter,
//! BHV_Timer and the plugins BHV_ConstantSpeed/Heading/Depth, BHV_StationKeep) is
//! accepted or refused by `helm check` the way the real helm does (issue 8, point 3).
//!
//! `user_missions/*.bhv` are our own missions, written from the behavior specs and from
//! the value forms the distribution's example missions use (`nextpt_lcolor=gray70`,
//! `line_color=white`, `priority`, `point = x=15, y=0`, `pts={...}, label=...`, ...).
//! The refusals are generated: one block per bad line, each must be reported with its
//! file and line.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

mod common;

const PLUGINS: &[&str] = &[
    "bhv-constant-speed",
    "bhv-constant-heading",
    "bhv-constant-depth",
    "bhv-station-keep",
];

/// The four plugin libraries, built once per test binary into a folder of their own.
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        common::lib_folder(
            &common::build_plugins(PLUGINS),
            PLUGINS,
            "user-missions-lib",
        )
    })
}

fn scratch(name: &str) -> PathBuf {
    common::scratch(Path::new("user_missions").join(name))
}

/// `helm check` of a mission whose helm block reads `bhv`; (exit code, all output).
fn check(name: &str, bhv: &Path) -> (i32, String) {
    let d = scratch(name);
    let moos = format!(
        "ServerHost = localhost\nServerPort = 9000\nCommunity = abe\n\
         LatOrigin = 43.825300\nLongOrigin = -70.330400\n\n\
         ProcessConfig = pHelmIvP\n{{\n  AppTick = 4\n  behaviors = {}\n\
         \x20 domain = course:0:359:360\n  domain = speed:0:4:41\n  domain = depth:0:100:101\n}}\n",
        bhv.display()
    );
    let mission = d.join("m.moos");
    std::fs::write(&mission, moos).expect("write mission");
    let out = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("check")
        .arg(&mission)
        .env("IVP_BEHAVIOR_DIRS", plugin_dir())
        .output()
        .expect("run helm");
    (out.status.code().unwrap_or(-1), common::text(&out))
}

fn ours(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/user_missions")
        .join(file)
}

#[test]
fn a_survey_with_every_waypoint_parameter_form_is_accepted() {
    let (code, text) = check("survey", &ours("survey.bhv"));
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("ok: 3 behavior(s): tour, waypt_return, w3"),
        "{text}"
    );
}

#[test]
fn loiter_timer_and_the_plugins_with_every_parameter_form_are_accepted() {
    let (code, text) = check("others", &ours("others.bhv"));
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("ok: 6 behavior(s): loiter, timer, cs, ch, cd, sk"),
        "{text}"
    );
}

/// Lines the real helm refuses (behaviors-std.md §2.1, §3.1, §4; behaviors-plugins.md
/// §2.1-5.1; behavior-common.md §1, §3.1), per behavior type.
const REFUSED: &[(&str, &[&str])] = &[
    (
        "BHV_Waypoint",
        &[
            "speed = -1",
            "speed = fast",
            "speed_alt = -0.5",
            "currix = -2",
            "greedy_tour = maybe",
            "wpt_status = TWO WORDS",
            "wpt_status = ",
            "wpt_index_var = A B",
            "wpt_dist_to_prev = A B",
            "post_suffix = A B",
            "cycleflag = NOEQUALS",
            "wptflag = X = ",
            "wptflag =  = 3",
            "wptflag = X = 1 [if] ((A = 1",
            "lead = far",
            "lead_damper = 0",
            "lead_damper = -1",
            "order = Reverse",
            "order = backwards",
            "repeat = -1",
            "repeat = lots",
            "radius = 0",
            "radius = -2",
            "capture_radius = x",
            "slip_radius = -1",
            "nm_radius = x",
            "capture_line = sometimes",
            "efficiency_measure = some",
            "crs_spd_zaic_ratio = 0",
            "patience = 100",
            "patience = 0.5",
            "visual_hints = vertex_color=notacolor",
            "visual_hints = nextpt_lcolor=gray71",
            "visual_hints = vertex_size=big",
            "visual_hints = label=tour",
            "visual_hints = edge_color=0,0,0",
            "visual_hints = edge_color=hex:00,00,00",
            "visual_hints = vertex_color=hex:bd:b7:6b",
            "visual_hints = vertex_color=0.5:0.5",
            "visual_hints = nextpt_color",
            "end_spd = slow_dist=0",
            "end_spd = slow_dist=5,stop_dist=10",
            "end_spd = fast",
            "points = ",
            "points = a,b:c,d",
            "point = nowhere",
            "newpt = x",
            "lead_condition = ((",
            "xpoints = 1,1:2,2",
            "speeed = 2",
            "_speed = 2",
        ],
    ),
    (
        "BHV_Loiter",
        &[
            "polygon = 0,0:10,10:0,10:10,0",
            "polygon = nonsense",
            "clockwise = sometimes",
            "speed = -1",
            "speed_alt = x",
            "use_alt_speed = maybe",
            "radius = -1",
            "nm_radius = x",
            "acquire_dist = -1",
            "patience = 100",
            "center_assign = nowhere",
            "xcenter_assign = x",
            "center_activate = yes",
            "mod_poly_rad = x",
            "slingshot = -1",
            "spiral_factor = x",
            "post_suffix = A B",
            "post_suffix = ",
            "lead = 8",
        ],
    ),
    (
        "BHV_Timer",
        &[
            "var_status_idle = A B",
            "var_status_running = T RUN",
            "speed = 2",
        ],
    ),
    (
        "BHV_ConstantSpeed",
        &[
            "speed = fast",
            "speed = 1e3",
            "peakwidth = x",
            "basewidth = x",
            "summitdelta = x",
            "speed_mismatch_var = A B",
            "heading = 3",
        ],
    ),
    (
        "BHV_ConstantHeading",
        &[
            "heading = north",
            "peakwidth = x",
            "complete_thresh = x",
            "heading_mismatch_var = A B",
        ],
    ),
    (
        "BHV_ConstantDepth",
        &[
            "depth = deep",
            "summitdelta = x",
            "depth_mismatch_var = A B",
        ],
    ),
    (
        "BHV_StationKeep",
        &[
            "station_pt = nowhere",
            "station_pt = present_position",
            "point = 1,2,3,4",
            "center_activate = yes",
            "hibernation_radius = 0",
            "hibernation_radius = -2",
            "hibernation_radius = -1.0",
            "hibernation_radius = x",
            "outer_radius = 0",
            "inner_radius = -1",
            "outer_speed = 0",
            "extra_speed = 0",
            "transit_speed = x",
            "swing_time = x",
            "speed = 2",
        ],
    ),
];

#[test]
fn every_line_the_real_helm_refuses_is_refused_with_file_and_line() {
    // One block per bad line, so that each block has exactly one problem.
    let mut bhv = String::new();
    let mut expected = Vec::new();
    let mut line = 1;
    for (ty, lines) in REFUSED {
        for bad in *lines {
            bhv.push_str(&format!(
                "Behavior = {ty}\n{{\n  name = b{}\n  {bad}\n}}\n",
                expected.len()
            ));
            expected.push((line + 3, *ty, *bad));
            line += 5;
        }
    }
    let d = scratch("refused-bhv");
    let file = d.join("bad.bhv");
    std::fs::write(&file, bhv).expect("write bhv");
    let (code, text) = check("refused", &file);
    assert_eq!(code, 1, "{text}");
    let mut missed = Vec::new();
    for (n, ty, bad) in &expected {
        let at = format!("{}:{n}:", file.display());
        let shown = text
            .lines()
            .any(|l| l.starts_with(&at) && l.contains(bad.split('=').next().unwrap_or(bad)));
        if !shown {
            missed.push(format!("{ty} line {n}: {bad}"));
        }
    }
    assert!(
        missed.is_empty(),
        "not refused:\n{}\n---\n{text}",
        missed.join("\n")
    );
    assert!(
        text.contains(&format!("{} configuration problem(s)", expected.len())),
        "{text}"
    );
}

#[test]
fn a_bad_colour_in_one_hint_refuses_the_line_and_names_it() {
    let d = scratch("colour-bhv");
    let file = d.join("c.bhv");
    std::fs::write(
        &file,
        "Behavior = BHV_Waypoint\n{\n  name = w\n  points = 0,0:10,10\n  \
         visual_hints = nextpt_lcolor=gray70\n  visual_hints = vertex_color=yellow, edge_color=grey_71\n}\n",
    )
    .expect("write bhv");
    let (code, text) = check("colour", &file);
    assert_eq!(code, 1, "{text}");
    let at = format!("{}:6:", file.display());
    assert!(
        text.lines()
            .any(|l| l.starts_with(&at) && l.contains("edge_color=grey_71")),
        "{text}"
    );
    assert!(!text.contains(&format!("{}:5:", file.display())), "{text}");
}
