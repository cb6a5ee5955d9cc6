//! BHV_HSLine allocates nothing per iteration in steady state (issue 21): its label is
//! asked of the helm once and its line written into a kept string.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, CountingAlloc, MockHelm};
use bhv_visuals::HsLine;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn hsline_allocates_nothing_per_iteration() {
    let mut b = HsLine::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("hsline");
    let mut made = 0;
    for k in 0..400 {
        let t = k as f64;
        helm.set("NAV_X", t * 0.5);
        helm.set("NAV_Y", -t * 0.25);
        helm.set("DESIRED_HEADING", (t * 7.0) % 360.0);
        helm.set("DESIRED_SPEED", 1.0 + (k % 5) as f64 * 0.25);
        helm.clear();
        let before = allocations();
        helm.with(|ctx| b.on_run(ctx));
        let n = allocations() - before;
        assert_eq!(helm.posted("VIEW_SEGLIST").len(), 1);
        if k >= 200 {
            made += n.saturating_sub(helm.recording_allocations());
        }
    }
    assert_eq!(made, 0, "allocations in 200 steady iterations");
}
