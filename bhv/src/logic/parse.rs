//! The splitting procedure of bhv-format.md §8.1.

use super::{Node, Op, Rhs};
use crate::error::LogicError;
use crate::number::{atof, is_number, strip_quotes};

/// Parses `text` into a tree and the list of variables it reads.
pub(crate) fn parse_expression(text: &str) -> Result<(Node, Vec<String>), LogicError> {
    let pre = preprocess(text);
    let mut p = Parser {
        whole: text,
        vars: Vec::new(),
    };
    if nesting(&pre).is_some_and(|d| d > MAX_DEPTH) {
        return Err(p.err(format!("parentheses nested more than {MAX_DEPTH} deep")));
    }
    let root = p.expr(&pre)?;
    Ok((root, p.vars))
}

/// Step 1: tabs → spaces, a space after every `)` and before every `(`,
/// `$ (` back to `$(`, trim.
fn preprocess(text: &str) -> String {
    let mut s = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '\t' => s.push(' '),
            ')' => s.push_str(") "),
            '(' => s.push_str(" ("),
            _ => s.push(c),
        }
    }
    s.replace("$ (", "$(").trim().to_string()
}

/// Deepest parenthesis nesting accepted. The parser recurses once per level (and strips
/// enclosing pairs in time proportional to depth × length), so without a bound a long
/// enough condition line overflowed the stack and aborted the helm (found by fuzzing).
/// Real conditions nest a few levels.
pub(crate) const MAX_DEPTH: i64 = 100;

/// Parentheses balance (`None` if not) and the deepest nesting.
fn nesting(e: &str) -> Option<i64> {
    let (mut depth, mut max): (i64, i64) = (0, 0);
    for b in e.bytes() {
        match b {
            b'(' => {
                depth += 1;
                max = max.max(depth);
            }
            b')' => {
                depth -= 1;
                if depth < 0 {
                    return None;
                }
            }
            _ => {}
        }
    }
    (depth == 0).then_some(max)
}

/// True if `e` is entirely enclosed by one matching pair of parentheses.
fn enclosed(e: &str) -> bool {
    let b = e.as_bytes();
    if b.len() < 2 || b[0] != b'(' || b[b.len() - 1] != b')' {
        return false;
    }
    let mut depth: i64 = 0;
    for (i, &c) in b.iter().enumerate() {
        match c {
            b'(' => depth += 1,
            b')' => depth -= 1,
            _ => {}
        }
        if depth == 0 {
            return i == b.len() - 1;
        }
    }
    false
}

/// `( ... )` or `!( ... )`.
fn grouped(e: &str) -> bool {
    enclosed(e) || e.strip_prefix('!').is_some_and(|r| enclosed(r.trim()))
}

enum Split<'a> {
    And(&'a str, &'a str),
    Or(&'a str, &'a str),
    Cmp(Op, &'a str, &'a str),
}

const CMP_OPS: [(&str, Op); 7] = [
    ("==", Op::Field),
    ("=", Op::Eq),
    ("!=", Op::Ne),
    (">=", Op::Ge),
    ("<=", Op::Le),
    (">", Op::Gt),
    ("<", Op::Lt),
];

/// Step 5: the first operator at parenthesis depth 0, left to right.
fn split(e: &str) -> Option<Split<'_>> {
    let b = e.as_bytes();
    let mut depth: i64 = 0;
    for i in 0..b.len() {
        match b[i] {
            b'(' => depth += 1,
            b')' => depth -= 1,
            _ => {}
        }
        if depth != 0 {
            continue;
        }
        if i > 0 && i + 3 <= b.len() {
            let w = &b[i - 1..i + 3];
            if w.eq_ignore_ascii_case(b" OR ") {
                return Some(Split::Or(&e[..i - 1], &e[i + 3..]));
            }
            if w.eq_ignore_ascii_case(b" AND") {
                return Some(Split::And(&e[..i - 1], &e[i + 3..]));
            }
        }
        for (tok, op) in CMP_OPS {
            if b[i..].starts_with(tok.as_bytes()) {
                return Some(Split::Cmp(op, &e[..i], &e[i + tok.len()..]));
            }
        }
    }
    None
}

const FORBIDDEN: &[char] = &['"', '<', '>', '=', '!', '(', ')'];

fn is_connective(s: &str) -> bool {
    s.eq_ignore_ascii_case("or") || s.eq_ignore_ascii_case("and")
}

fn valid_var_name(s: &str) -> bool {
    !s.is_empty() && !s.contains(FORBIDDEN) && !is_connective(s)
}

struct Parser<'t> {
    whole: &'t str,
    vars: Vec<String>,
}

impl Parser<'_> {
    fn err(&self, reason: String) -> LogicError {
        LogicError::new(self.whole, reason)
    }

    fn slot(&mut self, name: &str) -> usize {
        if let Some(i) = self.vars.iter().position(|v| v == name) {
            i
        } else {
            self.vars.push(name.to_string());
            self.vars.len() - 1
        }
    }

    fn expr(&mut self, e: &str) -> Result<Node, LogicError> {
        let mut e = e.trim();
        if nesting(e).is_none() {
            return Err(self.err(format!("unbalanced parentheses in [{e}]")));
        }
        while enclosed(e) {
            e = e[1..e.len() - 1].trim();
        }
        if let Some(rest) = e.strip_prefix('!') {
            let rest = rest.trim();
            if enclosed(rest) {
                return Ok(Node::Not(Box::new(self.expr(rest)?)));
            }
        }
        match split(e) {
            None => Err(self.err(format!("no operator in [{e}]"))),
            Some(Split::And(l, r)) => {
                let (l, r) = self.operands(l, r, "and")?;
                Ok(Node::And(Box::new(l), Box::new(r)))
            }
            Some(Split::Or(l, r)) => {
                let (l, r) = self.operands(l, r, "or")?;
                Ok(Node::Or(Box::new(l), Box::new(r)))
            }
            Some(Split::Cmp(op, l, r)) => self.comparison(op, l.trim(), r.trim()),
        }
    }

    fn operands(&mut self, l: &str, r: &str, conn: &str) -> Result<(Node, Node), LogicError> {
        let (l, r) = (l.trim(), r.trim());
        for side in [l, r] {
            if !grouped(side) {
                return Err(self.err(format!(
                    "each operand of '{conn}' must be parenthesized: [{side}] \
                     (chains need explicit grouping)"
                )));
            }
        }
        let ln = self.expr(l)?;
        let rn = self.expr(r)?;
        Ok((ln, rn))
    }

    fn comparison(&mut self, op: Op, l: &str, r: &str) -> Result<Node, LogicError> {
        if !valid_var_name(l) {
            return Err(self.err(format!("bad variable name [{l}]")));
        }
        let var = self.slot(l);
        let rhs = if let Some(inner) = r.strip_prefix("$(").and_then(|x| x.strip_suffix(')')) {
            let name = inner.trim();
            if !valid_var_name(name) {
                return Err(self.err(format!("bad variable reference [{r}]")));
            }
            Rhs::Var(self.slot(name))
        } else if is_number(r) {
            Rhs::Num(atof(r))
        } else {
            if r.is_empty() {
                return Err(self.err(format!("empty right operand after [{l}]")));
            }
            if is_connective(r) {
                return Err(self.err(format!("bad right operand [{r}]")));
            }
            let content = strip_quotes(r);
            if content.contains(FORBIDDEN) {
                return Err(self.err(format!("bad literal [{r}]")));
            }
            Rhs::Str(content.to_string())
        };
        Ok(Node::Cmp { op, var, rhs })
    }
}
