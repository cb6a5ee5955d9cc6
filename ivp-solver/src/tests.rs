//! Unit tests of the solver's pieces (odometer, bounds).

use super::*;

/// The stack odometer visits exactly the cells, in exactly the order, of the
/// reference's divide-per-cell count (the order fixes the search's tie-breaks).
#[test]
fn odometer_matches_the_divide_per_cell_order() {
    let cases: [(&[i32], &[i32]); 4] = [
        (&[9, 6], &[0, 359, 0, 40]),
        (&[9, 6], &[17, 19, 5, 12]),
        (&[4, 3, 2], &[3, 9, 0, 0, 1, 5]),
        (&[2], &[7, 7]),
    ];
    for (ppg, b) in cases {
        let mut stride = vec![];
        let mut total = 1usize;
        for &p in ppg {
            stride.push(total);
            total *= (400 / p as usize) + 1;
        }
        let dim = ppg.len();
        let (mut fast, mut slow) = (vec![], vec![]);
        for_each_cell(ppg, &stride, b, dim, |c| {
            fast.push(c);
            true
        });
        for_each_cell_any(ppg, &stride, b, dim, |c| {
            slow.push(c);
            true
        });
        assert!(!fast.is_empty());
        assert_eq!(fast, slow, "{ppg:?} {b:?}");
        let mut first = vec![];
        for_each_cell(ppg, &stride, b, dim, |c| {
            first.push(c);
            false
        });
        assert_eq!(first, slow[..1]);
    }
}

fn rng(seed: &mut u64) -> u64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    *seed >> 33
}

/// A random function over `dom`: random boxes and weights (overlapping, as some
/// builders make them), a random gel box, with or without a builder grid.
fn random_function(dom: &Domain, seed: &mut u64) -> IvpFunction {
    let dim = dom.size();
    let n = 1 + rng(seed) as usize % 40;
    let mut pieces = vec![];
    for _ in 0..n {
        let mut b = vec![];
        let mut w = vec![];
        for d in 0..dim {
            let pts = dom.var(d).points as u64;
            let lo = (rng(seed) % pts) as i32;
            let hi = lo + (rng(seed) % (pts - lo as u64)) as i32;
            b.push((lo, hi));
            w.push((rng(seed) % 2001) as f64 / 100.0 - 10.0);
        }
        w.push((rng(seed) % 20001) as f64 / 100.0 - 50.0);
        pieces.push((b, w));
    }
    let mut f = IvpFunction::from_pieces(dom.clone(), &pieces).unwrap();
    let gel = (0..dim)
        .map(|d| (rng(seed) % u64::from(dom.var(d).points + 2)) as u32)
        .collect();
    f.set_gelbox(gel).unwrap();
    if rng(seed).is_multiple_of(2) {
        f.build_grid();
    }
    f.set_pwt(1.0 + (rng(seed) % 100) as f64);
    f
}

