//! The row loops of the COLREGS AOFs' grid evaluation ([`super`]): per speed, a row of
//! CPA distances turned into utilities, each candidate's every rule computed and the
//! answer picked (no jumps), so that a row runs several candidates per instruction. On
//! a CPU with AVX2 each loop runs compiled for it (four candidates per instruction
//! instead of two; IEEE operations give the same bits at any width).

use std::cell::RefCell;

use behavior_api::contacts::engine::{BowStern, RowConsts, Sides};
use behavior_api::contacts::CpaEngine;
use behavior_api::geometry::angle360;
use behavior_api::ivp::{Domain, ValuesKey};
use behavior_api::mbutil::spare;

use super::Metric;

/// The courses of a grid as the rows read them, one list per quantity: the unit
/// vectors (for the CPA rows), the engine's per-degree cosines (`gamcos`, `cnhcos`,
/// `tancos`, [`behavior_api::contacts::engine::Heading::cosines`]) and, for R16, the
/// turn from ownship's heading. The lists are kept on the thread for the next grids
/// ([`Courses::give_back`]): a build asks for two grids every iteration, and the
/// plugin's shared spares hand out buffers of any size (taking one that is too small
/// would grow it, an allocation per grid).
#[derive(Default)]
pub(super) struct Courses {
    pub sins: Vec<f64>,
    pub coss: Vec<f64>,
    pub gams: Vec<f64>,
    pub cnhs: Vec<f64>,
    pub tans: Vec<f64>,
    /// 1 for a starboard (port) turn, else 0: numbers, not `bool`s, so that the row
    /// loop compares them in lanes as wide as its other numbers. Empty unless asked.
    pub star_turns: Vec<f64>,
    pub port_turns: Vec<f64>,
    /// The courses of `sins` and `coss`. The unit vectors depend on these alone (the
    /// engine's table), and a build asks for the same courses every iteration: kept
    /// lists of the same courses are used as they are.
    courses: ValuesKey,
}

/// More kept course lists than grids evaluated at once on a thread are let go.
const MAX_KEPT: usize = 4;

thread_local! {
    /// The lists of grids done with ([`Courses::give_back`]), emptied.
    static KEPT: RefCell<Vec<Courses>> = const { RefCell::new(Vec::new()) };
}

impl Courses {
    /// The unit vectors only (`sins`, `coss`) of the courses `xs` (indices of the
    /// domain's first variable), the other lists empty: kept lists of these courses if
    /// any, else kept lists (with the room of earlier grids) or new ones, filled.
    pub fn units(engine: &CpaEngine, domain: &Domain, xs: &[u32]) -> Self {
        let var = domain.var(0);
        let same = |c: &Self| c.courses.is(var, xs);
        // Else new lists until MAX_KEPT are kept (each grid's courses keep their own),
        // then the least lately used ones made again.
        let mut c = spare::take_kept_matching(&KEPT, same, MAX_KEPT);
        if same(&c) {
            return c;
        }
        c.sins.clear();
        c.coss.clear();
        // The engine's unit table looked up once for the whole list
        // ([`CpaEngine::units_into`]).
        engine.units_into(var.values_at(xs), (&mut c.sins, &mut c.coss));
        c.courses.set(var, xs);
        c
    }

    /// The courses `xs` (indices of the domain's first variable) for `engine` (with its
    /// tables), and their turns from ownship's heading `osh` when given: starboard for
    /// `angle360(c − osh)` in (0, 180), port above 180.
    pub fn of(engine: &CpaEngine, domain: &Domain, xs: &[u32], osh: Option<f64>) -> Self {
        let mut c = Self::units(engine, domain, xs);
        let courses = domain.var(0).values_at(xs);
        // Written in place (a push checks the capacity per course).
        let n = xs.len();
        let lists = (&mut c.gams, &mut c.cnhs, &mut c.tans);
        engine.cosines_into(courses.clone(), lists);
        if let Some(osh) = osh {
            c.star_turns.resize(n, 0.0);
            c.port_turns.resize(n, 0.0);
            let turns = c.star_turns.iter_mut().zip(&mut c.port_turns);
            for ((star, port), course) in turns.zip(courses) {
                let delta = angle360(course - osh);
                *star = f64::from(u8::from(delta > 0.0 && delta < 180.0));
                *port = f64::from(u8::from(delta > 180.0));
            }
        }
        c
    }

