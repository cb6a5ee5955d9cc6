//! BHV_AvdColregsV22's function build in steady state (give-way crossing): a ratchet on
//! the heap allocations per build, as `examples/colregs_build.rs` counts them less the
//! mock helm's copies of the postings (its reads of names and contacts still count).
//! What is left is mostly the function's buffers handed to the helm, which frees them,
//! so the library's spares never refill (an ABI change closes that).

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
    }
    assert!(builds > 50, "only {builds} builds in the steady half");
    let per_build = allocs as f64 / builds as f64;
    println!("{per_build:.1} allocations per build");
    // 23 per build (mock included) before the course lists and CPA tables were kept.
    assert!(per_build <= 9.5, "{per_build:.1} allocations per build");
}
