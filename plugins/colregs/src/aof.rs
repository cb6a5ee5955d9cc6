//! The analytical objective functions of the COLREGS modes (behaviors-contacts.md
//! §5.4): AOF_R13 (overtaking), AOF_R14 (head-on), AOF_R16 (give-way) and AOF_CPA,
//! each evaluated by the reflector on the decision grid.

use std::cell::RefCell;

use behavior_api::contacts::engine::Heading;
use behavior_api::contacts::CpaEngine;
use behavior_api::geometry::{angle360, rel_ang};
use behavior_api::ivp::reflector::eval_grid_pointwise;
use behavior_api::ivp::{Aof, Domain};
use behavior_api::mbutil::spare;

/// The contact and ownship as the functions see them.
#[derive(Clone, Copy, Debug)]
pub struct Scene {
    pub cnx: f64,
    pub cny: f64,
    pub cnh: f64,
    pub cnv: f64,
    pub osx: f64,
    pub osy: f64,
    pub osh: f64,
}

impl Scene {
    /// The engine with its per-degree tables, for functions that ask per-heading
    /// queries ([`CpaEngine::heading`]).
    pub fn engine(&self) -> CpaEngine {
        self.plain_engine().with_tables()
    }

    /// The engine without tables, for functions that ask CPAs only.
    pub fn plain_engine(&self) -> CpaEngine {
        CpaEngine::new(self.cnx, self.cny, self.cnh, self.cnv, self.osx, self.osy)
    }
}

/// CPA utility with a floor value at the collision distance: 0 below `mu`, 100 above
/// `big`, else `floor + (100 − floor)·(p − mu)/(big − mu)`.
#[derive(Clone, Copy, Debug)]
pub struct Metric {
    pub mu: f64,
    pub big: f64,
    pub floor: f64,
    /// `big == mu` gives 0 (R13, R16) instead of the formula.
    pub zero_when_equal: bool,
}

impl Metric {
    pub fn eval(&self, p: f64) -> f64 {
        if p < self.mu {
            0.0
        } else if p > self.big {
            100.0
        } else if self.big == self.mu {
            if self.zero_when_equal {
                0.0
            } else {
                self.floor
            }
        } else {
            self.floor + (100.0 - self.floor) * (p - self.mu) / (self.big - self.mu)
        }
    }

    /// [`Metric::eval`] with every case computed and the answer picked (no jumps, for
    /// rows of candidates): the same comparisons and the same formula. `EQUAL` must be
    /// [`Metric::equal`], which a row decides once (else every candidate tests it).
    #[inline(always)]
    pub fn eval_row<const EQUAL: bool>(&self, p: f64) -> f64 {
        let between = if !EQUAL {
            self.floor + (100.0 - self.floor) * (p - self.mu) / (self.big - self.mu)
        } else if self.zero_when_equal {
            0.0
        } else {
            self.floor
        };
        let above_low = if p > self.big { 100.0 } else { between };
        if p < self.mu {
            0.0
        } else {
            above_low
        }
    }

    /// `big == mu`: [`Metric::eval`] between them is a constant, not the formula.
    #[inline]
    pub fn equal(&self) -> bool {
        self.big == self.mu
    }
}

/// [`Aof::eval_grid`] for a COLREGS AOF of course × speed whose utility needs the CPA
/// distance within `tol`: the courses' unit vectors and `prep` once per course (into
/// `prepared`, emptied first: the caller's buffer), then per speed a row of CPA
/// distances ([`CpaEngine::cpa_dists`], no jumps) and `point(prepared course, speed,
/// CPA distance)` per course. `point` must give what [`Aof::eval`] gives with that CPA
/// distance (the one `cpa_at`/`cpa_unit` gives).
fn eval_rows<A: Aof + ?Sized, P>(
    aof: &A,
    (engine, tol): (&CpaEngine, f64),
    (domain, axes, out): (&Domain, &[&[u32]], &mut [f64]),
    (prepared, prep): (&mut Vec<P>, impl Fn(f64) -> P),
    point: impl Fn(&P, f64, f64) -> f64,
) {
    let [xs, ys] = axes else {
        return eval_grid_pointwise(aof, domain, axes, out);
    };
    if xs.is_empty() {
        return;
    }
    // The unit vectors in the thread's kept lists (given back below).
    let c = Courses::units(engine, domain, xs);
    prepared.clear();
    prepared.extend(xs.iter().map(|&i| prep(domain.value(0, i))));
    for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
        let v = domain.value(1, j);
        engine.cpa_dists((&c.sins, &c.coss), v, tol, row);
        point_row(row, prepared, v, &point);
    }
    c.give_back();
}

