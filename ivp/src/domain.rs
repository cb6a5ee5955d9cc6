//! IvP domain: an ordered list of discrete decision variables (spec §1).

use crate::error::{finite, IvpError};
use std::fmt;

/// One decision variable: `points` values `low + delta*j`, `j = 0..points-1`.
#[derive(Debug, Clone)]
pub struct DomainVar {
    pub name: String,
    pub low: f64,
    pub high: f64,
    pub points: u32,
}

/// Every field equal (as derived), the numbers compared before the name: domains are
/// compared every iteration (a library's known domain texts), and a name compare is a
/// call.
impl PartialEq for DomainVar {
    fn eq(&self, o: &Self) -> bool {
        self.points == o.points && self.low == o.low && self.high == o.high && self.name == o.name
    }
}

impl DomainVar {
    /// `(high-low)/(points-1)`, or 0 when `points == 1`.
    pub fn delta(&self) -> f64 {
        if self.points > 1 {
            (self.high - self.low) / f64::from(self.points - 1)
        } else {
            0.0
        }
    }

    /// Value of discrete index `j`: `low + delta*j` (multiply, then add).
    #[inline]
    pub fn value(&self, j: u32) -> f64 {
        self.low + self.delta() * f64::from(j)
    }

    /// The values of the indices `xs`, in their order: [`Self::value`] of each, the step
    /// computed once.
    #[inline]
    pub fn values_at<'a>(&self, xs: &'a [u32]) -> impl ExactSizeIterator<Item = f64> + Clone + 'a {
        let (low, delta) = (self.low, self.delta());
        xs.iter().map(move |&j| low + delta * f64::from(j))
    }
}

/// Value → index conversion rule ("snap type" 0, 1, 2 of the spec).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Snap {
    Floor,
    Ceil,
    /// Nearest, ties go down.
    Nearest,
}

/// An ordered set of decision variables.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Domain {
    vars: Vec<DomainVar>,
}

fn validate(name: &str, low: f64, high: f64, points: u32) -> Result<(), IvpError> {
    if name.is_empty() || name.contains([':', ',', ';']) || name.contains(char::is_whitespace) {
        return Err(IvpError::BadVarName(name.to_string()));
    }
    // Name the parameter only when it is bad: this runs on every function built.
    if !low.is_finite() {
        finite(&format!("{name}.low"), low)?;
    }
    if !high.is_finite() {
        finite(&format!("{name}.high"), high)?;
    }
    if points < 1 {
        let var = name.to_string();
        return Err(IvpError::PointsTooFew { var, points });
    }
    if low > high {
        let var = name.to_string();
        return Err(IvpError::LowAboveHigh { var, low, high });
    }
    if points == 1 && high != low {
        let var = name.to_string();
        return Err(IvpError::SinglePointRange { var, low, high });
    }
    Ok(())
}

fn perr(spec: &str, field: &str, reason: &str) -> IvpError {
    IvpError::Parse {
        spec: spec.to_string(),
        field: field.to_string(),
        reason: reason.to_string(),
    }
}

/// Compact number format: 5 decimals, trailing zeros and a trailing `.` removed (the one
/// formatter of MOOS-IvP's number strings).
/// `mbutil::compact(v, 5)` appended to `out`; whole numbers (the usual domain bounds) without an
/// intermediate string, by the same rule as `mbutil::compact`.
pub(crate) fn push_compact(out: &mut String, v: f64) {
    mbutil::push_compact(out, v, 5);
}

thread_local! {
    /// Domains of functions done with, for the next ones built on this thread (see
    /// `mbutil::spare`).
    static SPARE_DOMAINS: std::cell::RefCell<Vec<Domain>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A domain of copies of `vars`, in a spare domain's storage (its variable names
/// reused). Room for a few variables is kept, so that coupling two functions' domains
/// into one does not grow it.
// Public but hidden: for ivp-reflector only, not part of ivp's API.
#[doc(hidden)]
pub fn domain_of<'a>(vars: impl IntoIterator<Item = &'a DomainVar>) -> Domain {
    let spare = SPARE_DOMAINS.try_with(|s| s.borrow_mut().pop());
    let mut d = spare.ok().flatten().unwrap_or_default();
    d.assign_from(vars);
    d
}

/// Keep a domain's storage for later builds.
// Public but hidden: for ivp-reflector only, not part of ivp's API.
#[doc(hidden)]
pub fn give_domain(domain: Domain) {
    if domain.vars.capacity() > 0 {
        let _ = SPARE_DOMAINS.try_with(|s| mbutil::spare::keep(&mut s.borrow_mut(), domain));
    }
}

impl Domain {
    /// Empty domain.
    pub fn new() -> Self {
        Self::default()
    }

