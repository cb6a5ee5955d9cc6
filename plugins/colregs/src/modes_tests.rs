//! Mode classification at chosen geometries; each expected mode is worked out from
//! the relative bearings in the comments (compass degrees, ownship at the origin).

use super::*;
use behavior_api::contacts::Pose;

fn pose(x: f64, y: f64, hdg: f64, spd: f64) -> Pose {
    Pose { x, y, hdg, spd }
}

/// One update from `m` with outer ring `outer`, util distances 10/18.
fn step(m: &mut Machine, os: Pose, cn: Pose, outer: f64, rate: Option<f64>) -> Vec<Debug> {
    let rel = ContactRelation::new(os, cn);
    let i = Inputs {
        rel: &rel,
        os: (os.x, os.y, os.hdg, os.spd),
        cn: (cn.x, cn.y, cn.hdg),
        outer,
        min_util: 10.0,
        max_util: 18.0,
        giveway_bow_dist: -1.0,
        turn_radius: 0.0,
        crossed: false,
        turn_rate: rate,
    };
    let mut dbg = Vec::new();
    m.update(&i, &mut dbg);
    dbg
}

#[test]
fn head_on_enters_and_releases_on_opening_range() {
    // Contact 60 m dead ahead coming south: both relative bearings 0 (≤ 12), range
    // 60 < 2 × 80.
    let mut m = Machine::default();
    let dbg = step(
        &mut m,
        pose(0.0, 0.0, 0.0, 2.0),
        pose(0.0, 60.0, 180.0, 2.0),
        80.0,
        None,
    );
    assert_eq!((m.mode, m.submode), (Mode::HeadOn, Submode::None));
    assert_eq!(dbg, vec![Debug::HeadOn("entered head-on mode")]);
    assert_eq!(mode_index(m.mode, m.submode), 10);
    // Still head-on next iteration (closing, bearings unchanged).
    step(
        &mut m,
        pose(0.0, 2.0, 0.0, 2.0),
        pose(0.0, 58.0, 180.0, 2.0),
        80.0,
        None,
    );
    assert_eq!(m.mode, Mode::HeadOn);
    // Passed port to port: ownship (5, 70) north of the contact (0, 50), which heads
    // south: range 20.6 > 10 and opening → released; the CPA check then makes it cpa.
    let dbg = step(
        &mut m,
        pose(5.0, 70.0, 0.0, 2.0),
        pose(0.0, 50.0, 180.0, 2.0),
        80.0,
        None,
    );
    assert_eq!(dbg[0], Debug::HeadOn("release due to opening range"));
    assert_eq!(m.mode, Mode::Cpa);
}

#[test]
fn head_on_not_entered_off_the_bow() {
    // Contact at bearing 45 (> 12): not head-on; from starboard crossing → give-way.
    let mut m = Machine::default();
    let dbg = step(
        &mut m,
        pose(0.0, 0.0, 0.0, 2.0),
        pose(60.0, 60.0, 270.0, 2.0),
        100.0,
        None,
    );
    assert!(dbg.contains(&Debug::HeadOn("not entered due to rel bearing")));
    assert_eq!(m.mode, Mode::GiveWay);
}

#[test]
fn crossing_from_starboard_is_give_way_astern() {
    // Contact at (60, 60) heading west: os→cn bearing 45 (≤ 112.5), cn→os relative
    // bearing 225 − 270 = 315 (≥ 247.5): give-way. It crosses 60 m north of ownship,
    // far more than the bow acceptance (2·18 + 10)/3 = 15.3: pass astern.
    let mut m = Machine::default();
    let dbg = step(
        &mut m,
        pose(0.0, 0.0, 0.0, 2.0),
        pose(60.0, 60.0, 270.0, 2.0),
        100.0,
        None,
    );
    assert_eq!((m.mode, m.submode), (Mode::GiveWay, Submode::Stern));
    assert_eq!(mode_index(m.mode, m.submode), 20);
    assert!(dbg.iter().any(|d| matches!(d, Debug::BowDist(_))));
    // Once past its stern (ownship now on the contact's starboard side) → cpa.
    step(
        &mut m,
        pose(10.0, 65.0, 0.0, 2.0),
        pose(0.0, 60.0, 270.0, 2.0),
        100.0,
        None,
    );
    assert_eq!(m.mode, Mode::Cpa);
}

#[test]
fn crossing_from_port_is_stand_on() {
    // Contact at (−80, 100) heading east: os→cn bearing 360 − 38.7 = 321.3 (≥ 247.5),
    // cn→os relative bearing 141.3 − 90 = 51.3 (≤ 112.5), closing: stand-on. It reaches
    // x = 0 at t = 40 s, 20 m ahead of ownship (then at y = 80): bow distance 20 ≥ 18.
    let (os, cn) = (pose(0.0, 0.0, 0.0, 2.0), pose(-80.0, 100.0, 90.0, 2.0));
    let rel = ContactRelation::new(os, cn);
    assert!((rel.cn_crosses_os_bow_dist - 20.0).abs() < 1e-6);
    // In (315, 350] with x ≥ (18 + 10)/2: bow when the turn rate is known and < 3.
    let mut m = Machine::default();
    step(&mut m, os, cn, 150.0, None);
    assert_eq!((m.mode, m.submode), (Mode::StandOn, Submode::UnsureBow));
    let mut m = Machine::default();
    step(&mut m, os, cn, 150.0, Some(0.0));
    assert_eq!((m.mode, m.submode), (Mode::StandOn, Submode::Bow));
    assert_eq!(mode_index(m.mode, m.submode), 32);
    assert!(Machine::entered_standon(Mode::None, m.mode));
}

