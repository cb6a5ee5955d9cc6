use super::*;
use crate::number::Value;
use std::collections::HashMap;

fn src(pairs: &[(&str, Value)]) -> HashMap<String, Value> {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect()
}

fn s(v: &str) -> Value {
    Value::Str(v.to_string())
}

fn n(v: f64) -> Value {
    Value::Num(v)
}

/// Parses, updates from `pairs`, evaluates.
fn check(text: &str, pairs: &[(&str, Value)]) -> bool {
    let mut c = LogicCondition::parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
    c.update(&src(pairs));
    c.eval()
}

#[test]
fn valid_syntax() {
    for t in [
        "A = 1",
        "A=1",
        "A == x",
        "A != true",
        "A >= 2",
        "A <= 2",
        "A > 2",
        "A < 2",
        "(A = 1)",
        "((A = 1))",
        "!(A = 1)",
        "! (A = 1)",
        "(A = 1) and (B = 2)",
        "(A = 1) AND (B = 2)",
        "(A = 1) or (B = 2)",
        "(A = 1) Or (B = 2)",
        "(A=1)and(B=2)",
        "(A = 1) and ((B = 2) and (C = 3))",
        "(DEPLOY = true) and ((LEG <= 1) or (FORCE_A = yes))",
        "!(A = 1) and (B = 2)",
        "(A = 1) or !(B = 2)",
        "!((A = 1) or (B = 2))",
        "A = black and white",
        "A = hello world",
        "A = \"quoted\"",
        "A = $(B)",
        "A = $( B )",
        "A\t=\t1",
        "A = -3.5",
        "A = \"\"",
    ] {
        assert!(LogicCondition::parse(t).is_ok(), "{t:?} should parse");
    }
}

#[test]
fn invalid_syntax() {
    for t in [
        "",
        "A",
        "true",
        "(A)",
        "A = 1 and B = 2",
        "(A=1) and (B=2) and (C=3)",
        "(A = 1) and B = 2",
        "A = 1 and (B = 2)",
        "(A = 1",
        "A = 1)",
        ")A = 1(",
        "= 1",
        "or = 1",
        "AND = 1",
        "\"A\" = 1",
        "A = or",
        "A = AND",
        "A = ",
        "A = (x)",
        "A = <",
        "A =< 1",
        "A = \"x",
        "A = a\"b\"",
        "!A = 1",
        "(A) and (B = 1)",
        "A = $()",
        "not (A = 1)",
    ] {
        assert!(LogicCondition::parse(t).is_err(), "{t:?} should not parse");
    }
}

#[test]
fn literal_may_contain_connective_words() {
    assert!(check("A = black and white", &[("A", s("black and white"))]));
    assert!(!check("A = black and white", &[("A", s("black"))]));
    assert!(check("A = cats or dogs", &[("A", s("cats or dogs"))]));
}

#[test]
fn vars_in_order_deduplicated() {
    let c = LogicCondition::parse("(B = 1) and ((A = $(C)) or (B = 2))").unwrap();
    assert_eq!(c.vars(), ["B", "A", "C"]);
    assert_eq!(c.raw(), "(B = 1) and ((A = $(C)) or (B = 2))");
}

#[test]
fn comparison_operators_numbers() {
    let p = [("X", n(2.0))];
    assert!(check("X = 2", &p));
    assert!(check("X == 2", &p));
    assert!(!check("X != 2", &p));
    assert!(check("X < 3", &p));
    assert!(check("X <= 2", &p));
    assert!(!check("X > 2", &p));
    assert!(check("X >= 2", &p));
    assert!(check("X > -1", &p));
}

#[test]
fn comparison_operators_strings() {
    let p = [("X", s("beta"))];
    assert!(check("X = beta", &p));
    assert!(!check("X = Beta", &p), "case-sensitive");
    assert!(check("X != alpha", &p));
    assert!(check("X > alpha", &p));
    assert!(check("X >= beta", &p));
    assert!(check("X < gamma", &p));
    assert!(check("X <= beta", &p));
    assert!(!check("X < Beta", &p), "byte-wise: 'b' > 'B'");
    assert!(check("X = \"beta\"", &p));
    assert!(check("X = beta", &[("X", s("\"beta\""))]));
}

