//! Fuzz harness of the whole path a `.bhv` file takes into the helm (issue 10): the
//! reader, then every behavior's parameters (`set_param`: speeds, points, polygons,
//! flags, conditions, ...), then start-up and a few iterations with moving navigation
//! and the files' own variables as mail. Seeds are every `.bhv` text of the golden helm
//! cases and the missions; run by `cargo test` on a bounded budget (`FUZZ_CASES`,
//! `FUZZ_SECS`; see the `fuzzkit` crate).
//!
//! The shipped plugin libraries are loaded too (built once into the test's target
//! folder), so their parameters are fuzzed the same way.
//!
//! Invariants: no panic (a behavior's panic is caught by the helm and posted as
//! `BHV_ERROR ... behavior panicked`: that fails the case too), no hang, bounded memory.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use helm_engine::config::HelmConfig;
use helm_engine::factory::BehaviorFactory;
use helm_engine::posting::Value;
use helm_engine::{Helm, Mail};

mod common;

/// Every `.bhv` text of the repo: mission files and golden cases.
fn seeds() -> Vec<Vec<u8>> {
    let repo = common::workspace();
    let mut v = fuzzkit::seed_files(&repo.join("missions"), "bhv");
    for case in fuzzkit::seed_files(&repo.join("conformance/helm"), "toml") {
        let case = String::from_utf8(case).expect("a golden case is UTF-8");
        let doc: toml::Table = toml::from_str(&case).expect("toml");
        if let Some(b) = doc.get("bhv").and_then(|b| b.as_str()) {
            v.push(b.as_bytes().to_vec());
        }
    }
    // A V24 that runs without being spawned, so its parameters reach the run hook.
    v.push(OBSTACLE_SEED.as_bytes().to_vec());
    assert!(v.len() > 10);
    v
}

const OBSTACLE_SEED: &str = "Behavior = BHV_AvoidObstacleV24\n{\n  name = avd\n  pwt = 500\n  poly = pts={10,-40:10,-10:30,-10:30,-40},label=ob_1\n  id = ob_1\n  allowable_ttc = 5\n  min_util_cpa_dist = 3\n  max_util_cpa_dist = 7\n  pwt_outer_dist = 40\n  completed_dist = 60\n  rng_flag = <20 RNG = $[RNG],$[OIDX]\n  cpa_flag = CPA = $[CPA]\n  visual_hints = gut_lcolor=red, edge_size=2\n  can_disable = true\n}\n";

