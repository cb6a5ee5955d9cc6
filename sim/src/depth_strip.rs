//! The depth-over-time strip drawn under the map when the helm's domain has `depth`:
//! depth down the strip (surface at the top), time across, each surfacing marked, so a
//! UUV's dive / surface cycle is visible at a glance.

use std::fmt::Write as _;

/// Samples kept at most; older ones are thinned two to one (first and latest kept).
const CAP: usize = 4_000;
/// Height of the strip (its axes and labels included).
pub const STRIP_H: f64 = 170.0;
/// A vehicle shallower than this is at the surface.
const SURFACE: f64 = 0.2;

/// Depth over time, and whether to draw it.
#[derive(Clone, Debug, Default)]
pub struct DepthTrace {
    /// Set when the helm's domain has a `depth` variable (its `IVPHELM_DOMAIN`).
    pub enabled: bool,
    /// (seconds from the start, depth).
    samples: Vec<(f64, f64)>,
    /// Times a dive came back to the surface.
    surfacings: Vec<f64>,
    submerged: bool,
}

impl DepthTrace {
    pub fn push(&mut self, t: f64, depth: f64) {
        if !depth.is_finite() {
            return;
        }
        if depth > SURFACE {
            self.submerged = true;
        } else if self.submerged {
            self.submerged = false;
            if self.surfacings.len() < CAP {
                self.surfacings.push(t);
            }
        }
        if self.samples.len() >= CAP {
            let last = self.samples.pop();
            let mut i = 0;
            self.samples.retain(|_| {
                i += 1;
                i % 2 == 1
            });
            self.samples.extend(last);
        }
        self.samples.push((t, depth));
    }

    pub fn samples(&self) -> &[(f64, f64)] {
        &self.samples
    }

    /// When each dive ended at the surface (seconds from the start).
    pub fn surfacings(&self) -> &[f64] {
        &self.surfacings
    }

    pub fn max_depth(&self) -> f64 {
        self.samples.iter().map(|s| s.1).fold(0.0, f64::max)
    }
}

/// Draw the strip with its top at `top`, `width` wide; returns the height used.
pub fn draw(o: &mut String, trace: &DepthTrace, top: f64, width: f64) -> f64 {
    let (left, right) = (60.0, width - 30.0);
    let (y0, y1) = (top + 25.0, top + STRIP_H - 30.0);
    let t_end = trace.samples.last().map_or(1.0, |s| s.0).max(1.0);
    let d_max = trace.max_depth().max(1.0);
    let px = |t: f64| left + (right - left) * t / t_end;
    let py = |d: f64| y0 + (y1 - y0) * d / d_max;
    let _ = writeln!(
        o,
        r##"<text x="{left}" y="{:.1}" font-size="13" fill="#222">Depth over time (max {:.1} m, {} surfacing{})</text>"##,
        top + 15.0,
        trace.max_depth(),
        trace.surfacings.len(),
        if trace.surfacings.len() == 1 { "" } else { "s" }
    );
    let _ = writeln!(
        o,
        r##"<rect x="{left}" y="{y0:.1}" width="{:.1}" height="{:.1}" fill="#f3f8fc" stroke="#bbb"/>"##,
        right - left,
        y1 - y0
    );
    for s in &trace.surfacings {
        let x = px(*s);
        let _ = writeln!(
            o,
            r##"<path d="M{x:.1},{y0:.1} V{y1:.1}" stroke="#1e9e46" stroke-width="1" stroke-dasharray="3,3"/>"##
        );
    }
    let mut pts = String::new();
    for (t, d) in &trace.samples {
        let _ = write!(pts, "{:.1},{:.1} ", px(*t), py(*d));
    }
    let _ = writeln!(
        o,
        r##"<polyline points="{}" fill="none" stroke="#1f6fd1" stroke-width="1.8"/>"##,
        pts.trim_end()
    );
    let _ = writeln!(
        o,
        r##"<text x="{:.1}" y="{:.1}" font-size="11" fill="#555" text-anchor="end">0 m</text><text x="{:.1}" y="{:.1}" font-size="11" fill="#555" text-anchor="end">{d_max:.0} m</text><text x="{right:.1}" y="{:.1}" font-size="11" fill="#555" text-anchor="end">{t_end:.0} s</text>"##,
        left - 5.0,
        y0 + 4.0,
        left - 5.0,
        y1 + 4.0,
        y1 + 16.0
    );
    STRIP_H
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surfacings_are_counted_and_drawn() {
        let mut t = DepthTrace::default();
        for i in 0..300 {
            // Two dives to 10 m, each back at the surface.
            let phase = i % 150;
            let d = if phase < 100 {
                (phase as f64 / 5.0).min(10.0)
            } else {
                0.0
            };
            t.push(i as f64, d);
        }
        assert_eq!(t.surfacings().len(), 2);
        assert_eq!(t.max_depth(), 10.0);
        let mut o = String::new();
        assert_eq!(draw(&mut o, &t, 700.0, 900.0), STRIP_H);
        assert_eq!(o.matches("stroke-dasharray=\"3,3\"").count(), 2);
        assert!(o.contains("2 surfacings"));
    }

    #[test]
    fn thinning_keeps_the_ends() {
        let mut t = DepthTrace::default();
        for i in 0..(3 * CAP) {
            t.push(i as f64, 1.0);
        }
        assert!(t.samples().len() <= CAP);
        assert_eq!(t.samples()[0].0, 0.0);
        assert_eq!(t.samples().last().map(|s| s.0), Some((3 * CAP - 1) as f64));
    }
}