#[test]
fn string_number_mixing() {
    // §8.3 examples.
    assert!(check("A = 1", &[("A", s("1.0"))]));
    assert!(check("A = \"1\"", &[("A", n(1.0))]));
    assert!(check("A < 5", &[("A", s("\"3\""))]));
    // non-numeric string vs number: false for every operator
    for op in ["=", "!=", "<", "<=", ">", ">=", "=="] {
        assert!(!check(&format!("A {op} 1"), &[("A", s("abc"))]), "{op}");
        assert!(!check(&format!("A {op} abc"), &[("A", n(1.0))]), "{op}");
    }
}

#[test]
fn unset_makes_every_comparison_false() {
    for op in ["=", "!=", "<", "<=", ">", ">=", "=="] {
        assert!(!check(&format!("A {op} 1"), &[]), "{op}");
        assert!(!check(&format!("A {op} x"), &[]), "{op}");
        assert!(!check(&format!("A {op} $(B)"), &[("A", n(1.0))]), "{op}");
        assert!(!check(&format!("A {op} $(B)"), &[("B", n(1.0))]), "{op}");
    }
    // but negation of a false comparison is true
    assert!(check("!(A = 1)", &[]));
}

#[test]
fn variable_right_side() {
    assert!(check("A = $(B)", &[("A", n(3.0)), ("B", n(3.0))]));
    assert!(check("A < $(B)", &[("A", n(2.0)), ("B", n(3.0))]));
    assert!(check("A = $(B)", &[("A", s("x")), ("B", s("x"))]));
    assert!(check("A = $(B)", &[("A", s("3")), ("B", n(3.0))]));
}

#[test]
fn connectives() {
    let t = "(A = 1) and ((B = 2) or (C = 3))";
    assert!(check(t, &[("A", n(1.0)), ("B", n(2.0))]));
    assert!(check(t, &[("A", n(1.0)), ("C", n(3.0))]));
    assert!(!check(t, &[("A", n(1.0))]));
    assert!(!check(t, &[("B", n(2.0)), ("C", n(3.0))]));
    assert!(check(
        "!((A = 1) or (B = 2))",
        &[("A", n(0.0)), ("B", n(0.0))]
    ));
    assert!(!check(
        "!(A = 1) and (B = 2)",
        &[("A", n(1.0)), ("B", n(2.0))]
    ));
    assert!(check("(A = 1) OR (B = 2)", &[("B", n(2.0))]));
}

#[test]
fn field_match_verified_table() {
    let table = [
        ("A:B:C", "C", true),
        ("A:B:C", "B:C", true),
        ("A:B:C", "A:B", true),
        ("X:A:B", "A:B", true),
        ("A:B", "A:B", true),
        ("A", "A", true),
        ("AB", "A", false),
        ("A:B:C", "A:B:C", false),
        ("A:B:C:D", "A:B:C", false),
        ("A:B:C:D", "A:B:C:D", false),
        ("A:B:C:C", "A:B:C", true),
    ];
    for (l, r, want) in table {
        assert_eq!(field_match(l, r), want, "{l} == {r}");
        // and through a condition
        assert_eq!(
            check(&format!("M == {r}"), &[("M", s(l))]),
            want,
            "cond M == {r} with M={l}"
        );
    }
    assert!(!field_match("", ""));
    assert!(!field_match("A", "B"));
    assert!(field_match("ACTIVE:SURVEYING", "SURVEYING"));
    assert!(field_match("A : B", "B"));
    // §6.2: exact three-level value is not matched
    assert!(!check(
        "MODE==ACTIVE:SURVEYING:LEG",
        &[("MODE", s("ACTIVE:SURVEYING:LEG"))]
    ));
    // numbers: == is plain equality
    assert!(check("N == 4", &[("N", n(4.0))]));
}

