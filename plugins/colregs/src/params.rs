//! The COLREGS behaviors' own parameters (behaviors-contacts.md §5.1, §5.6, §5.8),
//! with what each version refuses.

use behavior_api::params::parse_bool;
use behavior_api::parse_number;

use crate::modes::{Mode, Submode};

/// Which of the three types this instance is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    V17,
    V19,
    V22,
}

impl Version {
    pub fn type_name(self) -> &'static str {
        match self {
            Version::V17 => "BHV_AvdColregsV17",
            Version::V19 => "BHV_AvdColregsV19",
            Version::V22 => "BHV_AvdColregsV22",
        }
    }
}

/// The relevance curve (`pwt_grade`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grade {
    Linear,
    Quadratic,
    Quasi,
}

/// `velocity_filter = min_spd=a,max_spd=b,pct=p` (§5.6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityFilter {
    pub min_spd: f64,
    pub max_spd: f64,
    pub pct: f64,
}

impl VelocityFilter {
    /// `None` unless the keys are known, the values numbers and the filter valid
    /// (a ≥ 0, b ≥ 0, a ≤ b, p ≤ 100; a missing `pct` stays −1 and is valid).
    pub fn parse(s: &str) -> Option<Self> {
        let (mut a, mut b, mut p) = (None, None, -1.0);
        for part in s.split(',').map(str::trim).filter(|x| !x.is_empty()) {
            let (k, v) = part.split_once('=')?;
            let v = parse_number(v.trim())?;
            match k.trim().to_ascii_lowercase().as_str() {
                "min_spd" => a = Some(v),
                "max_spd" => b = Some(v),
                "pct" => p = v,
                _ => return None,
            }
        }
        let (a, b) = (a?, b?);
        (a >= 0.0 && b >= 0.0 && a <= b && p <= 100.0).then_some(VelocityFilter {
            min_spd: a,
            max_spd: b,
            pct: p,
        })
    }

    /// The factor on the util distances for speeds `osv`, `cnv` (the reference's 100
    /// and `p` end cases are kept as they are: not divided by 100).
    pub fn factor(&self, osv: f64, cnv: f64) -> f64 {
        let e = osv.max(cnv);
        let (a, b, p) = (self.min_spd, self.max_spd, self.pct);
        if b - a <= 0.0 || e >= b {
            return 100.0;
        }
        if e <= a {
            return p;
        }
        ((p + (100.0 - p) * (e - a) / (b - a)) / 100.0).clamp(0.0, 1.0)
    }
}

/// The type's own parameters (the contact base holds the rest).
#[derive(Clone, Debug)]
pub struct Params {
    pub version: Version,
    pub pwt_outer_dist: f64,
    pub pwt_inner_dist: f64,
    pub min_util_cpa_dist: f64,
    pub max_util_cpa_dist: f64,
    pub completed_dist: f64,
    pub giveway_bow_dist: f64,
    pub turn_radius: f64,
    pub velocity_filter: Option<VelocityFilter>,
    pub headon_only: bool,
    pub pts_port_turns_ok: bool,
    pub post_status_info_on_idle: bool,
    pub grade: Grade,
    pub use_refinery: bool,
    pub check_plateaus: bool,
    pub contact_type_required: String,
    pub forced_mode: Option<Mode>,
    pub forced_submode: Option<Submode>,
}

impl Params {
    pub fn new(version: Version) -> Self {
        Params {
            version,
            pwt_outer_dist: 100.0,
            pwt_inner_dist: 90.0,
            min_util_cpa_dist: 10.0,
            max_util_cpa_dist: 75.0,
            completed_dist: 100.0,
            giveway_bow_dist: -1.0,
            turn_radius: 0.0,
            velocity_filter: None,
            headon_only: false,
            pts_port_turns_ok: true,
            post_status_info_on_idle: false,
            grade: Grade::Linear,
            use_refinery: false,
            check_plateaus: false,
            contact_type_required: String::new(),
            forced_mode: None,
            forced_submode: None,
        }
    }

    /// Whether this version knows `param` (the others are refused as bad parameters).
    fn knows(&self, param: &str) -> bool {
        let v22_only = matches!(
            param,
            "headon_only"
                | "eval_tol"
                | "velocity_filter"
                | "post_status_info_on_idle"
                | "pts_port_turns_ok"
        );
        let v19_up = matches!(
            param,
            "use_refinery" | "giveway_bow_dist" | "check_plateaus" | "pcheck_thresh"
        );
        match self.version {
            Version::V22 => true,
            Version::V19 => !v22_only,
            Version::V17 => !v22_only && !v19_up,
        }
    }

