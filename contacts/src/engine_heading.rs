//! The engine's per-candidate queries split in two: what depends on the candidate
//! heading only ([`Heading`]: its unit vector and the per-degree cosines) is looked up
//! once, then each speed costs a few multiplications. An objective function evaluated
//! on a (course, speed) grid asks every query for the same heading at many speeds.
//! Each `*_at` method is its plain counterpart's formula, operation for operation, so
//! the results are the same bit for bit (engine_tests.rs checks it at random).

use super::{cpa_of_ranged, deg_index, unit_of_degree, unit_table, Cpa, CpaEngine};

/// One candidate heading as the engine's queries use it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Heading {
    /// sin and cos of the heading's integer degree (the CPA's ownship velocity).
    sin: f64,
    cos: f64,
    /// The engine's per-degree cosines at that degree: `gamcos`, `cnhcos`, `tancos`.
    gam: f64,
    cnh: f64,
    tan: f64,
}

impl Heading {
    /// The per-degree cosines [`CpaEngine::bow_stern_of`] takes: `gamcos` and `tancos`.
    #[inline]
    pub fn gam_tan(&self) -> (f64, f64) {
        (self.gam, self.tan)
    }

    /// The per-degree cosines [`BowStarRate::of`] takes: `gamcos`, `cnhcos`, `tancos`.
    #[inline]
    pub fn cosines(&self) -> (f64, f64, f64) {
        (self.gam, self.cnh, self.tan)
    }
}

/// The unit vector [`CpaEngine::cpa_time`] takes for heading `h`.
#[inline]
fn unit_of(h: f64) -> (f64, f64) {
    if (0.0..360.0).contains(&h) {
        unit_table()[h as usize]
    } else {
        unit_of_degree(deg_index(h))
    }
}

impl CpaEngine {
    /// Heading `h` for the `*_at` queries (the per-degree cosines come from the tables of
    /// [`CpaEngine::with_tables`] when built, else computed: three cosines).
    pub fn heading(&self, h: f64) -> Heading {
        let (sin, cos) = unit_of(h);
        let i = deg_index(h);
        Heading {
            sin,
            cos,
            gam: self.gamcos(i),
            cnh: self.cnhcos(i),
            tan: self.tancos(i),
        }
    }

    /// The unit vector of heading `h`, all [`CpaEngine::cpa_unit`] needs (no cosines).
    #[inline]
    pub fn unit(&self, h: f64) -> (f64, f64) {
        unit_of(h)
    }

    /// [`CpaEngine::unit`] of each of `headings`, appended: sines to `sins`, cosines to
    /// `coss` (the table looked up once for all of them, not per heading).
    pub fn units_into(
        &self,
        headings: impl ExactSizeIterator<Item = f64>,
        (sins, coss): (&mut Vec<f64>, &mut Vec<f64>),
    ) {
        let table = unit_table();
        let (at, n) = (sins.len(), headings.len());
        // Written in place: a push checks the capacity per heading.
        sins.resize(at + n, 0.0);
        coss.resize(at + n, 0.0);
        for ((h, s), c) in headings.zip(&mut sins[at..]).zip(&mut coss[at..]) {
            // unit_of, with the table at hand.
            (*s, *c) = if (0.0..360.0).contains(&h) {
                // SAFETY: 0 <= h < 360, so h truncated fits a u32 (and indexes the table).
                table[unsafe { h.to_int_unchecked::<u32>() }.min(359) as usize]
            } else {
                unit_of_degree(deg_index(h))
            };
        }
    }

    /// [`CpaEngine::cpa_time`] for the heading whose [`CpaEngine::unit`] is `u`.
    #[inline]
    pub fn cpa_unit(&self, u: (f64, f64), v: f64, tol: f64) -> Cpa {
        let (s, c) = u;
        let v = v.max(0.0);
        cpa_of_ranged(
            self.osx - self.cnx,
            self.osy - self.cny,
            v * s - self.cn_vx,
            v * c - self.cn_vy,
            tol,
            || self.range_now,
        )
    }

    /// [`CpaEngine::cpa_time`] at a [`Heading`].
    #[inline]
    pub fn cpa_at(&self, hd: &Heading, v: f64, tol: f64) -> Cpa {
        self.cpa_unit((hd.sin, hd.cos), v, tol)
    }

    /// [`CpaEngine::bearing_rate`] at a [`Heading`].
    #[inline]
    pub fn bearing_rate_at(&self, hd: &Heading, v: f64) -> f64 {
        (-v * hd.tan + self.cn_tan) * self.tn_const
    }

