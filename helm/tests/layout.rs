//! The shape of the workspace, checked: who may depend on whom (from `cargo metadata`),
//! no circle of source files importing each other inside a crate, and no crate or file
//! too large to read in one sitting.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

/// The crates that make up the helm host (not the SDK, the behaviors or the formats).
const HELM_CRATES: &[&str] = &[
    "helm",
    "helm-engine",
    "behavior-loader",
    "helm-config",
    "helm-cycle",
    "helm-mission",
    "helm-conform",
    "helm-app",
    "helm-sim",
    "helm-sim-cli",
    "vehicle-model",
    "moos",
    "moosdb",
    "moos-mission",
];

/// At most this many lines of non-test code in one crate, and in one file.
const MAX_CRATE_LINES: usize = 5000;
const MAX_FILE_LINES: usize = 700;

struct Package {
    dir: PathBuf,
    /// Workspace packages this one depends on for building (not dev or build deps).
    deps: Vec<String>,
}

fn workspace_packages() -> BTreeMap<String, Package> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(common::workspace())
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .output()
        .expect("run cargo metadata");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).expect("metadata json");
    let mut packages = BTreeMap::new();
    for p in meta["packages"].as_array().expect("packages") {
        let name = p["name"].as_str().expect("name").to_string();
        let manifest = PathBuf::from(p["manifest_path"].as_str().expect("manifest"));
        let deps = p["dependencies"]
            .as_array()
            .expect("dependencies")
            .iter()
            .filter(|d| d["kind"].is_null() && d.get("path").is_some_and(|p| !p.is_null()))
            .map(|d| d["name"].as_str().expect("dep name").to_string())
            .collect();
        let dir = manifest.parent().expect("package dir").to_path_buf();
        packages.insert(name, Package { dir, deps });
    }
    packages
}

/// Every workspace package `name` depends on, directly or not.
fn closure(packages: &BTreeMap<String, Package>, name: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut todo = vec![name.to_string()];
    while let Some(n) = todo.pop() {
        for d in packages.get(&n).map_or(&[][..], |p| &p.deps[..]) {
            if seen.insert(d.clone()) {
                todo.push(d.clone());
            }
        }
    }
    seen
}

#[test]
fn crates_depend_only_downward() {
    let packages = workspace_packages();
    for needed in [
        "helm-engine",
        "helm-cycle",
        "helm-app",
        "helm-sim",
        "helm-sim-cli",
        "helm-conform",
        "behavior-api",
    ] {
        assert!(packages.contains_key(needed), "no package {needed}");
    }
    let forbid = |pkg: &str, banned: &[&str]| {
        let deps = closure(&packages, pkg);
        for b in banned {
            assert!(!deps.contains(*b), "{pkg} depends on {b}: {deps:?}");
        }
    };
    // The engine decides; it knows no sockets (moos: client and DB), app or simulator.
    forbid(
        "helm-engine",
        &[
            "moos",
            "moosdb",
            "helm-app",
            "helm-sim",
            "helm-sim-cli",
            "helm-conform",
            "helm",
        ],
    );
    // The cycle drives the engine; the drivers (app, simulator) depend on it, not it on them.
    forbid(
        "helm-cycle",
        &[
            "moos",
            "moosdb",
            "helm-app",
            "helm-sim",
            "helm-sim-cli",
            "helm-conform",
            "helm",
        ],
    );
    forbid(
        "helm-conform",
        &["moos", "moosdb", "helm-app", "helm-sim", "helm"],
    );
    // The client does not need the server.
    forbid("moos", &["moosdb"]);
    forbid("helm-app", &["helm-sim", "helm-conform", "helm"]);
    forbid(
        "helm-sim",
        &["helm-app", "helm-conform", "helm", "moosdb", "helm-sim-cli"],
    );
    // The command draws and writes; the simulation never calls back into it.
    forbid(
        "helm-sim-cli",
        &["helm-app", "helm-conform", "helm", "moosdb"],
    );
    forbid("vehicle-model", &["moos", "helm-engine"]);
    // The loader knows the SDK, not the engine that uses it.
    forbid(
        "behavior-loader",
        &[
            "helm-engine",
            "helm-cycle",
            "moos",
            "moosdb",
            "helm-sim",
            "helm",
        ],
    );
    forbid("behavior-api", HELM_CRATES);
    // Behaviors, built in or plugins, know the SDK and nothing of the helm.
    let mut behaviors = 0;
    for (name, p) in &packages {
        let under_plugins = p.dir.parent().is_some_and(|d| d.ends_with("plugins"));
        if under_plugins || name == "behaviors-std" {
            behaviors += 1;
            forbid(name, HELM_CRATES);
            assert!(
                p.deps.iter().any(|d| d == "behavior-api"),
                "{name} does not use behavior-api"
            );
        }
    }
    assert!(behaviors >= 5, "found only {behaviors} behavior crates");
}