/// The bounds the search prunes with (shared cell ranges, one-cell reads, tables;
/// from level 1, the first function has no cells)
/// are bit for bit the divide-per-cell cheap bounds summed left to right.
#[test]
fn bound_rest_equals_the_divide_per_cell_sum() {
    let doms = [
        Domain::parse("course:0:359:360,speed:0:4:41").unwrap(),
        Domain::parse("x:0:9:10,y:0:6:7,z:0:2:3").unwrap(),
        Domain::parse("x:0:20:21").unwrap(),
    ];
    let mut seed = 11u64;
    for round in 0..300 {
        let dom = &doms[round % doms.len()];
        let dim = dom.size();
        let m = 1 + rng(&mut seed) as usize % 5;
        let mut fs: Vec<IvpFunction> = (0..m).map(|_| random_function(dom, &mut seed)).collect();
        // Same gel boxes now and then, so functions share a grid geometry.
        if m > 1 && round.is_multiple_of(2) {
            let g = fs[0].gelbox().to_vec();
            fs[1].set_gelbox(g).unwrap();
        }
        let refs: Vec<&IvpFunction> = fs.iter().collect();
        let mut solver = Solver::new();
        solver.solve(dom, &refs).unwrap();
        let (funcs, active) = (&solver.funcs, &solver.active);
        for _ in 0..50 {
            let mut b = vec![];
            for d in 0..dim {
                let pts = dom.var(d).points as u64;
                let lo = (rng(&mut seed) % pts) as i32;
                b.push(lo);
                b.push(lo + (rng(&mut seed) % (pts - lo as u64)) as i32);
            }
            let acc = (rng(&mut seed) % 1000) as f64 / 7.0;
            for level in 1..active.len() {
                let mut want = acc;
                for &fi in &active[level..] {
                    let f = &funcs[fi];
                    want += if f.single {
                        f.global_ub
                    } else {
                        let (mut best, mut any) = (NO_BOUND, false);
                        for_each_cell(&f.ppg, &f.stride, &b, dim, |c| {
                            if f.cell_filled[c] && (!any || f.cell_ub[c] > best) {
                                best = f.cell_ub[c];
                                any = true;
                            }
                            true
                        });
                        best
                    };
                }
                let got = bound_rest(funcs, active, dim, level, &b, acc);
                assert_eq!(got.to_bits(), want.to_bits(), "round {round} box {b:?}");
            }
        }
    }
}

/// One pass for both extremes gives the two separate passes' values.
#[test]
fn min_max_wt_equals_min_wt_and_max_wt() {
    let dom = Domain::parse("x:0:9:10,y:0:6:7").unwrap();
    let mut seed = 5u64;
    for _ in 0..500 {
        let f = random_function(&dom, &mut seed);
        let (mn, mx) = f.min_max_wt();
        assert_eq!(mn.to_bits(), f.min_wt().to_bits());
        assert_eq!(mx.to_bits(), f.max_wt().to_bits());
    }
}

/// The solver's one-loop extremes equal the function's, bit for bit.
#[test]
fn solver_min_max_wt_equals_the_functions() {
    let doms = [
        Domain::parse("x:0:9:10,y:0:6:7").unwrap(),
        Domain::parse("x:0:359:360").unwrap(),
        Domain::parse("x:0:9:10,y:0:6:7,z:0:3:4").unwrap(),
        Domain::parse("x:0:4:5,y:0:6:7,z:0:3:4,t:0:2:3").unwrap(),
    ];
    let mut seed = 7u64;
    for round in 0..600 {
        let f = random_function(&doms[round % doms.len()], &mut seed);
        let (a, b) = min_max_wt(&FunctionView::from(&f));
        let (c, d) = f.min_max_wt();
        assert_eq!((a.to_bits(), b.to_bits()), (c.to_bits(), d.to_bits()));
    }
}

/// The last function's bit sets give exactly the pieces meeting a box.
#[test]
fn last_bits_meet_exactly_the_intersecting_pieces() {
    let doms = [
        Domain::parse("course:0:359:360,speed:0:4:41").unwrap(),
        Domain::parse("x:0:9:10,y:0:6:7,z:0:2:3").unwrap(),
        Domain::parse("x:0:20:21").unwrap(),
    ];
    let mut seed = 3u64;
    let mut bits = last_bits::LastBits::default();
    for round in 0..300 {
        let dom = &doms[round % doms.len()];
        let dim = dom.size();
        let pts: Vec<i32> = (0..dim).map(|d| dom.var(d).points as i32).collect();
        // Now and then the same boxes again (kept sets).
        let f = random_function(dom, &mut seed);
        let n = f.piece_count();
        for _ in 0..2 {
            assert!(bits.make(f.bounds(), n, &pts));
            for _ in 0..50 {
                let mut b = vec![];
                for &p in &pts {
                    let lo = (rng(&mut seed) % p as u64) as i32;
                    b.push(lo);
                    b.push(lo + (rng(&mut seed) % (p - lo) as u64) as i32);
                }
                let mut meet = [0u64; 4];
                assert!(bits.meeting(&b, &mut meet));
                for k in 0..n {
                    let want = intersects(&b, &f.bounds()[k * 2 * dim..(k + 1) * 2 * dim], dim);
                    assert_eq!(meet[k / 64] >> (k % 64) & 1 == 1, want, "round {round}");
                }
                assert!(meet
                    .iter()
                    .enumerate()
                    .all(|(w, &x)| w < bits.words() || x == 0));
            }
        }
    }
}

