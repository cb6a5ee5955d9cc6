//! Fuzz harnesses of the `.bhv` language (issue 10), run by `cargo test` on a bounded
//! budget (`FUZZ_CASES`, `FUZZ_SECS`; see the `fuzzkit` crate). Inputs are mutations of
//! the repo's real behavior files: `missions/*/*.bhv` and every `bhv` text of the golden
//! helm cases in `conformance/helm`.
//!
//! Invariants: no panic, no hang, bounded memory (fuzzkit); every reader error names the
//! file and a line that exists, and shows that line; what parses can be evaluated.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use bhv::logic::LogicCondition;
use bhv::number::Value;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every `.bhv` text of the repo: mission files and golden cases.
fn bhv_seeds() -> Vec<String> {
    let mut v: Vec<String> = fuzzkit::seed_files(&repo().join("missions"), "bhv")
        .into_iter()
        .map(|b| String::from_utf8(b).expect("a mission bhv is UTF-8"))
        .collect();
    for case in fuzzkit::seed_files(&repo().join("conformance/helm"), "toml") {
        let case = String::from_utf8(case).expect("a golden case is UTF-8");
        let doc: toml::Table = toml::from_str(&case).expect("toml");
        if let Some(b) = doc.get("bhv").and_then(|b| b.as_str()) {
            v.push(b.to_string());
        }
    }
    assert!(v.len() > 10, "too few seeds: {}", v.len());
    v
}

const BHV_DICT: &[&[u8]] = &[
    b"{",
    b"}",
    b"\n",
    b"\\\n",
    b"//",
    b"#include x.bhv\n",
    b"Behavior = BHV_Waypoint\n{\n",
    b"set MODE = ACTIVE {\n",
    b"} INACTIVE\n",
    b"initialize ",
    b"initialize_ ",
    b" = ",
    b",",
    b"\"",
    b"condition = ",
    b"endflag = ",
    b"templating = spawn\n",
    b"max_spawnings = 4294967296\n",
    b" and ",
    b" or ",
    b"(",
    b")",
    b"!",
    b"==",
    b"$(",
    b"[if]",
    b"\xff\xfe",
    b"\xc3",
    b"\t",
    b"\r",
];

/// Reader invariants on one input.
fn check_reader(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let file = Path::new("fuzz.bhv");
    let lines = text.split('\n').count();
    match bhv::parse_str(&text, file) {
        Ok(mut spec) => {
            for b in &spec.behaviors {
                assert!(b.line >= 1 && b.line <= lines, "behavior line {}", b.line);
                for l in &b.lines {
                    if l.param == "condition" {
                        if let Ok(mut c) = bhv::logic::parse_condition_param(&l.value) {
                            exercise(&mut c);
                        }
                    }
                    if l.param.ends_with("flag") {
                        let _ = bhv::parse_flag(&l.value);
                    }
                }
            }
            let info: HashMap<String, Value> = spec
                .inits
                .iter()
                .map(|i| (i.var.clone(), i.value.clone()))
                .collect();
            let _ = spec.modes.evaluate(&info);
            let _ = spec.modes.evaluate(&info);
            let _ = spec.modes.modeset_string();
            let _ = spec.modes.summary();
        }
        Err(e) => {
            assert_eq!(e.file, file);
            assert!(
                e.line >= 1 && e.line <= lines,
                "error line {} of {lines}",
                e.line
            );
            let shown = e.to_string();
            assert!(
                shown.starts_with(&format!("fuzz.bhv:{}: ", e.line)),
                "error does not name file:line: {shown}"
            );
            assert!(shown.contains(e.text.as_str()), "line not shown: {shown}");
            let _ = e.helm_warnings();
        }
    }
}

/// Give every variable of `c` a string or a number and evaluate.
fn exercise(c: &mut LogicCondition) {
    let mut info: HashMap<String, Value> = HashMap::new();
    for (i, v) in c.vars().iter().enumerate() {
        let val = if i % 2 == 0 {
            Value::Num(i as f64)
        } else {
            Value::Str(format!("v{i}"))
        };
        info.insert(v.clone(), val);
    }
    c.update(&info);
    let _ = c.eval();
    let _ = c.eval_fresh(&info);
}

#[test]
fn fuzz_bhv_reader() {
    let seeds: Vec<Vec<u8>> = bhv_seeds().into_iter().map(String::into_bytes).collect();
    fuzzkit::fuzz("bhv_reader", 8000, &seeds, BHV_DICT, check_reader);
}

/// Conditions, mode conditions and flags of the seed files.
fn logic_seeds() -> Vec<Vec<u8>> {
    let mut v = Vec::new();
    for text in bhv_seeds() {
        for line in text.lines() {
            let t = line.trim();
            if let Some((k, val)) = t.split_once('=') {
                let k = k.trim().to_ascii_lowercase();
                if k == "condition" || k.ends_with("flag") {
                    v.push(val.trim().as_bytes().to_vec());
                }
            } else if t.contains(" = ") || t.contains("!=") || t.contains('<') {
                v.push(t.as_bytes().to_vec());
            }
        }
    }
    v.sort();
    v.dedup();
    v.push(b"((A = 1) and (B < 2)) or !(C == x,y)".to_vec());
    v.push(b"X = $(Y)".to_vec());
    v
}

fn check_logic(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    if let Ok(mut c) = LogicCondition::parse(&text) {
        assert_eq!(c.raw(), text, "raw text round-trips");
        exercise(&mut c);
    }
    if let Ok(mut c) = LogicCondition::parse_mode(&text) {
        exercise(&mut c);
    }
    if let Ok(mut c) = bhv::logic::parse_condition_param(&text) {
        assert_eq!(c.raw(), text);
        exercise(&mut c);
    }
    if let Ok(bhv::FlagParam::Flag(f)) = bhv::parse_flag(&text) {
        if let Some(mut c) = f.condition {
            exercise(&mut c);
        }
    }
}

#[test]
fn fuzz_logic_conditions() {
    fuzzkit::fuzz("logic", 8000, &logic_seeds(), BHV_DICT, check_logic);
}

// Reproducers of crashes the harnesses found, kept as regression tests.

/// 1000 nested `!(` in one condition overflowed the stack (an abort, not a panic) in
/// the recursive descent; now any nesting deeper than 100 is a parse error, found fast.
#[test]
fn regression_deeply_nested_condition_is_an_error_not_a_stack_overflow() {
    for n in [101usize, 1000, 100_000] {
        let neg = format!("{}A = 1{}", "!(".repeat(n), ")".repeat(n));
        let e = LogicCondition::parse(&neg).expect_err("too deep");
        assert!(e.reason.contains("nested more than 100"), "{e}");
        let paren = format!("{}A = 1{}", "(".repeat(n), ")".repeat(n));
        assert!(LogicCondition::parse(&paren).is_err());
        let flag = format!("X = 1 [if] {neg}");
        assert!(bhv::parse_flag(&flag).is_err());
    }
    let mut chain = String::from("(A = 1)");
    for _ in 0..2000 {
        chain = format!("(A = 1) and ({chain})");
    }
    assert!(LogicCondition::parse(&chain).is_err());
    // 100 levels still parse and evaluate (on the 2 MB stack of a test thread).
    let ok = format!("{}A = 1{}", "!(".repeat(99), ")".repeat(99));
    let mut c = LogicCondition::parse(&ok).expect("100 levels are fine");
    c.set_double("A", 1.0);
    assert!(!c.eval(), "99 negations of true");
}
