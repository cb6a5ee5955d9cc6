use super::*;
use behavior_api::testing::MockHelm;

const RECT: &str = "pts={60,-12:60,6:80,6:80,-12},label=oba";

/// The m34_bo_alpha parameters, spawned for obstacle `oba`.
fn spawned() -> (AvoidObstacleV24, MockHelm) {
    let mut b = AvoidObstacleV24::new(&HelmDomain::new("course,0,359,360:speed,0,4,21"));
    let mut helm = MockHelm::new("avd_ob_oba");
    helm.priority = 500.0;
    for (p, v) in crate::EXAMPLE_PARAMS {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    (b, helm)
}

#[test]
fn template_posts_the_alert_request() {
    let mut b = AvoidObstacleV24::new(&HelmDomain::new("course,0,359,360:speed,0,4,21"));
    let mut helm = MockHelm::new("avd_ob_");
    assert!(helm.with(|ctx| b.set_param(ctx, "pwt_outer_dist", "15")));
    helm.with(|ctx| b.on_helm_start(ctx));
    assert!(
        helm.posted("OBM_ALERT_REQUEST").is_empty(),
        "not a template"
    );
    helm.with(|ctx| b.set_param(ctx, "helm_templating", "spawn"));
    helm.with(|ctx| b.set_param(ctx, "helm_updates", "OBSTACLE_ALERT"));
    helm.with(|ctx| b.on_params_complete(ctx));
    assert!(
        helm.posted("BHV_SETTINGS").is_empty(),
        "templates post no settings"
    );
    helm.with(|ctx| b.on_helm_start(ctx));
    assert_eq!(
        helm.last("OBM_ALERT_REQUEST").as_deref(),
        Some("name=avd_ob_,update_var=OBSTACLE_ALERT,alert_range=15")
    );
}

#[test]
fn bad_config_is_posted_with_the_name() {
    let (mut b, mut helm) = spawned();
    assert!(!helm.with(|ctx| b.set_param(ctx, "poly", "pts={0,0:5,2:10,0:5,10}")));
    assert_eq!(
        helm.last("BHV_BAD_CONFIG").as_deref(),
        Some("avd_ob_oba: obstacle is not convex")
    );
    assert!(!helm.with(|ctx| b.set_param(ctx, "buffer_dist", "3")));
}

#[test]
fn steers_clear_and_draws_the_three_polygons() {
    let (mut b, mut helm) = spawned();
    helm.with(|ctx| b.on_params_complete(ctx));
    assert_eq!(
        helm.last("BHV_SETTINGS").as_deref(),
        Some("type=BHV_AvoidObstacleV24,name=avd_ob_oba,allowable_ttc=5.00,min_util_cpa=3.00,max_util_cpa=7.00,pwt_outer_dist=15.00,pwt_inner_dist=5.00,completed_dist=15.00")
    );
    helm.nav(46.23959416797254, 0.0, 90.0, 2.0);
    helm.with(|ctx| b.on_every_state(ctx));
    let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
    // Relevance 0.113629 (see model tests) × pwt 500.
    assert!((f.pwt - 56.81371).abs() < 1e-4, "{}", f.pwt);
    let polys = helm.posted("VIEW_POLYGON");
    assert_eq!(polys.len(), 3);
    assert_eq!(
        polys[0],
        "pts={60,-12:60,6:80,6:80,-12},label=oba,label_color=white,edge_color=gray50,vertex_color=gray50,fill_color=gray60,vertex_size=0,edge_size=1"
    );
    assert!(polys[1].contains("label=oba_mid_poly") && polys[1].contains("fill_color=gray70"));
    assert!(polys[2].contains("label=oba_rim_poly"));
    // The holonomic warning every iteration unless holonomic_ok.
    assert_eq!(
        helm.last("BHV_WARNING").as_deref(),
        Some("avd_ob_oba: holo plat_model not best. Set holonomic_ok=true to silence")
    );
}

#[test]
fn resolved_id_completes_and_erases() {
    let (mut b, mut helm) = spawned();
    helm.with(|ctx| b.on_params_complete(ctx));
    helm.nav(50.0, 0.0, 90.0, 2.0);
    helm.strs.insert("OBM_RESOLVED".into(), "obz".into());
    helm.with(|ctx| b.on_every_state(ctx));
    assert!(helm.with(|ctx| b.on_run(ctx)).is_some());
    assert_eq!(helm.last("NOTED_RESOLVED").as_deref(), Some("obz"));
    assert_eq!(helm.completes, 0);
    helm.strs.insert("OBM_RESOLVED".into(), "oba".into());
    helm.with(|ctx| b.on_every_state(ctx));
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(helm.completes, 1);
    helm.clear();
    helm.with(|ctx| b.on_complete(ctx));
    assert_eq!(
        helm.posted("VIEW_POLYGON"),
        vec![
            "pts={0,0:9,0:0,9},active=false,label=oba",
            "pts={0,0:9,0:0,9},active=false,label=oba_mid_poly",
            "pts={0,0:9,0:0,9},active=false,label=oba_rim_poly",
        ]
    );
}

#[test]
fn completes_beyond_completed_dist() {
    let (mut b, mut helm) = spawned();
    helm.nav(40.0, 0.0, 90.0, 2.0); // range 20 > completed 15
    helm.with(|ctx| b.on_every_state(ctx));
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(helm.completes, 1);
}

#[test]
fn missing_cpa_distances_never_build() {
    // run R4: a template without the CPA distances.
    let mut b = AvoidObstacleV24::new(&HelmDomain::new("course,0,359,360:speed,0,4,21"));
    let mut helm = MockHelm::new("avd");
    for (p, v) in [
        ("poly", RECT),
        ("allowable_ttc", "5"),
        ("allstop_on_breach", "false"),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)));
    }
    helm.nav(45.0, 0.0, 90.0, 2.0);
    helm.with(|ctx| b.on_every_state(ctx));
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    let w = helm.posted("BHV_WARNING");
    assert!(
        w.contains(&"avd: Unable to init AOF_AvoidObstacleV24:min_util_cpa is not set".to_string())
    );
    assert_eq!(w.last().map(String::as_str), Some("avd: Obstacle Breached"));
    assert!(helm.posted("BHV_ERROR").is_empty());
}

