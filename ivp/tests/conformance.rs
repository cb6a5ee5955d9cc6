//! Runs every golden case of `conformance/ivp/*.toml` (format: comment block at
//! the top of each file). Fails if the folder or a required file is missing.

mod aof_waypoint;

use aof_waypoint::AofWaypoint;
use ivp::{couple, Domain, IvpFunction, ZaicHeq, ZaicLeq, ZaicPeak, ZaicSpd};
use ivp_reflector::Reflector;
use ivp_solver::Solver;
use std::path::PathBuf;
use toml::Value;

const REQUIRED: [&str; 5] = ["zaic_peak", "zaic_heq", "zaic_leq", "zaic_spd", "solver"];

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../conformance/ivp")
}

fn num(v: &Value) -> f64 {
    match v {
        Value::Float(f) => *f,
        Value::Integer(i) => *i as f64,
        Value::Boolean(b) => f64::from(u8::from(*b)),
        other => panic!("not a number: {other:?}"),
    }
}

fn nums(v: &Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(num).collect()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a.is_nan() && b.is_nan()) || (a - b).abs() <= tol
}

/// Apply a builder spec (`builder`, `domain`, `calls`, `maxval`); returns (call_ok, warnings, function).
fn build_zaic(spec: &Value) -> Result<(Vec<bool>, String, Option<IvpFunction>), String> {
    let builder = spec["builder"].as_str().ok_or("no builder")?;
    let dom =
        Domain::parse(spec["domain"].as_str().ok_or("no domain")?).map_err(|e| e.to_string())?;
    let var = dom.var(0).name.clone();
    let calls = spec["calls"].as_array().ok_or("no calls")?;
    let maxval = spec.get("maxval").and_then(Value::as_bool).unwrap_or(true);
    let mut oks = vec![];
    let arg = |c: &[Value], i: usize| c.get(i + 1).map(num);
    match builder {
        "ZAIC_PEAK" => {
            let mut z = ZaicPeak::new(&dom, &var).map_err(|e| e.to_string())?;
            for c in calls {
                let c = c.as_array().ok_or("call")?.as_slice();
                let ix = |n: usize| arg(c, n).map_or(0, |v| v as usize);
                let a = |i: usize| arg(c, i).unwrap_or(f64::NAN);
                let ok = match c[0].as_str().ok_or("call name")? {
                    "setSummit" => z.set_summit(a(0), ix(1)),
                    "setPeakWidth" => z.set_peak_width(a(0), ix(1)),
                    "setBaseWidth" => z.set_base_width(a(0), ix(1)),
                    "setSummitDelta" => z.set_summit_delta(a(0), ix(1)),
                    "setMinMaxUtil" => z.set_min_max_util(a(0), a(1), ix(2)),
                    "setParams" => z.set_params(a(0), a(1), a(2), a(3), a(4), a(5), ix(6)),
                    "addComponent" => {
                        z.add_component();
                        true
                    }
                    "setValueWrap" => {
                        z.set_value_wrap(c[1].as_bool().ok_or("bool")?);
                        true
                    }
                    "setSummitInsist" => {
                        z.set_summit_insist(c[1].as_bool().ok_or("bool")?);
                        true
                    }
                    other => return Err(format!("unknown ZAIC_PEAK call {other}")),
                };
                oks.push(ok);
            }
            let f = z.extract(maxval);
            Ok((oks, z.warnings().to_string(), f))
        }
        "ZAIC_HEQ" | "ZAIC_LEQ" => {
            macro_rules! run {
                ($z:expr) => {{
                    let mut z = $z;
                    for c in calls {
                        let c = c.as_array().ok_or("call")?.as_slice();
                        let a = |i: usize| arg(c, i).unwrap_or(f64::NAN);
                        let ok = match c[0].as_str().ok_or("call name")? {
                            "setSummit" => z.set_summit(a(0)),
                            "setBaseWidth" => z.set_base_width(a(0)),
                            "setSummitDelta" => z.set_summit_delta(a(0)),
                            "setMinMaxUtil" => z.set_min_max_util(a(0), a(1)),
                            other => return Err(format!("unknown {builder} call {other}")),
                        };
                        oks.push(ok);
                    }
                    let f = z.extract();
                    Ok((oks, z.warnings().to_string(), f))
                }};
            }
            if builder == "ZAIC_HEQ" {
                run!(ZaicHeq::new(&dom, &var).map_err(|e| e.to_string())?)
            } else {
                run!(ZaicLeq::new(&dom, &var).map_err(|e| e.to_string())?)
            }
        }
        "ZAIC_SPD" => {
            let mut z = ZaicSpd::new(&dom, &var).map_err(|e| e.to_string())?;
            for c in calls {
                let c = c.as_array().ok_or("call")?.as_slice();
                let a = |i: usize| arg(c, i).unwrap_or(f64::NAN);
                let d = |i: usize, dflt: f64| arg(c, i).unwrap_or(dflt);
                let ok = match c[0].as_str().ok_or("call name")? {
                    "setParams" => z.set_params(
                        a(0),
                        a(1),
                        a(2),
                        a(3),
                        a(4),
                        d(5, 0.0),
                        d(6, 0.0),
                        d(7, 100.0),
                    ),
                    "setMedSpeed" => z.set_med_speed(a(0)),
                    "setLowSpeed" => z.set_low_speed(a(0)),
                    "setHghSpeed" => z.set_hgh_speed(a(0)),
                    "setLowSpeedUtil" => z.set_low_speed_util(a(0)),
                    "setHghSpeedUtil" => z.set_hgh_speed_util(a(0)),
                    "setMinSpdUtil" => z.set_min_spd_util(a(0)),
                    "setMaxSpdUtil" => z.set_max_spd_util(a(0)),
                    "disableLowSpeed" => {
                        z.disable_low_speed();
                        true
                    }
                    "disableHighSpeed" => {
                        z.disable_high_speed();
                        true
                    }
                    other => return Err(format!("unknown ZAIC_SPD call {other}")),
                };
                oks.push(ok);
            }
            let f = z.extract();
            Ok((oks, z.warnings().to_string(), f))
        }
        other => Err(format!("unknown builder {other}")),
    }
}

