#![no_main]
//! Arbitrary bytes as a logic condition, a mode condition and a flag: never panics
//! (nor overflows the stack); what parses evaluates.

use std::collections::HashMap;

use bhv::logic::LogicCondition;
use bhv::number::Value;
use libfuzzer_sys::fuzz_target;

fn exercise(c: &mut LogicCondition) {
    let info: HashMap<String, Value> = c
        .vars()
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let val = if i % 2 == 0 {
                Value::Num(i as f64)
            } else {
                Value::Str(format!("v{i}"))
            };
            (v.clone(), val)
        })
        .collect();
    c.update(&info);
    let _ = c.eval();
    let _ = c.eval_fresh(&info);
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(mut c) = LogicCondition::parse(&text) {
        assert_eq!(c.raw(), text);
        exercise(&mut c);
    }
    if let Ok(mut c) = LogicCondition::parse_mode(&text) {
        exercise(&mut c);
    }
    if let Ok(mut c) = bhv::logic::parse_condition_param(&text) {
        exercise(&mut c);
    }
    if let Ok(bhv::FlagParam::Flag(f)) = bhv::parse_flag(&text) {
        if let Some(mut c) = f.condition {
            exercise(&mut c);
        }
    }
});