    /// Append a variable (fails on duplicate name, `low > high`, `points < 1`,
    /// `points == 1 && high != low`, non-finite bounds).
    pub fn add_var(
        &mut self,
        name: &str,
        low: f64,
        high: f64,
        points: u32,
    ) -> Result<(), IvpError> {
        validate(name, low, high, points)?;
        if self.index_of(name).is_some() {
            return Err(IvpError::DuplicateVar(name.to_string()));
        }
        self.vars.push(DomainVar {
            name: name.to_string(),
            low,
            high,
            points,
        });
        Ok(())
    }

    /// Parse `"course:0:359:360,speed:0:4:41"` (variables separated by `,`,
    /// each in the [`Domain::parse_var`] form).
    pub fn parse(spec: &str) -> Result<Domain, IvpError> {
        let mut d = Domain::new();
        for part in spec.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (v, _) = Domain::parse_var(part)?;
            d.add_var(&v.name, v.low, v.high, v.points)?;
        }
        Ok(d)
    }

    /// Parse one helm `domain =` value: `name:low:high:points[:optional]`, with `,`
    /// accepted as separator too. Field 4 may be `delta=d` (`0 < d <= high-low`,
    /// points = `trunc((high-low)/d + 1)`). Returns the variable and its optional flag.
    pub fn parse_var(s: &str) -> Result<(DomainVar, bool), IvpError> {
        let norm = s.trim().replace(',', ":");
        let f: Vec<&str> = norm.split(':').map(str::trim).collect();
        if f.len() != 4 && f.len() != 5 {
            return Err(perr(
                s,
                "fields",
                "expected name:low:high:points[:optional]",
            ));
        }
        let name = f[0];
        let low: f64 = f[1]
            .parse()
            .map_err(|_| perr(s, "low", "is not a number"))?;
        let high: f64 = f[2]
            .parse()
            .map_err(|_| perr(s, "high", "is not a number"))?;
        let points = if let Some(dtxt) = f[3].strip_prefix("delta=") {
            let d: f64 = dtxt
                .trim()
                .parse()
                .map_err(|_| perr(s, "delta", "is not a number"))?;
            if !(high > low && d > 0.0 && d <= high - low) {
                return Err(perr(s, "delta", "must satisfy 0 < delta <= high-low"));
            }
            let p = ((high - low) / d + 1.0).trunc();
            if p > f64::from(u32::MAX) {
                return Err(perr(s, "delta", "gives too many points"));
            }
            p as u32
        } else {
            f[3].parse::<u32>()
                .map_err(|_| perr(s, "points", "is not a non-negative integer"))?
        };
        validate(name, low, high, points)?;
        let optional = f.len() == 5 && f[4].eq_ignore_ascii_case("optional");
        Ok((
            DomainVar {
                name: name.to_string(),
                low,
                high,
                points,
            },
            optional,
        ))
    }

    /// Number of variables.
    pub fn size(&self) -> usize {
        self.vars.len()
    }

    /// Variable `i` (panics if out of range, like slice indexing).
    pub fn var(&self, i: usize) -> &DomainVar {
        &self.vars[i]
    }

    /// All variables in order.
    pub fn vars(&self) -> &[DomainVar] {
        &self.vars
    }

    /// Position of the variable called `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.vars.iter().position(|v| v.name == name)
    }

    /// `low + delta*index` of dimension `dim`.
    #[inline]
    pub fn value(&self, dim: usize, index: u32) -> f64 {
        self.vars[dim].value(index)
    }

    /// Value → index of dimension `dim` (spec §1 snap rules), clamped to the grid.
    pub fn snap(&self, dim: usize, value: f64, snap: Snap) -> u32 {
        let v = &self.vars[dim];
        let top = v.points.saturating_sub(1);
        if value.is_nan() || value <= v.low {
            return 0;
        }
        if value >= v.high {
            return top;
        }
        let delta = v.delta();
        if delta <= 0.0 {
            return 0;
        }
        let idx = match snap {
            Snap::Floor => ((value - v.low) / delta).trunc(),
            Snap::Ceil | Snap::Nearest => {
                let val = if snap == Snap::Nearest {
                    value - delta / 2.0
                } else {
                    value
                };
                let d = (val - v.low) / delta;
                let t = d.trunc();
                if d > t {
                    t + 1.0
                } else {
                    t
                }
            }
        };
        if idx <= 0.0 {
            0
        } else if idx >= f64::from(top) {
            top
        } else {
            idx as u32
        }
    }

    /// The listed variables in the listed order; empty if any is missing.
    pub fn sub_domain(&self, names: &[&str]) -> Domain {
        let mut out = Domain::new();
        for n in names {
            match self.index_of(n) {
                Some(i) if out.index_of(n).is_none() => out.vars.push(self.vars[i].clone()),
                Some(_) => {}
                None => return Domain::new(),
            }
        }
        out
    }

    /// `self` followed by the variables of `other` not already present.
    pub fn union(&self, other: &Domain) -> Domain {
        let mut out = self.clone();
        for v in &other.vars {
            if out.index_of(&v.name).is_none() {
                out.vars.push(v.clone());
            }
        }
        out
    }

    /// Append the variables of `other`, none of which is in `self` (the union of two
    /// disjoint domains, moving the variables instead of copying them).
    pub(crate) fn append_disjoint(&mut self, mut other: Domain) {
        debug_assert!(other.vars.iter().all(|v| self.index_of(&v.name).is_none()));
        self.vars.append(&mut other.vars);
        give_domain(other);
    }

    /// Become a copy of `vars`, reusing this domain's variables and names (room for a
    /// few variables is kept). Names of variables dropped or added go through the spare
    /// strings of [`mbutil::spare`].
    pub(crate) fn assign_from<'a>(&mut self, vars: impl IntoIterator<Item = &'a DomainVar>) {
        self.vars.reserve(4);
        let mut n = 0;
        for v in vars {
            if let Some(slot) = self.vars.get_mut(n) {
                slot.name.clear();
                slot.name.push_str(&v.name);
                (slot.low, slot.high, slot.points) = (v.low, v.high, v.points);
            } else {
                let mut name = mbutil::spare::string();
                name.push_str(&v.name);
                self.vars.push(DomainVar { name, ..*v });
            }
            n += 1;
        }
        for v in self.vars.drain(n..) {
            mbutil::spare::give_string(v.name);
        }
    }

    /// A domain of copies of `vars`, checked as [`Domain::from_vars`] checks them, built
    /// in the storage of a function recycled on this thread when there is one (see
    /// [`crate::IvpFunction::recycle`]).
    pub fn from_var_refs<'a>(
        vars: impl IntoIterator<Item = &'a DomainVar>,
    ) -> Result<Domain, IvpError> {
        let mut d = domain_of(&[]);
        for v in vars {
            let mut name = mbutil::spare::string();
            name.push_str(&v.name);
            d.vars.push(DomainVar { name, ..*v });
        }
        for (k, v) in d.vars.iter().enumerate() {
            validate(&v.name, v.low, v.high, v.points)?;
            if d.vars[..k].iter().any(|u| u.name == v.name) {
                return Err(IvpError::DuplicateVar(v.name.clone()));
            }
        }
        Ok(d)
    }

    /// The variables, moved out.
    pub(crate) fn into_vars(self) -> Vec<DomainVar> {
        self.vars
    }

    /// Build from already-validated variables.
    pub fn from_vars(vars: Vec<DomainVar>) -> Result<Domain, IvpError> {
        // The same checks as `add_var` one by one, keeping the variables (and their
        // names) instead of copying them: every plugin function crosses the ABI this way.
        for (k, v) in vars.iter().enumerate() {
            validate(&v.name, v.low, v.high, v.points)?;
            if vars[..k].iter().any(|u| u.name == v.name) {
                return Err(IvpError::DuplicateVar(v.name.clone()));
            }
        }
        Ok(Domain { vars })
    }

    /// `name;low;high;points` joined by `:` (the BHV_IPF `D` field).
    pub fn to_ipf_string(&self) -> String {
        let mut s = String::new();
        self.write_ipf(&mut s);
        s
    }

    /// [`Domain::to_ipf_string`] appended to `out` (no intermediate strings: BHV_IPF
    /// encodes it for every function of every iteration).
    pub fn write_ipf(&self, out: &mut String) {
        for (i, v) in self.vars.iter().enumerate() {
            if i > 0 {
                out.push(':');
            }
            out.push_str(&v.name);
            out.push(';');
            push_compact(out, v.low);
            out.push(';');
            push_compact(out, v.high);
            out.push(';');
            out.push_str(itoa::Buffer::new().format(v.points));
        }
    }
}