#[test]
fn sticky_types() {
    let mut c = LogicCondition::parse("A = 5").unwrap();
    c.set_double("A", 5.0);
    assert!(c.eval());
    c.set_string("A", "hello"); // rejected: slot is numeric
    assert!(c.eval());
    c.set_double("A", 6.0);
    assert!(!c.eval());

    let mut c = LogicCondition::parse("A = hello").unwrap();
    c.set_string("A", "hello");
    c.set_double("A", 3.0); // rejected: slot is a string
    assert!(c.eval());

    // update: string first, then number; a variable with both becomes a string
    let mut c = LogicCondition::parse("A = 7").unwrap();
    struct Both;
    impl VarSource for Both {
        fn string_val(&self, _: &str) -> Option<&str> {
            Some("x")
        }
        fn double_val(&self, _: &str) -> Option<f64> {
            Some(7.0)
        }
    }
    c.update(&Both);
    assert!(!c.eval(), "slot took the string 'x' first");
    // slots never cleared: absence in a later update keeps the value
    let mut c = LogicCondition::parse("A = 7").unwrap();
    c.update(&src(&[("A", n(7.0))]));
    c.update(&src(&[]));
    assert!(c.eval());
    // eval_fresh prefers the string and does not use slots
    let c = LogicCondition::parse("A = x").unwrap();
    assert!(c.eval_fresh(&Both));
    assert!(!c.eval());
    let c = LogicCondition::parse("A = 7").unwrap();
    assert!(!c.eval_fresh(&Both));
    assert!(c.eval_fresh(&src(&[("A", n(7.0))])));
}

#[test]
fn set_unknown_var_is_ignored() {
    let mut c = LogicCondition::parse("A = 1").unwrap();
    c.set_double("B", 1.0);
    assert!(!c.eval());
}

#[test]
fn condition_param_replaces_commas() {
    let mut c = parse_condition_param("DEPLOY, true").unwrap();
    assert_eq!(c.raw(), "DEPLOY, true");
    c.set_string("DEPLOY", "true");
    assert!(c.eval());
    assert!(parse_condition_param("A = x,y").is_err());
}

#[test]
fn mode_grammar_rejects_field_match() {
    assert!(LogicCondition::parse_mode("MODE == ACTIVE").is_err());
    assert!(LogicCondition::parse_mode("MODE = ACTIVE").is_ok());
    assert!(LogicCondition::parse_mode("RETURN != true").is_ok());
    assert!(LogicCondition::parse_mode("A = 1, B = 2").is_err());
}

#[test]
fn error_names_text() {
    let e = LogicCondition::parse("(A=1) and (B=2) and (C=3)").unwrap_err();
    assert_eq!(e.text, "(A=1) and (B=2) and (C=3)");
    assert!(e.to_string().contains("(A=1) and (B=2) and (C=3)"));
}

proptest::proptest! {
    #[test]
    fn parse_never_panics(t in "[A-Z()=!<>\" andor$,:0-9.-]{0,30}") {
        if let Ok(c) = LogicCondition::parse(&t) {
            let _ = c.eval();
        }
    }
}

/// `update` looks a typed slot's variable up once, in its own type, and ends with the
/// slots the rule "string first, then number, the first type sticks" gives.
#[test]
fn update_looks_up_once_per_typed_slot() {
    use std::cell::Cell;
    struct Counting {
        s: Option<&'static str>,
        d: Option<f64>,
        calls: Cell<u32>,
    }
    impl VarSource for Counting {
        fn string_val(&self, _: &str) -> Option<&str> {
            self.calls.set(self.calls.get() + 1);
            self.s
        }
        fn double_val(&self, _: &str) -> Option<f64> {
            self.calls.set(self.calls.get() + 1);
            self.d
        }
    }
    let src = |s, d| Counting {
        s,
        d,
        calls: Cell::new(0),
    };
    // Unset, then a number: two look-ups; afterwards one, and strings are ignored.
    let mut c = LogicCondition::parse("A = 7").unwrap();
    let none = src(None, None);
    c.update(&none);
    assert_eq!(none.calls.get(), 2);
    let num = src(None, Some(7.0));
    c.update(&num);
    assert!(c.eval());
    let both = src(Some("x"), Some(7.0));
    c.update(&both);
    assert_eq!(both.calls.get(), 1);
    assert!(c.eval(), "the numeric slot kept its type");
    // A string first: one look-up, and a number is ignored from then on.
    let mut c = LogicCondition::parse("A = x").unwrap();
    let s = src(Some("x"), Some(1.0));
    c.update(&s);
    assert_eq!(s.calls.get(), 1);
    assert!(c.eval());
    c.update(&src(None, Some(2.0)));
    assert!(c.eval(), "the string slot kept its value");
}

