//! Contact geometry: range, relative bearing, closest point of approach, and the
//! per-candidate engine the contact behaviors evaluate over their (course, speed) grid
//! (behaviors-contacts.md §1.3, contacts-appcast.md §3.5).
//!
//! Compass convention: 0 = +y (north), clockwise, degrees; velocity of heading h at
//! speed v is v·(sin h, cos h).

use geometry::rel_ang;
use mbutil::spare;

/// `geometry::angle360`, except that a huge finite angle (which its subtract-360 loop
/// would take forever on, e.g. a hostile `HDG=1000…0`) is wrapped by remainder.
pub fn angle360(a: f64) -> f64 {
    if a.abs() < 1e6 {
        geometry::angle360(a)
    } else if a.is_finite() {
        a.rem_euclid(360.0)
    } else {
        a
    }
}

/// `angle360`, then minus 360 above 180: (−180, 180].
pub fn angle180(a: f64) -> f64 {
    let a = angle360(a);
    if a > 180.0 {
        a - 360.0
    } else {
        a
    }
}

/// The 12-digit π the reference uses for the bearing-rate constant.
#[allow(clippy::approx_constant)] // deliberately not f64's π
const PI_12: f64 = 3.14159265359;

/// Distance between ownship and contact.
pub fn range(osx: f64, osy: f64, cnx: f64, cny: f64) -> f64 {
    (osx - cnx).hypot(osy - cny)
}

/// Bearing of the target relative to the bow of a vessel at (x, y) heading `h`, in
/// [0, 360): 0 dead ahead, 90 starboard beam.
///
/// ```
/// // A target due east of a vessel heading north is on its starboard beam.
/// assert_eq!(contacts::rel_bearing(0.0, 0.0, 0.0, 10.0, 0.0), 90.0);
/// ```
pub fn rel_bearing(x: f64, y: f64, h: f64, tx: f64, ty: f64) -> f64 {
    angle360(rel_ang(x, y, tx, ty) - h)
}

/// A closest point of approach: the distance and when (seconds from now, within the
/// horizon; 0 when the range is not closing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cpa {
    pub dist: f64,
    pub time: f64,
}

fn unit(h_deg: f64) -> (f64, f64) {
    let (s, c) = h_deg.to_radians().sin_cos();
    (s, c)
}

/// The CPA of two straight-line motions: `p` = ownship − contact, `w` = relative
/// velocity, `tol` = horizon. Not closing (or no relative motion) → current range at 0 s.
fn cpa_of(px: f64, py: f64, wx: f64, wy: f64, tol: f64) -> Cpa {
    cpa_of_ranged(px, py, wx, wy, tol, || px.hypot(py))
}

/// [`cpa_of`] with the current range `px.hypot(py)` supplied by `range_now` (the
/// engine has it already: hypot is costly, and an objective function asks this for
/// every candidate heading and speed).
#[inline]
fn cpa_of_ranged(
    px: f64,
    py: f64,
    wx: f64,
    wy: f64,
    tol: f64,
    range_now: impl FnOnce() -> f64,
) -> Cpa {
    let now = || Cpa {
        dist: range_now(),
        time: 0.0,
    };
    let ww = wx * wx + wy * wy;
    if ww == 0.0 {
        return now();
    }
    let t = -(px * wx + py * wy) / ww;
    if t.is_nan() || t <= 0.0 {
        return now();
    }
    let t = if t > tol { tol } else { t };
    let (dx, dy) = (px + wx * t, py + wy * t);
    let d2 = dx * dx + dy * dy;
    Cpa {
        dist: if d2 > 0.0 { d2.sqrt() } else { 0.0 },
        time: t,
    }
}

