//! The COLREGS plugin (bhv-colregs: BHV_AvdColregsV22, V19, V17) through the real
//! `helm check`: blocks written in the parameter forms the MOOS-IvP distribution's
//! missions use for these types (m2_berta's and m2_berta_otest's V19 templates with
//! `spawnxflag`, `exit_on_filter_group`, `post_per_contact_info`, `use_refinery`;
//! m34_bo_alpha's V19 plug with `giveway_bow_dist`; m2_track_cond's and
//! m2_berta_detect's V17 templates; the V22 template form of the golden cases) load
//! without a problem — our own names and values, the same forms — and bad values are
//! refused with the `.bhv` file and line.

mod common;

const PACKAGES: [&str; 1] = ["bhv-colregs"];

const MISSION: &str = "ServerHost = localhost\nServerPort = 9000\nCommunity = abe\nLatOrigin = 43.8\nLongOrigin = -70.3\n\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = m.bhv\n  domain = course:0:359:360\n  domain = speed:0:4:41\n}\n";

const GOOD_BHV: &str = r#"initialize AVOID = true
initialize MODE_OK = true

Behavior = BHV_AvdColregsV22
{
  name       = col22_
  pwt        = 140
  condition  = AVOID = true
  updates    = CONTACT_INFO_22
  templating = spawn

  runflag      = AVOIDING = running
  endflag      = AVOIDING = end
  endflag      = RESOLVED = $[CONTACT]

               contact = to-be-set
      on_no_contact_ok = true
           extrapolate = true
                 decay = 30,60
 post_per_contact_info = true
     velocity_filter = min_spd=0.5,max_spd=2.5,pct=30
           headon_only = false
     pts_port_turns_ok = true
              eval_tol = 90

        pwt_outer_dist = 70
        pwt_inner_dist = 40
        completed_dist = 75
     min_util_cpa_dist = 9
     max_util_cpa_dist = 20
             pwt_grade = quasi
}

Behavior = BHV_AvdColregsV19
{
  name       = col19_
  pwt        = 160
  condition  = AVOID = true
  condition  = MODE_OK = true
  updates    = CONTACT_INFO_19
  templating = spawn

	spawnxflag = SEEN=os=$[OWNSHIP],range=$[RANGE],contact=$[CONTACT],bng=$[OS_CN_REL_BNG]
             contact = to-be-set
    on_no_contact_ok = true
         extrapolate = true
               decay = 20,50

	exit_on_filter_group = true
	post_per_contact_info = true
  use_refinery = true

        pwt_outer_dist = 60
        pwt_inner_dist = 30
        completed_dist = 65
     min_util_cpa_dist = 7
     max_util_cpa_dist = 16
             pwt_grade = linear
   bearing_line_config = white:0, green:0.6, yellow:0.85, red:1.0
}

Behavior = BHV_AvdColregsV19
{
  name       = plug19_
  pwt        = 150
  condition  = AVOID = true
  updates    = CONTACT_INFO_P
  endflag    = RESOLVED = $[CONTACT]
  templating = spawn

             contact = to-be-set
    on_no_contact_ok = true
         extrapolate = true
               decay = 30,60

    giveway_bow_dist = 12
        use_refinery = true

      pwt_outer_dist = 25
      pwt_inner_dist = 12
      completed_dist = 45
   min_util_cpa_dist = 9
   max_util_cpa_dist = 14
           pwt_grade = linear
 bearing_line_config = white:0, green:0.65, yellow:0.8, red:1.0
}

Behavior = BHV_AvdColregsV17
{
  name         = col17_
  pwt          = 400
  condition    = AVOID = true
  updates      = CONTACT_INFO_17
  idleflag     = AVOIDING = idle
  activeflag   = AVOIDING = active
  inactiveflag = AVOIDING = inactive
  templating   = spawn

             contact = to-be-set
    on_no_contact_ok = true
         extrapolate = true
               decay = 30,60

        pwt_outer_dist = 45
        pwt_inner_dist = 15
        completed_dist = 45
     min_util_cpa_dist = 7
     max_util_cpa_dist = 14
             pwt_grade = linear
   bearing_line_config = white:0, green:0.65, yellow:0.8, red:1.0
}

Behavior = BHV_AvdColregsV22
{
  name    = col_fixed
  pwt     = 100
  contact = hal
  avoid_mode    = giveway
  avoid_submode = bow
}
"#;

fn check(name: &str, bhv: &str) -> (i32, String, String) {
    common::check_bhv("colregs_behaviors", &PACKAGES, name, MISSION, bhv)
}

#[test]
fn distribution_forms_check_ok_and_bad_values_name_file_and_line() {
    let (code, text, _) = check("good", GOOD_BHV);
    assert_eq!(code, 0, "{text}");
    // Templates are built once to validate them but are not in the set until spawned.
    assert!(text.contains("ok: 1 behavior(s): col_fixed"), "{text}");

    let bad = GOOD_BHV
        .replace(
            "             pwt_grade = quasi",
            "             pwt_grade = steep",
        )
        .replace("              eval_tol = 90", "              eval_tol = 4")
        .replace(
            "  use_refinery = true\n\n        pwt_outer_dist = 60",
            "  velocity_filter = min_spd=1,max_spd=2\n\n        pwt_outer_dist = 60",
        )
        .replace(
            "        completed_dist = 45\n     min_util_cpa_dist = 7",
            "        can_disable = true\n     min_util_cpa_dist = 7",
        )
        .replace("  avoid_submode = bow", "  avoid_submode = port")
        .replace(
            "     min_util_cpa_dist = 9\n     max_util_cpa_dist = 20",
            "     min_util_cpa_dist = -9\n     max_util_cpa_dist = 20",
        );
    let (code, text, path) = check("bad", &bad);
    assert_eq!(code, 1, "{text}");
    let line_of = |needle: &str| bad.lines().position(|l| l.contains(needle)).unwrap() + 1;
    for needle in [
        "pwt_grade = steep",
        "eval_tol = 4",
        // V19 has no velocity filter; V17 no able filter.
        "velocity_filter = min_spd=1,max_spd=2",
        "can_disable = true",
        "avoid_submode = port",
        "min_util_cpa_dist = -9",
    ] {
        let at = format!("{path}:{}:", line_of(needle));
        assert!(text.contains(&at), "{needle} not reported at {at}: {text}");
    }
}