/// The last index's cell bounds, made from per-coordinate terms, are the plain fold
/// of `maxVal(piece ∩ cell)` over each cell's pieces in array order, bit for bit.
#[test]
fn last_index_bounds_equal_the_clipped_max_val_fold() {
    let mut seed = 99u64;
    let mut cells_checked = 0;
    for _ in 0..300 {
        let dim = 1 + rng(&mut seed) as usize % 3;
        let pts: Vec<i32> = (0..dim).map(|_| 1 + (rng(&mut seed) % 60) as i32).collect();
        let ppg: Vec<i32> = pts
            .iter()
            .map(|&p| 1 + (rng(&mut seed) % p as u64) as i32)
            .collect();
        let n = 1 + rng(&mut seed) as usize % 12;
        let (mut boxes, mut weights) = (vec![], vec![]);
        for _ in 0..n {
            for &p in &pts {
                let lo = (rng(&mut seed) % p as u64) as i32;
                let hi = lo + (rng(&mut seed) % (p - lo) as u64) as i32;
                boxes.extend([lo, hi]);
            }
            for _ in 0..=dim {
                let w = (rng(&mut seed) % 2001) as f64 / 7.0 - 140.0;
                weights.push(if rng(&mut seed).is_multiple_of(9) {
                    -0.0
                } else {
                    w
                });
            }
        }
        let mut ix = LastIndex::default();
        ix.build(&ppg, &pts, &boxes, &weights, n);
        assert!(ix.on);
        let ncells: Vec<usize> = (0..dim)
            .map(|d| ((pts[d] + ppg[d] - 1) / ppg[d]) as usize)
            .collect();
        let total: usize = ncells.iter().product();
        for c in 0..total {
            let (mut cur, mut rest) = (vec![0; dim], c);
            for d in 0..dim {
                cur[d] = rest % ncells[d];
                rest /= ncells[d];
            }
            let mut want = f64::NEG_INFINITY;
            let mut list = vec![];
            for k in 0..n {
                let b = &boxes[k * 2 * dim..(k + 1) * 2 * dim];
                let meets = (0..dim).all(|d| {
                    let cell_lo = cur[d] as i32 * ppg[d];
                    b[2 * d] < cell_lo + ppg[d] && cell_lo <= b[2 * d + 1]
                });
                if !meets {
                    continue;
                }
                list.push(k as u32);
                let w = &weights[k * (dim + 1)..(k + 1) * (dim + 1)];
                let v = last_index::clip_max_val(b, w, &ppg, &cur);
                if v > want || v.is_nan() {
                    want = v;
                }
            }
            assert_eq!(ix.bound(c).to_bits(), want.to_bits(), "cell {c}");
            assert_eq!(ix.pieces(c), &list[..], "cell {c}");
            cells_checked += 1;
        }
    }
    assert!(cells_checked > 1000, "{cells_checked}");
}