    #[inline]
    fn beam_closing_at(&self, hd: &Heading, v: f64) -> f64 {
        let w = hd.cnh * v;
        if self.os_aft_of_cn() {
            w - self.cnv
        } else {
            self.cnv - w
        }
    }

    /// [`CpaEngine::passes_port_or_star`] at a [`Heading`].
    #[inline]
    pub fn passes_port_or_star_at(&self, hd: &Heading, v: f64) -> bool {
        self.on_beam() || self.beam_closing_at(hd, v) > 0.0
    }

    /// [`CpaEngine::passes_port`] at a [`Heading`].
    #[inline]
    pub fn passes_port_at(&self, hd: &Heading, v: f64) -> bool {
        if self.on_contact || !self.passes_port_or_star_at(hd, v) {
            return false;
        }
        if self.on_beam() {
            return self.os_port_of_cn();
        }
        if self.os_aft_of_cn() {
            self.bearing_rate_at(hd, v) > 0.0
        } else {
            self.bearing_rate_at(hd, v) < 0.0
        }
    }

    /// [`CpaEngine::passes_star`] at a [`Heading`].
    #[inline]
    pub fn passes_star_at(&self, hd: &Heading, v: f64) -> bool {
        if self.on_contact || !self.passes_port_or_star_at(hd, v) {
            return false;
        }
        !self.passes_port_at(hd, v)
    }

    /// [`CpaEngine::passes_port_dist`] at a [`Heading`].
    pub fn passes_port_dist_at(&self, hd: &Heading, v: f64) -> f64 {
        self.passes_side_dist_at(hd, v, true)
    }

    /// [`CpaEngine::passes_star_dist`] at a [`Heading`].
    pub fn passes_star_dist_at(&self, hd: &Heading, v: f64) -> f64 {
        self.passes_side_dist_at(hd, v, false)
    }

    fn passes_side_dist_at(&self, hd: &Heading, v: f64, port: bool) -> f64 {
        let (same, other) = if port {
            (self.os_port_of_cn(), self.os_star_of_cn())
        } else {
            (self.os_star_of_cn(), self.os_port_of_cn())
        };
        if self.on_contact || (self.on_beam() && other) {
            return -1.0;
        }
        if self.on_beam() && same {
            return self.rng;
        }
        let e = self.beam_closing_at(hd, v);
        if e <= 0.0 {
            return -1.0;
        }
        let t = self.range_epsilon / e;
        let g = t * hd.gam * v;
        let x = if same && g <= self.range_gamma {
            self.range_gamma - g
        } else if other && g > self.range_gamma {
            g - self.range_gamma
        } else {
            -1.0
        };
        if x < 0.0 {
            -1.0
        } else {
            x
        }
    }

    /// [`CpaEngine::crosses_stern`] at a [`Heading`].
    #[inline]
    pub fn crosses_stern_at(&self, hd: &Heading, v: f64) -> bool {
        if self.on_sternline {
            return true;
        }
        if v <= 0.0 || hd.gam <= 0.0 {
            return false;
        }
        let br = self.bearing_rate_at(hd, v);
        if self.os_port_of_cn() {
            br <= 0.0
        } else {
            br >= 0.0
        }
    }

    /// [`CpaEngine::crosses_bow`] at a [`Heading`].
    #[inline]
    pub fn crosses_bow_at(&self, hd: &Heading, v: f64) -> bool {
        if self.on_sternline {
            return true;
        }
        if v <= 0.0 || hd.gam <= 0.0 {
            return false;
        }
        let br = self.bearing_rate_at(hd, v);
        if self.os_port_of_cn() {
            br >= 0.0
        } else {
            br <= 0.0
        }
    }
}

/// The engine's facts about where ownship lies from the contact, which the
/// per-candidate rules branch on, taken once for a grid of candidates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sides {
    pub on_contact: bool,
    pub on_sternline: bool,
    pub on_beam: bool,
    pub port_of_cn: bool,
    pub aft_of_cn: bool,
}

/// What [`CpaEngine::bow_star_rate_at`] gives for one candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BowStarRate {
    /// [`CpaEngine::crosses_bow_at`].
    pub crosses_bow: bool,
    /// [`CpaEngine::passes_star_at`].
    pub passes_star: bool,
    /// [`CpaEngine::bearing_rate_at`].
    pub bearing_rate: f64,
}

impl CpaEngine {
    /// The side facts of this engine for [`CpaEngine::bow_star_rate_at`].
    pub fn sides(&self) -> Sides {
        Sides {
            on_contact: self.on_contact,
            on_sternline: self.on_sternline,
            on_beam: self.on_beam(),
            port_of_cn: self.os_port_of_cn(),
            aft_of_cn: self.os_aft_of_cn(),
        }
    }

