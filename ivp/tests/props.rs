//! Property tests: the solver against brute force, and builders never panic.

use ivp::{Domain, IvpFunction, ZaicHeq, ZaicLeq, ZaicPeak, ZaicSpd, ZaicVector};
use ivp_solver::Solver;
use proptest::prelude::*;

const NAMES: [&str; 3] = ["a", "b", "c"];

#[derive(Debug, Clone)]
struct FnSpec {
    vars: Vec<usize>,       // helm var indices, in the function's own order
    cuts: Vec<Vec<u32>>,    // per own dim: interval start points (sorted, first 0)
    weights: Vec<Vec<i32>>, // per piece: slopes + intercept (small integers: exact arithmetic)
    order_seed: u64,        // permutes the piece order
    pwt: i32,
}

fn domain_strategy() -> impl Strategy<Value = Vec<u32>> {
    prop::collection::vec(1u32..7, 1..=3)
}

fn fn_strategy(points: Vec<u32>) -> impl Strategy<Value = FnSpec> {
    let n = points.len();
    (
        prop::sample::subsequence((0..n).collect::<Vec<_>>(), 1..=n),
        any::<u64>(),
        1i32..4,
        any::<bool>(),
    )
        .prop_flat_map(move |(mut vars, seed, pwt, rev)| {
            if rev {
                vars.reverse();
            }
            let cut_strats: Vec<_> = vars
                .iter()
                .map(|&v| {
                    let p = points[v];
                    prop::collection::btree_set(1u32..p.max(2), 0..(p as usize)).prop_map(
                        move |s| {
                            let mut c: Vec<u32> = vec![0];
                            c.extend(s.into_iter().filter(|&x| x < p));
                            c
                        },
                    )
                })
                .collect();
            let dim = vars.len();
            (Just(vars), cut_strats, Just(seed), Just(pwt)).prop_flat_map(
                move |(vars, cuts, seed, pwt)| {
                    let count: usize = cuts.iter().map(Vec::len).product();
                    let w = prop::collection::vec(prop::collection::vec(-3i32..4, dim + 1), count);
                    (Just(vars.clone()), Just(cuts), w, Just(seed), Just(pwt)).prop_map(
                        |(vars, cuts, weights, order_seed, pwt)| FnSpec {
                            vars,
                            cuts,
                            weights,
                            order_seed,
                            pwt,
                        },
                    )
                },
            )
        })
}

fn build(spec: &FnSpec, helm: &Domain) -> IvpFunction {
    let names: Vec<&str> = spec.vars.iter().map(|&v| NAMES[v]).collect();
    let dom = helm.sub_domain(&names);
    let mut pieces = vec![];
    let count: usize = spec.cuts.iter().map(Vec::len).product();
    for k in 0..count {
        let mut rem = k;
        let mut b = vec![];
        for (d, c) in spec.cuts.iter().enumerate() {
            let i = rem % c.len();
            rem /= c.len();
            let hi = if i + 1 < c.len() {
                c[i + 1] - 1
            } else {
                dom.var(d).points - 1
            };
            b.push((c[i] as i32, hi as i32));
        }
        pieces.push((
            b,
            spec.weights[k]
                .iter()
                .map(|&x| f64::from(x))
                .collect::<Vec<f64>>(),
        ));
    }
    // Deterministic shuffle.
    let mut s = spec.order_seed;
    for i in (1..pieces.len()).rev() {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        pieces.swap(i, (s >> 33) as usize % (i + 1));
    }
    let mut f = IvpFunction::from_pieces(dom, &pieces).unwrap();
    f.set_pwt(f64::from(spec.pwt));
    f
}

/// Normalize/weight/translate exactly as the solver's addOF + align.
fn prepared(fs: &[IvpFunction], problem: &Domain) -> Vec<IvpFunction> {
    fs.iter()
        .map(|f| {
            let mut g = f.clone();
            if g.max_wt() - g.min_wt() > 100.0 {
                g.normalize(0.0, 100.0);
            }
            g.apply_weight(g.pwt());
            g.translate(problem).unwrap()
        })
        .collect()
}