    /// The lists kept for the thread's next grids (the unit vectors with their courses,
    /// the others emptied).
    pub fn give_back(mut self) {
        let lists = [&mut self.gams, &mut self.cnhs, &mut self.tans];
        for v in lists
            .into_iter()
            .chain([&mut self.star_turns, &mut self.port_turns])
        {
            v.clear();
        }
        spare::keep_in(&KEPT, self, MAX_KEPT);
    }
}

/// What a row of [`R16Aof`] utilities needs besides the courses: the engine's facts
/// and numbers, the metric and the row's speed.
#[derive(Clone, Copy)]
pub(super) struct R16Row {
    pub sides: Sides,
    pub consts: RowConsts,
    pub metric: Metric,
    pub v: f64,
}

/// `row[k]` (the CPA distance of course k at speed `r.v`) into `R16Aof::utility_with`
/// of that course, every rule computed and the answer picked (no jumps; the same
/// comparisons and formulas on the same values), `refused` being the pass's rule. On a
/// CPU with AVX2 the same loop runs compiled for it (four candidates per instruction;
/// IEEE operations give the same bits at any width).
pub(super) fn r16_row(
    r: &R16Row,
    c: &Courses,
    row: &mut [f64],
    refused: impl Fn(bool, bool, bool, bool) -> bool,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { r16_row_avx2(r, c, row, refused) };
    }
    r16_row_plain(r, c, row, refused);
}

/// [`r16_row`]'s loop compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn r16_row_avx2(
    r: &R16Row,
    c: &Courses,
    row: &mut [f64],
    refused: impl Fn(bool, bool, bool, bool) -> bool,
) {
    r16_row_plain(r, c, row, refused);
}

/// [`r16_row`]'s loop, for the target's baseline instructions (and inlined into
/// [`r16_row_avx2`]).
#[inline(always)]
fn r16_row_plain(
    r: &R16Row,
    c: &Courses,
    row: &mut [f64],
    refused: impl Fn(bool, bool, bool, bool) -> bool,
) {
    // Ownship's side of the contact and the metric's kind decided once per row (no
    // choice per candidate).
    match (r.sides.port_of_cn, r.metric.equal()) {
        (false, false) => r16_row_sides::<false, false>(r, c, row, refused),
        (false, true) => r16_row_sides::<false, true>(r, c, row, refused),
        (true, false) => r16_row_sides::<true, false>(r, c, row, refused),
        (true, true) => r16_row_sides::<true, true>(r, c, row, refused),
    }
}

/// [`r16_row_plain`] for ownship to port of the contact or not (`PORT`): `BowStern::of`
/// with that fact put in; `EQUAL` is [`Metric::equal`].
#[inline(always)]
fn r16_row_sides<const PORT: bool, const EQUAL: bool>(
    r: &R16Row,
    c: &Courses,
    row: &mut [f64],
    refused: impl Fn(bool, bool, bool, bool) -> bool,
) {
    let R16Row {
        sides,
        consts,
        metric,
        v,
    } = *r;
    let n = row.len().min(c.gams.len()).min(c.tans.len());
    let n = n.min(c.star_turns.len()).min(c.port_turns.len());
    let (gams, tans, row) = (&c.gams[..n], &c.tans[..n], &mut row[..n]);
    let (stars, ports) = (&c.star_turns[..n], &c.port_turns[..n]);
    let sides = Sides {
        port_of_cn: PORT,
        ..sides
    };
    for k in 0..n {
        let bs = BowStern::of(&sides, &consts, (gams[k], tans[k]), v);
        let turns = (stars[k] != 0.0, ports[k] != 0.0);
        let no = refused(bs.crosses_bow, bs.crosses_stern, turns.0, turns.1);
        let m = metric.eval_row::<EQUAL>(row[k]);
        row[k] = if no { 0.0 } else { m };
    }
}