fn check_zaic_case(case: &Value) -> Result<(), String> {
    let (oks, warnings, f) = build_zaic(case)?;
    let want_ok: Vec<bool> = case["call_ok"]
        .as_array()
        .ok_or("call_ok")?
        .iter()
        .map(|v| v.as_bool().unwrap_or(false))
        .collect();
    if oks != want_ok {
        return Err(format!("call_ok {oks:?} != {want_ok:?}"));
    }
    let produced = case["produced"].as_bool().ok_or("produced")?;
    if produced != f.is_some() {
        return Err(format!("produced {} != {produced}", f.is_some()));
    }
    let want_w = case.get("warnings").and_then(Value::as_str).unwrap_or("");
    if warnings != want_w {
        return Err(format!("warnings {warnings:?} != {want_w:?}"));
    }
    let Some(f) = f else { return Ok(()) };
    let n = case["pieces"].as_integer().ok_or("pieces")? as usize;
    if f.piece_count() != n {
        return Err(format!("piece count {} != {n}", f.piece_count()));
    }
    for (k, p) in case["piece_list"]
        .as_array()
        .ok_or("piece_list")?
        .iter()
        .enumerate()
    {
        let p = nums(p);
        let q = f.piece(k);
        let got = [
            f64::from(q.lo(0)),
            f64::from(q.hi(0)),
            q.weights()[0],
            q.weights()[1],
        ];
        if !(0..4).all(|i| close(got[i], p[i], 1e-9)) {
            return Err(format!("piece {k}: got {got:?} want {p:?}"));
        }
    }
    for (i, u) in nums(&case["utility"]).iter().enumerate() {
        let got = f.eval(&[i as u32]).unwrap_or(f64::NAN);
        if !close(got, *u, 1e-9) {
            return Err(format!("utility[{i}]: got {got} want {u}"));
        }
    }
    Ok(())
}

fn domain_of(v: &Value) -> Result<Domain, String> {
    let parts: Vec<&str> = v
        .as_array()
        .ok_or("domain list")?
        .iter()
        .filter_map(Value::as_str)
        .collect();
    Domain::parse(&parts.join(",")).map_err(|e| e.to_string())
}

fn build_function(fv: &Value) -> Result<IvpFunction, String> {
    match fv["kind"].as_str().ok_or("kind")? {
        "zaic" => build_zaic(&fv["zaic"])?
            .2
            .ok_or_else(|| "zaic produced nothing".to_string()),
        "coupled" => {
            let a = build_zaic(&fv["first"])?
                .2
                .ok_or("first produced nothing")?;
            let b = build_zaic(&fv["second"])?
                .2
                .ok_or("second produced nothing")?;
            let w = nums(&fv["couple"]);
            couple(a, b, w[0], w[1], true).ok_or_else(|| "coupler failed".to_string())
        }
        "reflector" => {
            let dom = domain_of(&fv["fdomain"])?;
            let aof = &fv["aof"];
            let g = |k: &str| aof.get(k).map(num).unwrap_or(0.0);
            let a = AofWaypoint::new(
                &dom,
                g("osx"),
                g("osy"),
                g("ptx"),
                g("pty"),
                g("desired_speed"),
            )?;
            let mut r = Reflector::new(&dom, &a);
            if let Some(s) = fv.get("uniform_piece").and_then(Value::as_str) {
                if !r.set_param("uniform_piece", s) {
                    return Err("uniform_piece rejected".into());
                }
            }
            if let Some(s) = fv.get("uniform_grid").and_then(Value::as_str) {
                if !r.set_param("uniform_grid", s) {
                    return Err("uniform_grid rejected".into());
                }
            }
            r.create(None, None);
            r.extract(true)
                .ok_or_else(|| "reflector produced nothing".to_string())
        }
        k => Err(format!("unknown kind {k}")),
    }
}

