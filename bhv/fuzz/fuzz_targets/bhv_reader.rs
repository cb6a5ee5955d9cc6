#![no_main]
//! Arbitrary bytes as a `.bhv` file: never panics; an error names file:line of a line
//! that exists and shows it; conditions and flags of what parses parse or fail cleanly.

use std::collections::HashMap;

use bhv::number::Value;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let file = std::path::Path::new("fuzz.bhv");
    match bhv::parse_str(&text, file) {
        Ok(mut spec) => {
            let mut info: HashMap<String, Value> = HashMap::new();
            for b in &spec.behaviors {
                for l in &b.lines {
                    if l.param == "condition" {
                        if let Ok(mut c) = bhv::logic::parse_condition_param(&l.value) {
                            for v in c.vars().to_vec() {
                                info.insert(v, Value::Num(1.0));
                            }
                            c.update(&info);
                            let _ = c.eval();
                        }
                    }
                    if l.param.ends_with("flag") {
                        let _ = bhv::parse_flag(&l.value);
                    }
                }
            }
            let _ = spec.modes.evaluate(&info);
        }
        Err(e) => {
            assert!(e.line >= 1 && e.line <= text.split('\n').count());
            let shown = e.to_string();
            assert!(shown.starts_with(&format!("fuzz.bhv:{}: ", e.line)));
            assert!(shown.contains(e.text.as_str()));
        }
    }
});