    /// [`CpaEngine::crosses_bow_at`], [`CpaEngine::passes_star_at`] and
    /// [`CpaEngine::bearing_rate_at`] of one candidate, with `s` this engine's
    /// [`CpaEngine::sides`]: the same comparisons on the same values, every one made and
    /// the answers combined without jumps (a grid of candidates then runs without
    /// mispredicted branches).
    #[inline(always)]
    pub fn bow_star_rate_at(&self, s: &Sides, hd: &Heading, v: f64) -> BowStarRate {
        BowStarRate::of(s, &self.row_consts(), (hd.gam, hd.cnh, hd.tan), v)
    }
}

impl BowStarRate {
    /// [`CpaEngine::bow_star_rate_at`] of the heading whose [`Heading::cosines`] are
    /// `(gam, cnh, tan)`, with the engine's [`Sides`] and [`RowConsts`] (for rows of
    /// candidates held as lists of numbers).
    #[inline(always)]
    pub fn of(s: &Sides, c: &RowConsts, (gam, cnh, tan): (f64, f64, f64), v: f64) -> Self {
        let br = c.bearing_rate(tan, v);
        // crosses_bow_at: on the stern line, or moving on a heading with gam > 0 and the
        // bearing rate of the right sign for ownship's side.
        // Negated, not `v > 0.0`: a NaN speed or cosine counts as moving, as it falls
        // through crosses_bow_at's `v <= 0.0 || gam <= 0.0` test.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        let moving = !(v <= 0.0) & !(gam <= 0.0);
        let (ge, le) = (br >= 0.0, br <= 0.0);
        let bow_sign = if s.port_of_cn { ge } else { le };
        let crosses_bow = s.on_sternline | (moving & bow_sign);
        // passes_star_at: passes port or starboard (on the beam, or the beam closing),
        // and not to port (on the beam: ownship on the port side; else the bearing rate
        // of the sign for fore or aft).
        let e = c.beam_closing(s.aft_of_cn, cnh, v);
        let either = s.on_beam | (e > 0.0);
        let (gt, lt) = (br > 0.0, br < 0.0);
        let off_beam_port = if s.aft_of_cn { gt } else { lt };
        let port = if s.on_beam {
            s.port_of_cn
        } else {
            off_beam_port
        };
        let passes_star = !s.on_contact & either & !port;
        BowStarRate {
            crosses_bow,
            passes_star,
            bearing_rate: br,
        }
    }
}

/// What [`CpaEngine::bow_stern_at`] gives for one candidate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BowStern {
    /// [`CpaEngine::crosses_bow_at`].
    pub crosses_bow: bool,
    /// [`CpaEngine::crosses_stern_at`].
    pub crosses_stern: bool,
}

impl CpaEngine {
    /// [`CpaEngine::crosses_bow_at`] and [`CpaEngine::crosses_stern_at`] of one
    /// candidate, with `s` this engine's [`CpaEngine::sides`]: the same comparisons on
    /// the same values, every one made and the answers combined without jumps.
    #[inline(always)]
    pub fn bow_stern_at(&self, s: &Sides, hd: &Heading, v: f64) -> BowStern {
        self.bow_stern_of(s, (hd.gam, hd.tan), v)
    }

    /// [`CpaEngine::bow_stern_at`] of the heading whose [`Heading::gam_tan`] is
    /// `(gam, tan)` (for rows of candidates held as lists of numbers).
    #[inline(always)]
    pub fn bow_stern_of(&self, s: &Sides, gam_tan: (f64, f64), v: f64) -> BowStern {
        BowStern::of(s, &self.row_consts(), gam_tan, v)
    }

    /// This engine's numbers the per-candidate rules use, to carry into a row loop.
    #[inline]
    pub fn row_consts(&self) -> RowConsts {
        RowConsts {
            cn_tan: self.cn_tan,
            tn_const: self.tn_const,
            cnv: self.cnv,
        }
    }
}

/// The numbers of one engine the per-candidate rules use besides the [`Sides`] (the
/// bearing-rate formula's and the contact's speed), apart from it: what a loop over
/// rows of candidates keeps in registers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowConsts {
    cn_tan: f64,
    tn_const: f64,
    cnv: f64,
}

impl RowConsts {
    /// `(cn_tan, tn_const, cnv)`: the numbers of [`Self::bearing_rate`] and
    /// [`Self::beam_closing`], for loops that write those formulas out.
    pub fn parts(&self) -> (f64, f64, f64) {
        (self.cn_tan, self.tn_const, self.cnv)
    }

