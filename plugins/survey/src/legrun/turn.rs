//! The turn generator LegRun uses at each end of its leg (behaviors-more.md §9.4): a
//! Williamson-like U-turn from a start point and heading back to an end point, as a
//! list of points `gap` degrees apart on up to three arcs.

use behavior_api::geometry::{angle180, angle360, project_point, rel_ang};

use super::engine::Pt;
use crate::zigzag::dist_to_line;

/// Inputs of one turn.
#[derive(Clone, Copy, Debug)]
pub struct Turn {
    pub start: Pt,
    pub heading: f64,
    pub end: Pt,
    pub radius: f64,
    pub gap: f64,
    /// Percent, −100..100.
    pub bias: f64,
    pub port: bool,
}

fn proj(deg: f64, d: f64, p: Pt) -> Pt {
    project_point(deg, d, p.0, p.1)
}

/// `for (δ = 0; δ ≤ lim; δ += g)` with the reference's floating accumulation.
fn sweep(lim: f64, g: f64, mut f: impl FnMut(f64)) {
    let mut d = 0.0;
    // A bound on the count keeps a degenerate step from looping for ever.
    let mut n = 0;
    while d <= lim && n < 100_000 {
        f(d);
        d += g;
        n += 1;
    }
}

impl Turn {
    /// The generated points.
    pub fn generate(&self) -> Vec<Pt> {
        let r = if self.radius > 0.0 { self.radius } else { 10.0 };
        let h = angle360(self.heading);
        let (s, e) = (self.start, self.end);
        // The bias limit uses the configured lane gap 0.1, not the measured one.
        let max_b = r - 0.05;
        let b = ((self.bias.clamp(-100.0, 100.0) / 100.0) * max_b).clamp(-max_b, max_b);
        let ad = angle180(rel_ang(s.0, s.1, e.0, e.1) - h);
        let ahead = proj(h, 20.0, s);
        let d = dist_to_line(e.0, e.1, s.0, s.1, ahead.0, ahead.1);
        let port = if d > 1.0 { ad < 0.0 } else { self.port };
        let q = proj(angle360(h + 90.0), 20.0, s);
        let mut n = dist_to_line(e.0, e.1, s.0, s.1, q.0, q.1);
        if !(-90.0 < ad && ad < 90.0) {
            n = -n;
        }
        let pa = angle360(h - 90.0);
        let sa = angle360(h + 90.0);
        let mut out = Vec::new();
        if 2.0 * r > d {
            self.variant_a(&mut out, r, d, b, n, port, (h, pa, sa));
        } else {
            self.variant_b(&mut out, r, d, n, port, (h, pa, sa));
        }
        if n < 0.0 {
            out.push(e);
        }
        out
    }