/// The module a source file is: `src/a/b.rs` and `src/a/b/mod.rs` are `a::b`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file
        .strip_prefix(src)
        .expect("under src")
        .with_extension("");
    let mut segs: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        segs.last().map(String::as_str),
        Some("lib" | "main" | "mod")
    ) {
        segs.pop();
    }
    segs
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The code of a file without its test module and comment lines: what it imports.
fn code_of(file: &Path) -> String {
    let text = std::fs::read_to_string(file).expect("read source");
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `use a::{b, c::{d, e}}` → `a::b`, `a::c::d`, `a::c::e`.
fn expand_use_tree(tree: &str) -> Vec<String> {
    let tree: String = tree.chars().filter(|c| !c.is_whitespace()).collect();
    let Some(open) = tree.find('{') else {
        return vec![tree];
    };
    let (prefix, body) = (&tree[..open], &tree[open + 1..tree.len().saturating_sub(1)]);
    let (mut items, mut depth, mut cur) = (Vec::new(), 0, String::new());
    for ch in body.chars() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        if ch == ',' && depth == 0 {
            items.push(std::mem::take(&mut cur));
        } else {
            cur.push(ch);
        }
    }
    items.push(cur);
    items
        .iter()
        .filter(|i| !i.is_empty())
        .flat_map(|i| expand_use_tree(i))
        .map(|i| format!("{prefix}{i}"))
        .collect()
}

/// The `crate::`/`super::` paths a file's code names, as module paths from the root.
fn referenced_paths(code: &str, module: &[String]) -> Vec<Vec<String>> {
    // `super` of `a/b.rs` (module a::b) is `a`; of `a/b/mod.rs` (also a::b) it is `a` too.
    let parent: Vec<String> = module[..module.len().saturating_sub(1)].to_vec();
    let resolve = |path: &str| -> Option<Vec<String>> {
        let mut segs = path.split("::").filter(|s| !s.is_empty());
        let mut out = match segs.next()? {
            "crate" => Vec::new(),
            "super" => parent.clone(),
            _ => return None,
        };
        for s in segs {
            let s = s.split(" as ").next().unwrap_or(s);
            if s == "self" || s == "*" || !s.chars().all(|c| c.is_alphanumeric() || c == '_') {
                break;
            }
            out.push(s.to_string());
        }
        Some(out)
    };
    let mut paths = Vec::new();
    let bytes = code.as_bytes();
    // Every `crate::x::y` / `super::x` path written inline or in a `use`.
    for start in ["crate::", "super::"] {
        let mut from = 0;
        while let Some(i) = code[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            if at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_') {
                continue;
            }
            let rest = &code[at..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(rest.len());
            let path = rest[..end].trim_end_matches(':');
            if rest[end..].starts_with('{') {
                // A use tree: read to its closing brace.
                let mut depth = 0;
                let mut close = end;
                for (k, ch) in rest[end..].char_indices() {
                    match ch {
                        '{' => depth += 1,
                        '}' => {
                            depth -= 1;
                            if depth == 0 {
                                close = end + k + 1;
                                break;
                            }
                        }
                        _ => {}
                    }
                }
                for p in expand_use_tree(&rest[..close]) {
                    paths.extend(resolve(&p));
                }
            } else {
                paths.extend(resolve(path));
            }
        }
    }
    paths
}

