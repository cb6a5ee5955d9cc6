//! Templating: behaviors spawned at run time from `templating = spawn|clone` blocks.

use helm::conform::{build_helm, replay, Case};
use helm::factory::BehaviorFactory;

fn case(bhv: &str, spawn_mail: &[(usize, &str)], steps: usize) -> Case {
    let mut text = format!(
        "name = \"spawn\"\ndomain = [\"course:0:359:360\", \"speed:0:4:41\"]\ncheck = []\nbhv = '''\n{bhv}\n'''\n[config]\nstart_in_drive = \"true\"\n"
    );
    for k in 0..steps {
        let t = 1000.0 + 0.25 * k as f64;
        text.push_str(&format!(
            "[[step]]\ntime = {t}\nmail = [[\"NAV_X\", 0.0], [\"NAV_Y\", 0.0], [\"NAV_HEADING\", 0.0], [\"NAV_SPEED\", 0.0]"
        ));
        for (at, m) in spawn_mail {
            if *at == k {
                text.push_str(&format!(", [\"TMR_SPAWN\", \"{m}\"]"));
            }
        }
        text.push_str("]\n");
    }
    toml::from_str(&text).expect("case parses")
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
    let factory = BehaviorFactory::with_builtins();
    let file = std::path::PathBuf::from("spawn.toml");
    let mut helm = build_helm(&c, &file, &factory).expect("helm builds");
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
    let factory = BehaviorFactory::with_builtins();
    let file = std::path::PathBuf::from("spawn.toml");
    let mut helm = build_helm(&c, &file, &factory).expect("helm builds");
    replay(&c, &mut helm, false);
    assert!(helm.behavior_names().is_empty());
}

#[test]
fn clone_templates_are_instances_too() {
    let bhv = TEMPLATE.replace("templating = spawn", "templating = clone");
    let c = case(&bhv, &[(6, "name=x")], 10);
    let factory = BehaviorFactory::with_builtins();
    let file = std::path::PathBuf::from("spawn.toml");
    let mut helm = build_helm(&c, &file, &factory).expect("helm builds");
    replay(&c, &mut helm, false);
    assert_eq!(helm.behavior_names(), vec!["tmr_", "tmr_x"]);
}