#[test]
fn overtaking_a_slower_contact_ahead() {
    // Contact 40 m ahead on the same heading at 1 m/s, ownship at 3: cn→os relative
    // bearing 180 (in [112.5, 247.5]), ownship reaches its beam (3 > 1). The contact
    // is dead ahead, not to port: overtake on its port side.
    let mut m = Machine::default();
    step(
        &mut m,
        pose(0.0, 0.0, 0.0, 3.0),
        pose(0.0, 40.0, 0.0, 1.0),
        80.0,
        None,
    );
    assert_eq!((m.mode, m.submode), (Mode::Overtaking, Submode::Port));
    assert_eq!(mode_index(m.mode, m.submode), 43);
    // Contact 5 m to port ahead: overtake on its starboard side.
    let mut m = Machine::default();
    step(
        &mut m,
        pose(0.0, 0.0, 0.0, 3.0),
        pose(-5.0, 40.0, 0.0, 1.0),
        80.0,
        None,
    );
    assert_eq!((m.mode, m.submode), (Mode::Overtaking, Submode::Starboard));
    assert_eq!(mode_index(m.mode, m.submode), 47);
}

#[test]
fn being_overtaken_is_stand_on_overtaken() {
    // Contact 40 m astern, 5 m to starboard, same heading at 3 vs ownship's 1: os→cn
    // bearing 172.9 (in [112.5, 247.5]), it passes ownship's beam with a CPA of 5 m
    // (≤ 18), range 40.3 > 18: not in extremis; it is on ownship's starboard side.
    let mut m = Machine::default();
    step(
        &mut m,
        pose(0.0, 0.0, 0.0, 1.0),
        pose(5.0, -40.0, 0.0, 3.0),
        80.0,
        None,
    );
    assert_eq!((m.mode, m.submode), (Mode::StandOnOt, Submode::Starboard));
    assert_eq!(mode_index(m.mode, m.submode), 0);
}

#[test]
fn outside_the_outer_ring_is_none_and_inside_otherwise_cpa() {
    // Contact astern going away: no rule applies; inside outer → cpa, outside → none.
    let mut m = Machine::default();
    step(
        &mut m,
        pose(0.0, 0.0, 0.0, 2.0),
        pose(30.0, -30.0, 180.0, 2.0),
        80.0,
        None,
    );
    assert_eq!((m.mode, m.submode), (Mode::Cpa, Submode::None));
    step(
        &mut m,
        pose(0.0, 0.0, 0.0, 2.0),
        pose(90.0, -90.0, 180.0, 2.0),
        80.0,
        None,
    );
    assert_eq!((m.mode, m.submode), (Mode::None, Submode::None));
}

#[test]
fn standon_table_rows() {
    let (mn, mx) = (10.0, 18.0);
    assert_eq!(
        standon_submode(355.0, 12.0, mn, mx, Some(-1.0)),
        Submode::Bow
    );
    assert_eq!(standon_submode(355.0, 5.0, mn, mx, None), Submode::Unsure);
    assert_eq!(
        standon_submode(355.0, -1.0, mn, mx, None),
        Submode::UnsureStern
    );
    assert_eq!(standon_submode(300.0, 18.0, mn, mx, None), Submode::Bow);
    assert_eq!(
        standon_submode(300.0, 15.0, mn, mx, Some(0.05)),
        Submode::Bow
    );
    assert_eq!(
        standon_submode(300.0, 15.0, mn, mx, Some(0.5)),
        Submode::UnsureBow
    );
    assert_eq!(standon_submode(300.0, -1.0, mn, mx, None), Submode::Stern);
    assert_eq!(
        standon_submode(260.0, 15.0, mn, mx, Some(0.0)),
        Submode::UnsureBow
    );
    assert_eq!(
        standon_submode(260.0, 3.0, mn, mx, Some(0.0)),
        Submode::Unsure
    );
}

#[test]
fn speed_in_heading_exact_cases() {
    assert_eq!(speed_in_heading(0.0, 2.0, 0.0), 2.0);
    assert_eq!(speed_in_heading(0.0, 2.0, 180.0), -2.0);
    assert_eq!(speed_in_heading(0.0, 2.0, 270.0), 0.0);
    assert!((speed_in_heading(0.0, 2.0, 60.0) - 1.0).abs() < 1e-12);
    assert_eq!(speed_in_heading(10.0, 0.0, 10.0), 0.0);
}
