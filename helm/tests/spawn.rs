//! Templating: behaviors spawned at run time from `templating = spawn|clone` blocks.

use helm_conform::{replay, Case};
use helm_engine::Helm;

mod common;

fn case(bhv: &str, spawn_mail: &[(usize, &str)], steps: usize) -> Case {
    common::nav_case("spawn", &format!("{bhv}\n"), steps, |k| {
        spawn_mail
            .iter()
            .filter(|(at, _)| *at == k)
            .map(|(_, m)| format!(", [\"TMR_SPAWN\", \"{m}\"]"))
            .collect()
    })
}

fn helm_of(c: &Case) -> Helm {
    common::builtin_case_helm(c, "spawn.toml")
}

const TEMPLATE: &str = "Behavior = BHV_Timer\n{\n  name = tmr_\n  templating = spawn\n  max_spawnings = 2\n  updates = TMR_SPAWN\n}\n";

#[test]
fn spawn_requests_create_named_behaviors_up_to_the_limit() {
    let c = case(
        TEMPLATE,
        &[
            (6, "name=a # duration=100"),
            (8, "name=b"),
            (10, "name=a"),
            (12, "name=c"),
        ],
        16,
    );
    let mut helm = helm_of(&c);
    assert!(
        helm.behavior_names().is_empty(),
        "a spawn template is not an instance"
    );
    replay(&c, &mut helm, false);
    assert_eq!(helm.behavior_names(), vec!["tmr_a", "tmr_b"]);
}

#[test]
fn a_bad_pair_aborts_the_spawn() {
    let c = case(TEMPLATE, &[(6, "name=a # nonsense=1")], 10);
    let mut helm = helm_of(&c);
    replay(&c, &mut helm, false);
    assert!(helm.behavior_names().is_empty());
}

#[test]
fn clone_templates_are_instances_too() {
    let bhv = TEMPLATE.replace("templating = spawn", "templating = clone");
    let c = case(&bhv, &[(6, "name=x")], 10);
    let mut helm = helm_of(&c);
    replay(&c, &mut helm, false);
    assert_eq!(helm.behavior_names(), vec!["tmr_", "tmr_x"]);
}
