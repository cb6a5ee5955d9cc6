//! BHV_AvdColregsV22's function build in steady state (give-way crossing): a ratchet on
//! the heap allocations per build, as `examples/colregs_build.rs` counts them less the
//! mock helm's copies of the postings (its reads of names and contacts still count).
//! The function is handed back after each build, as the helm does since behavior-api
//! 0.1.3, and a steady build allocates nothing.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, CountingAlloc, MockHelm};

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn colregs_builds_allocate_at_most_the_ratchet() {
    let mut b = bhv_colregs::Colregs::v22(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("col_hal");
    for (p, v) in [
        ("contact", "hal"),
        ("pwt_outer_dist", "200"),
        ("pwt_inner_dist", "100"),
        ("completed_dist", "250"),
        ("min_util_cpa_dist", "10"),
        ("max_util_cpa_dist", "18"),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    let rounds = 200;
    let (mut builds, mut allocs) = (0usize, 0usize);
    for k in 0..rounds {
        let t = k as f64 * 0.25;
        // The clock runs, as the helm's does: the contact's heading and bearing history
        // (a few seconds) then stays bounded instead of growing every round.
        helm.time = 1000.0 + t;
        helm.nav(0.0, t * 0.5, 0.0, 2.0);
        helm.contact("hal", 120.0 - t * 2.0, 90.0, 270.0, 2.0, "kayak");
        helm.clear();
        let before = allocations();
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx));
        let made = allocations() - before;
        if k >= rounds / 2 && f.is_some() {
            builds += 1;
            allocs += made.saturating_sub(helm.recording_allocations());
        }
        // As the helm does once it has copied a library's function (0.1.3,
        // `BehaviorLib::recycle_function`): its buffers go back for the next build.
        if let Some(f) = f {
            f.give_back();
        }
    }
    assert!(builds > 50, "only {builds} builds in the steady half");
    let per_build = allocs as f64 / builds as f64;
    println!("{per_build:.1} allocations per build");
    // 23 per build (mock included) before the course lists and CPA tables were kept, 9
    // before the function's buffers came back (0.1.3), 4 (the mock's reads) before the
    // mock wrote its answers into the caller's strings, none since.
    assert_eq!(
        allocs, 0,
        "{per_build:.2} allocations per build in steady state"
    );
}