    /// The bearing rate at speed `v` of the heading whose `tancos` is `tan`: the
    /// engine's formula ([`CpaEngine::bearing_rate_at`]).
    #[inline(always)]
    pub fn bearing_rate(&self, tan: f64, v: f64) -> f64 {
        (-v * tan + self.cn_tan) * self.tn_const
    }

    /// The beam closing speed at speed `v` of the heading whose `cnhcos` is `cnh`, with
    /// ownship aft of the contact or not (positive: passing port or starboard).
    #[inline(always)]
    pub fn beam_closing(&self, aft: bool, cnh: f64, v: f64) -> f64 {
        let w = cnh * v;
        if aft {
            w - self.cnv
        } else {
            self.cnv - w
        }
    }
}

impl BowStern {
    /// [`CpaEngine::bow_stern_of`] with the engine's [`Sides`] and [`BearingRates`].
    #[inline(always)]
    pub fn of(s: &Sides, c: &RowConsts, (gam, tan): (f64, f64), v: f64) -> Self {
        let br = c.bearing_rate(tan, v);
        // Negated, not `v > 0.0`: a NaN speed or cosine counts as moving, as it falls
        // through the `v <= 0.0 || gam <= 0.0` test.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        let moving = !(v <= 0.0) & !(gam <= 0.0);
        let (ge, le) = (br >= 0.0, br <= 0.0);
        let (bow_sign, stern_sign) = if s.port_of_cn { (ge, le) } else { (le, ge) };
        BowStern {
            crosses_bow: s.on_sternline | (moving & bow_sign),
            crosses_stern: s.on_sternline | (moving & stern_sign),
        }
    }
}

impl CpaEngine {
    /// [`CpaEngine::cpa_unit`]'s distance for a row of courses at one speed: `out[k]` is
    /// `cpa_unit((sins[k], coss[k]), v, tol).dist`. The row goes by chunks of a few
    /// candidates: a chunk none of which is closing is the range now throughout (about
    /// half of an avoidance grid's), the others have each candidate's every branch
    /// computed and the answer picked, with the same operations in the same order, so a
    /// chunk has no jumps and the CPU does several candidates at once (an objective
    /// function asks this for every corner of every tile of the grid). On a CPU with
    /// AVX2 the chunks are written in its instructions (four candidates per instruction
    /// instead of two; IEEE operations give the same bits at any width).
    pub fn cpa_dists(&self, units: (&[f64], &[f64]), v: f64, tol: f64, out: &mut [f64]) {
        self.cpa_dists_map(units, (v, tol), out, |d| d);
    }

    /// [`CpaEngine::cpa_dists`] at speed `v` and horizon `tol`, each distance `d` written
    /// as `f(d)`: `f` runs inside the row's loop (for an objective function's utility of
    /// the distance: no pass of its own over the row), so it should have no jumps either.
    /// `f` must be a function of its argument only: a row at speed 0 (all one value) is
    /// computed once and `f`'s answer copied, and so is `f` of the range now for the
    /// chunks that are not closing.
    #[inline]
    pub fn cpa_dists_map<F: Fn(f64) -> f64>(
        &self,
        units: (&[f64], &[f64]),
        at: (f64, f64),
        out: &mut [f64],
        f: F,
    ) {
        self.cpa_dists_flat(units, at, out, f, None);
    }

    /// [`CpaEngine::cpa_dists_map`] for an `f` with [`FlatEnds`] (when `Some`): the
    /// same bits, with the candidates whose CPA is surely in a flat end given that end's
    /// value without working out the distance (on a CPU with AVX2, by four candidates).
    #[inline]
    pub fn cpa_dists_flat<F: Fn(f64) -> f64>(
        &self,
        units: (&[f64], &[f64]),
        (v, tol): (f64, f64),
        out: &mut [f64],
        f: F,
        flat: Option<FlatEnds>,
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
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let ends = rows::Ends::of(&row, flat, &f);
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { rows::cpa_row_avx2(&row, units, out, f, ends) };
        }
        cpa_row(&row, units, out, f);
    }
}

#[path = "engine_rows.rs"]
mod rows;
pub(super) use rows::{cpa_entry, cpa_row, still_row, CpaRow};
#[cfg(all(test, target_arch = "x86_64"))]
pub(super) use rows::{cpa_row_avx2, Ends};
pub use rows::{AvoidRamp, FlatEnds};
#[cfg(target_arch = "x86_64")]
pub(super) use rows::{Lanes, WIDE};
