//! The contact-state quantities a contact behavior computes at each refresh
//! (behaviors-contacts.md §1.2), from ownship's and the contact's poses, with two
//! engines: E (the contact as contact, ownship as ownship) and R (roles swapped).

use crate::engine::CpaEngine;

/// A pose: position (m), heading (deg, compass), speed (m/s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub hdg: f64,
    pub spd: f64,
}

/// Horizon of `os_curr_cpa_dist` (s).
pub const CURR_CPA_HORIZON: f64 = 120.0;

/// Everything §1.2 lists, for one ownship/contact pair at one moment.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactRelation {
    pub range: f64,
    pub os_fore_of_cn: bool,
    pub os_aft_of_cn: bool,
    pub os_port_of_cn: bool,
    pub os_star_of_cn: bool,
    pub cn_fore_of_os: bool,
    pub cn_aft_of_os: bool,
    pub cn_port_of_os: bool,
    pub cn_star_of_os: bool,
    /// Bearing of the contact relative to ownship's bow, [0, 360).
    pub os_cn_rel_bng: f64,
    /// Bearing of ownship relative to the contact's bow, [0, 360).
    pub cn_os_rel_bng: f64,
    /// Compass bearing ownship → contact.
    pub os_cn_abs_bng: f64,
    /// Contact speed toward ownship's position (> 0 closing).
    pub cn_spd_in_os_pos: f64,
    pub rate_of_closure: f64,
    pub bearing_rate: f64,
    pub contact_rate: f64,
    pub range_gamma: f64,
    pub range_epsilon: f64,
    pub os_passes_cn: bool,
    pub os_passes_cn_port: bool,
    pub os_passes_cn_star: bool,
    pub cn_passes_os: bool,
    pub cn_passes_os_port: bool,
    pub cn_passes_os_star: bool,
    pub os_crosses_cn: bool,
    pub os_crosses_cn_stern: bool,
    pub os_crosses_cn_bow: bool,
    pub os_crosses_cn_bow_dist: f64,
    pub cn_crosses_os: bool,
    pub cn_crosses_os_stern: bool,
    pub cn_crosses_os_bow: bool,
    pub cn_crosses_os_bow_dist: f64,
    pub os_curr_cpa_dist: f64,
}