thread_local! {
    /// [`R13Aof::eval_grid`]'s prepared headings' list, kept for the thread's next grid.
    static HEADINGS: RefCell<Vec<Vec<Heading>>> = const { RefCell::new(Vec::new()) };
}

fn grid(domain: &Domain, index: &[u32]) -> (f64, f64) {
    (domain.value(0, index[0]), domain.value(1, index[1]))
}

/// AOF_CPA (CPA mode and in-extremis stand-on): CPA within `tol` seconds.
pub struct CpaAof {
    pub engine: CpaEngine,
    pub tol: f64,
    pub metric: Metric,
}

impl CpaAof {
    pub fn new(s: &Scene, tol: f64, mu: f64, big: f64) -> Option<Self> {
        (mu <= big).then(|| CpaAof {
            // Its utility asks CPAs only: no per-degree tables.
            engine: s.plain_engine(),
            tol,
            metric: Metric {
                mu,
                big,
                floor: 25.0,
                zero_when_equal: false,
            },
        })
    }

    pub fn utility(&self, c: f64, v: f64) -> f64 {
        self.utility_of_unit(self.engine.unit(c), v)
    }

    /// [`Self::utility`] of the course whose unit vector is `u`.
    #[inline]
    fn utility_of_unit(&self, u: (f64, f64), v: f64) -> f64 {
        self.metric.eval(self.engine.cpa_unit(u, v, self.tol).dist)
    }

    /// Per (row, speed index) the row's CPA distances at that speed with the metric
    /// taken inside the row's loop ([`CpaEngine::cpa_dists_map`]: no pass of its own
    /// over the row); `EQUAL` is [`Metric::equal`].
    fn cpa_rows<'r, const EQUAL: bool>(
        &self,
        c: &Courses,
        domain: &Domain,
        rows: impl Iterator<Item = (&'r mut [f64], &'r u32)>,
    ) {
        let metric = self.metric;
        let units = (&c.sins[..], &c.coss[..]);
        for (row, &j) in rows {
            let v = domain.value(1, j);
            let utility = |d| metric.eval_row::<EQUAL>(d);
            self.engine
                .cpa_dists_map(units, (v, self.tol), row, utility);
        }
    }
}

impl Aof for CpaAof {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        let (c, v) = grid(domain, index);
        self.utility(c, v)
    }
    /// The courses' unit vectors once, then per speed a row of CPA distances with the
    /// metric taken inside the row's loop ([`CpaEngine::cpa_dists_map`]: no pass of its
    /// own over the row).
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        let [xs, ys] = axes else {
            return eval_grid_pointwise(self, domain, axes, out);
        };
        if xs.is_empty() {
            return;
        }
        let c = Courses::units(&self.engine, domain, xs);
        let rows = out.chunks_exact_mut(xs.len()).zip(ys.iter());
        if self.metric.equal() {
            self.cpa_rows::<true>(&c, domain, rows);
        } else {
            self.cpa_rows::<false>(&c, domain, rows);
        }
        c.give_back();
    }
    /// Every slot of every row is written.
    fn eval_grid_fills(&self) -> bool {
        true
    }
}

/// Which side ownship overtakes on (R13).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Port,
    Starboard,
}

/// AOF_R13 (overtaking): CPA utility, and candidates passing on the wrong side too
/// close are refused.
pub struct R13Aof {
    pub engine: CpaEngine,
    pub tol: f64,
    pub metric: Metric,
    pub side: Side,
}

impl R13Aof {
    pub fn new(s: &Scene, tol: f64, mu: f64, big: f64, side: Option<Side>) -> Option<Self> {
        let side = side?;
        (mu <= big).then(|| R13Aof {
            engine: s.engine(),
            tol,
            metric: Metric {
                mu,
                big,
                floor: 15.0,
                zero_when_equal: true,
            },
            side,
        })
    }

    pub fn utility(&self, c: f64, v: f64) -> f64 {
        self.utility_at(&self.engine.heading(c), v)
    }

    /// [`Self::utility`] at a heading the engine prepared.
    #[inline]
    fn utility_at(&self, hd: &Heading, v: f64) -> f64 {
        self.utility_with(hd, v, self.engine.cpa_at(hd, v, self.tol).dist)
    }

    /// [`Self::utility_at`] given the CPA distance.
    #[inline]
    fn utility_with(&self, hd: &Heading, v: f64, cpa: f64) -> f64 {
        let u = self.metric.eval(cpa);
        if u > 0.0 && v != 0.0 {
            let e = &self.engine;
            let mu = self.metric.mu;
            let wrong = match self.side {
                Side::Port => e.passes_star_at(hd, v) && e.passes_port_dist_at(hd, v) < mu,
                Side::Starboard => e.passes_port_at(hd, v) && e.passes_star_dist_at(hd, v) < mu,
            };
            if wrong {
                return 0.0;
            }
        }
        u
    }
}

