//! `cargo bench -p ivp`: ZAIC builds, a coupled waypoint-like function, and solves
//! (the BHV_IPF text: `cargo bench -p ivp-ipf`).

use criterion::{criterion_group, criterion_main, Criterion};
use ivp::{couple, Domain, IvpFunction, ZaicHeq, ZaicLeq, ZaicPeak, ZaicSpd};
use ivp_solver::Solver;
use std::hint::black_box;

fn dom() -> Domain {
    Domain::parse("course:0:359:360,speed:0:4:41").unwrap()
}

fn waypoint(d: &Domain, bearing: f64, heading: f64, cruise: f64, pwt: f64) -> IvpFunction {
    let mut c = ZaicPeak::new(d, "course").unwrap();
    c.set_value_wrap(true);
    c.set_params(bearing, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
    let k = c.add_component();
    c.set_params(heading, 30.0, 180.0, 5.0, 0.0, 20.0, k);
    let mut s = ZaicPeak::new(d, "speed").unwrap();
    s.set_params(cruise, cruise / 2.0, 1.6, 20.0, 0.0, 100.0, 0);
    let mut f = couple(
        c.extract(false).unwrap(),
        s.extract(true).unwrap(),
        50.0,
        50.0,
        true,
    )
    .unwrap();
    f.set_pwt(pwt);
    f
}

fn builds(c: &mut Criterion) {
    let d = dom();
    c.bench_function("zaic_peak_speed", |b| {
        b.iter(|| {
            let mut z = ZaicPeak::new(&d, "speed").unwrap();
            z.set_params(black_box(2.0), 1.0, 1.6, 20.0, 0.0, 100.0, 0);
            z.extract(true).unwrap()
        })
    });
    c.bench_function("zaic_peak_course_2comp_wrap", |b| {
        b.iter(|| {
            let mut z = ZaicPeak::new(&d, "course").unwrap();
            z.set_value_wrap(true);
            z.set_params(black_box(63.43), 0.0, 180.0, 50.0, 0.0, 100.0, 0);
            let k = z.add_component();
            z.set_params(90.0, 30.0, 180.0, 5.0, 0.0, 20.0, k);
            z.extract(false).unwrap()
        })
    });
    c.bench_function("zaic_heq", |b| {
        b.iter(|| {
            let mut z = ZaicHeq::new(&d, "speed").unwrap();
            z.set_summit(black_box(1.37));
            z.set_base_width(0.66);
            z.set_summit_delta(5.0);
            z.extract().unwrap()
        })
    });
    c.bench_function("zaic_leq", |b| {
        b.iter(|| {
            let mut z = ZaicLeq::new(&d, "speed").unwrap();
            z.set_summit(black_box(2.63));
            z.set_base_width(0.71);
            z.extract().unwrap()
        })
    });
    c.bench_function("zaic_spd", |b| {
        b.iter(|| {
            let mut z = ZaicSpd::new(&d, "speed").unwrap();
            z.set_params(black_box(2.0), 0.1, 2.4, 70.0, 20.0, 0.0, 0.0, 100.0);
            z.extract().unwrap()
        })
    });
    c.bench_function("waypoint_coupled_build", |b| {
        b.iter(|| waypoint(&d, black_box(63.43), 90.0, 2.0, 100.0))
    });
}

fn solves(c: &mut Criterion) {
    let d = dom();
    let fs: Vec<IvpFunction> = vec![
        waypoint(&d, 63.43, 90.0, 2.0, 100.0),
        waypoint(&d, 200.0, 90.0, 1.2, 80.0),
        waypoint(&d, 320.0, 90.0, 3.0, 60.0),
        waypoint(&d, 10.0, 90.0, 2.5, 50.0),
        waypoint(&d, 135.0, 90.0, 0.8, 40.0),
    ];
    let counts: Vec<usize> = fs.iter().map(IvpFunction::piece_count).collect();
    eprintln!("piece counts: {counts:?}");
    let mut solver = Solver::new();
    let mut out = ivp_solver::Decision::default();
    for n in [2usize, 5] {
        let refs: Vec<&IvpFunction> = fs[..n].iter().collect();
        c.bench_function(&format!("solve_{n}_waypoints"), |b| {
            b.iter(|| {
                solver.solve_into(&d, black_box(&refs), &mut out).unwrap();
                out.utility
            })
        });
    }
}

criterion_group!(benches, builds, solves);
criterion_main!(benches);
