//! `testing::CountingAlloc` counts what this thread allocates, and only that: the
//! allocation tests of the plugins rely on both halves.

use behavior_api::testing::{allocations, CountingAlloc};

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn counts_this_threads_allocations_and_not_another_threads() {
    let before = allocations();
    let v: Vec<u64> = std::hint::black_box(Vec::with_capacity(16));
    let mut s = String::with_capacity(1);
    s.push_str(std::hint::black_box("grows past its capacity"));
    assert_eq!(
        allocations() - before,
        3,
        "two allocations and one reallocation"
    );
    drop((v, s));

    // Another thread allocating a thousand times while this one waits adds nothing.
    let before = allocations();
    std::thread::scope(|sc| {
        sc.spawn(|| {
            let start = allocations();
            for k in 0..1000u64 {
                std::hint::black_box(vec![k; 4]);
            }
            assert!(allocations() - start >= 1000);
        });
    });
    // Spawning a scoped thread may allocate on this thread (its handle); the other
    // thread's thousand allocations are not here.
    assert!(allocations() - before < 100, "{}", allocations() - before);
}