impl Aof for R13Aof {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        let (c, v) = grid(domain, index);
        self.utility(c, v)
    }
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        let e = &self.engine;
        let mut headings = spare::take_kept(&HEADINGS);
        eval_rows(
            self,
            (e, self.tol),
            (domain, axes, out),
            (&mut headings, |c| e.heading(c)),
            |hd, v, cpa| self.utility_with(hd, v, cpa),
        );
        headings.clear();
        spare::keep_in(&HEADINGS, headings, 1);
    }
    /// Every slot of every row is written.
    fn eval_grid_fills(&self) -> bool {
        true
    }
}

/// AOF_R14 (head-on): no crossing the contact's bow from its port side, no passing it
/// to starboard; CPA utility plus a reward for opening the bearing as a port-to-port
/// pass does.
pub struct R14Aof {
    pub engine: CpaEngine,
    pub tol: f64,
    pub metric: Metric,
    /// The bearing rate of the reference turn (both vessels 90° right), `b0`.
    pub b0: f64,
}

impl R14Aof {
    pub fn new(s: &Scene, tol: f64, mu: f64, big: f64) -> Option<Self> {
        if mu > big {
            return None;
        }
        // Contact at cn turned to relAng(cn, os) + 90, ownship turned to
        // relAng(os, cn) + 90, both at the contact's speed.
        let cnh_t = angle360(rel_ang(s.cnx, s.cny, s.osx, s.osy) + 90.0);
        let osh_t = angle360(rel_ang(s.osx, s.osy, s.cnx, s.cny) + 90.0);
        let turned = CpaEngine::new(s.cnx, s.cny, cnh_t, s.cnv, s.osx, s.osy);
        let b0 = turned.bearing_rate(osh_t, s.cnv);
        Some(R14Aof {
            engine: s.engine(),
            tol,
            metric: Metric {
                mu,
                big,
                floor: 25.0,
                zero_when_equal: false,
            },
            b0,
        })
    }

    pub fn utility(&self, c: f64, v: f64) -> f64 {
        self.utility_at(&self.engine.heading(c), v)
    }

    /// [`Self::utility`] at a heading the engine prepared.
    #[inline]
    fn utility_at(&self, hd: &Heading, v: f64) -> f64 {
        self.utility_with(hd, v, || self.engine.cpa_at(hd, v, self.tol).dist)
    }

    /// [`Self::utility_at`] with the CPA distance from `cpa` (asked only when used).
    #[inline]
    fn utility_with(&self, hd: &Heading, v: f64, cpa: impl FnOnce() -> f64) -> f64 {
        let e = &self.engine;
        if e.on_contact || (e.os_port_of_cn() && e.crosses_bow_at(hd, v)) || e.passes_star_at(hd, v)
        {
            return 0.0;
        }
        let m1 = self.metric.eval(cpa());
        let m3 = if self.b0 >= 0.0 {
            0.0
        } else {
            let br = e.bearing_rate_at(hd, v);
            if br >= 0.0 {
                0.0
            } else if br <= self.b0 {
                100.0
            } else {
                100.0 * br / self.b0
            }
        };
        m1 + m3
    }
}

impl Aof for R14Aof {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        let (c, v) = grid(domain, index);
        self.utility(c, v)
    }
    /// The courses once, then per speed a row of CPA distances and of utilities
    /// ([`rows::r14_row`]: [`Self::utility_with`] without jumps).
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        let [xs, ys] = axes else {
            return eval_grid_pointwise(self, domain, axes, out);
        };
        if xs.is_empty() {
            return;
        }
        let c = Courses::of(&self.engine, domain, xs, None);
        let k = R14Row {
            sides: self.engine.sides(),
            consts: self.engine.row_consts(),
            metric: self.metric,
            b0: self.b0,
            v: 0.0,
        };
        for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
            let v = domain.value(1, j);
            self.engine.cpa_dists((&c.sins, &c.coss), v, self.tol, row);
            r14_row(&R14Row { v, ..k }, &c, row);
        }
        c.give_back();
    }
    /// Every slot of every row is written.
    fn eval_grid_fills(&self) -> bool {
        true
    }
}

/// Which way ownship gives way (R16).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    Stern,
    Bow,
}

/// AOF_R16 (give-way): pass astern (or ahead) of the contact, turning the right way.
pub struct R16Aof {
    pub engine: CpaEngine,
    pub osh: f64,
    pub metric: Metric,
    pub pass: Pass,
    pub port_turns_ok: bool,
}