/// Circles of files in one crate's `src`, ignoring a module's links with its own parent
/// or children (declaring and re-exporting submodules is not a circle).
fn file_circles(src: &Path) -> Vec<Vec<String>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeMap<Vec<String>, PathBuf> = files
        .iter()
        .map(|f| (module_of(src, f), f.clone()))
        .collect();
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for (m, f) in &modules {
        let targets = edges.entry(m.clone()).or_default();
        for path in referenced_paths(&code_of(f), m) {
            // The deepest module file the path names.
            let target = (0..=path.len())
                .rev()
                .map(|k| path[..k].to_vec())
                .find(|p| modules.contains_key(p));
            let Some(t) = target else { continue };
            let nested = t.starts_with(m) || m.starts_with(&t);
            if !nested {
                targets.insert(t);
            }
        }
    }
    // A circle: two modules each reaching the other.
    let reach = |from: &Vec<String>| -> BTreeSet<Vec<String>> {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.clone()];
        while let Some(n) = todo.pop() {
            for t in edges.get(&n).into_iter().flatten() {
                if seen.insert(t.clone()) {
                    todo.push(t.clone());
                }
            }
        }
        seen
    };
    let mut circles = Vec::new();
    for m in modules.keys() {
        if reach(m).contains(m) {
            circles.push(m.clone());
        }
    }
    circles
}

fn member_src_dirs() -> Vec<(String, PathBuf)> {
    workspace_packages()
        .into_iter()
        .map(|(n, p)| (n, p.dir.join("src")))
        .filter(|(_, d)| d.is_dir())
        .collect()
}

#[test]
fn no_circle_of_files_importing_each_other() {
    let mut found = Vec::new();
    for (name, src) in member_src_dirs() {
        for m in file_circles(&src) {
            found.push(format!("{name}: {}", m.join("::")));
        }
    }
    assert!(
        found.is_empty(),
        "modules on an import circle:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_circle_check_sees_a_circle() {
    let dir = common::scratch("layout-circle/src");
    std::fs::write(dir.join("lib.rs"), "mod a;\nmod b;\n").unwrap();
    std::fs::write(dir.join("a.rs"), "use crate::b::B;\npub struct A;\n").unwrap();
    std::fs::write(dir.join("b.rs"), "use crate::{a::A, c};\npub struct B;\n").unwrap();
    let found = file_circles(&dir);
    assert_eq!(found, vec![vec!["a".to_string()], vec!["b".to_string()]]);
}

/// Lines of a file before its test module.
fn non_test_lines(file: &Path) -> usize {
    let text = std::fs::read_to_string(file).expect("read source");
    count_non_test_lines(&text)
}

/// Lines outside `#[cfg(test)]` items: the attribute, any attributes after it, and
/// the item it guards (one line ending in `;`, or a braced block) are not counted,
/// wherever in the file they stand.
fn count_non_test_lines(text: &str) -> usize {
    let mut lines = text.lines().peekable();
    let mut n = 0;
    while let Some(line) = lines.next() {
        if line.trim() != "#[cfg(test)]" {
            n += 1;
            continue;
        }
        while lines.next_if(|l| l.trim().starts_with("#[")).is_some() {}
        let mut depth = 0i64;
        let mut opened = false;
        for item in lines.by_ref() {
            depth += item.matches('{').count() as i64 - item.matches('}').count() as i64;
            opened |= item.contains('{');
            if (opened && depth <= 0) || (!opened && item.trim_end().ends_with(';')) {
                break;
            }
        }
    }
    n
}

#[test]
fn test_items_are_not_counted_wherever_they_stand() {
    let text = "fn a() {}\n#[cfg(test)]\nuse x::y;\nfn b() {\n}\n#[cfg(test)]\n#[allow(dead_code)]\nmod t {\n    fn c() {}\n}\nfn d() {}\n#[cfg(test)]\nmod tests;\n";
    assert_eq!(count_non_test_lines(text), 4);
}

#[test]
fn no_crate_or_file_too_large_to_read() {
    let mut problems = Vec::new();
    for (name, src) in member_src_dirs() {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        let mut total = 0;
        for f in files {
            // `tests.rs` and `*_tests.rs` modules hold unit tests only.
            if f.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.ends_with("tests.rs"))
            {
                continue;
            }
            let n = non_test_lines(&f);
            total += n;
            if n > MAX_FILE_LINES {
                problems.push(format!("{}: {n} lines", f.display()));
            }
        }
        if total > MAX_CRATE_LINES {
            problems.push(format!("crate {name}: {total} lines"));
        }
    }
    assert!(problems.is_empty(), "too large:\n{}", problems.join("\n"));
}
