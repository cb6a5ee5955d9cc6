//! BHV_OpRegion, BHV_OpRegionV24 (bhv-region), BHV_PModelView (bhv-visuals) and
//! BHV_Convoy (bhv-convoy) through the real `helm check`: blocks written in the forms
//! and with the values of the MOOS-IvP distribution's missions (ufld_convoy's Convoy as
//! behaviors-more.md §10 records it, m34_bo_alpha's PModelView, the op-region blocks of
//! the older missions and of the V24 test missions; written here, not copied) load
//! without a problem, and bad values are refused with the `.bhv` file and line.

mod common;

const PACKAGES: [&str; 3] = ["bhv-region", "bhv-visuals", "bhv-convoy"];

const MISSION: &str = "ServerHost = localhost\nServerPort = 9000\nCommunity = ben\nLatOrigin = 43.8\nLongOrigin = -70.3\n\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = m.bhv\n  domain = course:0:359:360\n  domain = speed:0:4:21\n}\n";

const GOOD_BHV: &str = r#"initialize DEPLOY = true

Behavior = BHV_OpRegion
{
  name       = opregion
  pwt        = 100
  condition  = DEPLOY = true
  polygon    = pts={-50,-40 : 100,20 : 180,20 : 180,-200 : -50,-200 : -100,-75}
  trigger_entry_time = 1
  trigger_exit_time  = 1
  max_time   = 3600
  max_depth  = 30
  min_altitude = 5
  breached_poly_flag = OPREG_BREACH = poly
  breached_time_flag = OPREG_BREACH = time
  reset_var  = OPREGION_RESET
  time_remaining_var = OPREGION_TIME_LEFT
  opregion_poly_var  = OPREGION_POLY
  visual_hints = edge_size=1, vertex_size=2, edge_color=gray50
}

Behavior = BHV_OpRegionV24
{
  name       = opregx
  pwt        = 300
  condition  = DEPLOY = true
  updates    = OPREGION_UPDATES
  core_poly  = pts={-10,-10 : 150,-10 : 150,-150 : -10,-150}
  save_dist  = 5
  halt_dist  = 10
  recover_spd = 1.2
  trigger_on_poly_entry = true
  trigger_entry_time = 1
  trigger_exit_time  = 1
  save_flag  = OPREG_SAVE = true
  savex_flag = OPREG_SAVE = false
  halt_flag  = OPREG_HALT = true
  draw_save_status = true
  draw_halt_status = false
  core_poly_var = OPREGION_CORE_POLY
}

Behavior = BHV_PModelView
{
  name      = pmv
  pwt       = 100
  condition = DEPLOY = true
  edge_color   = white
  vertex_color = white
  vertex_size  = 3
}

Behavior = BHV_Convoy
{
  name      = convoy
  pwt       = 100
  condition = DEPLOY = true
  updates   = UP_CONVOY
  contact   = abe
  rng_estop   = 15
  spd_max     = 4
  spd_slower  = 0.8
  spd_faster  = 1.2
  rng_tgating = 25
  rng_lagging = 40
  radius      = 8
  nm_radius   = 15
  inter_mark_range = 5
  max_mark_range   = 80
}
"#;

fn check(name: &str, bhv: &str) -> (i32, String, String) {
    common::check_bhv("region_behaviors", &PACKAGES, name, MISSION, bhv)
}

#[test]
fn distribution_forms_check_ok_and_bad_values_name_file_and_line() {
    let (code, text, _) = check("good", GOOD_BHV);
    assert_eq!(code, 0, "{text}");
    for t in [
        "BHV_OpRegion",
        "BHV_OpRegionV24",
        "BHV_PModelView",
        "BHV_Convoy",
    ] {
        assert!(text.contains(t), "{t} not loaded: {text}");
    }
    assert!(!text.contains("MALCONFIG"), "{text}");

    let bad = GOOD_BHV
        .replace("  max_time   = 3600", "  max_time   = -5")
        .replace(
            "  polygon    = pts={-50,-40 : 100,20 : 180,20 : 180,-200 : -50,-200 : -100,-75}",
            "  polygon    = 0,0 : 10,0 : 5,5 : 10,10 : 0,10",
        )
        .replace("  save_dist  = 5", "  save_dist  = -5")
        .replace("  recover_spd = 1.2", "  recover_spd = 0")
        .replace("  vertex_color = white", "  vertex_color = not_a_colour")
        .replace("  spd_faster  = 1.2", "  spd_faster  = 3.5")
        .replace("  inter_mark_range = 5", "  inter_mark_range = 0");
    let (code, text, path) = check("bad", &bad);
    assert_eq!(code, 1, "{text}");
    let line_of = |needle: &str| bad.lines().position(|l| l.contains(needle)).unwrap() + 1;
    for needle in [
        "max_time   = -5",
        "polygon    = 0,0 : 10,0",
        "save_dist  = -5",
        "recover_spd = 0",
        "vertex_color = not_a_colour",
        "spd_faster  = 3.5",
        "inter_mark_range = 0",
    ] {
        let at = format!("{path}:{}:", line_of(needle));
        assert!(text.contains(&at), "{needle} not reported at {at}: {text}");
    }
}
