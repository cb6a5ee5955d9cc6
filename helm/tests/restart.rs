//! RESTART_HELM: the behavior set is rebuilt from its blocks.

use helm_conform::{replay, Case};

mod common;

fn case(restart_at: Option<usize>, steps: usize) -> Case {
    let bhv = "initialize DEPLOY = true\nBehavior = BHV_Timer\n{\n  name = t\n  condition = DEPLOY = true\n  duration = 3\n}\n";
    common::nav_case("restart", bhv, steps, |k| {
        if restart_at == Some(k) {
            ", [\"RESTART_HELM\", \"type1\"]".into()
        } else {
            String::new()
        }
    })
}

fn names_after(c: &Case) -> Vec<String> {
    let mut helm = common::builtin_case_helm(c, "restart.toml");
    replay(c, &mut helm, false);
    helm.behavior_names()
}

#[test]
fn a_completed_behavior_is_gone_without_a_restart() {
    assert!(names_after(&case(None, 36)).is_empty());
}

#[test]
fn restart_rebuilds_the_behavior_set() {
    // The timer completes after 1 s warm-up + 3 s; the restart at 7.5 s rebuilds it and
    // restarts the warm-up, so at 8.75 s it is running again.
    assert_eq!(names_after(&case(Some(30), 36)), vec!["t"]);
}
