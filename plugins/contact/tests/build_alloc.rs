//! BHV_AvoidCollision's function build in steady state: a ratchet on the heap
//! allocations per build, as `examples/avd_build.rs` counts them less the mock helm's
//! copies of the postings (its reads of names and contacts still count). The function
//! is handed back after each build, as the helm does since behavior-api 0.1.3, and a
//! steady build allocates nothing.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, CountingAlloc, MockHelm};

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn avoid_collision_builds_allocate_at_most_the_ratchet() {
    let mut b = bhv_contact::AvoidCollision::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("avd_bob");
    for (p, v) in [("contact", "bob"), ("pwt_outer_dist", "200")] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    let rounds = 200;
    let (mut builds, mut allocs) = (0usize, 0usize);
    for k in 0..rounds {
        let t = k as f64;
        helm.nav(0.0, 0.0, (t * 7.0) % 360.0, 2.0);
        helm.contact(
            "bob",
            30.0 - t * 0.2,
            100.0 - t * 0.3,
            (t * 13.0) % 360.0,
            1.5,
            "kayak",
        );
        helm.clear();
        let before = allocations();
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx));
        let made = allocations() - before;
        if k >= rounds / 2 {
            assert!(f.is_some(), "round {k}: no function built");
            builds += 1;
            allocs += made.saturating_sub(helm.recording_allocations());
        }
        // As the helm does once it has copied a library's function (0.1.3,
        // `BehaviorLib::recycle_function`): its buffers go back for the next build.
        if let Some(f) = f {
            f.give_back();
        }
    }
    let per_build = allocs as f64 / builds as f64;
    println!("{per_build:.1} allocations per build");
    // 27 per build (mock included) before the reflector, tiling and AOF lists were
    // kept per thread, 7 before the function's buffers came back (0.1.3), 2 (the mock's
    // reads) before the mock wrote its answers into the caller's strings, none since.
    assert_eq!(
        allocs, 0,
        "{per_build:.1} allocations per build in steady state"
    );
}

/// An idle AvoidCollision (its contact out of range) posts its inactive bearing line
/// every iteration, into a kept string: nothing allocated.
#[test]
fn inactive_iterations_allocate_nothing() {
    let mut b = bhv_contact::AvoidCollision::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("avd_bob");
    for (p, v) in [
        ("contact", "bob"),
        ("pwt_outer_dist", "50"),
        (
            "bearing_line_config",
            "white:0, green:0.65, yellow:0.8, red:1.0",
        ),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    let mut made = 0;
    for k in 0..200 {
        helm.nav(0.0, 0.0, 90.0, 2.0);
        helm.contact("bob", 500.0 + k as f64, 400.0, 180.0, 1.5, "kayak");
        helm.clear();
        let before = allocations();
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx));
        assert!(f.is_none(), "out of range: no function");
        helm.with(|ctx| b.on_inactive(ctx));
        let n = allocations() - before;
        let lines = helm.posted("VIEW_SEGLIST");
        assert!(
            lines.iter().any(|l| l.contains("active=false")),
            "{lines:?}"
        );
        if k >= 100 {
            made += n.saturating_sub(helm.recording_allocations());
        }
    }
    assert_eq!(made, 0, "allocations in 100 inactive iterations");
}
