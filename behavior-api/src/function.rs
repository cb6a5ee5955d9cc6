//! The ABI-safe form of an IvP function.
//!
//! A behavior's objective function crosses from plugin to host as plain buffers: pieces
//! are stored contiguously (`bounds`: lo,hi per dimension per piece; `weights`: one slope
//! per dimension then the intercept, per piece). `RVec` carries its own deallocator, so the
//! host can take ownership of the plugin's buffers without copying them.

use abi_stable::std_types::{RString, RVec};
use abi_stable::StableAbi;

/// Domain texts of functions the host has read, for the next ones built here, and
/// where a domain's text is written before it goes into the ABI string: one thread
/// local for both, reached once per function.
struct Texts {
    spare: Vec<RString>,
    scratch: String,
    /// The texts of the last few domains written: a behavior's functions keep their
    /// domain from one iteration to the next, and a lookup is cheaper than writing the
    /// numbers again. Equal domains have the same text (only 0 and -0 differ in bits,
    /// and both are written `0`).
    known: Vec<(ivp::Domain, String)>,
}

/// More domains than a thread's behaviors use at once are written each time.
const KNOWN_DOMAINS: usize = 8;

thread_local! {
    static TEXTS: std::cell::RefCell<Texts> = const {
        std::cell::RefCell::new(Texts { spare: Vec::new(), scratch: String::new(), known: Vec::new() })
    };
}

/// `domain`'s text (`name,low,high,points` joined by `:`) in a spare string of this
/// thread when one is kept.
pub(crate) fn domain_text(domain: &ivp::Domain) -> RString {
    let written = TEXTS.try_with(|t| {
        let Ok(mut t) = t.try_borrow_mut() else {
            return None;
        };
        let t = &mut *t;
        let mut text = t.spare.pop().unwrap_or_default();
        text.clear();
        text.reserve(32 * domain.size());
        if let Some((_, known)) = t.known.iter().find(|(d, _)| d == domain) {
            text.push_str(known);
        } else {
            t.scratch.clear();
            domain.push_text(&mut t.scratch);
            text.push_str(&t.scratch);
            if t.known.len() < KNOWN_DOMAINS {
                t.known.push((domain.clone(), t.scratch.clone()));
            }
        }
        Some(text)
    });
    written.ok().flatten().unwrap_or_else(|| {
        let mut text = RString::new();
        text.reserve(32 * domain.size());
        let _ = std::fmt::Write::write_fmt(&mut text, format_args!("{domain}"));
        text
    })
}

/// An IvP function of degree 1 as plain data.
#[repr(C)]
#[derive(StableAbi, Clone, Debug, Default, PartialEq)]
pub struct FunctionData {
    /// The function's own domain, `name,low,high,points` per variable joined by `:`
    /// (the helm's `domainToString` form), in the function's dimension order.
    pub domain: RString,
    /// `2 * dim` integers per piece: `lo_0, hi_0, lo_1, hi_1, ...` (inclusive indices).
    pub bounds: RVec<i32>,
    /// `dim + 1` numbers per piece: slopes in dimension order, then the intercept.
    pub weights: RVec<f64>,
    /// Priority weight.
    pub pwt: f64,
    /// Grid cell size minus one per dimension (`points - 1` for a single cell).
    pub gelbox: RVec<u32>,
    /// Grid cell upper bounds as the builder left them (empty = none): the solver's
    /// pruning, and so exact ties in rare near-tie cases, depend on them.
    pub grid: RVec<f64>,
}

impl FunctionData {
    /// Number of dimensions, from the domain string.
    pub fn dim(&self) -> usize {
        if self.domain.is_empty() {
            0
        } else {
            // Counted by byte: called for every function every iteration.
            1 + self
                .domain
                .as_bytes()
                .iter()
                .filter(|&&b| b == b':')
                .count()
        }
    }

    /// Number of pieces, or `None` when the buffers disagree with each other.
    pub fn piece_count(&self) -> Option<usize> {
        let dim = self.dim();
        if dim == 0 || !self.bounds.len().is_multiple_of(2 * dim) {
            return None;
        }
        let n = self.bounds.len() / (2 * dim);
        (self.weights.len() == n * (dim + 1)).then_some(n)
    }
}

impl FunctionData {
    /// Move an `ivp` function into the ABI form: the piece buffers are moved, not copied.
    ///
    /// The domain text is written into a spare string of this thread and the rest of
    /// the function (its domain) is recycled for later builds (see
    /// [`ivp::IvpFunction::recycle`]).
    pub fn from_ivp(mut f: ivp::IvpFunction) -> FunctionData {
        let domain = domain_text(f.domain());
        let pwt = f.pwt();
        let (bounds, weights, gelbox, grid) = f.take_buffers();
        f.recycle();
        FunctionData {
            domain,
            bounds: bounds.into(),
            weights: weights.into(),
            pwt,
            gelbox: gelbox.into(),
            grid: grid.into(),
        }
    }

