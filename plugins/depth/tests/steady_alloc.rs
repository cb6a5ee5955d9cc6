//! The depth behaviors allocate nothing per iteration in steady state (issue 21): a
//! function built once is copied while its inputs hold, texts are read into kept strings.
//! Counted as the helm drives them (`on_run`, the function handed back afterwards), less
//! the mock helm's own copies of the postings.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, CountingAlloc, MockHelm};
use bhv_depth::{GoToDepth, MaxDepth, PeriodicSurface};

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

const HELM: &str = "course,0,359,360:speed,0,4,41:depth,0,100,101";

/// Allocations of rounds `warm..rounds` of `on_run`, `nav` setting the mock's
/// variables before each round.
fn steady<B: IvpBehavior>(
    b: &mut B,
    helm: &mut MockHelm,
    rounds: usize,
    mut nav: impl FnMut(&mut MockHelm, usize),
) -> (usize, usize) {
    let (mut made, mut functions) = (0, 0);
    for k in 0..rounds {
        nav(helm, k);
        helm.time += 0.25;
        helm.clear();
        let before = allocations();
        let f = helm.with(|ctx| b.on_run(ctx));
        let n = allocations() - before;
        if k >= rounds / 2 {
            made += n.saturating_sub(helm.recording_allocations());
            functions += usize::from(f.is_some());
        }
        if let Some(f) = f {
            f.give_back();
        }
    }
    (made, functions)
}

fn with_params<B: IvpBehavior>(mut b: B, name: &str, params: &[(&str, &str)]) -> (B, MockHelm) {
    let mut helm = MockHelm::new(name);
    for (p, v) in params {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
    }
    helm.with(|ctx| b.on_params_complete(ctx));
    (b, helm)
}

#[test]
fn max_depth_allocates_nothing_per_iteration() {
    let d = MaxDepth::new(&HelmDomain::new(HELM));
    let (mut b, mut helm) = with_params(
        d,
        "cap",
        &[("max_depth", "20"), ("depth_slack_var", "SLACK")],
    );
    let (made, functions) = steady(&mut b, &mut helm, 400, |h, k| {
        h.set("NAV_DEPTH", 5.0 + (k % 7) as f64);
    });
    assert_eq!(functions, 200);
    assert_eq!(made, 0, "allocations in 200 steady iterations");
}

#[test]
fn goto_depth_allocates_nothing_while_a_level_holds() {
    let d = GoToDepth::new(&HelmDomain::new(HELM));
    let (mut b, mut helm) = with_params(d, "levels", &[("depth", "12,1000")]);
    let (made, functions) = steady(&mut b, &mut helm, 400, |h, k| {
        h.set("NAV_DEPTH", 11.5 + (k % 3) as f64 * 0.25);
    });
    assert_eq!(functions, 200);
    assert_eq!(made, 0, "allocations in 200 steady iterations");
}

#[test]
fn periodic_surface_allocates_nothing_while_waiting() {
    let d = PeriodicSurface::new(&HelmDomain::new(HELM));
    let (mut b, mut helm) = with_params(
        d,
        "psurf",
        &[
            ("period", "100000"),
            ("mark_variable", "GPS_MARK"),
            ("acomms_mark_variable", "ACOMMS, 10, 30"),
        ],
    );
    helm.strs.insert("GPS_MARK".into(), "fix at 12:00".into());
    helm.strs.insert("ACOMMS".into(), "msg 1".into());
    let (made, _) = steady(&mut b, &mut helm, 400, |h, k| {
        h.set("NAV_DEPTH", 10.0 + (k % 5) as f64);
        h.set("NAV_SPEED", 1.5);
    });
    assert_eq!(made, 0, "allocations in 200 steady iterations");
}