fn problem_domain(helm: &Domain, fs: &[IvpFunction]) -> Domain {
    let mut used: Vec<&str> = vec![];
    for f in fs {
        for v in f.domain().vars() {
            if !used.contains(&v.name.as_str()) {
                used.push(&v.name);
            }
        }
    }
    if used.len() == helm.size() {
        helm.clone()
    } else {
        helm.sub_domain(&used)
    }
}

/// Reference: §6.2 leaf enumeration, first leaf with the maximum value wins.
fn reference(fs: &[IvpFunction]) -> Option<(Vec<u32>, f64)> {
    let dim = fs[0].dim();
    let mut best: Option<(Vec<i32>, Vec<f64>, f64)> = None;
    fn rec(
        fs: &[IvpFunction],
        lvl: usize,
        b: Vec<i32>,
        w: Vec<f64>,
        best: &mut Option<(Vec<i32>, Vec<f64>, f64)>,
    ) {
        let dim = w.len() - 1;
        if lvl == fs.len() {
            let mut v = w[dim];
            for d in 0..dim {
                v += w[d] * f64::from(if w[d] < 0.0 { b[2 * d] } else { b[2 * d + 1] });
            }
            if best.as_ref().is_none_or(|x| v > x.2) {
                *best = Some((b, w, v));
            }
            return;
        }
        for p in fs[lvl].pieces() {
            let mut nb = b.clone();
            let mut ok = true;
            for d in 0..dim {
                nb[2 * d] = b[2 * d].max(p.lo(d));
                nb[2 * d + 1] = b[2 * d + 1].min(p.hi(d));
                ok &= nb[2 * d] <= nb[2 * d + 1];
            }
            if ok {
                let nw: Vec<f64> = w.iter().zip(p.weights()).map(|(a, b)| a + b).collect();
                rec(fs, lvl + 1, nb, nw, best);
            }
        }
    }
    for p in fs[0].pieces() {
        let b: Vec<i32> = (0..dim).flat_map(|d| [p.lo(d), p.hi(d)]).collect();
        rec(fs, 1, b, p.weights().to_vec(), &mut best);
    }
    best.map(|(b, w, v)| {
        (
            (0..dim)
                .map(|d| (if w[d] < 0.0 { b[2 * d] } else { b[2 * d + 1] }) as u32)
                .collect(),
            v,
        )
    })
}

fn brute_max(fs: &[IvpFunction], problem: &Domain) -> f64 {
    let pts: Vec<u32> = problem.vars().iter().map(|v| v.points).collect();
    let total: usize = pts.iter().map(|&p| p as usize).product();
    let mut best = f64::NEG_INFINITY;
    for t in 0..total {
        let mut rem = t;
        let ix: Vec<u32> = pts
            .iter()
            .map(|&p| {
                let i = (rem % p as usize) as u32;
                rem /= p as usize;
                i
            })
            .collect();
        let v: f64 = fs.iter().map(|f| f.eval(&ix).unwrap()).sum();
        best = best.max(v);
    }
    best
}

