//! The depth, survey and visual behavior plugins (bhv-depth, bhv-survey, bhv-visuals)
//! through the real `helm check`: blocks written in the parameter forms of the
//! MOOS-IvP distribution's missions load without a problem, and bad values are refused
//! with the `.bhv` file and line.

mod common;

const PACKAGES: [&str; 3] = ["bhv-depth", "bhv-survey", "bhv-visuals"];

const MISSION: &str = "ServerHost = localhost\nServerPort = 9000\nCommunity = abe\nLatOrigin = 43.8\nLongOrigin = -70.3\n\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = m.bhv\n  domain = course:0:359:360\n  domain = speed:0:4:21\n  domain = depth:0:100:101\n}\n";

/// One block per type, in the forms the distribution's missions use (our own values).
const GOOD_BHV: &str = r#"initialize DEPLOY = true
initialize RETURN = false

Behavior = BHV_HSLine
{
  name        = hsline
  condition   = DEPLOY = true
  time_on_leg = 10
}

Behavior = BHV_BearingLine
{
  name          = bngl
  templating    = clone
  updates       = BEARING_POINT
  bearing_point = 100,-100
  line_pct      = 50
  show_pt       = true
}

Behavior = BHV_PeriodicSurface
{
  name                = surface
  pwt                 = 1000
  condition           = DEPLOY = true
  period              = 120
  max_time_at_surface = 60
  ascent_speed        = 1.0
  ascent_grade        = fullspeed
  zero_speed_depth    = 2
}

Behavior = BHV_MaxDepth
{
  name      = maxdepth
  max_depth = 7
  tolerance = 1
  duration  = no-time-limit
}

Behavior = BHV_MaxSpeed
{
  name      = maxspeed
  max_speed = 2.1
  basewidth = 0.2
  speed_slack_var = SPD_SLACK
}

Behavior = BHV_GoToDepth
{
  name          = levels
  condition     = DEPLOY = true
  depth         = 40,60:30,45:20,45
  repeat        = 2
  perpetual     = true
  capture_flag  = DEPTH_ACHIEVED
  capture_delta = 0.5
  endflag       = GOTO_DEPTH = false
}

Behavior = BHV_ZigZag
{
  name           = zig
  condition      = DEPLOY = true
  speed          = 3.0
  stem_on_active = true
  zig_first      = star
  max_zig_zags   = 1
  zig_angle      = 55
  hdg_thresh     = 2
  fierce_zigging = true
  perpetual      = true
  zigflag        = ZIGF = $[ZIGS]:$[ZAGS]
}

Behavior = BHV_LegRun
{
  name      = legs
  condition = RETURN = false
  endflag   = RETURN = true
  speed     = 2.5
  vx1       = 70,-35
  vx2       = -35,-85
  turn1_rad = 20
  turn2_rad = 20
  turn1_bias = 100
  turn2_bias = 100
  turn1_dir = port
  turn2_dir = star
  repeat    = 1
  leg_endflag  = LEG_END = $[LEG_ID]
  mid_leg_flag = MID = $[LEG_ID]
}
"#;

fn check(name: &str, bhv: &str) -> (i32, String, String) {
    common::check_bhv("more_behaviors", &PACKAGES, name, MISSION, bhv)
}

#[test]
fn distribution_forms_check_ok_and_bad_values_name_file_and_line() {
    let (code, text, _) = check("good", GOOD_BHV);
    assert_eq!(code, 0, "{text}");
    for name in [
        "hsline", "bngl", "surface", "maxdepth", "maxspeed", "levels", "zig", "legs",
    ] {
        assert!(text.contains(name), "{name} missing: {text}");
    }

    // x1_legs as shipped: `legflag` and `mid_pct` are not LegRun parameters.
    let bad = GOOD_BHV
        .replace(
            "  repeat    = 1\n",
            "  repeat    = 1\n  legflag = X = 1\n  mid_pct = 10\n",
        )
        .replace("  time_on_leg = 10", "  time_on_leg = 0")
        .replace("  zig_angle      = 55", "  zig_angle      = 80")
        .replace(
            "  ascent_grade        = fullspeed",
            "  ascent_grade        = steep",
        )
        .replace(
            "  depth         = 40,60:30,45:20,45",
            "  depth         = 40,-60",
        );
    let (code, text, path) = check("bad", &bad);
    assert_eq!(code, 1, "{text}");
    let line_of = |needle: &str| bad.lines().position(|l| l.contains(needle)).unwrap() + 1;
    for needle in [
        "time_on_leg = 0",
        "ascent_grade        = steep",
        "depth         = 40,-60",
        "zig_angle      = 80",
        "legflag = X = 1",
        "mid_pct = 10",
    ] {
        let at = format!("{path}:{}:", line_of(needle));
        assert!(text.contains(&at), "{needle} not reported at {at}: {text}");
    }
}
