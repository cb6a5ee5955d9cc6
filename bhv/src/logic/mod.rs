//! Logic expressions (conditions), bhv-format.md §8.
//!
//! A [`LogicCondition`] is parsed once into a tree whose comparisons refer
//! to variable *slots* by index. Behavior and mode conditions are
//! persistent: [`LogicCondition::update`] copies the current values into
//! the slots (with the type stickiness of §8.5) and [`LogicCondition::eval`]
//! evaluates without allocating. Flag `[if]` conditions use
//! [`LogicCondition::eval_fresh`], which reads the source directly.

mod eval;
mod parse;
mod stamps;

pub use crate::error::LogicError;
pub use eval::field_match;
pub use stamps::Stamps;

use crate::number::Value;
use std::collections::{BTreeMap, HashMap};

/// Where condition variables get their values (the helm's info buffer).
pub trait VarSource {
    /// The variable's string value, if it has one.
    fn string_val(&self, var: &str) -> Option<&str>;
    /// The variable's numeric value, if it has one.
    fn double_val(&self, var: &str) -> Option<f64>;
    /// The write stamps of a source that keeps them: every variable with a value then
    /// has a [`place`](VarSource::place), and every write of a value stamps it.
    fn stamps(&self) -> Option<&Stamps> {
        None
    }
    /// The variable's place in [`stamps`](VarSource::stamps), if the source has it.
    fn place(&self, _var: &str) -> Option<usize> {
        None
    }
}

impl VarSource for HashMap<String, Value> {
    fn string_val(&self, var: &str) -> Option<&str> {
        self.get(var).and_then(Value::as_str)
    }
    fn double_val(&self, var: &str) -> Option<f64> {
        self.get(var).and_then(Value::as_num)
    }
}

impl VarSource for BTreeMap<String, Value> {
    fn string_val(&self, var: &str) -> Option<&str> {
        self.get(var).and_then(Value::as_str)
    }
    fn double_val(&self, var: &str) -> Option<f64> {
        self.get(var).and_then(Value::as_num)
    }
}

/// Comparison operators (§8.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    /// `=`
    Eq,
    /// `==` (field match, §8.4)
    Field,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

/// Right side of a comparison.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Rhs {
    /// `$(NAME)`: slot index.
    Var(usize),
    /// Numeric constant.
    Num(f64),
    /// String literal, quotes removed.
    Str(String),
}

/// Expression tree.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Node {
    And(Box<Node>, Box<Node>),
    Or(Box<Node>, Box<Node>),
    Not(Box<Node>),
    Cmp { op: Op, var: usize, rhs: Rhs },
}

/// A persistent variable slot (§8.5).
#[derive(Clone, Debug, PartialEq)]
enum Slot {
    Unset,
    Str(String),
    Num(f64),
}

/// A parsed logic expression with persistent, type-sticky variable slots.
///
/// ```
/// use bhv::logic::LogicCondition;
/// let mut c = LogicCondition::parse("(DEPLOY = true) and (SPEED > 2)").unwrap();
/// assert!(!c.eval()); // unset variables make comparisons false
/// c.set_string("DEPLOY", "true");
/// c.set_double("SPEED", 3.0);
/// assert!(c.eval());
/// ```
#[derive(Clone, Debug)]
pub struct LogicCondition {
    raw: String,
    vars: Vec<String>,
    slots: Vec<Slot>,
    root: Node,
    follow: stamps::Follow,
}

impl LogicCondition {
    /// Parses a behavior-style condition (`==` allowed, commas kept as
    /// given; see [`parse_condition_param`] for the `condition =` value).
    pub fn parse(text: &str) -> Result<LogicCondition, LogicError> {
        let (root, vars) = parse::parse_expression(text)?;
        let slots = vec![Slot::Unset; vars.len()];
        Ok(LogicCondition {
            raw: text.to_string(),
            vars,
            slots,
            root,
            follow: stamps::Follow::default(),
        })
    }

    /// Parses a behavior `condition =` value: every `,` is first replaced
    /// by `=` (behavior-common.md §2), then [`LogicCondition::parse`].
    pub fn parse_condition_param(text: &str) -> Result<LogicCondition, LogicError> {
        let mut c = Self::parse(&text.replace(',', "="))?;
        c.raw = text.to_string();
        Ok(c)
    }

    /// Parses a mode-block condition (§6.1): like [`LogicCondition::parse`]
    /// but `==` is not allowed and commas are not converted.
    pub fn parse_mode(text: &str) -> Result<LogicCondition, LogicError> {
        if text.contains("==") {
            return Err(LogicError::new(
                text,
                "the field-match operator '==' is not allowed in a mode condition",
            ));
        }
        Self::parse(text)
    }

    /// The text as given to the parse function.
    pub fn raw(&self) -> &str {
        &self.raw
    }