const DICT: &[&[u8]] = &[
    b"\n  speed = ",
    b"\n  points = ",
    b"\n  polygon = ",
    b"\n  capture_radius = ",
    b"\n  duration = ",
    b"\n  pwt = ",
    b"\n  endflag = ",
    b"\n  condition = ",
    b"\n  updates = ",
    b"\n  templating = spawn",
    b"\n  perpetual = true",
    b"\n  repeat = ",
    b"\n  order = reverse",
    b"\n  lead = ",
    b"\n  center_activate = true",
    b"\n  clockwise = false",
    b"\n  station_pt = ",
    b"Behavior = BHV_Loiter\n{\n",
    b"Behavior = BHV_Waypoint\n{\n",
    b"Behavior = BHV_Timer\n{\n",
    b"Behavior = BHV_HSLine\n{\n",
    b"Behavior = BHV_BearingLine\n{\n",
    b"Behavior = BHV_MaxDepth\n{\n",
    b"Behavior = BHV_MaxSpeed\n{\n",
    b"Behavior = BHV_GoToDepth\n{\n",
    b"Behavior = BHV_PeriodicSurface\n{\n",
    b"Behavior = BHV_ZigZag\n{\n",
    b"Behavior = BHV_LegRun\n{\n",
    b"Behavior = BHV_ConstantSpeed\n{\n",
    b"Behavior = BHV_StationKeep\n{\n",
    b"Behavior = BHV_AvdColregsV22\n{\n  contact = gus",
    b"Behavior = BHV_AvdColregsV19\n{\n  contact = gus",
    b"Behavior = BHV_AvdColregsV17\n{\n  contact = gus",
    b"\n  pwt_outer_dist = ",
    b"\n  min_util_cpa_dist = ",
    b"\n  completed_dist = ",
    b"\n  giveway_bow_dist = ",
    b"\n  velocity_filter = min_spd=1,max_spd=3,pct=20",
    b"\n  avoid_mode = ",
    b"\n  avoid_submode = ",
    b"\n  eval_tol = ",
    b"\n  use_refinery = true",
    b"Behavior = BHV_AvoidObstacleV24\n{\n",
    b"\n  poly = ",
    b"\n  min_util_cpa_dist = ",
    b"\n  max_util_cpa_dist = ",
    b"\n  pwt_outer_dist = ",
    b"\n  completed_dist = ",
    b"\n  visual_hints = ",
    b"\n  rng_flag = <",
    b"\n  allowable_ttc = ",
    b"pts={60,-12:60,6:80,6:80,-12},label=oba",
    b"\n  depth = ",
    b"\n  max_depth = ",
    b"\n  period = ",
    b"\n  zig_first = ",
    b"\n  vx1 = ",
    b"\n  leg_length = ",
    b"\n  turn_rad = ",
    b"\n  capture_flag = ",
    b"Behavior = BHV_OpRegion\n{\n",
    b"Behavior = BHV_OpRegionV24\n{\n",
    b"\n  max_time = ",
    b"\n  min_altitude = ",
    b"\n  trigger_entry_time = ",
    b"\n  trigger_exit_time = ",
    b"\n  breached_poly_flag = ",
    b"\n  time_remaining_var = ",
    b"\n  reset_var = ",
    b"\n  visual_hints = ",
    b"\n  core_poly = ",
    b"\n  save_poly = ",
    b"\n  halt_poly = ",
    b"\n  save_dist = ",
    b"\n  halt_dist = ",
    b"\n  recover_spd = ",
    b"\n  trigger_on_poly_entry = ",
    b"\n  core_poly_var = ",
    b"\n  reset = true",
    b"Behavior = BHV_PModelView\n{\n",
    b"\n  vertex_color = ",
    b"\n  vertex_size = ",
    b"Behavior = BHV_Convoy\n{\n",
    b"\n  contact = ",
    b"\n  inter_mark_range = ",
    b"\n  max_mark_range = ",
    b"\n  cruise_speed = ",
    b"\n  spd_faster = ",
    b"\n  spd_slower = ",
    b"\n  rng_estop = ",
    b"\n  rng_safety = ",
    b"format=radial, x=0, y=0, radius=20, pts=8",
    b"0,0 : 10,10 : 0,20",
    b"1e308",
    b"-1e308",
    b"nan",
    b"inf",
    b"0",
    b"-1",
    b"4294967296",
    b"$(X)",
    b"$[NI]",
    b",",
    b":",
    b"=",
];

/// The helm of `spec` with the built-in behaviors, in drive at once.
fn builtin_helm(spec: bhv::SetSpec) -> Helm {
    helm_with(spec, &BehaviorFactory::with_builtins())
}

fn helm_with(spec: bhv::SetSpec, factory: &BehaviorFactory) -> Helm {
    let (config, _) = HelmConfig::from_lines(&common::block_lines(&common::DRIVE_BLOCK));
    Helm::new(config, spec, factory, "alpha", Vec::new())
}

/// Built-in behaviors and every shipped plugin library.
fn full_factory() -> &'static BehaviorFactory {
    static F: std::sync::OnceLock<BehaviorFactory> = std::sync::OnceLock::new();
    F.get_or_init(|| {
        let built = common::build_plugins(common::SHIPPED_PLUGINS);
        let dir = common::lib_folder(&built, common::SHIPPED_PLUGINS, "fuzz-plugins-lib");
        let (factory, _) = helm_mission::factory_for(&[dir]);
        for t in helm_engine::factory::SHIPPED_LIBRARY_TYPES {
            assert!(factory.knows(t), "{t} not loaded");
        }
        factory
    })
}

fn mail(var: &str, value: Value, t: f64) -> Mail {
    Mail {
        var: var.into(),
        value,
        time: t,
        source: "uSimMarine".into(),
        source_aux: String::new(),
    }
}

/// Longest behavior name the harness runs (see [`check`]).
const LONG_NAME: usize = 1500;