#[test]
fn inside_the_obstacle_is_a_breach() {
    let (mut b, mut helm) = spawned();
    helm.nav(70.0, 0.0, 90.0, 2.0);
    helm.with(|ctx| b.on_every_state(ctx));
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(
        helm.last("BHV_ERROR").as_deref(),
        Some("avd_ob_oba: Allstop: Obstacle Breached")
    );
}

#[test]
fn macros_and_flags() {
    let (mut b, mut helm) = spawned();
    assert!(helm.with(|ctx| b.set_param(ctx, "rng_flag", "<20 RNGF = $[OID]:$[RNG]")));
    assert!(helm.with(|ctx| b.set_param(
        ctx,
        "poly",
        "pts={60,-12:60,6:80,6:80,-12},label=ob_a_7"
    )));
    helm.nav(50.0, 0.0, 90.0, 2.0);
    helm.with(|ctx| b.on_every_state(ctx));
    assert_eq!(
        helm.flags.last().map(|f| f.0.as_str()),
        Some("RNGF = ob_a_7:10")
    );
    assert_eq!(
        b.expand("$[OIDX] $[RBNG] $[SIDE] $[MINU_CPA] $[CPA] $[SLOCK]."),
        "7 $[RBNG] star 3 10 ."
    );
}

#[test]
fn able_filter_strings() {
    assert_eq!(
        able_action("action=disable,obstacle_id=OBA", "oba", ""),
        Ok(Some("disable".into()))
    );
    assert_eq!(
        able_action("action=disable,obstacle_id=obb", "oba", ""),
        Ok(None)
    );
    assert_eq!(
        able_action("action=expunge,vsource=Sim", "", "sim"),
        Ok(Some("expunge".into()))
    );
    assert_eq!(able_action("action=disable", "oba", ""), Err(()));
    assert_eq!(
        able_action("action=zap,obstacle_id=oba", "oba", ""),
        Err(())
    );
    assert_eq!(
        able_action("action=disable,action=enable,obstacle_id=oba", "oba", ""),
        Err(())
    );
}

#[test]
fn refinery_cuts_plateaus_and_basins_into_the_function() {
    let (mut b, mut helm) = spawned();
    assert!(helm.with(|ctx| b.set_param(ctx, "use_refinery", "true")));
    helm.nav(50.0, 0.0, 90.0, 2.0);
    helm.with(|ctx| b.on_every_state(ctx));
    let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
    // Fewer pieces than the 840 uniform ones: whole course ranges became single pieces.
    let n = f.piece_count().unwrap();
    assert!(n < 840, "{n} pieces");
    // Course 90 runs into the obstacle (basin, 0); course 0 clears the rim (plateau, 100).
    assert_eq!(eval(&f, 90, 10), Some(0.0));
    assert_eq!(eval(&f, 0, 10), Some(100.0));
}

/// The function's value at (course index, speed index), from its pieces.
fn eval(f: &FunctionData, c: i32, s: i32) -> Option<f64> {
    let n = f.piece_count()?;
    (0..n).find_map(|k| {
        let b = &f.bounds[4 * k..4 * k + 4];
        let w = &f.weights[3 * k..3 * k + 3];
        (b[0] <= c && c <= b[1] && b[2] <= s && s <= b[3])
            .then(|| w[0] * f64::from(c) + w[1] * f64::from(s) + w[2])
    })
}

