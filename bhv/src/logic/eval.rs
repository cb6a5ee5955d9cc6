//! Evaluation (bhv-format.md §8.3, §8.4). Nothing here allocates.

use super::{Node, Op, Rhs};
use crate::number::{atof, is_number, strip_quotes};

/// A borrowed variable or constant value.
#[derive(Clone, Copy, Debug)]
pub(crate) enum ValRef<'a> {
    Unset,
    Str(&'a str),
    Num(f64),
}

pub(crate) fn eval_node<'a, F>(n: &'a Node, get: &F) -> bool
where
    F: Fn(usize) -> ValRef<'a>,
{
    match n {
        // Both sides evaluated (§8.3); no short-circuit semantics needed
        // since evaluation has no side effects, but keep it plain.
        Node::And(a, b) => {
            let x = eval_node(a, get);
            let y = eval_node(b, get);
            x && y
        }
        Node::Or(a, b) => {
            let x = eval_node(a, get);
            let y = eval_node(b, get);
            x || y
        }
        Node::Not(a) => !eval_node(a, get),
        Node::Cmp { op, var, rhs } => {
            let l = get(*var);
            let r = match rhs {
                Rhs::Var(i) => get(*i),
                Rhs::Num(v) => ValRef::Num(*v),
                Rhs::Str(s) => ValRef::Str(s),
            };
            compare(*op, l, r)
        }
    }
}

fn compare(op: Op, l: ValRef<'_>, r: ValRef<'_>) -> bool {
    match (l, r) {
        (ValRef::Unset, _) | (_, ValRef::Unset) => false,
        (ValRef::Str(a), ValRef::Str(b)) => {
            let (a, b) = (strip_quotes(a), strip_quotes(b));
            match op {
                Op::Eq => a == b,
                Op::Field => field_match(a, b),
                Op::Ne => a != b,
                Op::Lt => a < b,
                Op::Le => a <= b,
                Op::Gt => a > b,
                Op::Ge => a >= b,
            }
        }
        (ValRef::Num(a), ValRef::Num(b)) => num_cmp(op, a, b),
        (ValRef::Str(s), ValRef::Num(b)) => {
            let s = strip_quotes(s);
            is_number(s) && num_cmp(op, atof(s), b)
        }
        (ValRef::Num(a), ValRef::Str(s)) => {
            let s = strip_quotes(s);
            is_number(s) && num_cmp(op, a, atof(s))
        }
    }
}

fn num_cmp(op: Op, a: f64, b: f64) -> bool {
    match op {
        Op::Eq | Op::Field => a == b,
        Op::Ne => a != b,
        Op::Lt => a < b,
        Op::Le => a <= b,
        Op::Gt => a > b,
        Op::Ge => a >= b,
    }
}

fn comp_count(s: &str) -> usize {
    s.bytes().filter(|&b| b == b':').count() + 1
}

fn comp(s: &str, k: usize) -> &str {
    s.split(':').nth(k).map(str::trim).unwrap_or("")
}

/// The field match of `==` on strings (§8.4), exactly as verified:
/// `A:B:C == B:C` is true but `A:B:C == A:B:C` is false.
///
/// ```
/// use bhv::logic::field_match;
/// assert!(field_match("ACTIVE:SURVEYING", "SURVEYING"));
/// assert!(!field_match("A:B:C", "A:B:C"));
/// ```
pub fn field_match(s1: &str, s2: &str) -> bool {
    if !s1.contains(s2) && !s2.contains(s1) {
        return false;
    }
    // An empty string splits into no components.
    if s1.is_empty() || s2.is_empty() {
        return false;
    }
    let (n1, n2) = (comp_count(s1), comp_count(s2));
    let (short, ns, long, nl) = if n1 < n2 {
        (s1, n1, s2, n2)
    } else {
        (s2, n2, s1, n1)
    };
    let first = comp(short, 0);
    let mut j = 0usize;
    while j < nl {
        if first == comp(long, j) {
            let mut ok = true;
            for k in 1..ns {
                j += k;
                if j >= nl || comp(short, k) != comp(long, j) {
                    ok = false;
                }
            }
            if ok {
                return true;
            }
        }
        j += 1;
    }
    false
}
