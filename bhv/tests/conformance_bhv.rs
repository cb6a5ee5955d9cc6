//! Every `bhv` text of the golden helm cases must parse without error, and
//! so must their `condition` and flag lines.

use std::path::{Path, PathBuf};

fn cases_dir() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = std::fs::canonicalize(manifest).unwrap_or_else(|_| manifest.to_path_buf());
    manifest.join("..").join("conformance").join("helm")
}

#[test]
fn every_golden_bhv_parses() {
    let dir = cases_dir();
    let entries = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("conformance folder {} missing: {e}", dir.display()));
    let mut n = 0;
    for entry in entries {
        let path = entry.unwrap_or_else(|e| panic!("{e}")).path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{e}"));
        let doc: toml::Table =
            toml::from_str(&text).unwrap_or_else(|e| panic!("{}: bad toml: {e}", path.display()));
        let Some(bhv_text) = doc.get("bhv").and_then(|v| v.as_str()) else {
            panic!("{}: no bhv field", path.display());
        };
        let spec =
            bhv::parse_str(bhv_text, &path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(!spec.behaviors.is_empty(), "{}", path.display());
        for b in &spec.behaviors {
            for l in &b.lines {
                if l.param == "condition" {
                    bhv::logic::parse_condition_param(&l.value)
                        .unwrap_or_else(|e| panic!("{}:{}: {e}", path.display(), l.line));
                }
                // The common flags (behavior-common.md); a behavior's own `*_flag`
                // parameter (GoToDepth's `capture_flag = LVL`) is not flag syntax.
                const COMMON_FLAGS: [&str; 9] = [
                    "runflag",
                    "runxflag",
                    "activeflag",
                    "inactiveflag",
                    "idleflag",
                    "endflag",
                    "spawnflag",
                    "spawnxflag",
                    "configflag",
                ];
                if COMMON_FLAGS.contains(&l.param.replace('_', "").as_str()) {
                    bhv::parse_flag(&l.value)
                        .unwrap_or_else(|e| panic!("{}:{}: {e}", path.display(), l.line));
                }
            }
        }
        n += 1;
    }
    assert!(n > 0, "no cases in {}", dir.display());
}
