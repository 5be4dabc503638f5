//! The station's configuration (`--config station.toml`) over arbitrary text: no panic, and a
//! refusal names what is wrong (the TOML parser's line and field, or the field and its range).

#![no_main]

use libfuzzer_sys::fuzz_target;
use session::config::{ConfigError, StationConfig};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match StationConfig::from_toml(text, "fuzz.toml") {
        Ok(cfg) => {
            // What validated serialises and reads back to the same configuration.
            let back = toml::to_string(&cfg).expect("a valid config serialises");
            let again = StationConfig::from_toml(&back, "fuzz.toml")
                .unwrap_or_else(|e| panic!("a valid config did not read back: {e}\n{back}"));
            assert_eq!(again, cfg);
        }
        Err(e) => {
            let msg = e.to_string();
            match &e {
                ConfigError::Parse { message, .. } => assert!(!message.is_empty(), "{msg}"),
                ConfigError::Section { section, message } => {
                    assert!(!section.is_empty() && !message.is_empty(), "{msg}")
                }
                ConfigError::OutOfRange { field, allowed, .. } => {
                    assert!(!field.is_empty() && !allowed.is_empty(), "{msg}")
                }
                ConfigError::Read { .. } => panic!("no file was read: {msg}"),
            }
        }
    }
});
