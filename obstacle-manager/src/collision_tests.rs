use super::*;

/// The lines m2_berta_otest and m34_bo_alpha set (obstacles.md §4).
fn m34() -> CollisionConfig {
    let mut c = CollisionConfig::default();
    for (p, v) in [
        ("collision_dist", "1"),
        ("near_miss_dist", "5"),
        ("encounter_dist", "14"),
        ("encounter_flag", "OB_TOTAL_ENCOUNTERS=$ENC_CNT"),
        ("encounter_flag", "OB_TOTAL_NEAR_MISSES=$MISS_CNT"),
        ("encounter_flag", "OB_TOTAL_COLLISIONS=$COLL_CNT"),
        ("encounter_flag", "OB_ENCOUNTER = $DIST"),
        ("near_miss_flag", "OB_NEAR_MISS = $DIST"),
        ("collision_flag", "OB_COLLISION = $DIST"),
        (
            "near_miss_flag",
            "OB_NEAR_MISS_FULL = vname=$VNAME,ob=$ID,dist=$DIST",
        ),
        (
            "collision_flag",
            "OB_COLLISION_FULL = vname=$VNAME,ob=$ID,dist=$DIST",
        ),
    ] {
        c.set(p, v).unwrap_or_else(|e| panic!("{p}: {e}"));
    }
    assert!(c.finish().is_empty());
    c
}

fn find<'a>(p: &'a [Posting], var: &str) -> Option<&'a Value> {
    p.iter().find(|p| p.var == var).map(|p| &p.val)
}

/// A vehicle passing the 10x10 square at (0..10, 0..10) along y = `y`, 1 m per step,
/// from x = −30 to x = 40; the postings of every step.
fn pass(d: &mut CollisionDetector, name: &str, y: f64) -> Vec<Posting> {
    let mut all = Vec::new();
    for k in -30..=40 {
        all.extend_from_slice(d.step(0.0, &[(name, f64::from(k), y)]));
    }
    all
}

#[test]
fn encounters_near_misses_and_collisions() {
    let mut d = CollisionDetector::new(m34());
    d.known_obstacle("pts={0,0:0,10:10,10:10,0},label=ob_0", 0.0)
        .unwrap();
    // 3 m above the top edge: a near miss, counted when the encounter ends.
    let p = pass(&mut d, "abe", 13.0);
    assert_eq!((d.encounters(), d.near_misses(), d.collisions()), (1, 1, 0));
    assert_eq!(find(&p, "OB_NEAR_MISS"), Some(&Value::Num(3.0)));
    assert_eq!(
        find(&p, "OB_NEAR_MISS_FULL"),
        Some(&Value::Str("vname=abe,ob=ob_0,dist=3".into()))
    );
    assert_eq!(find(&p, "OB_TOTAL_ENCOUNTERS"), Some(&Value::Num(1.0)));
    assert_eq!(find(&p, "OB_TOTAL_NEAR_MISSES"), Some(&Value::Num(1.0)));
    assert_eq!(find(&p, "OB_ENCOUNTER"), Some(&Value::Num(3.0)));
    // Through it: a collision (inside counts as 0).
    let p = pass(&mut d, "ben", 5.0);
    assert_eq!((d.encounters(), d.near_misses(), d.collisions()), (2, 1, 1));
    assert_eq!(find(&p, "OB_COLLISION"), Some(&Value::Num(0.0)));
    assert_eq!(find(&p, "OB_TOTAL_COLLISIONS"), Some(&Value::Num(1.0)));
    // 10 m away: an encounter only; 20 m away: nothing.
    pass(&mut d, "cal", 20.0);
    pass(&mut d, "dan", 30.0);
    assert_eq!((d.encounters(), d.near_misses(), d.collisions()), (3, 1, 1));
    let closest: Vec<(&str, f64)> = d.pairs().map(|((v, _), s)| (v, s.closest)).collect();
    assert_eq!(
        closest,
        [("abe", 3.0), ("ben", 0.0), ("cal", 10.0), ("dan", 20.0)]
    );
    assert_eq!(d.global_min(), Some(0.0));
}

#[test]
fn an_encounter_still_under_way_is_not_counted() {
    let mut d = CollisionDetector::new(CollisionConfig::default());
    d.known_obstacle("pts={0,0:0,10:10,10:10,0},label=a", 0.0)
        .unwrap();
    for k in -30..=5 {
        d.step(0.0, &[("abe", f64::from(k), 5.0)]);
    }
    assert_eq!(d.encounters(), 0);
    assert_eq!(d.pairs().next().map(|(_, s)| s.encounter_min), Some(0.0));
}

#[test]
fn clear_keeps_young_obstacles_and_config_fixups() {
    let mut d = CollisionDetector::new(CollisionConfig::default());
    d.known_obstacle("pts={0,0:0,10:10,10},label=a", 0.0)
        .unwrap();
    d.known_obstacle("pts={0,0:0,10:10,10},label=b", 8.0)
        .unwrap();
    d.clear("all", 10.0);
    assert_eq!(d.obstacles().map(|(l, _)| l).collect::<Vec<_>>(), ["b"]);
    assert!(d
        .known_obstacle("pts={0,0:10,0:5,1:10,10:0,10}", 0.0)
        .is_err());
    let mut c = CollisionConfig::default();
    c.set("collision_dist", "8").unwrap();
    c.set("encounter_dist", "6").unwrap();
    assert_eq!(c.finish().len(), 2);
    assert_eq!((c.near_miss_dist, c.encounter_dist), (8.0, 8.0));
    assert!(c.set("bin_delta", "0").is_err());
    assert!(c.set("collision_flag", "NOEQUALS").is_err());
}
