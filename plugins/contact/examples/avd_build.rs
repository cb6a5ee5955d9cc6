//! Builds BHV_AvoidCollision's objective function over and over (for profiling the
//! build: `valgrind --tool=callgrind` on it, or `perf`). Prints a checksum of the
//! weights so the build is not optimized away and two versions can be compared, and the
//! heap allocations per round of the last half of the rounds (the steady state), counted
//! by a global allocator.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, CountingAlloc, MockHelm};

/// Counts allocations and reallocations (see [`allocations`]).
#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let mut b = bhv_contact::AvoidCollision::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("avd_bob");
    for (p, v) in [("contact", "bob"), ("pwt_outer_dist", "200")] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    let mut sum = 0u64;
    let (mut counted, mut allocs) = (0usize, 0usize);
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
        let before = allocations();
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx));
        if k >= rounds / 2 {
            counted += 1;
            allocs += allocations() - before;
        }
        if let Some(f) = f {
            for x in f.weights.iter().chain(f.grid.iter()).chain([&f.pwt]) {
                sum = sum.wrapping_mul(0x100_0000_01b3).wrapping_add(x.to_bits());
            }
            for &x in f.bounds.iter() {
                sum = sum.wrapping_mul(31).wrapping_add(x as u64);
            }
            // As the helm hands a copied function back (0.1.3).
            f.give_back();
        }
    }
    println!("{sum:x}");
    println!(
        "{:.1} allocations per round",
        allocs as f64 / counted.max(1) as f64
    );
}
