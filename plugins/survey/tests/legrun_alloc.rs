//! BHV_LegRun's texts (VIEW_POINT / VIEW_SEGLIST specs, labels) allocate nothing in
//! steady state, and stay the texts they were; ZigZag's whole iteration (function
//! included) allocates nothing either.
//!
//! The behavior runs on a domain without `course`, so `on_run` stops before building
//! its IvP function (the function build is not measured here); the copies the mock
//! helm makes of each posting are counted and taken off.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, fnv, CountingAlloc, MockHelm};
use bhv_survey::LegRun;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// `x=` and `y=` of a point spec.
fn spec_xy(spec: &str) -> Option<(f64, f64)> {
    let field = |k: &str| {
        spec.split(',')
            .find_map(|f| f.strip_prefix(k))
            .and_then(|v| v.parse().ok())
    };
    Some((field("x=")?, field("y=")?))
}

/// The first full cycle (leg, turn, leg, turn): the buffers reach their sizes (the
/// wrap detector's track history grows by doubling until a turn ends).
const WARM_UP: usize = 250;

#[test]
fn legrun_texts_allocate_nothing_in_steady_state() {
    let mut b = LegRun::new(&HelmDomain::new("speed,0,4,41"));
    let mut helm = MockHelm::new("legs");
    let params = [
        ("speed", "2.5"),
        ("capture_radius", "3"),
        ("slip_radius", "15"),
        ("vx1", "60,-30"),
        ("vx2", "-40,-70"),
        ("turn1_dir", "port"),
        ("turn2_dir", "star"),
        ("turn1_rad", "18"),
        ("turn2_rad", "18"),
        ("visual_hints", "nextpt_vertex_color=red, turn_edge_size=2"),
    ];
    for (p, v) in params {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
    }
    helm.with(|ctx| b.on_params_complete(ctx));
    helm.posts.reserve(64);
    let (mut x, mut y) = (0.0f64, 0.0f64);
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    let (mut steady, mut steady_iters, mut switch_iters) = (0usize, 0usize, 0usize);
    let mut modes = std::collections::BTreeSet::new();
    for i in 0..600 {
        helm.nav(x, y, 0.0, 2.5);
        helm.time += 1.0;
        helm.clear();
        let before = allocations();
        helm.with(|ctx| b.on_run(ctx));
        let after = allocations();
        let made = (after - before).saturating_sub(helm.recording_allocations());
        modes.insert(b.mode().name());
        let switched = helm.posts.iter().any(|p| p.0 == "LR_MODE");
        if made > 0 && std::env::var_os("SHOW").is_some() {
            eprintln!(
                "{i}: {made} {:?}",
                helm.posts.iter().map(|p| &p.0).collect::<Vec<_>>()
            );
        }
        if i >= WARM_UP && !switched {
            steady += made;
            steady_iters += 1;
        } else if switched {
            switch_iters += 1;
        }
        // The vehicle heads 2.5 m toward the posted track point (the next waypoint
        // when the track point is erased).
        let mut aim = None;
        for (var, val, key) in &helm.posts {
            fnv(&mut hash, var);
            fnv(&mut hash, val);
            fnv(&mut hash, key);
            if var == "VIEW_POINT" && (key == "trk" || key == "wpt") && aim.is_none() {
                aim = spec_xy(val).filter(|_| !val.contains("active=false"));
            }
        }
        if let Some((ax, ay)) = aim {
            let d = (ax - x).hypot(ay - y);
            if d > 0.0 {
                let step = d.min(2.5);
                x += step * (ax - x) / d;
                y += step * (ay - y) / d;
            }
        }
    }
    eprintln!(
        "legrun: steady allocations {steady} over {steady_iters} iterations; \
         {switch_iters} mode switches; modes {modes:?}; hash {hash:#x}"
    );
    // Legs and turns both ran, so every VIEW_* text was posted.
    assert_eq!(modes.len(), 4, "{modes:?}");
    assert!(steady_iters > 300);
    assert_eq!(steady, 0, "allocations in steady state");
    // The postings of the texts before they were kept (recorded from the old code).
    assert_eq!(hash, EXPECTED_HASH);

    // The kept texts follow a moved leg and new hints.
    let p1 = |helm: &MockHelm| {
        let p = helm
            .posts
            .iter()
            .rev()
            .find(|p| p.0 == "VIEW_POINT" && p.2 == "p1");
        p.map(|p| p.1.clone()).unwrap_or_default()
    };
    for (param, value, expect) in [
        (
            "vx1",
            "70,-30",
            "x=70,y=-30,label=abe_p1,label_color=invisible,vertex_color=orange,vertex_size=10.5",
        ),
        (
            "visual_hints",
            "legpt_vertex_color=red",
            "x=70,y=-30,label=abe_p1,label_color=invisible,vertex_color=red,vertex_size=10.5",
        ),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, param, value)));
        helm.with(|ctx| b.on_params_complete(ctx));
        helm.clear();
        helm.with(|ctx| b.on_run(ctx));
        assert_eq!(p1(&helm), expect, "{param}");
    }
}

const EXPECTED_HASH: u64 = 0x2dad_031d_ae1c_c0af;

/// ZigZag's function (course and speed) and lines, built every iteration, allocate
/// nothing once warm: the speed function is kept while the speed holds, the course
/// builder and the line texts are kept.
#[test]
fn zigzag_function_and_lines_allocate_nothing_in_steady_state() {
    use bhv_survey::ZigZag;
    let mut b = ZigZag::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("zig");
    for (p, v) in [
        ("speed", "2"),
        ("zig_angle", "30"),
        ("max_zig_zags", "100000"),
        ("visual_hints", "draw_req_hdg=true"),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
    }
    let (mut made, mut functions) = (0, 0);
    let (mut x, mut y, mut h) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..600 {
        helm.nav(x, y, h, 2.0);
        helm.time += 0.25;
        helm.clear();
        let before = allocations();
        let f = helm.with(|ctx| b.on_run(ctx));
        let n = allocations() - before;
        if k >= 300 {
            made += n.saturating_sub(helm.recording_allocations());
            functions += usize::from(f.is_some());
        }
        if let Some(f) = f {
            f.give_back();
        }
        // Turn a little toward the requested heading each step.
        h = (h + 3.0) % 360.0;
        x += 0.5 * h.to_radians().sin();
        y += 0.5 * h.to_radians().cos();
    }
    assert!(functions > 250, "{functions} functions");
    assert_eq!(made, 0, "allocations in 300 steady iterations");
}
