//! BHV_StationKeep allocates nothing per iteration in steady state (issue 21): its
//! circles' texts are kept by what they show.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, CountingAlloc, MockHelm};
use bhv_station_keep::StationKeep;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn station_keep_allocates_nothing_per_iteration() {
    let mut b = StationKeep::new(&HelmDomain::new("course,0,359,360:speed,0,2,21"));
    let mut helm = MockHelm::new("skeep");
    for (p, v) in [
        ("station_pt", "50,-40"),
        ("outer_radius", "15"),
        ("inner_radius", "4"),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
    }
    helm.with(|ctx| b.on_params_complete(ctx));
    let (mut made, mut functions) = (0, 0);
    for k in 0..400 {
        let t = k as f64;
        // Drifting around the station, inside and outside the inner circle.
        helm.nav(
            50.0 + 8.0 * (t * 0.05).sin(),
            -40.0 + 8.0 * (t * 0.05).cos(),
            (t * 3.0) % 360.0,
            1.0,
        );
        helm.time += 0.25;
        helm.clear();
        let before = allocations();
        let f = helm.with(|ctx| b.on_run(ctx));
        let n = allocations() - before;
        if k >= 200 {
            made += n.saturating_sub(helm.recording_allocations());
            functions += usize::from(f.is_some());
        }
        if let Some(f) = f {
            f.give_back();
        }
    }
    assert!(functions > 0, "no function built");
    assert_eq!(made, 0, "allocations in 200 steady iterations");
}