/// An index built again and again (boxes kept with new weights, weights kept, boxes
/// new, cells new) has every cell's list and bound of an index built fresh, bit for bit.
#[test]
fn last_index_rebuilt_equals_a_fresh_one() {
    let mut seed = 7u64;
    let mut kept_boxes = 0;
    for _ in 0..60 {
        let dim = 1 + rng(&mut seed) as usize % 3;
        let pts: Vec<i32> = (0..dim).map(|_| 1 + (rng(&mut seed) % 50) as i32).collect();
        let mut ppg: Vec<i32> = pts
            .iter()
            .map(|&p| 1 + (rng(&mut seed) % p as u64) as i32)
            .collect();
        let n = 1 + rng(&mut seed) as usize % 10;
        let mut reused = LastIndex::default();
        let (mut boxes, mut weights) = (vec![], vec![]);
        for round in 0..12 {
            let what = rng(&mut seed) % 5;
            if round == 0 || what == 0 {
                boxes.clear();
                for _ in 0..n {
                    for &p in &pts {
                        let lo = (rng(&mut seed) % p as u64) as i32;
                        let hi = lo + (rng(&mut seed) % (p - lo) as u64) as i32;
                        boxes.extend([lo, hi]);
                    }
                }
            } else {
                kept_boxes += 1;
            }
            if what == 1 {
                // New cells over the same boxes.
                let d = rng(&mut seed) as usize % dim;
                ppg[d] = 1 + (rng(&mut seed) % pts[d] as u64) as i32;
            }
            if round == 0 || what != 2 {
                weights.clear();
                for _ in 0..n * (dim + 1) {
                    let w = (rng(&mut seed) % 2001) as f64 / 7.0 - 140.0;
                    weights.push(match rng(&mut seed) % 11 {
                        0 => -0.0,
                        1 => f64::NAN,
                        _ => w,
                    });
                }
            }
            let mut fresh = LastIndex::default();
            fresh.build(&ppg, &pts, &boxes, &weights, n);
            reused.build(&ppg, &pts, &boxes, &weights, n);
            assert!(fresh.on && reused.on);
            let total: usize = (0..dim)
                .map(|d| ((pts[d] + ppg[d] - 1) / ppg[d]) as usize)
                .product();
            for c in 0..total {
                assert_eq!(reused.bound(c).to_bits(), fresh.bound(c).to_bits());
                assert_eq!(reused.pieces(c), fresh.pieces(c));
            }
        }
    }
    assert!(kept_boxes > 300, "{kept_boxes}");
}

/// Functions read in place from buffers of their own (as a plugin's are, over a domain
/// made apart) give the decisions of the owned functions, bit for bit.
#[test]
fn views_of_copied_buffers_solve_like_the_functions() {
    let helm = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
    let subs = [
        helm.clone(),
        helm.sub_domain(&["course"]),
        helm.sub_domain(&["speed"]),
    ];
    let mut seed = 5u64;
    let (mut owned, mut viewed) = (Solver::new(), Solver::new());
    let (mut want, mut got) = (Decision::default(), Decision::default());
    for round in 0..200 {
        let m = 1 + rng(&mut seed) as usize % 4;
        let fs: Vec<IvpFunction> = (0..m)
            .map(|k| random_function(&subs[(round + k) % subs.len()], &mut seed))
            .collect();
        // Every buffer copied, every domain rebuilt: nothing shared with `fs`.
        let parts: Vec<_> = fs
            .iter()
            .map(|f| {
                let d = Domain::from_vars(f.domain().vars().to_vec()).unwrap();
                let b = (
                    f.bounds().to_vec(),
                    f.weights().to_vec(),
                    f.gelbox().to_vec(),
                );
                (d, b, f.grid_bounds().to_vec(), f.pwt())
            })
            .collect();
        let views: Vec<FunctionView<'_>> = parts
            .iter()
            .map(|(d, (b, w, g), grid, pwt)| FunctionView::checked(d, b, w, g, grid, *pwt).unwrap())
            .collect();
        let refs: Vec<&IvpFunction> = fs.iter().collect();
        let a = owned.solve_into(&helm, &refs, &mut want).unwrap();
        let b = viewed.solve_views_into(&helm, &views, &mut got).unwrap();
        assert_eq!((a, &want.indices), (b, &got.indices), "round {round}");
        assert_eq!(
            want.utility.to_bits(),
            got.utility.to_bits(),
            "round {round}"
        );
    }
}

