#![no_main]
//! Arbitrary bytes as a `.moos` mission file: never panics; an error names the file.

use libfuzzer_sys::fuzz_target;
use moos::mission::MissionFile;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match MissionFile::parse(&text, std::path::Path::new("fuzz.moos")) {
        Ok(m) => {
            for g in ["ServerHost", "ServerPort", "MOOSTimeWarp", "Community"] {
                let _ = m.global(g);
                let _ = m.global_f64(g);
                let _ = m.global_bool(g);
            }
            for app in ["pHelmIvP", "uSimMarine"] {
                if let Some(lines) = m.process_config(app) {
                    for l in lines {
                        let _ = moos::mission::config_f64(&l.value);
                    }
                }
                let _ = m.config_value(app, "AppTick");
            }
        }
        Err(e) => assert!(e.to_string().contains("fuzz.moos")),
    }
});
