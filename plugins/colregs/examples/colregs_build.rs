//! Builds BHV_AvdColregsV22's objective function over and over, the contact crossing
//! from starboard (give-way), for profiling the build (`valgrind --tool=callgrind` on
//! it, or `perf`). Prints a checksum of the weights (so two versions can be compared)
//! and the heap allocations per build of the last half of the rounds (the steady
//! state), counted by a global allocator.

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
    // The contact's start (x, y), from the next two arguments.
    let arg = |i: usize, d: f64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(d)
    };
    let (cnx, cny) = (arg(2, 120.0), arg(3, 90.0));
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
    let mut sum = 0u64;
    let (mut builds, mut allocs) = (0usize, 0usize);
    for k in 0..rounds {
        let t = k as f64 * 0.25;
        // The clock runs, as the helm's does (the behavior's history stays bounded).
        helm.time = 1000.0 + t;
        helm.nav(0.0, t * 0.5, 0.0, 2.0);
        // Coming from starboard, heading west at 2 m/s.
        helm.contact("hal", cnx - t * 2.0, cny, 270.0, 2.0, "kayak");
        let before = allocations();
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx));
        if k >= rounds / 2 {
            builds += 1;
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
    let mode = b.expand_macros("$[FULL_MODE]").unwrap_or_default();
    println!("{sum:x} mode {mode}");
    println!(
        "{:.1} allocations per round",
        allocs as f64 / builds.max(1) as f64
    );
}
