//! BHV_AvoidObstacleV24 (bhv-obstacle) and the three deprecated obstacle types through the
//! real `helm check` (obstacles.md §1.15, §5): the V24 template as m34_bo_alpha writes it
//! (names and values of §5, written here) loads without a problem; a V24 block with a
//! parameter it does not take is refused at its line; BHV_AvoidObstacleV21,
//! BHV_AvoidObstacleX and BHV_AvoidObstacle, as m2_berta_otest, m2_berta_tx and
//! s1_alpha_obstaclemgr write them, are refused at configuration with the real helm's
//! four deprecation lines, naming BHV_AvoidObstacleV24.

mod common;

const PACKAGES: [&str; 1] = ["bhv-obstacle"];

const MISSION: &str = "ServerHost = localhost\nServerPort = 9000\nCommunity = abe\nLatOrigin = 43.8\nLongOrigin = -70.3\n\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = m.bhv\n  domain = course:0:359:360\n  domain = speed:0:4:21\n}\n";

/// m34_bo_alpha's V24 template (obstacles.md §5), with a waypoint so the set is not empty.
const M34_V24: &str = r#"initialize DEPLOY = true

Behavior = BHV_Waypoint
{
  name      = transit
  condition = DEPLOY = true
  speed     = 2
  points    = 150,0
}

Behavior = BHV_AvoidObstacleV24
{
  name       = avd_ob_
  pwt        = 500
  condition  = DEPLOY = true
  templating = spawn
  updates    = OBSTACLE_ALERT

       use_refinery = true
      allowable_ttc = 5
  min_util_cpa_dist = 3
  max_util_cpa_dist = 7
     pwt_outer_dist = 15
     pwt_inner_dist = 5
     completed_dist = 15
}
"#;

/// The V21 block of m2_berta_otest (and, with the type changed, m2_berta_tx's X block).
const V21_BLOCK: &str = r#"Behavior = TYPE
{
  name       = avdob_
  pwt        = 300
  condition  = DEPLOY = true
  templating = spawn
  updates    = OBSTACLE_ALERT
  use_refinery = true

      allowable_ttc = 12
     pwt_outer_dist = 15
     pwt_inner_dist = 5
     completed_dist = 18
  min_util_cpa_dist = 4
  max_util_cpa_dist = 8
  visual_hints = obstacle_edge_color = white
  visual_hints = buffer_min_fill_transparency = 0.25
}
"#;

/// s1_alpha_obstaclemgr's BHV_AvoidObstacle template.
const PLAIN_BLOCK: &str = r#"Behavior = BHV_AvoidObstacle
{
  name       = avoid_obstacle_
  pwt        = 500
  condition  = DEPLOY = true
  templating = spawn
  updates    = OBSTACLE_ALERT
  allowable_ttc  = 5
  buffer_dist    = 5
  pwt_outer_dist = 19
  pwt_inner_dist = 10
  completed_dist = 51
}
"#;

fn check(name: &str, bhv: &str) -> (i32, String, String) {
    common::check_bhv("obstacle_behaviors", &PACKAGES, name, MISSION, bhv)
}

#[test]
fn m34_bo_alpha_v24_template_checks_ok() {
    let (code, text, _) = check("m34", M34_V24);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("ok: 1 behavior(s): transit"), "{text}");
}

#[test]
fn v24_refuses_what_it_does_not_take_at_its_line() {
    // m2_berta_obstacles' `buffer_dist = 3` (run R2: config warning, MALCONFIG), and a
    // completed_dist set before a larger pwt_outer_dist (§1.2.1).
    let bad = M34_V24
        .replace("       use_refinery = true", "        buffer_dist = 3")
        .replace(
            "     pwt_inner_dist = 5\n     completed_dist = 15",
            "     pwt_inner_dist = 5",
        );
    let bad = bad.replace(
        "      allowable_ttc = 5",
        "     completed_dist = 10\n      allowable_ttc = 5",
    );
    let (code, text, path) = check("v24_bad", &bad);
    assert_eq!(code, 1, "{text}");
    let line_of = |needle: &str| bad.lines().position(|l| l.contains(needle)).unwrap() + 1;
    for needle in ["buffer_dist = 3", "pwt_outer_dist = 15"] {
        let at = format!("{path}:{}:", line_of(needle));
        assert!(text.contains(&at), "{needle} not reported at {at}: {text}");
    }
}

/// The four lines the real helm adds for a deprecated type (run R2).
fn deprecation_lines(ty: &str) -> [String; 4] {
    [
        format!("{ty} is no longer supported."),
        "Use BHV_AvoidObstacleV24 or newer instead.".into(),
        "Set i_understand_this_behavior_is_deprecated=true".into(),
        "to suppress this warning and use at your own risk.".into(),
    ]
}

#[test]
fn deprecated_types_are_refused_with_the_real_helms_reason() {
    let cases = [
        (
            "v21",
            "BHV_AvoidObstacleV21",
            V21_BLOCK.replace("TYPE", "BHV_AvoidObstacleV21"),
        ),
        (
            "x",
            "BHV_AvoidObstacleX",
            V21_BLOCK.replace("TYPE", "BHV_AvoidObstacleX"),
        ),
        ("plain", "BHV_AvoidObstacle", PLAIN_BLOCK.to_string()),
    ];
    for (name, ty, block) in cases {
        let bhv = format!("initialize DEPLOY = true\n\n{block}");
        let (code, text, path) = check(name, &bhv);
        assert_eq!(code, 1, "{ty}: {text}");
        let line = bhv.lines().position(|l| l.starts_with("Behavior")).unwrap() + 1;
        for w in deprecation_lines(ty) {
            let want = format!("{path}:{line}: {w}");
            assert!(text.contains(&want), "{ty}: missing `{want}`: {text}");
        }
        assert!(!text.contains("unknown behavior type"), "{text}");

        // Acknowledged, the real helm would run it; this helm does not have it and says
        // so, naming the replacement.
        let ack = bhv.replace(
            "  pwt        = ",
            "  i_understand_this_behavior_is_deprecated = true\n  pwt        = ",
        );
        let (code, text, _) = check(&format!("{name}_ack"), &ack);
        assert_eq!(code, 1, "{ty}: {text}");
        assert!(!text.contains("is no longer supported"), "{text}");
        assert!(
            text.contains(&format!("{ty} is deprecated and not provided by this helm"))
                && text.contains("use BHV_AvoidObstacleV24 instead"),
            "{text}"
        );
    }
}
