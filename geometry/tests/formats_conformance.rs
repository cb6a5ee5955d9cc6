//! Runs every worked example of geometry-formats.md §9 (a verbatim copy lives in
//! `tests/data/`): validity, every vertex bit for bit, and the printed specs at
//! precisions 1 and 3; plus the number-formatting table F. Prints `N passed, M failed`.

use geometry::{fmt_x, parse_point, parse_polygon, parse_seglist, Polygon, Seglist, Vertex};
use std::path::Path;

const SPEC: &str = include_str!("data/geometry-formats.md");

/// One worked example block.
#[derive(Default, Debug)]
struct Example {
    id: String,
    kind: String,
    input: String,
    result: String,
    pts: Option<String>,
    pt: Option<String>,
    spec1: Option<String>,
    spec3: Option<String>,
    spec: Option<String>,
}

/// A JSON string literal (the `in` line).
fn json_string(lit: &str) -> String {
    let inner = lit
        .strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or_else(|| panic!("not a JSON string: {lit}"));
    let mut out = String::new();
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('r') => out.push('\r'),
            Some('b') => out.push('\u{8}'),
            Some('f') => out.push('\u{c}'),
            Some('u') => {
                let hex: String = chars.by_ref().take(4).collect();
                let code = u32::from_str_radix(&hex, 16).expect("\\u escape");
                out.push(char::from_u32(code).expect("\\u code point"));
            }
            Some(other) => out.push(other),
            None => panic!("dangling escape in {lit}"),
        }
    }
    out
}

fn examples(spec: &str) -> Vec<Example> {
    let section = &spec[spec.find("## 9.").expect("section 9")..];
    let mut out = Vec::new();
    let mut lines = section.lines();
    while let Some(line) = lines.next() {
        if line.trim() != "```text" {
            continue;
        }
        let mut ex = Example::default();
        for l in lines.by_ref() {
            if l.trim() == "```" {
                break;
            }
            let (tag, rest) = l.split_once(char::is_whitespace).unwrap_or((l, ""));
            let rest = rest.trim_start();
            match tag {
                "in" => ex.input = json_string(rest.trim_end()),
                "result" => ex.result = rest.to_string(),
                "pts" => ex.pts = Some(rest.to_string()),
                "pt" => ex.pt = Some(rest.to_string()),
                "spec1" => ex.spec1 = Some(rest.to_string()),
                "spec3" => ex.spec3 = Some(rest.to_string()),
                "spec" => ex.spec = Some(rest.to_string()),
                id if ex.id.is_empty() => {
                    ex.id = id.to_string();
                    ex.kind = rest.split_whitespace().next().unwrap_or("").to_string();
                }
                _ => panic!("unexpected line {l:?}"),
            }
        }
        out.push(ex);
    }
    out
}

/// Compare a field; on difference, a description.
fn check<T: PartialEq + std::fmt::Debug>(what: &str, expected: T, got: T) -> Result<(), String> {
    if expected == got {
        Ok(())
    } else {
        Err(format!("{what}: expected {expected:?}, got {got:?}"))
    }
}

fn f(t: &str) -> f64 {
    t.parse().unwrap_or_else(|_| panic!("bad number {t:?}"))
}

/// The `pts` line as (x, y, z, property) per vertex.
fn expected_vertices(line: &str) -> Vec<(f64, f64, f64, String)> {
    line.split(" : ")
        .map(|v| {
            let mut fields = v.trim().split(',');
            let x = f(fields.next().expect("x"));
            let y = f(fields.next().expect("y"));
            let (mut z, mut prop) = (0.0, String::new());
            let rest: Vec<&str> = fields.collect();
            let rest = rest.join(",");
            let mut rest = rest.as_str();
            if let Some(r) = rest.strip_prefix("z=") {
                let (zt, after) = r
                    .split_once(",prop=")
                    .map_or((r, None), |(a, b)| (a, Some(b)));
                z = f(zt);
                prop = after.unwrap_or("").to_string();
                rest = "";
            }
            if let Some(p) = rest.strip_prefix("prop=") {
                prop = p.to_string();
            }
            (x, y, z, prop)
        })
        .collect()
}

fn check_vertices(ex: &Example, pts: &[Vertex], props: &[String]) -> Result<(), String> {
    let expected = ex.pts.as_deref().map(expected_vertices).unwrap_or_default();
    check("n", expected.len(), pts.len())?;
    for (i, (e, v)) in expected.iter().zip(pts).enumerate() {
        let prop = props.get(i).map_or("", String::as_str);
        let got = (v.x, v.y, v.z.unwrap_or(0.0), prop.to_string());
        if got.0.to_bits() != e.0.to_bits()
            || got.1.to_bits() != e.1.to_bits()
            || got.2 != e.2
            || got.3 != e.3
        {
            return Err(format!("vertex {i}: expected {e:?}, got {got:?}"));
        }
    }
    Ok(())
}