    /// Variables read by the expression (left sides and `$(NAME)` right
    /// sides), de-duplicated, in order of appearance.
    pub fn vars(&self) -> &[String] {
        &self.vars
    }

    /// Assigns, for every variable of the expression that `src` knows,
    /// first its string value and then its numeric value (§8.5; a slot keeps
    /// the type it first received).
    /// A source with [`Stamps`] is asked only for the variables written since.
    pub fn update(&mut self, src: &dyn VarSource) {
        if let Some(st) = src.stamps() {
            return stamps::update_stamped(self, src, st);
        }
        self.follow.forget();
        for (var, slot) in self.vars.iter().zip(self.slots.iter_mut()) {
            read_slot(slot, var, src);
        }
    }

    /// [`update`](LogicCondition::update), then [`eval`](LogicCondition::eval); the
    /// evaluation is skipped while no slot has changed since the last one.
    pub fn update_eval(&mut self, src: &dyn VarSource) -> bool {
        self.update(src);
        if let Some(r) = self.follow.result {
            return r;
        }
        let r = self.eval();
        self.follow.result = Some(r);
        r
    }

    /// Assigns a string value to `var`'s slot (ignored if the slot is
    /// numeric or the expression does not read `var`).
    pub fn set_string(&mut self, var: &str, v: &str) {
        if let Some(i) = self.slot_of(var) {
            assign_str(&mut self.slots[i], v);
            self.follow.unread(i);
        }
    }

    /// Assigns a numeric value to `var`'s slot (ignored if the slot holds a
    /// string or the expression does not read `var`).
    pub fn set_double(&mut self, var: &str, v: f64) {
        if let Some(i) = self.slot_of(var) {
            assign_num(&mut self.slots[i], v);
            self.follow.unread(i);
        }
    }

    /// Evaluates with the persistent slot values (§8.3).
    pub fn eval(&self) -> bool {
        eval::eval_node(&self.root, &|i| match self.slots.get(i) {
            Some(Slot::Str(s)) => eval::ValRef::Str(s),
            Some(Slot::Num(v)) => eval::ValRef::Num(*v),
            _ => eval::ValRef::Unset,
        })
    }

    /// Evaluates reading `src` directly, ignoring (and not touching) the
    /// slots; a variable with both a string and a numeric value is a string.
    /// Used for flag `[if]` conditions, which are rebuilt at every posting.
    pub fn eval_fresh(&self, src: &dyn VarSource) -> bool {
        eval::eval_node(&self.root, &|i| {
            let Some(var) = self.vars.get(i) else {
                return eval::ValRef::Unset;
            };
            if let Some(s) = src.string_val(var) {
                eval::ValRef::Str(s)
            } else if let Some(d) = src.double_val(var) {
                eval::ValRef::Num(d)
            } else {
                eval::ValRef::Unset
            }
        })
    }

    fn slot_of(&self, var: &str) -> Option<usize> {
        self.vars.iter().position(|v| v == var)
    }
}

/// Free-function form of [`LogicCondition::parse_condition_param`].
pub fn parse_condition_param(text: &str) -> Result<LogicCondition, LogicError> {
    LogicCondition::parse_condition_param(text)
}

/// Assigns `var`'s value from `src` to its slot; whether the slot changed. A typed slot
/// ignores values of the other type, so only its own type is looked up (one look-up per
/// variable, not two: this runs for every condition of every behavior every iteration).
fn read_slot(slot: &mut Slot, var: &str, src: &dyn VarSource) -> bool {
    match slot {
        Slot::Str(s) => match src.string_val(var) {
            Some(v) if v != s => {
                s.clear();
                s.push_str(v);
                true
            }
            _ => false,
        },
        // Compared by bits: an assignment of the same number changes nothing.
        Slot::Num(n) => match src.double_val(var) {
            Some(d) if d.to_bits() != n.to_bits() => {
                *n = d;
                true
            }
            _ => false,
        },
        Slot::Unset => {
            if let Some(v) = src.string_val(var) {
                *slot = Slot::Str(v.to_string());
            } else if let Some(d) = src.double_val(var) {
                *slot = Slot::Num(d);
            } else {
                return false;
            }
            true
        }
    }
}

fn assign_str(slot: &mut Slot, v: &str) {
    match slot {
        Slot::Unset => *slot = Slot::Str(v.to_string()),
        Slot::Str(s) => {
            s.clear();
            s.push_str(v);
        }
        Slot::Num(_) => {}
    }
}

fn assign_num(slot: &mut Slot, v: f64) {
    match slot {
        Slot::Unset | Slot::Num(_) => *slot = Slot::Num(v),
        Slot::Str(_) => {}
    }
}

#[cfg(test)]
mod tests;