    /// Keep a function's domain text (once the host has read it) for a later
    /// [`FunctionData::from_ivp`] on this thread. The text keeps its own allocator,
    /// so one from a plugin is reused as it is, not copied.
    pub fn recycle_domain(text: RString) {
        let _ = TEXTS.try_with(|t| {
            if let Ok(mut t) = t.try_borrow_mut() {
                if t.spare.len() < 64 && text.capacity() > 0 {
                    t.spare.push(text);
                }
            }
        });
    }

    /// The host's side of [`FunctionData::from_ivp`]: the function placed on the helm
    /// domain's variables, or why it is rejected. Its domain and buffers go into
    /// storage recycled on this thread (see [`ivp::IvpFunction::recycle`]) and its domain
    /// text is kept for the next `from_ivp`.
    pub fn into_ivp_on(self, helm: &ivp::Domain) -> Result<ivp::IvpFunction, String> {
        self.place_on(helm, false)
    }

    /// [`FunctionData::into_ivp_on`] for a function made by a loaded library: its
    /// buffers belong to the library's allocator (moving them into the host would copy
    /// them into new allocations), so they are copied into the host's recycled storage
    /// and handed back to the library's allocator.
    pub fn copied_onto(self, helm: &ivp::Domain) -> Result<ivp::IvpFunction, String> {
        self.place_on(helm, true)
    }

    fn place_on(self, helm: &ivp::Domain, copy: bool) -> Result<ivp::IvpFunction, String> {
        let mut vars = Vec::new();
        self.helm_vars_into(helm, &mut vars)?;
        self.place_with(helm, &vars, copy)
    }

    /// The helm-domain index of each of the function's variables, in its dimension
    /// order, into `out` (cleared first); or why the function is rejected: a variable
    /// the helm lacks, or one not on the helm's grid for it. A host that saw the same
    /// domain text before may keep the answer and call [`FunctionData::place_with`].
    pub fn helm_vars_into(&self, helm: &ivp::Domain, out: &mut Vec<usize>) -> Result<(), String> {
        out.clear();
        for spec in self.domain.as_str().split(':').filter(|s| !s.is_empty()) {
            let mut f = spec.split(',');
            let name = f.next().unwrap_or("");
            let Some(i) = helm.index_of(name) else {
                return Err(format!("DomainVar {name} not recognized "));
            };
            let var = helm.var(i);
            // The function must be on the helm's grid for that variable, not only share
            // its name.
            let num = |s: Option<&str>| s.and_then(|s| s.parse::<f64>().ok());
            let same = num(f.next()).is_some_and(|v| (v - var.low).abs() <= 1e-5)
                && num(f.next()).is_some_and(|v| (v - var.high).abs() <= 1e-5)
                && num(f.next()).is_some_and(|v| v == f64::from(var.points));
            if !same {
                return Err(format!(
                    "IvP function rejected: its variable `{spec}` is not the helm's `{name}` grid"
                ));
            }
            out.push(i);
        }
        Ok(())
    }

    /// The function placed on the helm domain's variables `vars` (what
    /// [`FunctionData::helm_vars_into`] found for this domain text); `copy` for a
    /// function made by a loaded library (see [`FunctionData::copied_onto`]).
    pub fn place_with(
        self,
        helm: &ivp::Domain,
        vars: &[usize],
        copy: bool,
    ) -> Result<ivp::IvpFunction, String> {
        if copy {
            // The copy is placed; the library's buffers are then freed here (a host
            // that can hand them back uses `copy_placed` and the library's
            // `BehaviorLib::recycle_function`).
            return self.copy_placed(helm, vars);
        }
        let fd = self;
        let domain = placed_domain(helm, vars)?;
        FunctionData::recycle_domain(fd.domain);
        let (bounds, weights, gelbox, grid) = (
            fd.bounds.into_vec(),
            fd.weights.into_vec(),
            fd.gelbox.into_vec(),
            fd.grid.into_vec(),
        );
        ivp::IvpFunction::from_buffers(domain, bounds, weights, gelbox, grid, fd.pwt)
            .map_err(rejected)
    }

    /// [`FunctionData::place_with`] for a function made by a loaded library, leaving it
    /// whole: its buffers are copied into the host's recycled storage, and the caller
    /// hands the function back to the library (`BehaviorLib::recycle_function`, 0.1.3),
    /// whose next build then reuses them.
    pub fn copy_placed(
        &self,
        helm: &ivp::Domain,
        vars: &[usize],
    ) -> Result<ivp::IvpFunction, String> {
        let domain = placed_domain(helm, vars)?;
        copied_function(
            domain,
            &self.bounds,
            &self.weights,
            &self.gelbox,
            &self.grid,
            self.pwt,
        )
        .map_err(rejected)
    }