impl ContactRelation {
    /// ```
    /// use contacts::relation::{ContactRelation, Pose};
    /// let os = Pose { x: 0.0, y: 0.0, hdg: 0.0, spd: 2.0 };
    /// let cn = Pose { x: 0.0, y: 100.0, hdg: 180.0, spd: 3.0 };
    /// let r = ContactRelation::new(os, cn);
    /// assert_eq!((r.range, r.rate_of_closure), (100.0, 5.0));
    /// assert!(r.os_curr_cpa_dist < 1e-9);
    /// ```
    pub fn new(os: Pose, cn: Pose) -> Self {
        let e = CpaEngine::new(cn.x, cn.y, cn.hdg, cn.spd, os.x, os.y);
        let r = CpaEngine::new(os.x, os.y, os.hdg, os.spd, cn.x, cn.y);
        let (osh, osv) = (os.hdg, os.spd);
        let (cnh, cnv) = (cn.hdg, cn.spd.max(0.0));
        // Each engine's per-degree cosines at its vessel's heading, looked up once for
        // the queries that have an `*_at` form (the same numbers, bit for bit, as the
        // plain queries, each of which would compute them again).
        let (eh, rh) = (e.heading(osh), r.heading(cnh));
        ContactRelation {
            range: e.rng,
            os_fore_of_cn: e.os_fore_of_cn(),
            os_aft_of_cn: e.os_aft_of_cn(),
            os_port_of_cn: e.os_port_of_cn(),
            os_star_of_cn: e.os_star_of_cn(),
            cn_fore_of_os: r.os_fore_of_cn(),
            cn_aft_of_os: r.os_aft_of_cn(),
            cn_port_of_os: r.os_port_of_cn(),
            cn_star_of_os: r.os_star_of_cn(),
            os_cn_rel_bng: r.beta,
            cn_os_rel_bng: e.beta,
            os_cn_abs_bng: e.abs_os_cn,
            cn_spd_in_os_pos: e.cn_to_os,
            rate_of_closure: e.roc(osh, osv),
            bearing_rate: e.bearing_rate_at(&eh, osv),
            contact_rate: r.bearing_rate_at(&rh, cnv),
            range_gamma: e.range_gamma,
            range_epsilon: e.range_epsilon,
            os_passes_cn: e.passes_port_or_star_at(&eh, osv),
            os_passes_cn_port: e.passes_port_at(&eh, osv),
            os_passes_cn_star: e.passes_star_at(&eh, osv),
            cn_passes_os: r.passes_port_or_star_at(&rh, cnv),
            cn_passes_os_port: r.passes_port_at(&rh, cnv),
            cn_passes_os_star: r.passes_star_at(&rh, cnv),
            os_crosses_cn: e.crosses_bow_or_stern(osh, osv),
            os_crosses_cn_stern: e.crosses_stern_at(&eh, osv),
            os_crosses_cn_bow: e.crosses_bow_at(&eh, osv),
            os_crosses_cn_bow_dist: e.crosses_bow_dist(osh, osv),
            cn_crosses_os: r.crosses_bow_or_stern(cnh, cnv),
            cn_crosses_os_stern: r.crosses_stern_at(&rh, cnv),
            cn_crosses_os_bow: r.crosses_bow_at(&rh, cnv),
            cn_crosses_os_bow_dist: r.crosses_bow_dist(cnh, cnv),
            os_curr_cpa_dist: e.cpa_at(&eh, osv, CURR_CPA_HORIZON).dist,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_on() {
        // Ownship north at 2 from the origin; contact 100 m north heading south at 3.
        let os = Pose {
            x: 0.0,
            y: 0.0,
            hdg: 0.0,
            spd: 2.0,
        };
        let cn = Pose {
            x: 0.0,
            y: 100.0,
            hdg: 180.0,
            spd: 3.0,
        };
        let r = ContactRelation::new(os, cn);
        // Each dead ahead of the other: fore, and on the starboard side by the
        // convention that a relative bearing of 0 is starboard only.
        assert!(r.os_fore_of_cn && !r.os_aft_of_cn && r.os_star_of_cn && !r.os_port_of_cn);
        assert!(r.cn_fore_of_os && r.cn_star_of_os && !r.cn_port_of_os);
        assert_eq!(
            (r.os_cn_rel_bng, r.cn_os_rel_bng, r.os_cn_abs_bng),
            (0.0, 0.0, 0.0)
        );
        // Contact closes at its full 3 m/s; together 5 m/s; they meet at t = 20 s.
        assert_eq!(r.cn_spd_in_os_pos, 3.0);
        assert_eq!(r.rate_of_closure, 5.0);
        assert!(r.os_curr_cpa_dist < 1e-9); // sin(180°) is 1.2e-16, not 0
                                            // Bearing constant; ownship is on the contact's bow line, so it "crosses".
        assert_eq!(r.bearing_rate, 0.0);
        assert!(r.os_crosses_cn && r.cn_crosses_os);
    }

    #[test]
    fn contact_crossing_from_starboard() {
        // Ownship north at 2; contact 100 m east, 100 m north, heading west at 2: a
        // collision course (both reach (0,100) at t = 50 s).
        let os = Pose {
            x: 0.0,
            y: 0.0,
            hdg: 0.0,
            spd: 2.0,
        };
        let cn = Pose {
            x: 100.0,
            y: 100.0,
            hdg: 270.0,
            spd: 2.0,
        };
        let r = ContactRelation::new(os, cn);
        assert!((r.range - 100.0 * 2f64.sqrt()).abs() < 1e-9);
        assert!((r.os_cn_rel_bng - 45.0).abs() < 1e-9); // on ownship's starboard bow
        assert!(r.cn_star_of_os && r.cn_fore_of_os);
        // Ownship is on the contact's port bow: β = 225 − 270 → 315.
        assert!((r.cn_os_rel_bng - 315.0).abs() < 1e-9);
        assert!(r.os_port_of_cn && r.os_fore_of_cn);
        // Closing at 2·cos45 from each side = 2.828 m/s; CPA ~0 (within rounding).
        assert!((r.rate_of_closure - 2.0 * 2f64.sqrt()).abs() < 1e-9);
        assert!(r.os_curr_cpa_dist < 1e-6);
        // Constant bearing, decreasing range.
        assert!(r.bearing_rate.abs() < 1e-9);
    }
}