/// The closest approach within `tol` seconds if ownship holds heading `osh` / speed
/// `osv` and the contact holds `cnh` / `cnv` (negative speeds count as 0).
///
/// ```
/// // Head-on: ownship at the origin north at 2 m/s, contact 100 m north heading south
/// // at 3 m/s: they meet (CPA 0) after 100 / 5 = 20 s.
/// let c = contacts::cpa(0.0, 0.0, 0.0, 2.0, 0.0, 100.0, 180.0, 3.0, 120.0);
/// assert!(c.dist < 1e-9 && (c.time - 20.0).abs() < 1e-9);
/// ```
#[allow(clippy::too_many_arguments)]
pub fn cpa(
    osx: f64,
    osy: f64,
    osh: f64,
    osv: f64,
    cnx: f64,
    cny: f64,
    cnh: f64,
    cnv: f64,
    tol: f64,
) -> Cpa {
    let (os_s, os_c) = unit(osh);
    let (cn_s, cn_c) = unit(angle360(cnh));
    let (osv, cnv) = (osv.max(0.0), cnv.max(0.0));
    cpa_of(
        osx - cnx,
        osy - cny,
        osv * os_s - cnv * cn_s,
        osv * os_c - cnv * cn_c,
        tol,
    )
}

/// `cos(rad(a))`, but exactly 0 when `a` is exactly 90 (the reference's special case).
fn cos_star(a: f64) -> f64 {
    if a == 90.0 {
        0.0
    } else {
        a.to_radians().cos()
    }
}

/// `|a − b|` folded into [0, 180].
fn fold(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    if d > 180.0 {
        360.0 - d
    } else {
        d
    }
}

/// The integer degree a candidate heading is looked up by (⌊h⌋ of h in [0, 360)).
/// `unit(d)` for an integer degree 0..=359, from a table: a behavior's objective function
/// asks for the same 360 headings tens of thousands of times per iteration, and the
/// table holds exactly what `unit` computes.
fn unit_of_degree(d: f64) -> (f64, f64) {
    // deg_index gives an integer in 0..=359; anything else is computed.
    match unit_table().get(d as usize) {
        Some(&u) if d == (d as usize) as f64 => u,
        _ => unit(d),
    }
}

/// `unit(i)` for i = 0..=359.
fn unit_table() -> &'static [(f64, f64); 360] {
    static TABLE: std::sync::OnceLock<[(f64, f64); 360]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| unit(i as f64)))
}

/// The entry of a [`CpaEngine::roc_cosines`] table that [`CpaEngine::roc_with`] uses for
/// heading `h`.
#[inline]
pub fn roc_cosine(cos: &[f64; 360], h: f64) -> f64 {
    cos[roc_index(h)]
}

/// Where [`roc_cosine`] reads heading `h` in a table (below 360): a function of `h`
/// alone, so a grid's courses keep theirs from one table to the next.
#[inline]
pub fn roc_index(h: f64) -> usize {
    let i = if (0.0..360.0).contains(&h) {
        h as usize
    } else {
        deg_index(h) as usize
    };
    i.min(359)
}

fn deg_index(h: f64) -> f64 {
    let h = angle360(h);
    if h.is_finite() {
        h.floor().min(359.0)
    } else {
        0.0
    }
}

/// The cosine of `a` degrees, 0 at 90 and 270 exactly ([`CpaEngine::roc`]'s).
#[inline(always)]
fn cos_or_zero(a: f64) -> f64 {
    if a == 90.0 || a == 270.0 {
        0.0
    } else {
        a.to_radians().cos()
    }
}

/// The contact geometry engine (the reference's "OG" engine): a contact pose and
/// ownship's position, reset once per iteration, then asked per candidate heading `h`
/// and speed `v` of ownship. Candidate headings count by their integer degree (⌊h⌋),
/// which is exact on the usual 1-degree course grid. Per-degree values are computed on
/// demand (the same numbers as the reference's tables, without building 4 × 360 of
/// them per reset).
#[derive(Clone, Debug, PartialEq)]
pub struct CpaEngine {
    osx: f64,
    osy: f64,
    cnx: f64,
    cny: f64,
    cnh: f64,
    cnv: f64,
    cn_vx: f64,
    cn_vy: f64,
    /// Current range.
    pub rng: f64,
    /// Compass bearing ownship → contact.
    pub abs_os_cn: f64,
    /// Bearing of ownship relative to the contact's bow, [0, 360).
    pub beta: f64,
    pub on_contact: bool,
    pub on_bowline: bool,
    pub on_sternline: bool,
    /// Contact speed toward ownship (> 0 closing).
    pub cn_to_os: f64,
    /// Distance from ownship to the contact's bow-stern line (γ-range).
    pub range_gamma: f64,
    /// Distance from ownship to the contact's beam line (ε-range).
    pub range_epsilon: f64,
    theta_gam: f64,
    theta_tn: f64,
    cn_tan: f64,
    tn_const: f64,
    /// Per-degree values, when an objective function asked for them ([`Self::with_tables`]).
    tables: Option<Box<DegreeTables>>,
    /// `rng` as computed at reset (kept private: `rng` is public and could be changed).
    range_now: f64,
}