    /// The domain of a function over the helm's variables `vars` (what
    /// [`FunctionData::helm_vars_into`] found), or why it is rejected: for a host that
    /// reads the function's buffers in place instead of [`FunctionData::copy_placed`].
    pub fn placed_domain(helm: &ivp::Domain, vars: &[usize]) -> Result<ivp::Domain, String> {
        placed_domain(helm, vars)
    }

    /// What [`FunctionData::copy_placed`] says of buffers failing `e`'s check.
    pub fn rejection(e: ivp::IvpError) -> String {
        rejected(e)
    }

    /// The library's side of [`FunctionData::copy_placed`]: this function's buffers and
    /// domain text go back into the spare storage of the thread (and library) that
    /// built it, where [`FunctionData::from_ivp`] and the `ivp` builders take them.
    pub fn give_back(self) {
        ivp::zaic::spare::give_function_buffers(
            self.bounds.into_vec(),
            self.weights.into_vec(),
            self.gelbox.into_vec(),
            self.grid.into_vec(),
        );
        FunctionData::recycle_domain(self.domain);
    }

    /// Variable names of the function's domain, in dimension order.
    pub fn var_names(&self) -> impl Iterator<Item = &str> {
        self.domain
            .as_str()
            .split(':')
            .filter(|s| !s.is_empty())
            .map(|v| v.split(',').next().unwrap_or(""))
    }
}

/// A function over `domain` whose buffers are copies of these, in this thread's spare
/// storage (no allocation once the spares hold room), checked like any function.
pub(crate) fn copied_function(
    domain: ivp::Domain,
    bounds: &[i32],
    weights: &[f64],
    gelbox: &[u32],
    grid: &[f64],
    pwt: f64,
) -> Result<ivp::IvpFunction, ivp::IvpError> {
    let (bounds, weights, gelbox, grid) =
        ivp::zaic::spare::function_buffers_from(bounds, weights, gelbox, grid);
    ivp::IvpFunction::from_buffers(domain, bounds, weights, gelbox, grid, pwt)
}

fn rejected(e: ivp::IvpError) -> String {
    format!("IvP function rejected: {e}")
}

/// The function's domain: the helm's variables `vars`, in the function's order.
fn placed_domain(helm: &ivp::Domain, vars: &[usize]) -> Result<ivp::Domain, String> {
    if vars.iter().any(|&i| i >= helm.size()) {
        return Err(format!(
            "IvP function rejected: a variable index past the helm's {}",
            helm.size()
        ));
    }
    ivp::Domain::from_var_refs(vars.iter().map(|&i| helm.var(i))).map_err(rejected)
}

impl From<ivp::IvpFunction> for FunctionData {
    fn from(f: ivp::IvpFunction) -> Self {
        FunctionData::from_ivp(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The text of a domain seen before is the one written afresh, for more domains
    /// than are remembered, -0 and fractions included.
    #[test]
    fn remembered_domain_texts_are_the_written_ones() {
        let specs = [
            "depth:0:50:51",
            "depth:-0:50:51",
            "course:0:359:360,speed:0:4:41",
            "speed:0:4:41,course:0:359:360",
            "x:0.5:2.25:8",
            "x:-3.125:7:5",
            "speed:0:5:51",
            "depth:0:100:101",
            "y:1:1:1",
            "z:-1e20:1e20:3",
        ];
        for round in 0..3 {
            for spec in specs {
                let d = ivp::Domain::parse(spec).unwrap();
                let text = domain_text(&d);
                assert_eq!(text.as_str(), d.to_string(), "{spec}, round {round}");
                FunctionData::recycle_domain(text);
            }
        }
    }

    /// `give_back` keeps the buffers as the four separate gives did: the next copy
    /// finds them again.
    #[test]
    fn given_back_buffers_are_reused() {
        let d = ivp::Domain::parse("x:0:9:10").unwrap();
        let f = ivp::IvpFunction::from_pieces(d, &[(vec![(0, 9)], vec![1.0, 2.0])]).unwrap();
        let fd = crate::sdk::copy_function_data(&f, 3.0);
        let (b, w) = (fd.bounds.as_ptr(), fd.weights.as_ptr());
        fd.give_back();
        let again = crate::sdk::copy_function_data(&f, 3.0);
        assert_eq!((again.bounds.as_ptr(), again.weights.as_ptr()), (b, w));
    }
}