    /// A type parameter (lower-cased name): `None` when it is not one of this type's,
    /// else whether the value was accepted. `eval_tol` is returned through `tol`.
    pub fn set(&mut self, param: &str, value: &str, tol: &mut f64) -> Option<bool> {
        if !self.knows(param) {
            return None;
        }
        let v = value.trim();
        let num = parse_number(v);
        let non_neg = num.filter(|n| *n >= 0.0);
        let ok = match param {
            "pwt_outer_dist" => non_neg.map(|n| {
                self.pwt_outer_dist = n;
                self.pwt_inner_dist = self.pwt_inner_dist.min(n);
            }),
            "pwt_inner_dist" => non_neg.map(|n| {
                self.pwt_inner_dist = n;
                self.pwt_outer_dist = self.pwt_outer_dist.max(n);
            }),
            "min_util_cpa_dist" => non_neg.map(|n| {
                self.min_util_cpa_dist = n;
                self.max_util_cpa_dist = self.max_util_cpa_dist.max(n);
            }),
            "max_util_cpa_dist" => non_neg.map(|n| {
                self.max_util_cpa_dist = n;
                self.min_util_cpa_dist = self.min_util_cpa_dist.min(n);
            }),
            "completed_dist" => non_neg.map(|n| {
                self.completed_dist = n;
                self.pwt_outer_dist = self.pwt_outer_dist.min(n);
                self.pwt_inner_dist = self.pwt_inner_dist.min(n);
                self.completed_floor();
            }),
            "giveway_bow_dist" => non_neg.map(|n| {
                let hi = match self.version {
                    Version::V22 => 2.0 * self.max_util_cpa_dist,
                    _ => self.max_util_cpa_dist,
                };
                self.giveway_bow_dist = n.max(self.min_util_cpa_dist).min(hi);
                self.completed_floor();
            }),
            "turn_radius" => non_neg.map(|n| {
                self.turn_radius = n;
                self.completed_floor();
            }),
            "eval_tol" => num.filter(|n| *n >= 5.0 && *n <= 300.0).map(|n| *tol = n),
            "velocity_filter" => VelocityFilter::parse(v).map(|f| self.velocity_filter = Some(f)),
            "headon_only" => bool_into(&mut self.headon_only, v),
            "pts_port_turns_ok" => bool_into(&mut self.pts_port_turns_ok, v),
            "post_status_info_on_idle" => bool_into(&mut self.post_status_info_on_idle, v),
            // Accepted, since the distribution's V19/V22 missions all set it, but inert:
            // the spec leaves the refinery's plateau boxes unspecified (§5.5), so the
            // CPA mode's pieces are the plain tiling (the reference's differ near the
            // plateau edges when it is on).
            "use_refinery" => bool_into(&mut self.use_refinery, v),
            "check_plateaus" => bool_into(&mut self.check_plateaus, v),
            "check_validity" | "verbose" => parse_bool(v, false).map(|_| ()),
            "pcheck_thresh" => non_neg.map(|_| ()),
            "pwt_grade" => {
                let g = match v.to_ascii_lowercase().as_str() {
                    "linear" => Some(Grade::Linear),
                    "quadratic" => Some(Grade::Quadratic),
                    "quasi" => Some(Grade::Quasi),
                    _ => None,
                };
                g.map(|g| self.grade = g)
            }
            // Stored, with no effect (as in the reference).
            "contact_type_required" => {
                (!v.is_empty()).then(|| self.contact_type_required = v.to_ascii_lowercase())
            }
            "avoid_mode" => Mode::parse_forced(&v.to_ascii_lowercase()).map(|m| {
                self.forced_mode = Some(m);
                self.forced_submode = Some(Submode::None);
            }),
            "avoid_submode" => {
                let mode = self.forced_mode.unwrap_or(Mode::None);
                Submode::parse_for(mode, &v.to_ascii_lowercase())
                    .map(|s| self.forced_submode = Some(s))
            }
            _ => return None,
        };
        Some(ok.is_some())
    }

    /// After `completed_dist`, `giveway_bow_dist` or `turn_radius`: the completion
    /// distance is never below the outer ring (a later `pwt_outer_dist` is not checked).
    fn completed_floor(&mut self) {
        if self.completed_dist < self.pwt_outer_dist {
            self.completed_dist = self.pwt_outer_dist;
        }
    }

    /// Relevance by range (§5.4.0), clamped to [0, 1].
    pub fn relevance(&self, range: f64) -> f64 {
        let (outer, inner) = (self.pwt_outer_dist, self.pwt_inner_dist);
        if range >= outer {
            return 0.0;
        }
        if range <= inner {
            return 1.0;
        }
        let d = ((outer - range) / (outer - inner)).clamp(0.0, 1.0);
        let g = match self.grade {
            Grade::Linear => d,
            Grade::Quadratic => d * d,
            Grade::Quasi => d.powf(1.5),
        };
        g.clamp(0.0, 1.0)
    }
}