/// The reference's per-degree tables (`gamcos`, `cnhcos`, `tancos`), the same numbers the
/// on-demand path computes.
#[derive(Clone, Debug, PartialEq)]
struct DegreeTables {
    gam: [f64; 360],
    cnh: [f64; 360],
    tan: [f64; 360],
}

/// `cos_star(fold(d, theta))` for every integer degree d = 0..=359: a per-degree
/// table of [`CpaEngine::with_tables`].
fn degree_table(theta: f64, out: &mut [f64; 360]) {
    for (i, o) in out.iter_mut().enumerate() {
        *o = cos_star(fold(f64::from(i as u16), theta));
    }
}

/// How many per-degree tables a thread keeps.
const KEPT_TABLES: usize = 4;

/// The per-degree tables last used on this thread, by the bits of their angle, the
/// least recently used replaced first (an engine asks three: the two of a contact
/// holding its course stay while the third changes every iteration). A table is a
/// function of its angle alone, so a kept one is the table [`degree_table`] would
/// build, bit for bit.
struct KeptTables {
    angles: [Option<u64>; KEPT_TABLES],
    tables: [[f64; 360]; KEPT_TABLES],
    /// When each slot was last used (a count of uses).
    used: [u64; KEPT_TABLES],
    uses: u64,
}

impl KeptTables {
    /// The table of `theta` into `out`, from the kept ones or built (and kept).
    fn table(&mut self, theta: f64, out: &mut [f64; 360]) {
        let key = Some(theta.to_bits());
        self.uses += 1;
        let k = match self.angles.iter().position(|&a| a == key) {
            Some(k) => k,
            None => {
                // The least recently used slot (an empty one has never been used).
                let k = (0..KEPT_TABLES).min_by_key(|&k| self.used[k]).unwrap_or(0);
                degree_table(theta, &mut self.tables[k]);
                self.angles[k] = key;
                k
            }
        };
        self.used[k] = self.uses;
        *out = self.tables[k];
    }
}

thread_local! {
    static KEPT: std::cell::RefCell<KeptTables> = const {
        std::cell::RefCell::new(KeptTables {
            angles: [None; KEPT_TABLES],
            tables: [[0.0; 360]; KEPT_TABLES],
            used: [0; KEPT_TABLES],
            uses: 0,
        })
    };
}

/// How many spare table boxes a thread keeps (more than engines with tables alive at
/// once on a thread are let go).
const SPARE_TABLES: usize = 4;

