//! A problem of one function (the others' priority weights not positive): a waypoint
//! alone. Its pieces are the search's leaves, so the decision is the first piece with
//! the greatest `maxVal` (`Search::run` with one function); here it is found without
//! the set-up of a search (grid, bound terms, last index, groups) the scan never
//! reads. The pieces' `maxVal`s are made by the set-up's own code (see
//! `Solver::prepare_fresh`), so they are the same bit for bit.

use super::*;
use crate::setup::keys_now;

/// How [`Solver::run_lone`] gets the lone function's pieces.
#[derive(Clone, Copy)]
pub(super) enum Lone {
    /// Prepared afresh (as the first function), its key off.
    Fresh(usize),
    /// Kept as it was prepared (as the first function, see [`Solver::prepare`]).
    Kept(usize),
}

impl Solver {
    /// The only function of `functions` the search would use, and how it is had, when
    /// the lone path may take the problem: a function the set-up would key now is left
    /// to it, so keys are made and used as always.
    pub(super) fn lone(&mut self, helm: &Domain, functions: &[FunctionView<'_>]) -> Option<Lone> {
        #[cfg(test)]
        if self.no_lone {
            return None;
        }
        if self.prob_to_helm.is_empty() {
            return None;
        }
        let mut active = functions
            .iter()
            .enumerate()
            .filter(|(_, f)| f.pwt() > 0.0 || f.pwt().is_nan());
        let (fi, f) = active.next()?;
        if active.next().is_some() {
            return None;
        }
        // As `Solver::prepare` asks, in its order.
        if self.funcs[fi].key.on {
            let mut same = None;
            if self.same_problem(helm, &mut same)
                && self.funcs[fi]
                    .key
                    .matches(&self.funcs[fi].src_bounds, f, true)
            {
                return Some(Lone::Kept(fi));
            }
        }
        let misses = self.funcs[fi].key.misses.saturating_add(1);
        if keys_now(misses, f.piece_count()) {
            // The set-up keys it now.
            return None;
        }
        Some(Lone::Fresh(fi))
    }

    /// [`Solver::run`] for the lone function (see [`Solver::lone`]): kept, or prepared
    /// as the first function with its key off; then the first piece with the greatest
    /// `maxVal`, taken as `Search::run` takes leaves (the first always, then one
    /// greater), and the decision at the edges its weights point to.
    pub(super) fn run_lone(
        &mut self,
        helm: &Domain,
        lone: Lone,
        functions: &[FunctionView<'_>],
        out: &mut Decision,
    ) -> Result<bool, IvpError> {
        let dim = self.prob_to_helm.len();
        let fi = match lone {
            Lone::Fresh(fi) => {
                let key = &mut self.funcs[fi].key;
                key.on = false;
                key.misses = key.misses.saturating_add(1);
                self.prepare_fresh::<true>(fi, &functions[fi], helm, dim, true)?;
                fi
            }
            Lone::Kept(fi) => {
                self.funcs[fi].key.misses = 0;
                #[cfg(test)]
                {
                    self.kept += 1;
                }
                fi
            }
        };
        let f = &functions[fi];
        self.active.clear();
        self.active.push(fi);
        #[cfg(test)]
        {
            self.stats = (0, 0, 0, 0, 0);
            self.lone_solves += 1;
        }
        let p = &self.funcs[fi];
        let (bl, wl) = (2 * dim, dim + 1);
        let boxes = if p.borrowed {
            f.bounds()
        } else {
            &p.bounds[..]
        };
        let count = (boxes.len() / bl).min(p.weights.len() / wl).min(p.n);
        // The pieces' `maxVal`s: made by the set-up (a first function's always are),
        // else as `Search::run` makes them.
        let at = if p.piece_ub.len() == p.n {
            first_greatest(p.piece_ub[..count].iter().copied())
        } else {
            let mv = |q: usize| max_val(&boxes[q * bl..][..bl], &p.weights[q * wl..][..wl]);
            first_greatest((0..count).map(mv))
        };
        let Some((q, best)) = at else {
            return Ok(false);
        };
        let (qb, qw) = (&boxes[q * bl..][..bl], &p.weights[q * wl..][..wl]);
        decide_at(&self.prob_to_helm, &mut self.prev, helm, (qb, qw), out);
        out.utility = best;
        Ok(true)
    }
}

/// The position and value of the leaf `Search::run` keeps of `values` in order: the
/// first taken whatever its value (NaN too), then each greater one.
#[inline(always)]
fn first_greatest(mut values: impl Iterator<Item = f64>) -> Option<(usize, f64)> {
    let mut best = values.next()?;
    let mut at = 0;
    for (q, v) in values.enumerate() {
        if v > best {
            (best, at) = (v, q + 1);
        }
    }
    Some((at, best))
}