fn check_specs(ex: &Example, spec: impl Fn(usize) -> String) -> Result<(), String> {
    let spec1 = ex.spec1.clone().unwrap_or_default();
    let spec3 = match ex.spec3.as_deref() {
        Some("= spec1") | None => spec1.clone(),
        Some(s) => s.to_string(),
    };
    check("spec1", spec1, spec(1))?;
    check("spec3", spec3, spec(3))
}

fn flag(result: &str, name: &str) -> Option<bool> {
    let word = result
        .split_whitespace()
        .find_map(|w| w.strip_prefix(&format!("{name}=")))?;
    Some(word == "yes")
}

fn run_polygon(ex: &Example) -> Result<(), String> {
    let got: Option<Polygon> = parse_polygon(&ex.input);
    let valid = !ex.result.starts_with("INVALID");
    check("valid", valid, got.is_some())?;
    let Some(p) = got else { return Ok(()) };
    check("convex", flag(&ex.result, "convex"), Some(p.is_convex()))?;
    check(
        "active",
        flag(&ex.result, "active"),
        Some(p.attrs.active != Some(false)),
    )?;
    check_vertices(ex, p.vertices(), p.props())?;
    check_specs(ex, |prec| p.spec(prec))
}

fn run_seglist(ex: &Example) -> Result<(), String> {
    let got: Option<Seglist> = parse_seglist(&ex.input);
    let valid = !ex.result.starts_with("INVALID");
    check("valid", valid, got.is_some())?;
    let Some(s) = got else { return Ok(()) };
    check(
        "active",
        flag(&ex.result, "active"),
        Some(s.attrs.active != Some(false)),
    )?;
    check_vertices(ex, &s.pts, &s.props)?;
    check_specs(ex, |prec| s.spec(prec))
}

fn run_point(ex: &Example) -> Result<(), String> {
    let got = parse_point(&ex.input);
    let valid = !ex.result.starts_with("INVALID");
    check("valid", valid, got.is_some())?;
    let Some(p) = got else { return Ok(()) };
    check(
        "active",
        flag(&ex.result, "active"),
        Some(p.attrs.active != Some(false)),
    )?;
    let e: Vec<f64> = ex.pt.as_deref().unwrap_or("").split(',').map(f).collect();
    let z = p.z.unwrap_or(0.0);
    if e.len() != 3
        || e[0].to_bits() != p.x.to_bits()
        || e[1].to_bits() != p.y.to_bits()
        || e[2] != z
    {
        return Err(format!("point: expected {e:?}, got {:?}", (p.x, p.y, z)));
    }
    check("spec", ex.spec.clone().unwrap_or_default(), p.spec())
}

/// The rows of table F: (id, value, precision, expected).
fn format_cases(spec: &str) -> Vec<(String, f64, usize, String)> {
    spec.lines()
        .filter(|l| l.starts_with("| F-"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(|c| c.trim().trim_matches('`')).collect();
            (
                cells[1].to_string(),
                f(cells[2]),
                cells[3].parse().expect("d"),
                cells[4].to_string(),
            )
        })
        .collect()
}

/// The copy must be the shared spec when that is present: `../shared/specs/` next to the
/// workspace root (the main checkout), or beside one of its ancestors (a worktree).
#[test]
fn the_copy_is_the_shared_spec() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .expect("workspace root");
    let shared = root
        .ancestors()
        .skip(1)
        .map(|dir| dir.join("shared/specs/geometry-formats.md"))
        .find(|p| p.is_file());
    if let Some(shared) = shared {
        let text = std::fs::read_to_string(&shared).expect("readable shared spec");
        assert!(
            text == SPEC,
            "tests/data/geometry-formats.md differs from {}",
            shared.display()
        );
    }
}

#[test]
fn worked_examples() {
    let mut failures = Vec::new();
    let mut passed = 0;
    let exs = examples(SPEC);
    for ex in &exs {
        let r = match ex.kind.as_str() {
            "polygon" => run_polygon(ex),
            "seglist" => run_seglist(ex),
            "point" => run_point(ex),
            k => Err(format!("unknown kind {k}")),
        };
        match r {
            Ok(()) => passed += 1,
            Err(e) => failures.push(format!("{} {:?}: {e}", ex.id, ex.input)),
        }
    }
    let fcases = format_cases(SPEC);
    for (id, v, d, expected) in &fcases {
        let got = fmt_x(*v, *d);
        if &got == expected {
            passed += 1;
        } else {
            failures.push(format!(
                "{id} fmt_x({v}, {d}): expected {expected}, got {got}"
            ));
        }
    }
    for f in &failures {
        println!("FAIL {f}");
    }
    println!("{passed} passed, {} failed", failures.len());
    assert_eq!(
        exs.len() + fcases.len(),
        378,
        "the spec announces 378 examples"
    );
    assert!(
        failures.is_empty(),
        "{} worked examples failed",
        failures.len()
    );
}
