//! Steady iterations allocate nothing: once the obstacles are known and nothing
//! changes, a mail batch (ownship's NAV_X/NAV_Y) and `iterate` (prune, hulls skipped,
//! ranges, the alert step) of the manager, a step of the obstacle simulator between
//! refreshes and a step of the collision counter run without a heap allocation
//! (counted by this test binary's own global allocator, on this thread). Postings that
//! do go out (alerts, refreshes, OBM_DIST_TO_OBJ) allocate their values.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use obstacle_manager::{
    CollisionConfig, CollisionDetector, Config, MailValue, ObstacleFile, ObstacleManager,
    ObstacleSim, SimConfig, SimVehicle,
};

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

struct Counting;

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocs() -> usize {
    ALLOCS.with(Cell::get)
}

#[test]
fn steady_iterations_allocate_nothing() {
    let mut cfg = Config::default();
    for (p, v) in [
        ("post_dist_to_polys", "false"),
        ("max_age_per_point", "1000000"),
        ("given_obstacle", "pts={60,-12:60,6:80,6:80,-12},label=oba"),
        (
            "given_obstacle",
            "pts={160,-12:160,6:180,6:180,-12},label=obb",
        ),
    ] {
        cfg.set(p, v).expect("config");
    }
    let mut m = ObstacleManager::new(cfg, 0.0);
    let text = "poly = pts={60,-12:60,6:80,6:80,-12},label=ob_0\n\
                poly = pts={160,-12:160,6:180,6:180,-12},label=ob_1\n";
    let file = ObstacleFile::parse(text, "obstacles.txt").expect("file");
    let mut sc = SimConfig::default();
    sc.set("refresh_interval", "1000000").expect("sim config");
    let mut sim = ObstacleSim::new(sc, file, || 0.5);
    let mut det = CollisionDetector::new(CollisionConfig::default());
    // Warm-up: the request, a cluster of points, the first refresh.
    let mut mail = vec![
        ("NAV_X", MailValue::Num(50.0)),
        ("NAV_Y", MailValue::Num(0.0)),
        (
            "OBM_ALERT_REQUEST",
            MailValue::Str("name=avd_,update_var=OBSTACLE_ALERT,alert_range=15"),
        ),
    ];
    for p in ["x=100,y=5,key=pa", "x=104,y=9,key=pa", "x=101,y=12,key=pa"] {
        mail.push(("TRACKED_FEATURE", MailValue::Str(p)));
    }
    m.handle_mail(0.0, &mail);
    let first = m.iterate(0.0).len();
    assert!(first >= 3, "connect, alert, hull drawings: {first}");
    let seen = [SimVehicle {
        name: "alpha",
        x: 50.0,
        y: 0.0,
        color: None,
    }];
    let mut rng = || 0.5;
    for p in sim.step(0.0, &seen, &mut rng).to_vec() {
        if p.var == "KNOWN_OBSTACLE" {
            det.known_obstacle(p.val.as_str().unwrap_or_default(), 0.0)
                .expect("known obstacle");
        }
    }
    let nav = [
        ("NAV_X", MailValue::Num(50.0)),
        ("NAV_Y", MailValue::Num(0.0)),
    ];
    let vehicles = [("alpha", 50.0, 0.0), ("bravo", 120.0, 30.0)];
    for k in 1..4 {
        let t = f64::from(k);
        m.handle_mail(t, &nav);
        m.iterate(t);
        sim.step(t, &seen, &mut rng);
        det.step(t, &vehicles);
    }
    for k in 4..30 {
        let t = f64::from(k);
        let before = allocs();
        m.handle_mail(t, &nav);
        let n = m.iterate(t).len();
        let s = sim.step(t, &seen, &mut rng).len();
        let d = det.step(t, &vehicles).len();
        let used = allocs() - before;
        assert_eq!((n, s, d), (0, 0, 0), "nothing to post at step {k}");
        assert_eq!(used, 0, "step {k} allocated {used} times");
    }
    assert_eq!(m.obstacles().count(), 3);
    assert_eq!(det.pairs().count(), 4);
}