/// Buffers broken one way or another are rejected by [`CheckedFunction`] exactly when
/// `IvpFunction::from_buffers` rejects them, with the same error; good ones read back
/// as they were given.
#[test]
fn checked_functions_reject_what_owned_functions_reject() {
    struct Parts(Vec<i32>, Vec<f64>, Vec<u32>, Vec<f64>);
    impl PieceBuffers for Parts {
        fn bounds(&self) -> &[i32] {
            &self.0
        }
        fn weights(&self) -> &[f64] {
            &self.1
        }
        fn gelbox(&self) -> &[u32] {
            &self.2
        }
        fn grid(&self) -> &[f64] {
            &self.3
        }
        fn pwt(&self) -> f64 {
            2.0
        }
    }
    let dom = std::sync::Arc::new(Domain::parse("x:0:9:10,y:0:6:7").unwrap());
    let mut seed = 9u64;
    for round in 0..500 {
        let f = random_function(&dom, &mut seed);
        let mut p = Parts(
            f.bounds().to_vec(),
            f.weights().to_vec(),
            f.gelbox().to_vec(),
            f.grid_bounds().to_vec(),
        );
        match round % 6 {
            0 => p.0[1] = 10,
            1 => p.0[0] = -1,
            2 => {
                p.1.pop();
            }
            3 => p.2.push(1),
            4 => p.3.push(0.5),
            _ => {}
        }
        let owned = IvpFunction::from_buffers(
            (*dom).clone(),
            p.0.clone(),
            p.1.clone(),
            p.2.clone(),
            p.3.clone(),
            2.0,
        );
        match (CheckedFunction::new(p, dom.clone()), owned) {
            (Ok(c), Ok(o)) => {
                let v = c.view();
                assert_eq!((v.bounds(), v.weights()), (o.bounds(), o.weights()));
                assert_eq!((v.gelbox(), v.grid_bounds()), (o.gelbox(), o.grid_bounds()));
                assert_eq!((v.piece_count(), v.pwt()), (o.piece_count(), o.pwt()));
            }
            (Err((_, a)), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
            (c, o) => panic!("round {round}: checked {} but owned {o:?}", c.is_ok()),
        }
    }
}

/// `Clip::narrows`, looking at the set bits of `dims` only, answers as the test of
/// every dimension with a checked shift did (every set bit is below the dimension).
#[test]
fn clip_narrows_equals_the_test_of_every_dimension() {
    let mut x = 0x853c_49e6_748f_ea9bu64;
    let mut next = |n: u64| {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x % n
    };
    for _ in 0..20_000 {
        let dim = 1 + next(3) as usize;
        let pts: Vec<i32> = (0..dim).map(|_| 1 + next(5) as i32).collect();
        let b: Vec<i32> = (0..dim)
            .flat_map(|d| {
                let lo = next(pts[d] as u64) as i32;
                [lo, lo + next((pts[d] - lo) as u64) as i32]
            })
            .collect();
        let dims = next(1 << dim) as u32;
        let clip = Clip {
            boxes: &[],
            weights: &[],
            ubs: &[],
            n: 0,
            dims,
            from: 0,
        };
        let old = (0..pts.len()).any(|d| {
            dims & 1u32.checked_shl(d as u32).unwrap_or(0) != 0
                && (b[2 * d] > 0 || b[2 * d + 1] < pts[d] - 1)
        });
        assert_eq!(clip.narrows(&b, &pts), old, "{dims:b} {b:?} {pts:?}");
    }
}

/// The first level's tight loops four pieces a step (`first_simd.rs`), the scalar loop
/// going on from where they stop, pass over the same pieces and raise the same doubt
/// as the scalar loops alone, over values full of NaN, infinities and signed zeros.
#[cfg(target_arch = "x86_64")]
#[test]
fn first_level_simd_loops_stop_where_the_scalar_ones_do() {
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let odd = [
        0.0,
        -0.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1.0,
        -1.0,
    ];
    let value = |seed: &mut u64| match rng(seed) % 10 {
        0 => odd[rng(seed) as usize % odd.len()],
        // Few distinct values: many sums land exactly on the limits.
        1..=4 => (rng(seed) % 9) as f64 - 4.0,
        _ => (rng(seed) % 20001) as f64 / 100.0 - 100.0,
    };
    for round in 0..20_000 {
        let n = rng(&mut seed) as usize % 40;
        let (nub, nsum) = (
            1 + rng(&mut seed) as usize % 9,
            1 + rng(&mut seed) as usize % 9,
        );
        let cell = |seed: &mut u64, len: usize| match rng(seed) % 4 {
            0 => NO_CELL,
            _ => (rng(seed) as usize % len) as u32,
        };
        let mvs: Vec<f64> = (0..n).map(|_| value(&mut seed)).collect();
        let cells: Vec<u32> = (0..n).map(|_| cell(&mut seed, nub)).collect();
        let tops: Vec<u32> = (0..n).map(|_| cell(&mut seed, nsum)).collect();
        let ub: Vec<f64> = (0..nub).map(|_| value(&mut seed)).collect();
        let sums: Vec<f64> = (0..nsum).map(|_| value(&mut seed)).collect();
        let (last_ub, best) = (value(&mut seed), value(&mut seed));
        let floor = if rng(&mut seed).is_multiple_of(2) {
            best - 2.0
        } else {
            value(&mut seed)
        };
        let watch = rng(&mut seed).is_multiple_of(2);
        let start = if n == 0 {
            0
        } else {
            rng(&mut seed) as usize % n
        };
        // The scalar loops as `Search::run_indexed` has them.
        let two = |mut q: usize, doubt: &mut bool| {
            while q < n {
                let rb = mvs[q] + last_ub;
                if rb <= best {
                    if watch && rb > floor {
                        *doubt = true;
                    }
                    q += 1;
                    continue;
                }
                let c = cells[q];
                let tb = if c != NO_CELL {
                    mvs[q] + ub[c as usize]
                } else {
                    rb
                };
                if tb <= floor {
                    q += 1;
                    continue;
                }
                break;
            }
            q
        };
        let mid = |mut q: usize| {
            while q < n && tops[q] != NO_CELL {
                let c = cells[q];
                let lb = if c != NO_CELL {
                    ub[c as usize]
                } else {
                    last_ub
                };
                if (mvs[q] + sums[tops[q] as usize]) + lb <= floor {
                    q += 1;
                } else {
                    break;
                }
            }
            q
        };
        // The tables as the AVX2 loops read them: one more entry, for no cell.
        let ub_out: Vec<f64> = ub.iter().copied().chain([last_ub]).collect();
        let sums_nan: Vec<f64> = sums.iter().copied().chain([f64::NAN]).collect();
        let t = first_simd::Two {
            mvs: &mvs,
            cells: &cells,
            ub: &ub_out,
            last_ub,
            best,
            floor,
        };
        let (mut plain, mut fast) = (false, false);
        let want = two(start, &mut plain);
        // SAFETY: AVX2 checked above.
        let (at, d) = unsafe { first_simd::pass_two(&t, start, n, watch) };
        // Where the scalar loop stops, or with fewer than four pieces left.
        assert!(at == want || (at < want && n - at < 4), "round {round}");
        fast |= d;
        assert_eq!((two(at, &mut fast), fast), (want, plain), "round {round}");
        let t = first_simd::Mid {
            mvs: &mvs,
            cells: &cells,
            ub: &ub_out,
            tops: &tops,
            sums: &sums_nan,
            lim: floor,
        };
        // SAFETY: AVX2 checked above.
        let at = unsafe { first_simd::pass_mid(&t, start, n) };
        let want = mid(start);
        assert!(at == want || (at < want && n - at < 4), "round {round}");
        assert_eq!(mid(at), want, "round {round}");
    }
}