fn recorded_function(fv: &Value) -> Result<IvpFunction, String> {
    let dom = domain_of(&fv["fdomain"])?;
    let dim = dom.size();
    let (mut b, mut w) = (vec![], vec![]);
    for p in fv["pieces"].as_array().ok_or("pieces")? {
        let p = nums(p);
        b.extend(p[..2 * dim].iter().map(|&x| x as i32));
        w.extend_from_slice(&p[2 * dim..]);
    }
    let gel: Vec<u32> = nums(&fv["gelbox"]).iter().map(|&x| x as u32).collect();
    IvpFunction::from_flat(dom, b, w, gel).map_err(|e| e.to_string())
}

fn compare_pieces(built: &IvpFunction, rec: &IvpFunction, tol: f64) -> Result<(), String> {
    if built.domain() != rec.domain() {
        return Err(format!("domain {} != {}", built.domain(), rec.domain()));
    }
    if built.piece_count() != rec.piece_count() || built.gelbox() != rec.gelbox() {
        return Err(format!(
            "pieces {}/{} gelbox {:?}/{:?}",
            built.piece_count(),
            rec.piece_count(),
            built.gelbox(),
            rec.gelbox()
        ));
    }
    if built.bounds() != rec.bounds() {
        return Err("piece bounds differ".into());
    }
    for (i, (a, b)) in built.weights().iter().zip(rec.weights()).enumerate() {
        if !close(*a, *b, tol) {
            return Err(format!("weight {i}: built {a} recorded {b}"));
        }
    }
    Ok(())
}

fn check_solver_case(case: &Value) -> Result<(), String> {
    let dom = domain_of(&case["domain"])?;
    let (mut built, mut rec) = (vec![], vec![]);
    for fv in case["function"].as_array().ok_or("function")? {
        let pwt = num(&fv["pwt"]);
        let mut r = recorded_function(fv)?;
        r.set_pwt(pwt);
        // Builders (ZAIC, reflector) leave a grid on their functions; the coupler does not.
        if fv["kind"].as_str() != Some("coupled") {
            r.build_grid();
        }
        let mut b = build_function(fv)?;
        b.set_pwt(pwt);
        let tol = if fv["kind"].as_str() == Some("reflector") {
            1e-6
        } else {
            1e-9
        };
        compare_pieces(&b, &r, tol).map_err(|e| format!("function {}: {e}", fv["name"]))?;
        rec.push(r);
        built.push(b);
    }
    let result = &case["result"];
    let mut solver = Solver::new();
    for (label, fs) in [("recorded", &rec), ("built", &built)] {
        let refs: Vec<&IvpFunction> = fs.iter().collect();
        let before: Vec<IvpFunction> = fs.clone();
        let d = solver
            .solve_problem(&dom, &refs)
            .map_err(|e| e.to_string())?
            .ok_or("no decision")?;
        if &before != fs {
            return Err("solver modified its inputs".into());
        }
        for (i, v) in dom.vars().iter().enumerate() {
            let want = num(&result[v.name.as_str()]);
            if d.values[i] != Some(want) {
                return Err(format!(
                    "{label}: {} = {:?}, want {want}",
                    v.name, d.values[i]
                ));
            }
        }
        let want_u = num(&result["utility"]);
        if !close(d.utility, want_u, 1e-6) {
            return Err(format!("{label}: utility {} want {want_u}", d.utility));
        }
    }
    Ok(())
}

#[test]
fn conformance_ivp() {
    let dir = dir();
    assert!(
        dir.is_dir(),
        "conformance folder missing: {}",
        dir.display()
    );
    for r in REQUIRED {
        assert!(
            dir.join(format!("{r}.toml")).is_file(),
            "conformance file missing: {r}.toml"
        );
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    let mut total_failed = 0;
    let mut report = String::new();
    for path in files {
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let text = std::fs::read_to_string(&path).unwrap();
        let doc: Value = toml::from_str(&text).unwrap_or_else(|e| panic!("{stem}: {e}"));
        let cases = doc
            .get("case")
            .and_then(Value::as_array)
            .unwrap_or_else(|| panic!("{stem}: no [[case]]"));
        assert!(!cases.is_empty(), "{stem}: no cases");
        let (mut pass, mut fail) = (0, 0);
        for case in cases {
            let name = case.get("name").and_then(Value::as_str).unwrap_or("?");
            let res = if case.get("function").is_some() {
                check_solver_case(case)
            } else {
                check_zaic_case(case)
            };
            match res {
                Ok(()) => pass += 1,
                Err(e) => {
                    fail += 1;
                    report.push_str(&format!("  FAIL {stem}/{name}: {e}\n"));
                }
            }
        }
        println!("{stem}: {pass} passed, {fail} failed");
        total_failed += fail;
    }
    print!("{report}");
    assert_eq!(total_failed, 0, "conformance failures:\n{report}");
}
