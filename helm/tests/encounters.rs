//! Encounters: a helm with a transit waypoint and a BHV_AvoidCollision template meets a
//! contact head-on, crossing and overtaking. Everything runs in this process on a
//! simulated clock: ownship's kinematic model follows the helm's DESIRED_*, the contact
//! sails a straight line and reports itself as pNodeReporter would (`NODE_REPORT`), and
//! a pContactMgrV20 (the `contact-manager` library) turns the helm's alert request and
//! the reports into the alert that spawns the avoidance behavior.
//!
//! Without avoidance each contact would pass through ownship (closest approach 0); the
//! tests assert the closest approach stays above the behavior's `min_util_cpa_dist` and
//! that the avoidance behavior was indeed spawned for the contact.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use contact_manager::{Config, ContactManager, MailValue};
use helm_engine::posting::Value;
use helm_engine::{Helm, Mail};
use vehicle_model::{Kinematics, VehicleModel};

mod common;

const MIN_UTIL_CPA_DIST: f64 = 8.0;

/// The mission, with the folder of the behavior libraries.
fn moos(plugins: &Path) -> String {
    format!(
        "ServerHost = localhost\nServerPort = 9000\nCommunity = alpha\n\
LatOrigin = 43.8253\nLongOrigin = -70.3304\n\n\
ProcessConfig = pHelmIvP\n{{\n  AppTick = 4\n  behaviors = encounter.bhv\n  \
ivp_behavior_dir = {}\n  \
domain = course:0:359:360\n  domain = speed:0:4:41\n  start_in_drive = true\n}}\n\n{SIM}",
        plugins.display()
    )
}

const SIM: &str = "\
ProcessConfig = uSimMarine\n{\n  start_x = 0\n  start_y = 0\n  start_heading = 0\n  \
speed_lag = 1.0\n  turn_rate = 20\n}\n";

const BHV: &str = "initialize DEPLOY = true\ninitialize AVOID = true\n\n\
Behavior = BHV_Waypoint\n{\n  name = transit\n  pwt = 100\n  condition = DEPLOY = true\n  \
speed = 2\n  capture_radius = 4\n  points = 0,300\n}\n\n\
Behavior = BHV_AvoidCollision\n{\n  name = avd_\n  pwt = 300\n  condition = AVOID = true\n  \
updates = CONTACT_INFO\n  templating = spawn\n  endflag = CONTACT_RESOLVED = $[CONTACT]\n  \
contact = to-be-set\n  on_no_contact_ok = true\n  extrapolate = true\n  decay = 30,60\n  \
pwt_outer_dist = 50\n  pwt_inner_dist = 20\n  completed_dist = 75\n  \
min_util_cpa_dist = 8\n  max_util_cpa_dist = 25\n  pwt_grade = linear\n}\n";

/// The shipped plugins (AvoidCollision among them), built once.
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let built = common::build_plugins(common::SHIPPED_PLUGINS);
        common::lib_folder(&built, common::SHIPPED_PLUGINS, "encounter-plugins-lib")
    })
}

fn mail(var: &str, value: Value, time: f64, source: &str) -> Mail {
    Mail {
        var: var.into(),
        value,
        time,
        source: source.into(),
        source_aux: String::new(),
    }
}

/// A contact on a straight line: start, heading (compass degrees), speed.
#[derive(Clone, Copy)]
struct Contact {
    x: f64,
    y: f64,
    hdg: f64,
    spd: f64,
}

impl Contact {
    fn at(&self, t: f64) -> (f64, f64) {
        let h = self.hdg.to_radians();
        (
            self.x + h.sin() * self.spd * t,
            self.y + h.cos() * self.spd * t,
        )
    }
}

/// What an encounter did.
struct Outcome {
    closest: f64,
    spawned: bool,
    ownship_end: (f64, f64),
}

