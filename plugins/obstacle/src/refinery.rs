//! The refinery of `use_refinery = true` (obstacles.md §1.9): courses that certainly clear
//! the rim polygon become a plateau (utility 100), courses into the obstacle and the
//! side-locked-out courses a basin (utility 0), handed to the reflector as regions.

use std::collections::VecDeque;

use behavior_api::geometry::{angle360, Polygon};
use behavior_api::ivp::reflector::{box_subtract, intersects, IndexBox};
use behavior_api::ivp::{Domain, Snap};

use crate::model::{seglr_cpa, Pose, Side};

/// Disjoint plateau and basin boxes (index space, every speed), in the order they go to
/// the reflector.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Regions {
    pub plateaus: Vec<IndexBox>,
    pub basins: Vec<IndexBox>,
}

/// Index boxes for headings `hmin..hmax` (wrapping through 0 when `hmin > hmax`) and
/// every speed (`buildBoxesSpdAll`).
fn boxes_spd_all(domain: &Domain, crs: usize, spd: usize, hmin: f64, hmax: f64) -> Vec<IndexBox> {
    let mut lo = domain.snap(crs, hmin, Snap::Ceil);
    let mut hi = domain.snap(crs, hmax, Snap::Floor);
    let last = domain.var(crs).points.saturating_sub(1);
    let spd_all = (0, domain.var(spd).points.saturating_sub(1));
    let mk = |a: u32, b: u32| {
        let mut bx = vec![(0, 0); domain.size()];
        bx[crs] = (a, b);
        bx[spd] = spd_all;
        bx
    };
    let mid = || domain.snap(crs, (hmin + hmax) / 2.0, Snap::Nearest);
    if hmin <= hmax {
        if lo > hi {
            lo = mid();
            hi = lo;
        }
        vec![mk(lo, hi)]
    } else {
        if hi > lo {
            lo = mid();
            hi = lo;
        }
        vec![mk(0, hi), mk(lo, last)]
    }
}

/// Plateau headings from the rim CPAs (§1.9 step 2).
fn plateau_range(rim: &[f64; 360]) -> Option<(f64, f64)> {
    let hit = |i: usize| rim[i] <= 0.0;
    if (0..360).all(hit) || !(0..360).any(hit) {
        return None;
    }
    if rim[0] > 0.0 && rim[359] > 0.0 {
        let bmin = (1..=358).rev().find(|&i| hit(i))? + 1;
        let bmax = (1..=358).find(|&i| hit(i))? - 1;
        Some((bmin as f64, bmax as f64))
    } else {
        let bmin = (0..=358).find(|&i| !hit(i))?;
        let bmax = ((bmin + 1)..=358).find(|&i| hit(i)).map_or(0, |i| i - 1);
        Some((bmin as f64, bmax as f64))
    }
}

/// Basin headings from the gut CPAs (§1.9 step 3): one clear heading at each end.
fn basin_range(gut: &[f64; 360]) -> Option<(f64, f64)> {
    let hit = |i: usize| gut[i] <= 0.0;
    if (0..360).all(hit) || !(0..360).any(hit) {
        return None;
    }
    if hit(0) && hit(359) {
        let bmin = (1..=358).rev().find(|&i| !hit(i))?;
        let bmax = (1..=358).find(|&i| !hit(i))?;
        Some((bmin as f64, bmax as f64))
    } else {
        let h = (0..=358).find(|&i| hit(i))?;
        let bmin = if h == 0 { 359 } else { h - 1 };
        let bmax = ((h + 1)..=358).find(|&i| !hit(i))?;
        Some((bmin as f64, bmax as f64))
    }
}

/// Regions for ownship `os` against the gut and rim polygons, with the side lock.
pub fn regions(
    gut: &Polygon,
    rim: &Polygon,
    os: Pose,
    lock: Option<Side>,
    domain: &Domain,
) -> Regions {
    let (Some(crs), Some(spd)) = (domain.index_of("course"), domain.index_of("speed")) else {
        return Regions::default();
    };
    let mut cpa_rim = [0.0; 360];
    let mut cpa_gut = [0.0; 360];
    for a in 0..360 {
        cpa_rim[a] = seglr_cpa(rim, os, a as f64);
        cpa_gut[a] = seglr_cpa(gut, os, a as f64);
    }
    let mut boxes: Vec<(IndexBox, f64)> = Vec::new();
    if let Some((lo, hi)) = plateau_range(&cpa_rim) {
        boxes.extend(
            boxes_spd_all(domain, crs, spd, lo, hi)
                .into_iter()
                .map(|b| (b, 4.0)),
        );
    }
    // The reference gates the basin on the rim's clear headings, not the gut's.
    let rim_clear = cpa_rim.iter().any(|c| *c > 0.0);
    if let Some((lo, hi)) = basin_range(&cpa_gut).filter(|_| rim_clear) {
        boxes.extend(
            boxes_spd_all(domain, crs, spd, lo, hi)
                .into_iter()
                .map(|b| (b, -2.0)),
        );
    }
    let locked = match lock {
        Some(Side::Star) => Some((165.0, 350.0)),
        Some(Side::Port) => Some((10.0, 195.0)),
        _ => None,
    };
    if let Some((a, b)) = locked {
        let (lo, hi) = (angle360(os.heading + a), angle360(os.heading + b));
        boxes.extend(
            boxes_spd_all(domain, crs, spd, lo, hi)
                .into_iter()
                .map(|b| (b, -3.0)),
        );
    }
    make_disjoint(boxes)
}

