//! `cargo bench -p ivp-ipf`: the BHV_IPF text of a contact-sized function (1512
//! pieces), into a reused string as the helm writes it every iteration.

use criterion::{criterion_group, criterion_main, Criterion};
use ivp::{Domain, IvpFunction};
use std::hint::black_box;

fn dom() -> Domain {
    Domain::parse("course:0:359:360,speed:0:4:41").unwrap()
}

/// BHV_IPF of a 72 x 21 uniform tiling (the size of a collision-avoidance function):
/// every piece's bounds and three weights of the usual magnitudes.
fn encodes(c: &mut Criterion) {
    let d = dom();
    let mut pieces = Vec::new();
    let mut seed = 5u64;
    for i in 0..72 {
        for j in 0..21 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            let r = (seed >> 11) as f64 / (1u64 << 53) as f64;
            let lo_s = j * 41 / 21;
            let hi_s = ((j + 1) * 41 / 21 - 1).max(lo_s);
            pieces.push((
                vec![(i * 5, i * 5 + 4), (lo_s, hi_s)],
                vec![r * 3.0 - 1.5, 0.25 - r, r * 100.0],
            ));
        }
    }
    let mut f = IvpFunction::from_pieces(d, &pieces).unwrap();
    f.set_pwt(300.0);
    f.set_context("1234:avd_abe");
    let mut text = String::new();
    c.bench_function("ipf_encode_1512_pieces", |b| {
        b.iter(|| {
            ivp_ipf::encode_into(black_box(&f), &mut text);
            text.len()
        })
    });
}

criterion_group!(benches, encodes);
criterion_main!(benches);