fn encounter(tag: &str, bob: Contact, seconds: f64) -> Outcome {
    let dir = common::scratch(format!("encounter-{tag}"));
    std::fs::write(dir.join("encounter.moos"), moos(plugin_dir())).unwrap();
    std::fs::write(dir.join("encounter.bhv"), BHV).unwrap();
    let loaded = helm_mission::load(&dir.join("encounter.moos"), &[], "pHelmIvP")
        .expect("the encounter mission loads");
    let (mut helm, mission): (Helm, _) = loaded.into_helm();
    assert!(
        helm.config_warnings().is_empty(),
        "{:?}",
        helm.config_warnings()
    );
    let mut boat = Kinematics::from_mission(&mission);
    let mut manager = ContactManager::new("alpha", Config::default(), Some((43.8253, -70.3304)));

    let t0 = 1000.0;
    let dt = 0.25;
    let mut echo: Vec<Mail> = helm
        .startup(t0)
        .iter()
        .map(|p| mail(&p.var, p.value.clone(), t0, "pHelmIvP"))
        .collect();
    let mut to_manager: Vec<(String, Value)> = echo
        .iter()
        .map(|m| (m.var.clone(), m.value.clone()))
        .collect();
    let mut closest = f64::INFINITY;
    let mut spawned = false;
    let steps = (seconds / dt) as usize;
    for k in 1..=steps {
        let t = t0 + k as f64 * dt;
        for _ in 0..5 {
            boat.step(dt / 5.0);
        }
        let nav = boat.nav();
        let (cx, cy) = bob.at(t - t0);
        closest = closest.min((nav.x - cx).hypot(nav.y - cy));
        let report = format!(
            "NAME=bob,X={cx:.2},Y={cy:.2},SPD={},HDG={},DEP=0,TYPE=kayak,TIME={t:.2}",
            bob.spd, bob.hdg
        );

        // The contact manager: ownship, the report, and what the helm asked of it.
        let mut mgr_mail: Vec<(&str, MailValue<'_>)> = nav
            .vars()
            .iter()
            .map(|(v, x)| (*v, MailValue::Num(*x)))
            .collect();
        mgr_mail.push(("NODE_REPORT", MailValue::Str(&report)));
        for (var, value) in &to_manager {
            if let Value::Str(s) = value {
                mgr_mail.push((var.as_str(), MailValue::Str(s)));
            }
        }
        manager.handle_mail(t, &mgr_mail);
        let alerts: Vec<Mail> = manager
            .iterate(t)
            .iter()
            .map(|p| {
                let value = match &p.val {
                    contact_manager::Value::Str(s) => Value::Str(s.clone()),
                    contact_manager::Value::Num(n) => Value::Num(*n),
                };
                mail(&p.var, value, t, "pContactMgrV20")
            })
            .collect();

        let mut batch = std::mem::take(&mut echo);
        for (var, v) in nav.vars() {
            batch.push(mail(var, Value::Num(v), t, "uSimMarine"));
        }
        batch.push(mail("NODE_REPORT", Value::Str(report), t, "uFldNodeComms"));
        batch.extend(alerts);
        helm.handle_mail(t, &batch);
        to_manager.clear();
        let posted = helm.iterate(t).to_vec();
        for p in &posted {
            if let Value::Num(v) = p.value {
                boat.on_mail(&p.var, v);
            }
            if p.var == "IVPHELM_LIFE_EVENT" {
                if let Value::Str(s) = &p.value {
                    spawned |= s.contains("bname=avd_bob") && s.contains("event=spawn");
                }
            }
            if p.var == "BCM_ALERT_REQUEST" {
                to_manager.push((p.var.clone(), p.value.clone()));
            }
            if helm.is_subscribed(&p.var) {
                echo.push(mail(&p.var, p.value.clone(), t, "pHelmIvP"));
            }
        }
    }
    let end = boat.nav();
    Outcome {
        closest,
        spawned,
        ownship_end: (end.x, end.y),
    }
}

fn assert_avoided(tag: &str, o: &Outcome) {
    println!(
        "{tag}: closest approach {:.1} m, ownship ends at {:.0},{:.0}",
        o.closest, o.ownship_end.0, o.ownship_end.1
    );
    assert!(o.spawned, "{tag}: no avd_bob was spawned");
    assert!(
        o.closest > MIN_UTIL_CPA_DIST,
        "{tag}: closest approach {:.2} m, under min_util_cpa_dist {MIN_UTIL_CPA_DIST}",
        o.closest
    );
    // Avoiding is not giving up: ownship still made its way north.
    assert!(
        o.ownship_end.1 > 150.0,
        "{tag}: ended at {:?}",
        o.ownship_end
    );
}

#[test]
fn head_on() {
    let bob = Contact {
        x: 0.0,
        y: 200.0,
        hdg: 180.0,
        spd: 2.0,
    };
    let o = encounter("head-on", bob, 160.0);
    assert_avoided("head-on", &o);
}

#[test]
fn crossing_from_starboard() {
    // Both reach 0,100 at 50 s.
    let bob = Contact {
        x: 100.0,
        y: 100.0,
        hdg: 270.0,
        spd: 2.0,
    };
    let o = encounter("crossing", bob, 160.0);
    assert_avoided("crossing", &o);
}

#[test]
fn overtaking() {
    // Ownship at 2 m/s catches a contact 40 m ahead at 0.8 m/s after about 33 s.
    let bob = Contact {
        x: 0.0,
        y: 40.0,
        hdg: 0.0,
        spd: 0.8,
    };
    let o = encounter("overtaking", bob, 160.0);
    assert_avoided("overtaking", &o);
}