/// What a row of [`super::R14Aof`] utilities needs besides the courses: the engine's
/// facts and numbers, the metric, the reference bearing rate `b0` and the row's speed.
#[derive(Clone, Copy)]
pub(super) struct R14Row {
    pub sides: Sides,
    pub consts: RowConsts,
    pub metric: Metric,
    pub b0: f64,
    pub v: f64,
}

/// `row[k]` (the CPA distance of course k at speed `r.v`) into `R14Aof::utility_with`
/// of that course, every rule computed and the answer picked (no jumps; the same
/// comparisons and formulas on the same values).
pub(super) fn r14_row(r: &R14Row, c: &Courses, row: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { r14_row_avx2(r, c, row) };
    }
    r14_row_plain(r, c, row);
}

/// [`r14_row`]'s loop compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn r14_row_avx2(r: &R14Row, c: &Courses, row: &mut [f64]) {
    r14_row_with::<true>(r, c, row);
}

#[cfg(target_arch = "x86_64")]
#[path = "aof_rows_avx2.rs"]
mod avx2;

/// [`r14_row`]'s loop, for the target's baseline instructions (and inlined into
/// [`r14_row_avx2`]): one loop per combination of the engine's side facts, so that the
/// rules' choices between comparisons are made once per row, not per candidate.
#[inline(always)]
pub(super) fn r14_row_plain(r: &R14Row, c: &Courses, row: &mut [f64]) {
    r14_row_with::<false>(r, c, row);
}

/// [`r14_row_plain`], its candidates four at a time by [`avx2::r14_lanes`] if `WIDE`
/// (only under [`r14_row_avx2`]).
#[inline(always)]
fn r14_row_with<const WIDE: bool>(r: &R14Row, c: &Courses, row: &mut [f64]) {
    if r.metric.equal() {
        r14_row_metric::<WIDE, true>(r, c, row);
    } else {
        r14_row_metric::<WIDE, false>(r, c, row);
    }
}

/// [`r14_row_plain`] with the metric's kind decided (`EQUAL`: [`Metric::equal`]).
#[inline(always)]
fn r14_row_metric<const WIDE: bool, const EQUAL: bool>(r: &R14Row, c: &Courses, row: &mut [f64]) {
    let s = &r.sides;
    match (s.port_of_cn, s.aft_of_cn, s.on_beam) {
        (false, false, false) => r14_row_sides::<WIDE, EQUAL, false, false, false>(r, c, row),
        (false, false, true) => r14_row_sides::<WIDE, EQUAL, false, false, true>(r, c, row),
        (false, true, false) => r14_row_sides::<WIDE, EQUAL, false, true, false>(r, c, row),
        (false, true, true) => r14_row_sides::<WIDE, EQUAL, false, true, true>(r, c, row),
        (true, false, false) => r14_row_sides::<WIDE, EQUAL, true, false, false>(r, c, row),
        (true, false, true) => r14_row_sides::<WIDE, EQUAL, true, false, true>(r, c, row),
        (true, true, false) => r14_row_sides::<WIDE, EQUAL, true, true, false>(r, c, row),
        (true, true, true) => r14_row_sides::<WIDE, EQUAL, true, true, true>(r, c, row),
    }
}

/// [`r14_row_plain`] for ownship to port of the contact (`PORT`), aft of it (`AFT`) and
/// on its beam (`BEAM`): those facts are constants in
/// [`behavior_api::contacts::engine::BowStarRate::of`]'s rules written out here, so its
/// choices fold away. Refused (utility 0) is
/// `on_contact | (PORT & crosses_bow) | passes_star`.
#[inline(always)]
fn r14_row_sides<
    const WIDE: bool,
    const EQUAL: bool,
    const PORT: bool,
    const AFT: bool,
    const BEAM: bool,