/// Cases that got past the reader, and those that also posted a decision.
static BUILT: AtomicUsize = AtomicUsize::new(0);
static DECIDED: AtomicUsize = AtomicUsize::new(0);
/// Cases where a COLREGS behavior ran its modes (posted its relevance).
static COLREGS_RAN: AtomicUsize = AtomicUsize::new(0);

fn check(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(spec) = bhv::parse_str(&text, Path::new("fuzz.bhv")) else {
        return;
    };
    // Known, reported, not fixed here (ivp/ is not ours): a behavior name of 1950+
    // characters leaves BHV_IPF packets a 1-character body, so one iteration posts
    // thousands of 2 kB packets (see the ignored test below). Left out of the harness.
    let long_name = spec
        .behaviors
        .iter()
        .flat_map(|b| &b.lines)
        .any(|l| l.param == "name" && l.value.len() > LONG_NAME);
    if long_name {
        return;
    }
    BUILT.fetch_add(1, Ordering::Relaxed);
    let inits: Vec<(String, bhv::Value)> = spec
        .inits
        .iter()
        .map(|i| (i.var.clone(), i.value.clone()))
        .collect();
    let mut helm = helm_with(spec, full_factory());
    let mut posts = Vec::new();
    posts.extend(helm.startup(1000.0).iter().cloned());
    for k in 0..8 {
        let t = 1001.0 + k as f64;
        let mut m = vec![
            mail("NAV_X", Value::Num(3.0 * k as f64), t),
            mail("NAV_Y", Value::Num(-20.0 - 2.0 * k as f64), t),
            mail("NAV_HEADING", Value::Num((40.0 * k as f64) % 360.0), t),
            mail("NAV_SPEED", Value::Num(1.5), t),
            mail("NAV_DEPTH", Value::Num(0.0), t),
        ];
        // A contact crossing ownship's track, and the alert the golden cases' contact
        // templates spawn on, so contact behaviors run their modes too.
        let report = format!(
            "NAME=gus,X={},Y={},SPD=2,HDG=200,DEP=0,TYPE=kayak,TIME={t}",
            10.0 + 4.0 * k as f64,
            20.0 - 5.0 * k as f64
        );
        m.push(mail("NODE_REPORT", Value::Str(report), t));
        m.push(mail(
            "CONTACT_INFO",
            Value::Str("name=gus # contact=gus".into()),
            t,
        ));
        // The files' own variables, flipped now and then, to move conditions and modes.
        for (i, (var, v)) in inits.iter().enumerate() {
            let value = match v {
                bhv::Value::Num(x) => Value::Num(*x + k as f64),
                bhv::Value::Str(s) if (k + i) % 3 == 0 => Value::Str(format!("{s}x")),
                bhv::Value::Str(s) => Value::Str(s.clone()),
            };
            m.push(mail(var, value, t));
        }
        helm.handle_mail(t, &m);
        posts.extend(helm.iterate(t).iter().cloned());
    }
    if posts.iter().any(|p| p.var == "DESIRED_SPEED") {
        DECIDED.fetch_add(1, Ordering::Relaxed);
    }
    if posts
        .iter()
        .any(|p| p.var.starts_with("COL") && p.var.contains("_RELEVANCE"))
    {
        COLREGS_RAN.fetch_add(1, Ordering::Relaxed);
    }
    for p in &posts {
        if let Value::Str(s) = &p.value {
            assert!(!s.contains("behavior panicked"), "{} = {s}", p.var);
        }
    }
}

#[test]
fn fuzz_helm_behaviors() {
    // Build the plugin libraries before the first case, outside the per-case watchdog.
    full_factory();
    fuzzkit::fuzz("helm_behaviors", 4000, &seeds(), DICT, check);
    let (built, decided) = (
        BUILT.load(Ordering::Relaxed),
        DECIDED.load(Ordering::Relaxed),
    );
    println!("helm_behaviors: {built} inputs read, {decided} of them drove (DESIRED_SPEED)");
    let colregs = COLREGS_RAN.load(Ordering::Relaxed);
    println!("helm_behaviors: {colregs} ran a COLREGS behavior's modes");
    assert!(
        decided > 0,
        "no case reached a decision: the harness tests nothing"
    );
}

