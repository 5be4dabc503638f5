//! A therapist's regimen (`--regimen`, or sent by the hub) over arbitrary text: no panic, a
//! refusal names the exercise and the field, and what validated is safe for the haptic chain.

#![no_main]

use libfuzzer_sys::fuzz_target;
use station::regimen::{Regimen, RegimenError};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Regimen::from_toml(text, "fuzz.toml") {
        Ok(r) => {
            assert!(!r.exercises.is_empty());
            for e in &r.exercises {
                if let Some(h) = &e.haptic {
                    // A regimen's haptic settings never exceed the strongest wheel it may name.
                    h.validate(station::regimen::MAX_DEVICE_TORQUE_NM)
                        .unwrap_or_else(|err| panic!("validated regimen, invalid haptics: {err}"));
                }
            }
            let back = toml::to_string(&r).expect("a valid regimen serialises");
            let again = Regimen::from_toml(&back, "fuzz.toml")
                .unwrap_or_else(|e| panic!("a valid regimen did not read back: {e}\n{back}"));
            assert_eq!(again, r);
        }
        Err(e) => {
            let msg = e.to_string();
            match &e {
                RegimenError::Parse { message, .. } => assert!(!message.is_empty(), "{msg}"),
                RegimenError::Invalid { index, message, .. } => {
                    assert!(*index >= 1 && !message.is_empty(), "{msg}")
                }
                RegimenError::Read { .. } => panic!("no file was read: {msg}"),
            }
        }
    }
});