    #[allow(clippy::too_many_arguments)]
    fn variant_a(
        &self,
        out: &mut Vec<Pt>,
        r: f64,
        d: f64,
        b: f64,
        n: f64,
        port: bool,
        a: (f64, f64, f64),
    ) {
        let (h, pa, sa) = a;
        let s = self.start;
        let g = self.gap;
        let theta = ((r + d / 2.0) / (2.0 * r)).acos();
        let theta_d = theta * 180.0 / std::f64::consts::PI;
        let mut w = 2.0 * (90.0 - theta_d);
        let b0 = 2.0 * r * theta.sin();
        let mut be = b0;
        let k1 = r + d / 2.0 - b;
        let k2 = r + d / 2.0 + b;
        if b != 0.0 {
            for k in [k1, k2] {
                let m = (4.0 * r * r - k * k).sqrt();
                if be < m {
                    be = m + 1.0;
                }
            }
        }
        let (mut c0, mut c1, mut c2) = if port {
            (proj(pa, d / 2.0 - b, s), proj(sa, r, s), proj(pa, r + d, s))
        } else {
            (proj(sa, d / 2.0 - b, s), proj(sa, r + d, s), proj(pa, r, s))
        };
        let mut c3 = proj(h, be, c0);
        if n > 0.0 {
            c0 = proj(h, n, c0);
            c1 = proj(h, n, c1);
            c2 = proj(h, n, c2);
            c3 = proj(h, n, c3);
            out.push(s);
        }
        let _ = c0;
        let mut th1 = theta_d;
        let mut th2 = (180.0 - w) / 2.0;
        if be > b0 {
            let deg = |x: f64| x * 180.0 / std::f64::consts::PI;
            let h1 = (be * be + k1 * k1).sqrt() / 2.0;
            let h2 = (be * be + k2 * k2).sqrt() / 2.0;
            th1 = deg((be / k1).atan()) - deg((r / h1).acos());
            th2 = deg((be / k2).atan()) - deg((r / h2).acos());
            w = 180.0 - (th1 + th2);
        }
        if port {
            sweep(th1, g, |dl| out.push(proj(angle360(pa + dl), r, c1)));
            let a0 = angle360(h + 90.0 + th1);
            sweep(360.0 - w, g, |dl| out.push(proj(angle360(a0 - dl), r, c3)));
            let a0 = angle360(sa - th2);
            sweep(th2, g, |dl| out.push(proj(angle360(a0 + dl), r, c2)));
        } else {
            sweep(th1, g, |dl| out.push(proj(angle360(sa - dl), r, c2)));
            let a0 = angle360(h - 90.0 - th1);
            sweep(360.0 - w, g, |dl| out.push(proj(angle360(a0 + dl), r, c3)));
            let a0 = angle360(pa + th2);
            sweep(th2, g, |dl| out.push(proj(angle360(a0 - dl), r, c1)));
        }
    }

    fn variant_b(&self, out: &mut Vec<Pt>, r: f64, d: f64, n: f64, port: bool, a: (f64, f64, f64)) {
        let (h, pa, sa) = a;
        let s = self.start;
        let k = d / 2.0 - r;
        let c0 = proj(if port { pa } else { sa }, d / 2.0, s);
        let mut c1 = proj(sa, k, c0);
        let mut c2 = proj(pa, k, c0);
        if n > 0.0 {
            c1 = proj(h, n, c1);
            c2 = proj(h, n, c2);
            out.push(s);
        }
        let g = self.gap;
        if port {
            sweep(90.0, g, |dl| out.push(proj(angle360(h + 90.0 - dl), r, c1)));
            sweep(90.0, g, |dl| out.push(proj(angle360(h - dl), r, c2)));
        } else {
            sweep(90.0, g, |dl| out.push(proj(angle360(h - 90.0 + dl), r, c2)));
            sweep(90.0, g, |dl| out.push(proj(angle360(h + dl), r, c1)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference's preview path for turn 1 of P1 = 70,−35, P2 = −35,−85, radius 20,
    /// bias 100, gap 20, port (behaviors-more.md §9.4).
    #[test]
    fn worked_example_turn_one() {
        let (p1, p2) = ((70.0, -35.0), (-35.0, -85.0));
        let th = rel_ang(p1.0, p1.1, p2.0, p2.1);
        let t = Turn {
            start: p1,
            heading: angle360(th + 180.0),
            end: p1,
            radius: 20.0,
            gap: 20.0,
            bias: 100.0,
            port: true,
        };
        let pts = t.generate();
        let r1 = |p: Pt| ((p.0 * 10.0).round() / 10.0, (p.1 * 10.0).round() / 10.0);
        assert_eq!(r1(pts[0]), (70.0, -35.0));
        assert_eq!(r1(pts[1]), (76.7, -33.1));
        assert_eq!(r1(pts[2]), (83.6, -33.7));
        assert_eq!(r1(pts[pts.len() - 2]), (112.7, -15.6));
        // The loop closes on P1. (The reference's path also ends with P1 itself, from a
        // tiny negative N we do not reproduce: our N here is +0, so no trailing vertex.)
        let last = *pts.last().unwrap();
        assert!((last.0 - p1.0).hypot(last.1 - p1.1) < 0.1);
    }
}