/// A source keeping write stamps, like the helm's info buffer.
#[derive(Default)]
struct Stamped {
    names: Vec<String>,
    vals: Vec<(Option<String>, Option<f64>)>,
    stamps: Stamps,
}

impl Stamped {
    fn write(&mut self, var: &str, v: &Value) {
        let i = match self.names.iter().position(|n| n == var) {
            Some(i) => i,
            None => {
                self.names.push(var.to_string());
                self.vals.push((None, None));
                self.names.len() - 1
            }
        };
        match v {
            Value::Str(s) => self.vals[i].0 = Some(s.clone()),
            Value::Num(d) => self.vals[i].1 = Some(*d),
        }
        self.stamps.write(i);
    }
}

impl VarSource for Stamped {
    fn string_val(&self, var: &str) -> Option<&str> {
        let i = self.place(var)?;
        self.vals[i].0.as_deref()
    }
    fn double_val(&self, var: &str) -> Option<f64> {
        self.vals[self.place(var)?].1
    }
    fn stamps(&self) -> Option<&Stamps> {
        Some(&self.stamps)
    }
    fn place(&self, var: &str) -> Option<usize> {
        self.names.iter().position(|n| n == var)
    }
}

/// The same values without stamps: every update reads every variable.
struct Plain<'a>(&'a Stamped);

impl VarSource for Plain<'_> {
    fn string_val(&self, var: &str) -> Option<&str> {
        self.0.string_val(var)
    }
    fn double_val(&self, var: &str) -> Option<f64> {
        self.0.double_val(var)
    }
}

#[test]
fn stamped_update_skips_unwritten_and_rereads_set_slots() {
    let mut src = Stamped::default();
    let mut c = LogicCondition::parse("(A = x) and (B < 3)").unwrap();
    assert!(!c.update_eval(&src), "nothing known");
    src.write("A", &s("x"));
    src.write("B", &n(2.0));
    assert!(c.update_eval(&src), "new variables are found");
    c.set_string("A", "y");
    assert!(!c.eval());
    assert!(c.update_eval(&src), "a slot set directly is read again");
    src.write("B", &n(2.0)); // the same value again
    assert!(c.update_eval(&src));
    // A condition read from two sources follows the one it read last.
    let mut other = Stamped::default();
    other.write("B", &n(5.0));
    assert!(!c.update_eval(&other));
    assert!(c.update_eval(&src));
    c.update(&Plain(&other));
    assert!(!c.eval());
    assert!(
        c.update_eval(&src),
        "after a plain source, all is read again"
    );
}

proptest::proptest! {
    /// Stamped updates leave exactly the slots and result full updates leave, whatever
    /// the writes (new, repeated, either type), direct slot sets and source switches.
    #[test]
    fn stamped_update_equals_full_update(
        steps in proptest::collection::vec((0u8..6, 0usize..4, 0u8..4), 1..40)
    ) {
        let names = ["A", "B", "C", "D"];
        let text = "((A = x) or (B < 2)) and ((!(C = $(D))) or (D == x:y))";
        let (mut fast, mut full) = (LogicCondition::parse(text).unwrap(), LogicCondition::parse(text).unwrap());
        let (mut one, mut two) = (Stamped::default(), Stamped::default());
        let mut use_two = false;
        for (kind, var, val) in steps {
            let var = names[var];
            let sv = ["x", "y", "x:y", "1"][usize::from(val)];
            match kind {
                0 => one.write(var, &s(sv)),
                1 => one.write(var, &n(f64::from(val))),
                2 => two.write(var, &s(sv)),
                3 => { fast.set_string(var, sv); full.set_string(var, sv); }
                4 => { fast.set_double(var, f64::from(val)); full.set_double(var, f64::from(val)); }
                _ => use_two = !use_two,
            }
            let src = if use_two { &two } else { &one };
            let got = fast.update_eval(src);
            full.update(&Plain(src));
            proptest::prop_assert_eq!(got, full.eval());
            proptest::prop_assert_eq!(&fast.slots, &full.slots);
        }
    }
}