fn bool_into(field: &mut bool, v: &str) -> Option<()> {
    parse_bool(v, *field).map(|b| *field = b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(p: &mut Params, k: &str, v: &str) -> Option<bool> {
        let mut tol = 0.0;
        p.set(k, v, &mut tol)
    }

    #[test]
    fn pairs_and_completed_dist() {
        let mut p = Params::new(Version::V22);
        assert_eq!(set(&mut p, "pwt_outer_dist", "50"), Some(true));
        assert_eq!((p.pwt_outer_dist, p.pwt_inner_dist), (50.0, 50.0));
        assert_eq!(set(&mut p, "pwt_inner_dist", "120"), Some(true));
        assert_eq!((p.pwt_outer_dist, p.pwt_inner_dist), (120.0, 120.0));
        // Completed below outer: outer and inner come down to it, then the floor rule
        // leaves completed at the (lowered) outer.
        assert_eq!(set(&mut p, "completed_dist", "80"), Some(true));
        assert_eq!((p.pwt_outer_dist, p.completed_dist), (80.0, 80.0));
        assert_eq!(set(&mut p, "min_util_cpa_dist", "-1"), Some(false));
        assert_eq!(set(&mut p, "pwt_grade", "QUASI"), Some(true));
        assert_eq!(set(&mut p, "pwt_grade", "cubic"), Some(false));
    }

    #[test]
    fn giveway_bow_dist_is_clipped_per_version() {
        let mut p = Params::new(Version::V22);
        assert_eq!(set(&mut p, "giveway_bow_dist", "500"), Some(true));
        assert_eq!(p.giveway_bow_dist, 150.0); // 2 × 75
        let mut p = Params::new(Version::V19);
        assert_eq!(set(&mut p, "giveway_bow_dist", "500"), Some(true));
        assert_eq!(p.giveway_bow_dist, 75.0);
        assert_eq!(set(&mut p, "giveway_bow_dist", "1"), Some(true));
        assert_eq!(p.giveway_bow_dist, 10.0);
        let mut p = Params::new(Version::V17);
        assert_eq!(set(&mut p, "giveway_bow_dist", "10"), None);
        assert_eq!(set(&mut p, "use_refinery", "true"), None);
    }

    #[test]
    fn version_only_parameters() {
        for k in [
            "headon_only",
            "pts_port_turns_ok",
            "post_status_info_on_idle",
        ] {
            assert_eq!(set(&mut Params::new(Version::V22), k, "true"), Some(true));
            assert_eq!(set(&mut Params::new(Version::V19), k, "true"), None);
        }
        let mut p = Params::new(Version::V22);
        let mut tol = 0.0;
        assert_eq!(p.set("eval_tol", "4", &mut tol), Some(false));
        assert_eq!(p.set("eval_tol", "301", &mut tol), Some(false));
        assert_eq!(p.set("eval_tol", "60", &mut tol), Some(true));
        assert_eq!(tol, 60.0);
    }

    #[test]
    fn forced_modes() {
        let mut p = Params::new(Version::V22);
        assert_eq!(set(&mut p, "avoid_mode", "giveway"), Some(true));
        assert_eq!(set(&mut p, "avoid_submode", "port"), Some(false));
        assert_eq!(set(&mut p, "avoid_submode", "bow"), Some(true));
        assert_eq!(set(&mut p, "avoid_mode", "sideways"), Some(false));
    }

    #[test]
    fn velocity_filter_by_hand() {
        assert!(VelocityFilter::parse("min_spd=2,max_spd=1,pct=10").is_none());
        assert!(VelocityFilter::parse("min_spd=1,max_spd=3,pct=101").is_none());
        assert!(VelocityFilter::parse("min_spd=1,max_spd=3,foo=1").is_none());
        let f = VelocityFilter::parse("MIN_SPD=1, max_spd=3, pct=20").unwrap();
        assert_eq!(f.factor(0.5, 0.2), 20.0); // below min: p as is
        assert_eq!(f.factor(3.0, 0.0), 100.0); // at max: 100 (sic)
                                               // Half way: (20 + 80·0.5) / 100.
        assert!((f.factor(1.0, 2.0) - 0.6).abs() < 1e-12);
        assert_eq!(
            VelocityFilter::parse("min_spd=1,max_spd=3").unwrap().pct,
            -1.0
        );
    }

    #[test]
    fn relevance_by_hand() {
        let mut p = Params::new(Version::V22);
        let mut tol = 0.0;
        p.set("pwt_outer_dist", "80", &mut tol);
        p.set("pwt_inner_dist", "50", &mut tol);
        assert_eq!(p.relevance(80.0), 0.0);
        assert_eq!(p.relevance(50.0), 1.0);
        assert_eq!(p.relevance(10.0), 1.0); // clamped, unlike AvoidCollision
        assert_eq!(p.relevance(65.0), 0.5);
        // The spec's observed value: range 79.385 → 0.615/30.
        assert!((p.relevance(79.385) - 0.0205).abs() < 1e-4);
        p.grade = Grade::Quadratic;
        assert_eq!(p.relevance(65.0), 0.25);
    }
}
