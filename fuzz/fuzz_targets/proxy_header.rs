//! The hub's PROXY protocol reader (`netlink::proxy_protocol::header`) over arbitrary bytes, as
//! a trusted balancer's connection would deliver them: no panic; never a byte read past the
//! header or past the largest header taken; a header read from the stream parses the same from
//! its bytes alone; an error is one of the named kinds with a sentence.
//!
//! The first byte picks a prefix (none, the version-2 signature, `PROXY `) so that most inputs
//! reach the version-specific code, the rest follows it.

#![no_main]

use libfuzzer_sys::fuzz_target;
use netlink::proxy_protocol::header::{self, MAX_V2_HEADER_BYTES, ProxyHeaderError};

const V2_SIGNATURE: &[u8] = b"\r\n\r\n\0\r\nQUIT\n";

fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let mut bytes = match pick % 3 {
        0 => Vec::new(),
        1 => V2_SIGNATURE.to_vec(),
        _ => b"PROXY ".to_vec(),
    };
    bytes.extend_from_slice(rest);
    let runtime = tokio::runtime::Builder::new_current_thread()
        .build()
        .unwrap();
    let mut stream = std::io::Cursor::new(bytes.clone());
    let got = runtime.block_on(header::read_header(&mut stream));
    let used = stream.position() as usize;
    assert!(used <= MAX_V2_HEADER_BYTES, "read {used} bytes");
    match got {
        Ok(h) => assert_eq!(header::parse(&bytes[..used]).unwrap(), h),
        Err(ProxyHeaderError::Io(e)) => panic!("a cursor cannot fail: {e}"),
        Err(e) => assert!(e.to_string().len() > 20, "{e}"),
    }
});
