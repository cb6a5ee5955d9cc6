//! The contact behavior plugin (bhv-contact: BHV_AvoidCollision, BHV_CutRange,
//! BHV_Trail, BHV_Shadow) through the real `helm check`: blocks written in the
//! parameter forms of the MOOS-IvP distribution's missions (m2_berta's and m3_casar's
//! AvoidCollision templates, m3_casar's Trail template, the CutRange template form of
//! behaviors-contacts.md §2) load without a problem, and bad values — including
//! `use_refinery = true`, which this helm does not build — are refused with the `.bhv`
//! file and line.

mod common;

const PACKAGES: [&str; 1] = ["bhv-contact"];

const MISSION: &str = "ServerHost = localhost\nServerPort = 9000\nCommunity = abe\nLatOrigin = 43.8\nLongOrigin = -70.3\n\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = m.bhv\n  domain = course:0:359:360\n  domain = speed:0:4:21\n}\n";

/// One block per form, our own names and values.
const GOOD_BHV: &str = r#"initialize AVOID = true
initialize TRAILING_OK = true
initialize CHASE = true

Behavior = BHV_AvoidCollision
{
  name         = avdc_
  pwt          = 250
  condition    = AVOID = true
  updates      = CONTACT_INFO
  idleflag     = AVOIDING = idle
  activeflag   = AVOIDING = active
  inactiveflag = AVOIDING = inactive
  runflag      = AVOIDING = running
  endflag      = AVOIDING = end
  endflag      = CONTACT_RESOLVED = $[CONTACT]
  templating   = spawn

             contact = to-be-set
    on_no_contact_ok = true
         extrapolate = true
               decay = 20,40

      pwt_outer_dist = 45
      pwt_inner_dist = 15
      completed_dist = 90
   min_util_cpa_dist = 6
   max_util_cpa_dist = 20
           pwt_grade = linear
 bearing_line_config = white:0, green:0.6, yellow:0.75, red:1.0
}

Behavior = BHV_AvoidCollision
{
  name       = avd_old
  pwt        = 150
  condition  = AVOID = true
  updates    = CONTACT_INFO_OLD
  endflag    = CONTACT_RESOLVED = $[CONTACT],avd
  templating = spawn

             contact = to-be-set
      pwt_outer_dist = 60
      pwt_inner_dist = 25
      completed_dist = 130
   min_util_cpa_dist = 7
   max_util_cpa_dist = 22
        active_grade = quadratic
    on_no_contact_ok = true
         extrapolate = true
               decay = 30,60
             cnflag  = @<20 CLOSE_CALL = $[CN_NAME]
       use_refinery  = false
         match_name  = gus
}

Behavior = BHV_Trail
{
  name       = trailer
  pwt        = 100
  condition  = TRAILING_OK = true
  runflag    = TRAIL = true
  idleflag   = TRAIL = false
  updates    = TRAIL_INFO
  templating = spawn

           contact = to-be-set
    pwt_outer_dist = 110
         nm_radius = 16
            radius = 6
       trail_angle = 150
       trail_range = 30
  trail_angle_type = relative
  on_no_contact_ok = true
       extrapolate = true
             decay = 30,60
 bearing_line_config = white:0, green:0.65, yellow:0.8, red:1.0
}

Behavior = BHV_CutRange
{
  name       = cut_range
  pwt        = 120
  condition  = CHASE = true
  updates    = UPDATES_CUT
  templating = spawn

         contact = to-be-set
  pwt_outer_dist = 90
  pwt_inner_dist = 15
     giveup_dist = 110
        patience = 50
      match_type = kayak
      pursueflag = PURSUING = $[CONTACT]
      giveupflag = PURSUING = none
}

Behavior = BHV_Shadow
{
  name              = shadow_fixed
  condition         = CHASE = false
  contact           = hal
  pwt_outer_dist    = 40
  hdg_peakwidth     = 15
  spd_basewidth     = 1.5
}
"#;

fn check(name: &str, bhv: &str) -> (i32, String, String) {
    common::check_bhv("contact_behaviors", &PACKAGES, name, MISSION, bhv)
}

#[test]
fn distribution_forms_check_ok_and_bad_values_name_file_and_line() {
    let (code, text, _) = check("good", GOOD_BHV);
    assert_eq!(code, 0, "{text}");
    // Templates are built once to validate them but are not in the set until spawned.
    assert!(text.contains("ok: 1 behavior(s): shadow_fixed"), "{text}");

    let bad = GOOD_BHV
        .replace(
            "       use_refinery  = false",
            "       use_refinery  = true",
        )
        .replace(
            "           pwt_grade = linear",
            "           pwt_grade = cubic",
        )
        .replace(
            "  trail_angle_type = relative",
            "  trail_angle_type = sideways",
        )
        .replace("        patience = 50", "        patience = 150")
        .replace("  hdg_peakwidth     = 15", "  hdg_peakwidth     = -15")
        .replace(
            "               decay = 20,40",
            "               decay = 40,20",
        );
    let (code, text, path) = check("bad", &bad);
    assert_eq!(code, 1, "{text}");
    let line_of = |needle: &str| bad.lines().position(|l| l.contains(needle)).unwrap() + 1;
    for needle in [
        "use_refinery  = true",
        "pwt_grade = cubic",
        "trail_angle_type = sideways",
        "patience = 150",
        "decay = 40,20",
        "hdg_peakwidth     = -15",
    ] {
        let at = format!("{path}:{}:", line_of(needle));
        assert!(text.contains(&at), "{needle} not reported at {at}: {text}");
    }
    // Known parameters with a refused value are said to be that, not unknown.
    for p in ["use_refinery = true", "pwt_grade = cubic"] {
        assert!(text.contains(&format!("bad value: {p}")), "{p}: {text}");
    }
}