fn volume(b: &IndexBox) -> u64 {
    b.iter().map(|&(lo, hi)| u64::from(hi - lo + 1)).product()
}

/// Larger |value| first (equal: larger box first); a box that meets an earlier one
/// keeps only its parts outside it (§1.9 step 6).
fn make_disjoint(mut boxes: Vec<(IndexBox, f64)>) -> Regions {
    boxes.sort_by(|a, b| {
        b.1.abs()
            .total_cmp(&a.1.abs())
            .then_with(|| volume(&b.0).cmp(&volume(&a.0)))
    });
    let mut queue: VecDeque<(IndexBox, f64)> = boxes.into();
    let mut majors: Vec<(IndexBox, f64)> = Vec::new();
    while let Some((bx, v)) = queue.pop_front() {
        let hit = majors.iter().find(|(m, _)| intersects(&bx, m));
        match hit {
            Some((m, _)) => {
                for piece in box_subtract(&bx, m).into_iter().rev() {
                    queue.push_front((piece, v));
                }
            }
            None => majors.push((bx, v)),
        }
    }
    let mut out = Regions::default();
    for (b, v) in majors {
        if v >= 0.0 {
            out.plateaus.push(b);
        } else {
            out.basins.push(b);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn domain() -> Domain {
        let mut d = Domain::new();
        d.add_var("course", 0.0, 359.0, 360).unwrap();
        d.add_var("speed", 0.0, 4.0, 21).unwrap();
        d
    }

    #[test]
    fn boxes_wrap_through_north() {
        let d = domain();
        // 350..10 wraps: [0,10] and [350,359], every speed index 0..20.
        assert_eq!(
            boxes_spd_all(&d, 0, 1, 350.0, 10.0),
            vec![vec![(0, 10), (0, 20)], vec![(350, 359), (0, 20)]]
        );
        // 10.5..11.5 rounds inward to 11..11.
        assert_eq!(
            boxes_spd_all(&d, 0, 1, 10.5, 11.5),
            vec![vec![(11, 11), (0, 20)]]
        );
    }

    #[test]
    fn ranges_from_hits() {
        // Headings 80..=100 run into the rim: no wrap (0 and 359 clear) → the plateau is
        // 101..=79 through north: bmin = 100 + 1, bmax = 80 − 1.
        let mut rim = [5.0; 360];
        for c in rim.iter_mut().take(101).skip(80) {
            *c = 0.0;
        }
        assert_eq!(plateau_range(&rim), Some((101.0, 79.0)));
        // The same hits in the gut: the basin takes one clear heading each side, 79..101.
        assert_eq!(basin_range(&rim), Some((79.0, 101.0)));
        assert_eq!(plateau_range(&[5.0; 360]), None);
    }

    #[test]
    fn obstacle_ahead_gives_plateau_and_basin_disjoint() {
        // os (40,0) heading 90, the rectangle x 60..80, y −12..6 ahead; rim grown by 7.
        let gut = Polygon::from_xy(&[(60.0, -12.0), (60.0, 6.0), (80.0, 6.0), (80.0, -12.0)]);
        let rim = behavior_api::geometry::obstacle::buffer_polygon(&gut, 7.0, 30.0);
        let os = Pose {
            x: 40.0,
            y: 0.0,
            heading: 90.0,
        };
        let r = regions(&gut, &rim, os, Some(Side::Star), &domain());
        assert!(!r.plateaus.is_empty() && !r.basins.is_empty());
        // Course 90 (straight in) is in a basin, course 0 (north, clear) in a plateau.
        let inside = |b: &IndexBox, c: u32| b[0].0 <= c && c <= b[0].1;
        assert!(r.basins.iter().any(|b| inside(b, 90)));
        assert!(r.plateaus.iter().any(|b| inside(b, 0)));
        // Disjoint: no course index in two regions.
        for c in 0..360 {
            let n = r
                .plateaus
                .iter()
                .chain(&r.basins)
                .filter(|b| inside(b, c))
                .count();
            assert!(n <= 1, "course {c} in {n} regions");
        }
    }
}