/// The expansion as a chain of `str::replace`, each on the previous one's result (the
/// reference's order), with the values computed independently of `expand_into`.
fn replace_chain(b: &AvoidObstacleV24, text: &str) -> String {
    let label = &b.params.obstacle.attrs.label;
    let oidx = label.rsplit_once('_').map_or("", |(_, t)| t);
    let (bng, side) = match (b.pose, b.derived.as_ref()) {
        (Some(os), Some(d)) => (
            rel_ang(os.x, os.y, d.centre.0, d.centre.1),
            d.passing_side.as_str(),
        ),
        _ => (0.0, "n/a"),
    };
    let rng = b.derived.as_ref().map_or(-1.0, |d| d.range);
    let slock = b.side_lock.map_or("", Side::as_str);
    let n = |v: f64| compact(v, 3);
    text.replace("$[RNG]", &n(rng))
        .replace("$[BNG]", &n(bng))
        .replace("$[SIDE]", side)
        .replace("$[OIDX]", oidx)
        .replace("$[OID]", label)
        .replace("$[CPA]", &n(b.cpa_reported))
        .replace("$[SLOCK]", slock)
        .replace("$[MINU_CPA]", &n(b.params.min_util_cpa))
        .replace("$[MAXU_CPA]", &n(b.params.max_util_cpa))
}

/// Texts made of macros, pieces of macros and other text, repeated and adjacent.
const PIECES: [&str; 24] = [
    "$[RNG]",
    "$[BNG]",
    "$[SIDE]",
    "$[OIDX]",
    "$[OID]",
    "$[CPA]",
    "$[SLOCK]",
    "$[MINU_CPA]",
    "$[MAXU_CPA]",
    "$[RBNG]",
    "$[",
    "]",
    "$",
    "[",
    "$[OI",
    "D]",
    "X]",
    "$[MINU_",
    "CPA]",
    "ü",
    "日本",
    " = ",
    ",",
    "$[$[RNG]]",
];

/// Labels whose inserted values hold macros: expanded when later in the order (`$[CPA]`
/// after `$[OID]`), kept when earlier (`$[SIDE]`), and `$[OIDX]`'s value `$[OID]`.
const LABELS: [&str; 9] = [
    "oba",
    "ob_a_7",
    "x_$[CPA]",
    "a_$[OID]",
    "$[SIDE]_$[MAXU_CPA]",
    "ö_ñ$[SLOCK]$[RNG]",
    "ob_D]",
    "",
    "_",
];

#[test]
fn expansion_is_the_replace_chain() {
    let (mut b, mut helm) = spawned();
    helm.with(|ctx| b.on_params_complete(ctx));
    let (mut text, mut spare, mut num) = (String::new(), String::new(), String::new());
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move |n: usize| {
        // xorshift64: a fixed, repeatable sequence.
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    let mut checked = 0;
    // Without a pose first (range -1, side n/a), then at fractional ranges and bearings.
    for (k, nav) in [
        None,
        Some((47.3, -1.7)),
        Some((50.0, 0.0)),
        Some((56.125, 9.5)),
    ]
    .into_iter()
    .enumerate()
    {
        if let Some((x, y)) = nav {
            helm.nav(x, y, 37.0, 2.0);
            helm.with(|ctx| b.on_every_state(ctx));
            assert!(b.derived.is_some(), "nav {k}");
        }
        b.side_lock = [None, Some(Side::Star), Some(Side::Port), None][k];
        b.cpa_reported = [-1.0, 4.56789, 10.0, 0.0005][k];
        b.params.min_util_cpa = [3.0, 2.5, 1.0 / 3.0, -0.0][k];
        b.params.max_util_cpa = [7.0, 7.125, 1e20, 8.0][k];
        for label in LABELS {
            b.params.obstacle.attrs.label = label.to_string();
            for t in PIECES.iter().chain(LABELS.iter()) {
                let want = replace_chain(&b, t);
                assert_eq!(b.expand(t), want, "{t:?} label {label:?}");
            }
            for _ in 0..400 {
                let s: String = (0..next(9)).map(|_| PIECES[next(PIECES.len())]).collect();
                let want = replace_chain(&b, &s);
                assert_eq!(b.expand(&s), want, "{s:?} label {label:?}");
                // Kept buffers holding earlier texts give the same.
                b.expand_into(&s, &mut text, &mut spare, &mut num);
                assert_eq!(text, want, "{s:?} label {label:?}, kept buffers");
                checked += usize::from(s != want);
            }
        }
    }
    assert!(checked > 5000, "only {checked} texts had a macro expanded");
}