fn scenario() -> impl Strategy<Value = (Vec<u32>, Vec<FnSpec>)> {
    domain_strategy().prop_flat_map(|pts| {
        let p2 = pts.clone();
        (Just(pts), prop::collection::vec(fn_strategy(p2), 1..=3))
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn solver_matches_brute_force_and_tie_rule((pts, specs) in scenario()) {
        let mut helm = Domain::new();
        for (i, &p) in pts.iter().enumerate() {
            helm.add_var(NAMES[i], 0.0, f64::from(p.max(2) - 1) * 0.5 * f64::from(u8::from(p > 1)), p).unwrap();
        }
        let fs: Vec<IvpFunction> = specs.iter().map(|s| build(s, &helm)).collect();
        let refs: Vec<&IvpFunction> = fs.iter().collect();
        let mut solver = Solver::new();
        let d = solver.solve(&helm, &refs).unwrap().expect("a decision");
        let problem = problem_domain(&helm, &fs);
        let prep = prepared(&fs, &problem);
        // Never beaten by a scan of all grid points.
        let bm = brute_max(&prep, &problem);
        prop_assert!(d.utility >= bm - 1e-9, "solver {} < brute force {}", d.utility, bm);
        // Decision point attains it.
        let ix: Vec<u32> = problem.vars().iter().map(|v| d.indices[helm.index_of(&v.name).unwrap()].unwrap()).collect();
        let at: f64 = prep.iter().map(|f| f.eval(&ix).unwrap()).sum();
        prop_assert!((at - bm).abs() < 1e-9, "decision value {} != max {}", at, bm);
        // Same leaf as the §6.2 reference enumeration.
        let (rix, rv) = reference(&prep).unwrap();
        prop_assert_eq!(ix, rix);
        prop_assert_eq!(d.utility, rv);
        // Unused helm variables get no decision.
        for (h, v) in helm.vars().iter().enumerate() {
            prop_assert_eq!(d.values[h].is_some(), problem.index_of(&v.name).is_some());
        }
    }

    #[test]
    fn zaic_peak_never_panics(points in 1u32..50, low in -10.0f64..10.0, span in 0.0f64..100.0,
                              p in prop::collection::vec(prop_oneof![-200.0f64..200.0, Just(f64::NAN), Just(f64::INFINITY), Just(0.0)], 6),
                              wrap in any::<bool>(), insist in any::<bool>(), maxval in any::<bool>(), comps in 0usize..3) {
        let high = if points == 1 { low } else { low + span };
        let dom = match Domain::parse(&format!("x:{low}:{high}:{points}")) { Ok(d) => d, Err(_) => return Ok(()) };
        let mut z = ZaicPeak::new(&dom, "x").unwrap();
        z.set_value_wrap(wrap);
        z.set_summit_insist(insist);
        for k in 0..=comps {
            if k > 0 { z.add_component(); }
            z.set_params(p[0], p[1], p[2], p[3], p[4], p[5], k);
        }
        if let Ok(f) = z.try_extract(maxval) {
            check_valid(&f);
        }
    }

    #[test]
    fn other_zaics_never_panic(points in 1u32..50, span in 0.0f64..20.0,
                               p in prop::collection::vec(prop_oneof![-50.0f64..150.0, Just(f64::NAN), Just(-0.0)], 8)) {
        let high = if points == 1 { 0.0 } else { span.max(0.1) };
        let dom = Domain::parse(&format!("s:0:{high}:{points}")).unwrap();
        let mut h = ZaicHeq::new(&dom, "s").unwrap();
        h.set_summit(p[0]); h.set_base_width(p[1]); h.set_summit_delta(p[2]); h.set_min_max_util(p[3], p[4]);
        if let Ok(f) = h.try_extract() { check_valid(&f); }
        let mut l = ZaicLeq::new(&dom, "s").unwrap();
        l.set_summit(p[0]); l.set_base_width(p[1]); l.set_summit_delta(p[2]); l.set_min_max_util(p[3], p[4]);
        if let Ok(f) = l.try_extract() { check_valid(&f); }
        let mut s = ZaicSpd::new(&dom, "s").unwrap();
        s.set_params(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
        if let Ok(f) = s.try_extract() { check_valid(&f); }
        let mut v = ZaicVector::new(&dom, "s").unwrap();
        v.set_domain_vals(&p[..4]);
        v.set_range_vals(&p[4..]);
        if let Ok(f) = v.try_extract() { check_valid(&f); }
    }
}

fn check_valid(f: &IvpFunction) {
    let raw = f.clone().into_raw_parts();
    IvpFunction::from_raw_parts(raw).expect("builder output is a valid function");
}