/// Found by this harness: ivp-solver.md §9.2's `body = 2000 - (len(id) + 50)` reaches 0
/// for an id (behavior name ^ iteration) of 1950+ characters, and the function string
/// went out one character per 2 kB packet (~3000 BHV_IPF packets, 6 MB, per iteration).
/// The body now has a floor (`ivp-ipf`, QUIRKS.md).
#[test]
fn long_behavior_names_do_not_multiply_bhv_ipf_packets() {
    let base = common::ALPHA_BHV;
    let text = base.replacen("waypt_survey", &"l".repeat(2000), 1);
    let spec = bhv::parse_str(&text, Path::new("long.bhv")).expect("parses");
    let mut helm = builtin_helm(spec);
    helm.startup(1000.0);
    let nav = |t: f64| {
        ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]
            .iter()
            .map(|v| mail(v, Value::Num(1.0), t))
            .collect::<Vec<_>>()
    };
    helm.handle_mail(1001.0, &nav(1001.0));
    let n = helm
        .iterate(1001.0)
        .iter()
        .filter(|p| p.var == "BHV_IPF")
        .count();
    assert!(n < 10, "{n} BHV_IPF packets in one iteration");
}

/// The obstacle manager's alert mail (obstacles.md §1.3) into a V24 template: fuzzed
/// `name=...#poly=...#id=...` strings spawn (or fail to spawn) instances, which then run
/// a few iterations with `OBM_RESOLVED` and able-filter mail. No panic, no hang.
#[test]
fn fuzz_obstacle_alerts() {
    const TEMPLATE: &str = "Behavior = BHV_AvoidObstacleV24\n{\n  name = avd_ob_\n  pwt = 500\n  templating = spawn\n  updates = OBSTACLE_ALERT\n  allowable_ttc = 5\n  min_util_cpa_dist = 3\n  max_util_cpa_dist = 7\n  pwt_outer_dist = 15\n  pwt_inner_dist = 5\n  completed_dist = 15\n  can_disable = true\n}\n";
    let seeds: Vec<Vec<u8>> = [
        "name=avd_ob_oba#poly=pts={60,-12:60,6:80,6:80,-12},label=oba#id=oba",
        "name=avd_ob_pa#poly=pts={0,-5:0,5:8,5:8,-5},label=pa,vsource=sim#id=pa",
        "name=avd_ob_x#poly=format=radial,x=5,y=0,radius=4,pts=8,label=x#id=x",
        "name=avd_ob_y#poly=pts={3,3}#id=y",
    ]
    .iter()
    .map(|s| s.as_bytes().to_vec())
    .collect();
    full_factory();
    let dict: &[&[u8]] = &[
        b"#", b"name=", b"poly=", b"id=", b"pts={", b"}", b":", b",label=", b"nan", b"1e308",
    ];
    fuzzkit::fuzz("obstacle_alerts", 1500, &seeds, dict, |data| {
        let alert = String::from_utf8_lossy(data).into_owned();
        let spec = bhv::parse_str(TEMPLATE, Path::new("t.bhv")).expect("the template parses");
        let mut helm = helm_with(spec, full_factory());
        helm.startup(1000.0);
        for k in 0..6 {
            let t = 1001.0 + k as f64;
            let mut m = vec![
                mail("NAV_X", Value::Num(2.0 * k as f64), t),
                mail("NAV_Y", Value::Num(0.0), t),
                mail("NAV_HEADING", Value::Num(90.0), t),
                mail("NAV_SPEED", Value::Num(2.0), t),
            ];
            if k < 2 {
                m.push(mail("OBSTACLE_ALERT", Value::Str(alert.clone()), t));
            }
            if k == 4 {
                m.push(mail(
                    "BHV_ABLE_FILTER",
                    Value::Str(alert.replace('#', ",")),
                    t,
                ));
                m.push(mail("OBM_RESOLVED", Value::Str(alert.clone()), t));
            }
            helm.handle_mail(t, &m);
            for p in helm.iterate(t) {
                if let Value::Str(s) = &p.value {
                    assert!(!s.contains("behavior panicked"), "{} = {s}", p.var);
                }
            }
        }
    });
}