thread_local! {
    /// The table boxes of dropped engines ([`CpaEngine`]'s `Drop`), for the thread's next
    /// [`CpaEngine::with_tables`]; their contents are stale until it rewrites them.
    static SPARE: std::cell::RefCell<Vec<Box<DegreeTables>>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// A spare table box of the thread's, or a new one (contents to be overwritten).
fn spare_tables() -> Box<DegreeTables> {
    spare::take_kept_or(&SPARE, || {
        Box::new(DegreeTables {
            gam: [0.0; 360],
            cnh: [0.0; 360],
            tan: [0.0; 360],
        })
    })
}

/// An engine's tables go back to the thread's spares (dropped when they are full, or
/// when the thread is ending and its store is gone).
impl Drop for CpaEngine {
    fn drop(&mut self) {
        if let Some(t) = self.tables.take() {
            spare::keep_in(&SPARE, t, SPARE_TABLES);
        }
    }
}

impl CpaEngine {
    /// Reset with the contact's pose (`cnh` put through angle360, negative `cnv` → 0)
    /// and ownship's position.
    pub fn new(cnx: f64, cny: f64, cnh: f64, cnv: f64, osx: f64, osy: f64) -> Self {
        let cnh = angle360(cnh);
        let cnv = cnv.max(0.0);
        let (s, c) = unit(cnh);
        let rng = range(osx, osy, cnx, cny);
        let abs_os_cn = rel_ang(osx, osy, cnx, cny);
        let ang_cn_os = rel_ang(cnx, cny, osx, osy);
        let beta = angle360(ang_cn_os - cnh);
        let on_contact = osx == cnx && osy == cny;
        let on_bowline = ang_cn_os == cnh;
        let on_sternline = ang_cn_os == angle360(cnh - 180.0);
        let b = if beta <= 180.0 { beta } else { 360.0 - beta };
        let (range_gamma, range_epsilon) = if b == 0.0 || b == 180.0 {
            (0.0, rng)
        } else {
            let g = rng * (90.0 - b).to_radians().cos();
            (g, (rng * rng - g * g).sqrt())
        };
        let mut e = CpaEngine {
            osx,
            osy,
            cnx,
            cny,
            cnh,
            cnv,
            cn_vx: cnv * s,
            cn_vy: cnv * c,
            rng,
            abs_os_cn,
            beta,
            on_contact,
            on_bowline,
            on_sternline,
            cn_to_os: cnv * cos_star(beta),
            range_gamma,
            range_epsilon,
            theta_gam: 0.0,
            theta_tn: angle360(abs_os_cn + 90.0),
            cn_tan: 0.0,
            tn_const: 360.0 / (2.0 * rng * PI_12),
            tables: None,
            range_now: rng,
        };
        e.theta_gam = if e.os_port_of_cn() {
            angle360(cnh + 90.0)
        } else {
            angle360(cnh - 90.0)
        };
        e.cn_tan = cnv * cos_star(angle180(cnh - e.theta_tn).abs());
        e
    }

    // The side predicates are inlined: the objective functions ask them per grid point,
    // across the crate boundary.
    #[inline]
    pub fn os_fore_of_cn(&self) -> bool {
        !self.on_contact && (self.beta <= 90.0 || self.beta >= 270.0)
    }
    #[inline]
    pub fn os_aft_of_cn(&self) -> bool {
        !self.on_contact && (90.0..=270.0).contains(&self.beta)
    }
    #[inline]
    pub fn os_port_of_cn(&self) -> bool {
        !self.on_contact && self.beta >= 180.0
    }
    #[inline]
    pub fn os_star_of_cn(&self) -> bool {
        !self.on_contact && self.beta <= 180.0
    }
    #[inline]
    pub fn on_bowstern(&self) -> bool {
        self.on_contact || self.on_bowline || self.on_sternline
    }
    #[inline]
    pub fn on_beam(&self) -> bool {
        self.on_contact || (self.os_fore_of_cn() && self.os_aft_of_cn())
    }
    /// The contact is closing on ownship (its own motion only).
    #[inline]
    pub fn closing(&self) -> bool {
        self.cn_to_os > 0.0
    }

    /// The engine with its per-degree tables built (1080 cosines once): for an objective
    /// function, which asks thousands of candidate headings per reset. Results are
    /// bit-identical to the engine without tables.
    ///
    /// Each table depends on one angle only (the contact's heading, or a bearing), and
    /// the last few tables built on this thread are kept by that angle's bits
    /// ([`KeptTables`]): a contact holding its course keeps two of the three from one
    /// iteration to the next.
    ///
    /// The tables' box is a spare one of the thread's when there is one ([`SPARE`]:
    /// dropped engines give theirs back), so a steady run of builds allocates none;
    /// all three tables are written in full here, whatever the box held.
    pub fn with_tables(mut self) -> Self {
        let mut t = self.tables.take().unwrap_or_else(spare_tables);
        KEPT.with_borrow_mut(|kept| {
            kept.table(self.theta_gam, &mut t.gam);
            kept.table(self.cnh, &mut t.cnh);
            kept.table(self.theta_tn, &mut t.tan);
        });
        self.tables = Some(t);
        self
    }

    /// A table entry for an integer degree `i` (what [`deg_index`] gives).
    fn table(&self, i: f64, pick: fn(&DegreeTables) -> &[f64; 360]) -> Option<f64> {
        let t = self.tables.as_deref()?;
        pick(t).get(i as usize).copied()
    }

    fn gamcos(&self, i: f64) -> f64 {
        self.table(i, |t| &t.gam)
            .unwrap_or_else(|| cos_star(fold(i, self.theta_gam)))
    }
    fn cnhcos(&self, i: f64) -> f64 {
        self.table(i, |t| &t.cnh)
            .unwrap_or_else(|| cos_star(fold(i, self.cnh)))
    }
    fn relcos(&self, i: f64) -> f64 {
        cos_or_zero(angle360(self.abs_os_cn - i))
    }
    fn tancos(&self, i: f64) -> f64 {
        self.table(i, |t| &t.tan)
            .unwrap_or_else(|| cos_star(fold(i, self.theta_tn)))
    }

    /// Closest approach within `tol` s if ownship holds (h, v); see [`cpa`] (here with
    /// the heading's integer degree).
    // Inlined into the objective functions of the contact plugins, which call it for
    // every corner of every tile of the decision grid.
    #[inline]
    pub fn cpa(&self, h: f64, v: f64, tol: f64) -> f64 {
        self.cpa_time(h, v, tol).dist
    }

    /// Closest approach and the time to it within the horizon `tol`.
    #[inline]
    pub fn cpa_time(&self, h: f64, v: f64, tol: f64) -> Cpa {
        // A heading already in [0, 360) (every grid heading) skips angle360's loops:
        // its ⌊h⌋ is the same table row deg_index gives.
        let (s, c) = if (0.0..360.0).contains(&h) {
            unit_table()[h as usize]
        } else {
            unit_of_degree(deg_index(h))
        };
        let v = v.max(0.0);
        // `range_now` is `(osx − cnx).hypot(osy − cny)`, the very value cpa_of computes.
        cpa_of_ranged(
            self.osx - self.cnx,
            self.osy - self.cny,
            v * s - self.cn_vx,
            v * c - self.cn_vy,
            tol,
            || self.range_now,
        )
    }

    /// Rate of closure (m/s, > 0 when the range decreases) if ownship holds (h, v).
    #[inline]
    pub fn roc(&self, h: f64, v: f64) -> f64 {
        v * self.relcos(deg_index(h)) + self.cn_to_os
    }

    /// Least and greatest rate of closure at speed `vmax` over headings 0, 1, …, 359.
    /// The heading cosines [`CpaEngine::roc`] uses, for every integer heading 0..=359: an
    /// objective function asking `roc` per grid point computes them once with this and
    /// calls [`CpaEngine::roc_with`].
    pub fn roc_cosines(&self) -> [f64; 360] {
        let b = self.abs_os_cn;
        if !(0.0..360.0).contains(&b) {
            return std::array::from_fn(|i| self.relcos(i as f64));
        }
        // From a bearing in [0, 360), `b - i` is below 360 and above -360: angle360's
        // loops add 360 once to a negative one and do nothing else (the same angles).
        std::array::from_fn(|i| {
            let a = b - i as f64;
            cos_or_zero(if a < 0.0 { a + 360.0 } else { a })
        })
    }

    /// [`CpaEngine::roc`] with the cosine looked up in `cos` (from
    /// [`CpaEngine::roc_cosines`] of this engine): the same value, without a `cos` per call.
    #[inline]
    pub fn roc_with(&self, cos: &[f64; 360], h: f64, v: f64) -> f64 {
        self.roc_of_cosine(roc_cosine(cos, h), v)
    }

    /// [`CpaEngine::roc_with`] given the table entry [`roc_cosine`] reads for the heading.
    #[inline]
    pub fn roc_of_cosine(&self, cosine: f64, v: f64) -> f64 {
        v * cosine + self.cn_to_os
    }

    /// [`CpaEngine::min_max_roc`] with the cosines looked up in `cos` (from
    /// [`CpaEngine::roc_cosines`] of this engine): the same pair, without a `cos` per
    /// heading.
    pub fn min_max_roc_with(&self, cos: &[f64; 360], vmax: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &c in cos {
            // Heading i's cosine is relcos(deg_index(i)) = relcos(i): roc(i, vmax).
            let r = self.roc_of_cosine(c, vmax);
            lo = lo.min(r);
            hi = hi.max(r);
        }
        (lo, hi)
    }

    pub fn min_max_roc(&self, vmax: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..360 {
            let r = self.roc(f64::from(i), vmax);
            lo = lo.min(r);
            hi = hi.max(r);
        }
        (lo, hi)
    }

    /// Bearing rate (deg/s) of the contact seen from ownship holding (h, v).
    pub fn bearing_rate(&self, h: f64, v: f64) -> f64 {
        (-v * self.tancos(deg_index(h)) + self.cn_tan) * self.tn_const
    }

    /// The speed difference along the contact's heading that decides whether ownship
    /// reaches the contact's beam line.
    fn beam_closing(&self, h: f64, v: f64) -> f64 {
        let w = self.cnhcos(deg_index(h)) * v;
        if self.os_aft_of_cn() {
            w - self.cnv
        } else {
            self.cnv - w
        }
    }

    /// Ownship will pass the contact's beam (either side).
    pub fn passes_port_or_star(&self, h: f64, v: f64) -> bool {
        self.on_beam() || self.beam_closing(h, v) > 0.0
    }

    /// Ownship passes the contact on the contact's port side.
    pub fn passes_port(&self, h: f64, v: f64) -> bool {
        self.passes_port_at(&self.heading(h), v)
    }

    /// Ownship passes the contact on the contact's starboard side.
    pub fn passes_star(&self, h: f64, v: f64) -> bool {
        self.passes_star_at(&self.heading(h), v)
    }

    /// Passing distance on the contact's port side, −1 when not passing port.
    pub fn passes_port_dist(&self, h: f64, v: f64) -> f64 {
        self.passes_port_dist_at(&self.heading(h), v)
    }

    /// Passing distance on the contact's starboard side, −1 when not passing starboard.
    pub fn passes_star_dist(&self, h: f64, v: f64) -> f64 {
        self.passes_star_dist_at(&self.heading(h), v)
    }

    /// Ownship will cross the contact's bow-stern line.
    pub fn crosses_bow_or_stern(&self, h: f64, v: f64) -> bool {
        if self.on_bowstern() {
            return true;
        }
        v > 0.0 && self.gamcos(deg_index(h)) > 0.00001
    }

    /// Ownship crosses astern of the contact.
    pub fn crosses_stern(&self, h: f64, v: f64) -> bool {
        self.crosses_stern_at(&self.heading(h), v)
    }

    /// Ownship crosses ahead of the contact (true on the stern line too, as the
    /// reference has it).
    pub fn crosses_bow(&self, h: f64, v: f64) -> bool {
        self.crosses_bow_at(&self.heading(h), v)
    }

    /// How far ahead of the contact ownship crosses its bow line, −1 when it does not.
    pub fn crosses_bow_dist(&self, h: f64, v: f64) -> f64 {
        if self.on_bowline {
            return self.rng;
        }
        if self.on_sternline || self.on_contact {
            return -1.0;
        }
        let i = deg_index(h);
        let s = self.gamcos(i) * v;
        if s <= 0.0 {
            return -1.0;
        }
        let t = self.range_gamma / s;
        let mut x = t * self.cnhcos(i) * v - t * self.cnv;
        x += if self.os_fore_of_cn() {
            self.range_epsilon
        } else {
            -self.range_epsilon
        };
        if x < 0.0 {
            -1.0
        } else {
            x
        }
    }

    /// How far astern of the contact ownship crosses its stern line, −1 when it does not.
    pub fn crosses_stern_dist(&self, h: f64, v: f64) -> f64 {
        if self.on_sternline {
            return self.rng;
        }
        if self.on_bowline || self.on_contact {
            return -1.0;
        }
        let i = deg_index(h);
        let s = self.gamcos(i) * v;
        if s <= 0.0 {
            return -1.0;
        }
        let t = self.range_gamma / s;
        let eps = if self.os_fore_of_cn() {
            -self.range_epsilon
        } else {
            self.range_epsilon
        };
        let x = t * self.cnv + eps - t * self.cnhcos(i) * v;
        if x < 0.0 {
            -1.0
        } else {
            x
        }
    }
}

#[path = "engine_heading.rs"]
mod heading;
#[path = "engine_roc.rs"]
mod roc;
#[path = "engine_zip.rs"]
mod zip;
pub use heading::{AvoidRamp, BowStarRate, BowStern, FlatEnds, Heading, RowConsts, Sides};

#[cfg(test)]
#[path = "engine_tests.rs"]
mod tests;
