//! RESTART_HELM: the behavior set is rebuilt from its blocks.

use helm::conform::{build_helm, replay, Case};
use helm::factory::BehaviorFactory;

fn case(restart_at: Option<usize>, steps: usize) -> Case {
    let bhv = "initialize DEPLOY = true\nBehavior = BHV_Timer\n{\n  name = t\n  condition = DEPLOY = true\n  duration = 3\n}\n";
    let mut text = format!(
        "name = \"restart\"\ndomain = [\"course:0:359:360\", \"speed:0:4:41\"]\ncheck = []\nbhv = '''\n{bhv}'''\n[config]\nstart_in_drive = \"true\"\n"
    );
    for k in 0..steps {
        let t = 1000.0 + 0.25 * k as f64;
        text.push_str(&format!(
            "[[step]]\ntime = {t}\nmail = [[\"NAV_X\", 0.0], [\"NAV_Y\", 0.0], [\"NAV_HEADING\", 0.0], [\"NAV_SPEED\", 0.0]"
        ));
        if restart_at == Some(k) {
            text.push_str(", [\"RESTART_HELM\", \"type1\"]");
        }
        text.push_str("]\n");
    }
    toml::from_str(&text).expect("case parses")
}

fn names_after(c: &Case) -> Vec<String> {
    let factory = BehaviorFactory::with_builtins();
    let file = std::path::PathBuf::from("restart.toml");
    let mut helm = build_helm(c, &file, &factory).expect("helm builds");
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