/// The give-way horizon, fixed whatever `time_on_leg` is.
pub const R16_TOL: f64 = 120.0;

impl R16Aof {
    /// `Err` with the reasons the reference joins into its init error.
    pub fn new(
        s: &Scene,
        mu: f64,
        big: f64,
        pass: Option<Pass>,
        port_turns_ok: bool,
    ) -> Result<Self, Vec<&'static str>> {
        let mut why = Vec::new();
        if mu > big {
            why.push("collision distance above all-clear distance");
        }
        let Some(pass) = pass else {
            why.push("bad passing side");
            return Err(why);
        };
        if !why.is_empty() {
            return Err(why);
        }
        Ok(R16Aof {
            engine: s.engine(),
            osh: s.osh,
            metric: Metric {
                mu,
                big,
                floor: 25.0,
                zero_when_equal: true,
            },
            pass,
            port_turns_ok,
        })
    }

    pub fn utility(&self, c: f64, v: f64) -> f64 {
        self.utility_at(&self.course(c), v)
    }

    /// What [`Self::utility_at`] needs of course `c`: the engine's heading, and whether
    /// it is a starboard or a port turn from ownship's heading.
    fn course(&self, c: f64) -> (Heading, bool, bool) {
        let delta = angle360(c - self.osh);
        let star_turn = delta > 0.0 && delta < 180.0;
        let port_turn = delta > 180.0;
        (self.engine.heading(c), star_turn, port_turn)
    }

    /// [`Self::utility`] at a course prepared by [`Self::course`].
    #[inline]
    fn utility_at(&self, p: &(Heading, bool, bool), v: f64) -> f64 {
        self.utility_with(p, v, || self.engine.cpa_at(&p.0, v, R16_TOL).dist)
    }

    /// [`Self::utility_at`] with the CPA distance from `cpa` (asked only when used).
    #[inline]
    fn utility_with(
        &self,
        &(ref hd, star_turn, port_turn): &(Heading, bool, bool),
        v: f64,
        cpa: impl FnOnce() -> f64,
    ) -> f64 {
        let e = &self.engine;
        let refused = match self.pass {
            Pass::Stern if self.port_turns_ok => {
                e.crosses_bow_at(hd, v) || (!star_turn && !e.crosses_stern_at(hd, v))
            }
            Pass::Stern => !e.crosses_stern_at(hd, v) || port_turn,
            Pass::Bow => star_turn && !e.crosses_bow_at(hd, v),
        };
        if refused {
            return 0.0;
        }
        self.metric.eval(cpa())
    }
}

impl R16Aof {
    /// [`Aof::eval_grid`] with the pass's rule `refused` of (crosses bow, crosses stern,
    /// starboard turn, port turn), a constant of the row loops: the courses once, then
    /// per speed a row of CPA distances and of utilities ([`r16_row`]).
    fn eval_grid_with(
        &self,
        (domain, axes, out): (&Domain, &[&[u32]], &mut [f64]),
        refused: impl Fn(bool, bool, bool, bool) -> bool + Copy,
    ) {
        let [xs, ys] = axes else {
            return eval_grid_pointwise(self, domain, axes, out);
        };
        if xs.is_empty() {
            return;
        }
        let c = Courses::of(&self.engine, domain, xs, Some(self.osh));
        let k = R16Row {
            sides: self.engine.sides(),
            consts: self.engine.row_consts(),
            metric: self.metric,
            v: 0.0,
        };
        for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
            let v = domain.value(1, j);
            self.engine.cpa_dists((&c.sins, &c.coss), v, R16_TOL, row);
            r16_row(&R16Row { v, ..k }, &c, row, refused);
        }
        c.give_back();
    }
}

impl Aof for R16Aof {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        let (c, v) = grid(domain, index);
        self.utility(c, v)
    }
    /// [`Self::utility_with`]'s rules without jumps: `||` as `|`, `&&` as `&`.
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        let grid = (domain, axes, out);
        match self.pass {
            Pass::Stern if self.port_turns_ok => {
                self.eval_grid_with(grid, |bow, stern, star_turn, _| bow | (!star_turn & !stern))
            }
            Pass::Stern => self.eval_grid_with(grid, |_, stern, _, port_turn| !stern | port_turn),
            Pass::Bow => self.eval_grid_with(grid, |bow, _, star_turn, _| star_turn & !bow),
        }
    }
    /// Every slot of every row is written.
    fn eval_grid_fills(&self) -> bool {
        true
    }
}

#[path = "aof_rows.rs"]
mod rows;
use rows::{point_row, r14_row, r16_row, Courses, R14Row, R16Row};

#[cfg(test)]
#[path = "aof_tests.rs"]
mod tests;