>(
    r: &R14Row,
    c: &Courses,
    row: &mut [f64],
) {
    let R14Row {
        sides: s,
        consts,
        metric,
        b0,
        v,
    } = *r;
    let n = row
        .len()
        .min(c.gams.len())
        .min(c.cnhs.len())
        .min(c.tans.len());
    let (gams, cnhs, tans) = (&c.gams[..n], &c.cnhs[..n], &c.tans[..n]);
    let row = &mut row[..n];
    // Every candidate refused: on the contact, crossing the bow from port on the stern
    // line, or passing to starboard on the beam from starboard.
    if s.on_contact || (PORT && s.on_sternline) || (BEAM && !PORT) {
        row.fill(0.0);
        return;
    }
    // BowStarRate::of's refusals with the row's facts put in (the rows refused whole
    // are done above): crossing the bow (to port) is `moving & gam > 0 & br >= 0`, where
    // `moving` (`!(v <= 0)`) is the row's; passing to starboard is nothing on the beam
    // (ownship then to port), else `e > 0 & !port` with `port` the bearing rate's sign
    // for aft or fore. Each refusal is one comparison's pick of 0 or the utility, in
    // turn: no combined truth values, which the compiler would narrow and widen again
    // in every step of the AVX2 loop.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let bow_rule = PORT && !(v <= 0.0);
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        let lists = (gams, cnhs, tans);
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        let reward = !(b0 >= 0.0);
        // SAFETY: WIDE only under r14_row_avx2, whose caller checked AVX2.
        done = unsafe {
            use avx2::r14_lanes;
            match (bow_rule, reward) {
                (false, false) => r14_lanes::<EQUAL, false, AFT, BEAM, false>(r, lists, row),
                (false, true) => r14_lanes::<EQUAL, false, AFT, BEAM, true>(r, lists, row),
                (true, false) => r14_lanes::<EQUAL, true, AFT, BEAM, false>(r, lists, row),
                (true, true) => r14_lanes::<EQUAL, true, AFT, BEAM, true>(r, lists, row),
            }
        };
    }
    for k in done..n {
        let (gam, cnh, tan) = (gams[k], cnhs[k], tans[k]);
        let br = consts.bearing_rate(tan, v);
        let m1 = metric.eval_row::<EQUAL>(row[k]);
        let scaled = 100.0 * br / b0;
        let beyond = if br <= b0 { 100.0 } else { scaled };
        let opening = if br >= 0.0 { 0.0 } else { beyond };
        let m3 = if b0 >= 0.0 { 0.0 } else { opening };
        let mut u = m1 + m3;
        if bow_rule {
            let crossing = if br >= 0.0 { 0.0 } else { u };
            u = if gam <= 0.0 { u } else { crossing };
        }
        if !BEAM {
            let e = consts.beam_closing(AFT, cnh, v);
            let port = if AFT { br > 0.0 } else { br < 0.0 };
            let star = if port { u } else { 0.0 };
            u = if e > 0.0 { star } else { u };
        }
        row[k] = u;
    }
}

/// `row[k] = point(&prepared[k], v, row[k])` for every k (the row's CPA distances into
/// utilities). On a CPU with AVX2 the same loop runs compiled for it: a `point` without
/// jumps then does four candidates per instruction (IEEE operations give the same bits
/// at any width).
pub(super) fn point_row<P>(
    row: &mut [f64],
    prepared: &[P],
    v: f64,
    point: &impl Fn(&P, f64, f64) -> f64,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { point_row_avx2(row, prepared, v, point) };
    }
    point_row_plain(row, prepared, v, point);
}

/// [`point_row`]'s loop compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn point_row_avx2<P>(
    row: &mut [f64],
    prepared: &[P],
    v: f64,
    point: &impl Fn(&P, f64, f64) -> f64,
) {
    point_row_plain(row, prepared, v, point);
}

/// [`point_row`]'s loop, for the target's baseline instructions (and inlined into
/// [`point_row_avx2`]).
#[inline(always)]
fn point_row_plain<P>(
    row: &mut [f64],
    prepared: &[P],
    v: f64,
    point: &impl Fn(&P, f64, f64) -> f64,
) {
    for (o, p) in row.iter_mut().zip(prepared) {
        *o = point(p, v, *o);
    }
}
