//! BHV_Trail's texts (the trail point's VIEW_POINT, its numbers) allocate nothing in
//! steady state, and stay the texts they were.
//!
//! The behavior runs on a domain without `course`, so `on_run` stops before building
//! its IvP function (the function build is not measured here); the copies the mock
//! helm makes of each posting are counted and taken off.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, fnv, CountingAlloc, MockHelm};
use bhv_contact::Trail;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn trail_texts_allocate_nothing_in_steady_state() {
    let mut b = Trail::new(&HelmDomain::new("speed,0,4,41"));
    let mut helm = MockHelm::new("trail_abe");
    for (p, v) in [
        ("contact", "abe"),
        ("trail_range", "30"),
        ("nm_radius", "15"),
        ("radius", "5"),
        ("pwt_outer_dist", "200"),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    helm.with(|ctx| b.on_params_complete(ctx));
    helm.posts.reserve(64);
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    let (mut steady, mut iters, mut regions) = (0usize, 0usize, std::collections::BTreeSet::new());
    // The contact heads east at 1.5 m/s; ownship closes in from the west at 2 m/s and
    // then keeps station on the trail point, so every region is visited.
    let (mut ox, oy) = (0.0f64, 48.0f64);
    for i in 0..400 {
        let t = f64::from(i);
        helm.time += 1.0;
        helm.contact("abe", 100.0 + 1.5 * t, 50.0, 90.0, 1.5, "kayak");
        ox += if i < 140 { 2.0 } else { 1.5 };
        helm.nav(ox, oy, 90.0, 1.5);
        helm.clear();
        helm.with(|ctx| b.on_every_state(ctx));
        helm.clear();
        let before = allocations();
        helm.with(|ctx| b.on_run(ctx));
        let after = allocations();
        let made = (after - before).saturating_sub(helm.recording_allocations());
        if made > 0 && std::env::var_os("SHOW").is_some() {
            eprintln!("{i}: {made}");
        }
        if i >= 5 {
            steady += made;
            iters += 1;
        }
        for (var, val, key) in &helm.posts {
            fnv(&mut hash, var);
            fnv(&mut hash, val);
            fnv(&mut hash, key);
            if var == "REGION" {
                regions.insert(val.clone());
            }
        }
    }
    eprintln!(
        "trail: steady allocations {steady} over {iters} iterations; {regions:?}; hash {hash:#x}"
    );
    assert_eq!(regions.len(), 3, "{regions:?}");
    assert_eq!(steady, 0, "allocations in steady state");
    // The postings as the old code made them (recorded from it).
    assert_eq!(hash, EXPECTED_HASH);
}

const EXPECTED_HASH: u64 = 0x8189_9b4e_4a10_57d6;