/// `domainToString`: `name,low,high,points` joined by `:`.
impl fmt::Display for Domain {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut text = String::with_capacity(32 * self.vars.len());
        self.push_text(&mut text);
        f.write_str(&text)
    }
}

impl Domain {
    /// The domain's text (`course,0,359,360:speed,0,4,41`, what `Display` shows)
    /// appended to `out`: plugins turn every function's domain into this text each
    /// iteration (FunctionData), so no formatter and no intermediate strings.
    pub fn push_text(&self, out: &mut String) {
        for (i, v) in self.vars.iter().enumerate() {
            if i > 0 {
                out.push(':');
            }
            out.push_str(&v.name);
            for x in [v.low, v.high] {
                out.push(',');
                if x == 0.0 {
                    out.push('0');
                } else if x.fract() == 0.0 && x.abs() < 1e15 {
                    out.push_str(itoa::Buffer::new().format(x as i64));
                } else {
                    push_compact(out, x);
                }
            }
            out.push(',');
            out.push_str(itoa::Buffer::new().format(v.points));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Variables are equal exactly when every field is (names, bounds, points).
    #[test]
    fn variables_equal_only_in_every_field() {
        let v = |name: &str, low, high, points| DomainVar {
            name: name.into(),
            low,
            high,
            points,
        };
        let a = v("course", 0.0, 359.0, 360);
        assert_eq!(a, a.clone());
        for b in [
            v("coarse", 0.0, 359.0, 360),
            v("course", -0.5, 359.0, 360),
            v("course", 0.0, 358.0, 360),
            v("course", 0.0, 359.0, 359),
            v("course", f64::NAN, 359.0, 360),
        ] {
            assert_ne!(a, b);
        }
    }

    #[test]
    fn value_and_display() {
        let d = Domain::parse("course:0:359:360,speed:0:2:21").unwrap();
        assert_eq!(d.value(1, 3), 0.30000000000000004);
        assert_eq!(d.to_string(), "course,0,359,360:speed,0,2,21");
        let s = Domain::parse("speed:0:1.5:16").unwrap();
        assert_eq!(s.to_string(), "speed,0,1.5,16");
    }

    #[test]
    fn bad_vars_are_named() {
        let mut d = Domain::new();
        assert!(matches!(
            d.add_var("x", 0.0, 1.0, 0),
            Err(IvpError::PointsTooFew { .. })
        ));
        assert!(matches!(
            d.add_var("x", 2.0, 1.0, 3),
            Err(IvpError::LowAboveHigh { .. })
        ));
        assert!(matches!(
            d.add_var("x", 0.0, 1.0, 1),
            Err(IvpError::SinglePointRange { .. })
        ));
        assert!(matches!(
            d.add_var("x", f64::NAN, 1.0, 3),
            Err(IvpError::NotFinite { .. })
        ));
        d.add_var("x", 0.0, 1.0, 3).unwrap();
        assert!(matches!(
            d.add_var("x", 0.0, 1.0, 3),
            Err(IvpError::DuplicateVar(_))
        ));
        let e = Domain::parse("speed:0:abc:3").unwrap_err();
        assert!(e.to_string().contains("high"), "{e}");
    }

    #[test]
    fn parse_delta_and_optional() {
        let (v, opt) = Domain::parse_var("depth:0:100:delta=0.5:Optional").unwrap();
        assert_eq!(v.points, 201);
        assert!(opt);
        assert!(Domain::parse_var("depth:0:100:delta=200").is_err());
    }

    #[test]
    fn snap_rules() {
        let d = Domain::parse("speed:0:2:21").unwrap();
        assert_eq!(d.snap(0, 0.25, Snap::Floor), 2);
        assert_eq!(d.snap(0, 0.25, Snap::Ceil), 3);
        assert_eq!(d.snap(0, 0.26, Snap::Nearest), 3);
        assert_eq!(d.snap(0, -1.0, Snap::Nearest), 0);
        assert_eq!(d.snap(0, 5.0, Snap::Nearest), 20);
    }

    #[test]
    fn sub_and_union() {
        let d = Domain::parse("course:0:359:360,speed:0:2:21").unwrap();
        assert_eq!(d.sub_domain(&["speed", "course"]).var(0).name, "speed");
        assert_eq!(d.sub_domain(&["speed", "depth"]).size(), 0);
        let e = Domain::parse("depth:0:10:11,speed:0:2:21").unwrap();
        assert_eq!(
            d.union(&e).to_string(),
            "course,0,359,360:speed,0,2,21:depth,0,10,11"
        );
    }

    #[test]
    fn push_compact_is_compact() {
        let mut seed = 5u64;
        let mut out = String::from("w=");
        for k in 0..50_000 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let scale = [1e-7, 1e-4, 1.0, 1e3, 1e9, 1e17][k % 6];
            let v = ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale;
            for v in [
                v,
                v.round(),
                -0.0,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ] {
                out.truncate(2);
                push_compact(&mut out, v);
                assert_eq!(&out[2..], mbutil::compact(v, 5), "{v}");
            }
        }
    }

    #[test]
    fn copies_reuse_and_check() {
        let d = Domain::parse("course:0:359:360,speed:0:2:21").unwrap();
        let mut e = Domain::parse("a:0:1:2,b:0:1:2,c:0:1:2").unwrap();
        e.assign_from(d.vars());
        assert_eq!(e, d);
        e.assign_from(&d.vars()[1..]);
        assert_eq!(e, d.sub_domain(&["speed"]));
        let f = Domain::from_var_refs([d.var(1), d.var(0)]).unwrap();
        assert_eq!(f, d.sub_domain(&["speed", "course"]));
        assert!(matches!(
            Domain::from_var_refs([d.var(0), d.var(0)]),
            Err(IvpError::DuplicateVar(_))
        ));
    }
}
