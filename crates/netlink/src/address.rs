//! A `host:port` from the command line or a settings file, resolved once.

use std::io;
use std::net::{SocketAddr, ToSocketAddrs};

/// The first socket address `address` (`host:port`) resolves to; errors name it as `what`
/// (the flag or setting it came from, e.g. `--stations`).
pub fn resolve(what: &str, address: &str) -> io::Result<SocketAddr> {
    address
        .to_socket_addrs()
        .map_err(|e| {
            io::Error::new(
                e.kind(),
                format!("{what} `{address}` does not resolve: {e}"),
            )
        })?
        .next()
        .ok_or_else(|| {
            io::Error::new(
                io::ErrorKind::NotFound,
                format!("{what} `{address}` has no address"),
            )
        })
}

#[cfg(test)]
mod tests {
    use super::resolve;

    #[test]
    fn a_loopback_address_resolves_and_a_bad_one_is_named_by_its_flag() {
        assert_eq!(resolve("--web", "127.0.0.1:8443").unwrap().port(), 8443);
        let e = resolve("--stations", "no port here")
            .unwrap_err()
            .to_string();
        assert!(e.contains("--stations `no port here`"), "{e}");
    }
}
