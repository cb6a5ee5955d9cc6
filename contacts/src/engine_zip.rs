//! CPA rows whose distances go straight into a function of the distance and a second
//! number per course (an objective function's blend of the CPA with the course's own
//! term): one pass over the row instead of a row of distances written, then read again
//! by a pass of its own.

#[cfg(target_arch = "x86_64")]
use super::heading::Lanes;
use super::heading::{cpa_entry, cpa_row, still_row, CpaRow};
use super::CpaEngine;

impl CpaEngine {
    /// [`CpaEngine::cpa_dists`] at speed `v` and horizon `tol`, the distance `d` of
    /// course `k` written as `f(d, col[k])` (as far as `out`, the units and `col` all
    /// reach): the values of the distances written first and `f` applied to them after,
    /// bit for bit. `f` should have no jumps (it runs several courses at once).
    pub fn cpa_dists_zip<F: Fn(f64, f64) -> f64>(
        &self,
        (sins, coss): (&[f64], &[f64]),
        (v, tol): (f64, f64),
        col: &[f64],
        out: &mut [f64],
        f: F,
    ) {
        let row = CpaRow {
            v: v.max(0.0),
            px: self.osx - self.cnx,
            py: self.osy - self.cny,
            cn_vx: self.cn_vx,
            cn_vy: self.cn_vy,
            now: self.range_now,
            tol,
        };
        let n = out.len().min(sins.len()).min(coss.len()).min(col.len());
        let (units, col, out) = ((&sins[..n], &coss[..n]), &col[..n], &mut out[..n]);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { cpa_zip_avx2(&row, units, col, out, f) };
        }
        cpa_row(&row, units, out, |d| d);
        for (o, &c) in out.iter_mut().zip(col) {
            *o = f(*o, c);
        }
    }
}

/// [`CpaEngine::cpa_dists_zip`] for AVX2 (all lists of one length): the chunks of
/// [`super::heading::cpa_row_avx2`] with its [`Lanes`] (the same operations: the same
/// distances), each distance put through `f` with its course's number as the chunk is done. A chunk
/// none of whose courses is closing is the range now throughout.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn cpa_zip_avx2<F: Fn(f64, f64) -> f64>(
    row: &CpaRow,
    (sins, coss): (&[f64], &[f64]),
    col: &[f64],
    out: &mut [f64],
    f: F,
) {
    use super::heading::WIDE;
    use std::arch::x86_64::_mm256_storeu_pd;
    if still_row(row, (sins, coss), out, &|d| d) {
        for (o, &c) in out.iter_mut().zip(col) {
            *o = f(*o, c);
        }
        return;
    }
    let lanes = Lanes::of(row);
    let (sc, s_rest) = sins.as_chunks::<WIDE>();
    let (cc, c_rest) = coss.as_chunks::<WIDE>();
    let (kc, k_rest) = col.as_chunks::<WIDE>();
    let (oc, o_rest) = out.as_chunks_mut::<WIDE>();
    for (((o, s), c), k) in oc.iter_mut().zip(sc).zip(cc).zip(kc) {
        let (u, any) = lanes.closing(s, c);
        if !any {
            for (o, &k) in o.iter_mut().zip(k) {
                *o = f(row.now, k);
            }
            continue;
        }
        let mut d = [0.0; WIDE];
        for (h, &u) in u.iter().enumerate() {
            // SAFETY: `d` holds VECS vectors of 4.
            unsafe { _mm256_storeu_pd(d.as_mut_ptr().add(4 * h), lanes.dist(u, Lanes::ww(u))) };
        }
        for ((o, &d), &k) in o.iter_mut().zip(&d).zip(k) {
            *o = f(d, k);
        }
    }
    for (((o, &s), &c), &k) in o_rest.iter_mut().zip(s_rest).zip(c_rest).zip(k_rest) {
        *o = f(cpa_entry(row, (s, c), &|d| d), k);
    }
}

impl CpaEngine {
    /// The [`Heading::cosines`](super::Heading::cosines) of [`CpaEngine::heading`] for
    /// each of `headings`, into `gams`, `cnhs` and `tans` (emptied first): a heading in
    /// [0, 360) is its integer degree's entry of the tables, read directly (deg_index of
    /// such a heading is its truncation), the others as `heading` finds them.
    pub fn cosines_into(
        &self,
        headings: impl ExactSizeIterator<Item = f64>,
        (gams, cnhs, tans): (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>),
    ) {
        let n = headings.len();
        for v in [&mut *gams, &mut *cnhs, &mut *tans] {
            v.clear();
            v.resize(n, 0.0);
        }
        let lists = gams.iter_mut().zip(cnhs.iter_mut()).zip(tans.iter_mut());
        let tables = self.tables.as_deref();
        for (((gam, cnh), tan), h) in lists.zip(headings) {
            (*gam, *cnh, *tan) = match tables {
                Some(t) if (0.0..360.0).contains(&h) => {
                    let i = (h as usize).min(359);
                    (t.gam[i], t.cnh[i], t.tan[i])
                }
                _ => self.heading(h).cosines(),
            };
        }
    }
}
