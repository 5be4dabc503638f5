//! `telerehab recover` over arbitrary and truncated recordings: no panic; a refusal says why;
//! what it writes is a finished recording any MCAP reader opens, holding what it says it
//! copied.

#![no_main]

use libfuzzer_sys::fuzz_target;
use station::record::recover::recover;
use std::io::Cursor;

fuzz_target!(|data: &[u8]| {
    match recover(data, Cursor::new(Vec::new())) {
        Ok((copied, out)) => {
            let bytes = out.into_inner();
            let summary = mcap::Summary::read(&bytes)
                .expect("the recovered file has a readable summary")
                .expect("the recovered file has a summary section");
            assert_eq!(summary.channels.len(), copied.channels);
            let mut n = 0u64;
            for m in mcap::MessageStream::new(&bytes).expect("the recovered file reads") {
                m.expect("every recovered message reads back");
                n += 1;
            }
            assert_eq!(n, copied.messages);
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
});
