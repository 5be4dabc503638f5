//! Reading one PROXY protocol header (version 1, text, or version 2, binary) from the start of
//! a connection: exactly the header's bytes are read, never one past it (the TLS handshake
//! follows on the same stream), and never more than [`MAX_V1_HEADER_BYTES`] or
//! [`MAX_V2_HEADER_BYTES`]. The bytes are framed here and parsed by the `ppp` crate.

use std::fmt;
use std::io;
use std::net::SocketAddr;

use tokio::io::{AsyncRead, AsyncReadExt};

/// Longest version-1 header, bytes, `\r\n` included (the protocol's own bound).
pub const MAX_V1_HEADER_BYTES: usize = 107;
/// Longest version-2 header taken, bytes: the 16-byte fixed part and up to 1 KiB of addresses
/// and TLVs (HAProxy's `send-proxy-v2` sends 12 bytes of addresses for IPv4, 36 for IPv6,
/// and TLVs only when `proxy-v2-options` asks for them).
pub const MAX_V2_HEADER_BYTES: usize = 16 + 1024;

/// The 12 bytes every version-2 header starts with.
const V2_SIGNATURE: [u8; 12] = *b"\r\n\r\n\0\r\nQUIT\n";
/// What every version-1 header starts with.
const V1_PREFIX: &[u8] = b"PROXY ";
/// Bytes read before the version is known: no header is shorter (`PROXY UNKNOWN\r\n` is 15).
const FIRST_READ: usize = 8;

/// What a valid header says about the connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProxyHeader {
    /// The balancer relays a client: its address and port.
    Proxied {
        /// The client's address as the balancer saw it (IPv4-mapped IPv6 made IPv4).
        source: SocketAddr,
    },
    /// The balancer speaks for itself (`LOCAL`, a health check) or gives no usable address
    /// (`UNKNOWN`, `UNSPEC`, a UNIX socket): the connection keeps the balancer's address.
    Local,
}

impl ProxyHeader {
    /// The address the connection from `peer` (the balancer) is taken to come from.
    pub fn client_address(self, peer: SocketAddr) -> SocketAddr {
        match self {
            Self::Proxied { source } => source,
            Self::Local => peer,
        }
    }
}

/// Why a connection from a trusted balancer was closed before its first byte of TLS.
#[derive(Debug)]
pub enum ProxyHeaderError {
    /// The connection ended after `read` bytes, before a whole header (0: a bare TCP check).
    Closed {
        /// Bytes received before the end.
        read: usize,
    },
    /// The first bytes are not a PROXY header's (a client connected past the balancer, or a
    /// balancer not configured to send one).
    Missing,
    /// A header longer than this hub takes.
    Oversized {
        /// Its length, bytes (as far as known).
        bytes: usize,
    },
    /// A header that does not parse.
    Malformed(String),
    /// No whole header within the handshake timeout.
    TimedOut,
    /// The socket failed.
    Io(io::Error),
}

impl fmt::Display for ProxyHeaderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Closed { read: 0 } => write!(f, "closed before sending a PROXY protocol header"),
            Self::Closed { read } => write!(
                f,
                "closed after {read} bytes, before the end of its PROXY protocol header"
            ),
            Self::Missing => write!(
                f,
                "did not start with a PROXY protocol header (a client past the balancer, or a \
                 balancer without `send-proxy-v2`)"
            ),
            Self::Oversized { bytes } => write!(
                f,
                "sent a PROXY protocol header of {bytes} bytes, more than the {MAX_V1_HEADER_BYTES} \
                 (version 1) or {MAX_V2_HEADER_BYTES} (version 2) taken"
            ),
            Self::Malformed(why) => write!(f, "sent a malformed PROXY protocol header: {why}"),
            Self::TimedOut => write!(
                f,
                "sent no whole PROXY protocol header within the handshake timeout"
            ),
            Self::Io(e) => write!(f, "failed while its PROXY protocol header was read: {e}"),
        }
    }
}

impl std::error::Error for ProxyHeaderError {}

/// Reads into `buf[*read..]` until it is full; an end of stream is [`ProxyHeaderError::Closed`].
async fn fill<R: AsyncRead + Unpin>(
    stream: &mut R,
    buf: &mut [u8],
    read: &mut usize,
) -> Result<(), ProxyHeaderError> {
    while *read < buf.len() {
        match stream.read(&mut buf[*read..]).await {
            Ok(0) => return Err(ProxyHeaderError::Closed { read: *read }),
            Ok(n) => *read += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(ProxyHeaderError::Io(e)),
        }
    }
    Ok(())
}

/// Reads one PROXY protocol header from the start of `stream`, no byte past its end. No
/// timeout here: the caller bounds it ([`super::ProxiedListener`] by the handshake timeout).
pub async fn read_header<R: AsyncRead + Unpin>(
    stream: &mut R,
) -> Result<ProxyHeader, ProxyHeaderError> {
    let mut first = [0u8; FIRST_READ];
    let mut read = 0;
    fill(stream, &mut first, &mut read).await?;
    if first.starts_with(V1_PREFIX) {
        read_v1(stream, first).await
    } else if first == V2_SIGNATURE[..FIRST_READ] {
        read_v2(stream, first).await
    } else {
        Err(ProxyHeaderError::Missing)
    }
}

/// The rest of a version-1 header, a byte at a time up to its `\r\n` (at most 107 bytes).
async fn read_v1<R: AsyncRead + Unpin>(
    stream: &mut R,
    first: [u8; FIRST_READ],
) -> Result<ProxyHeader, ProxyHeaderError> {
    let mut line = first.to_vec();
    while !line.ends_with(b"\n") {
        if line.len() >= MAX_V1_HEADER_BYTES {
            return Err(ProxyHeaderError::Oversized { bytes: line.len() });
        }
        let mut byte = [0u8; 1];
        let mut got = 0;
        fill(stream, &mut byte, &mut got)
            .await
            .map_err(|e| match e {
                ProxyHeaderError::Closed { .. } => ProxyHeaderError::Closed { read: line.len() },
                other => other,
            })?;
        line.push(byte[0]);
    }
    parse(&line)
}

/// The rest of a version-2 header: the fixed part, then as many bytes as it announces.
async fn read_v2<R: AsyncRead + Unpin>(
    stream: &mut R,
    first: [u8; FIRST_READ],
) -> Result<ProxyHeader, ProxyHeaderError> {
    let mut fixed = [0u8; 16];
    fixed[..FIRST_READ].copy_from_slice(&first);
    let mut read = FIRST_READ;
    fill(stream, &mut fixed, &mut read).await?;
    if fixed[..12] != V2_SIGNATURE {
        return Err(ProxyHeaderError::Missing);
    }
    let total = 16 + usize::from(u16::from_be_bytes([fixed[14], fixed[15]]));
    if total > MAX_V2_HEADER_BYTES {
        return Err(ProxyHeaderError::Oversized { bytes: total });
    }
    let mut header = vec![0u8; total];
    header[..16].copy_from_slice(&fixed);
    fill(stream, &mut header, &mut read).await?;
    parse(&header)
}

/// Parses a whole header (`bytes` holds it and nothing after it).
pub fn parse(bytes: &[u8]) -> Result<ProxyHeader, ProxyHeaderError> {
    use ppp::v1;
    use ppp::v2;
    let malformed = |e: &dyn fmt::Display| ProxyHeaderError::Malformed(e.to_string());
    let proxied = |ip: std::net::IpAddr, port: u16| ProxyHeader::Proxied {
        source: SocketAddr::new(ip.to_canonical(), port),
    };
    if bytes.starts_with(&V2_SIGNATURE) {
        let header = v2::Header::try_from(bytes).map_err(|e| malformed(&e))?;
        if header.len() != bytes.len() {
            return Err(ProxyHeaderError::Malformed(format!(
                "{} bytes past its end",
                bytes.len() - header.len()
            )));
        }
        return Ok(match (header.command, header.addresses) {
            (v2::Command::Local, _) => ProxyHeader::Local,
            (v2::Command::Proxy, v2::Addresses::IPv4(a)) => {
                proxied(a.source_address.into(), a.source_port)
            }
            (v2::Command::Proxy, v2::Addresses::IPv6(a)) => {
                proxied(a.source_address.into(), a.source_port)
            }
            (v2::Command::Proxy, v2::Addresses::Unspecified | v2::Addresses::Unix(_)) => {
                ProxyHeader::Local
            }
        });
    }
    let header = v1::Header::try_from(bytes).map_err(|e| malformed(&e))?;
    if header.header.len() != bytes.len() {
        return Err(ProxyHeaderError::Malformed(
            "bytes past its `\\r\\n`".to_owned(),
        ));
    }
    Ok(match header.addresses {
        v1::Addresses::Tcp4(a) => proxied(a.source_address.into(), a.source_port),
        v1::Addresses::Tcp6(a) => proxied(a.source_address.into(), a.source_port),
        v1::Addresses::Unknown => ProxyHeader::Local,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppp::v2;
    use proptest::prelude::*;

    const TLS_HELLO_START: &[u8] = &[0x16, 0x03, 0x01, 0x02, 0x00, 0x01, 0x00, 0x01, 0xfc];

    /// Reads a header from `bytes` followed by a TLS ClientHello's first bytes; the header and
    /// what was left unread.
    fn read(bytes: &[u8]) -> (Result<ProxyHeader, ProxyHeaderError>, Vec<u8>) {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        let mut input = bytes.to_vec();
        input.extend_from_slice(TLS_HELLO_START);
        let mut stream = io::Cursor::new(input);
        let header = runtime.block_on(read_header(&mut stream));
        let rest = stream.get_ref()[stream.position() as usize..].to_vec();
        (header, rest)
    }

    fn v2_header(command: v2::Command, from: &str, to: &str) -> Vec<u8> {
        let addresses: v2::Addresses = (
            from.parse::<SocketAddr>().unwrap(),
            to.parse::<SocketAddr>().unwrap(),
        )
            .into();
        let version_command = v2::Version::Two as u8 | command as u8;
        v2::Builder::with_addresses(version_command, v2::Protocol::Stream, addresses)
            .build()
            .unwrap()
    }

    #[test]
    fn version_2_ipv4_and_ipv6_give_the_client_and_leave_the_tls_bytes_unread() {
        let header = v2_header(v2::Command::Proxy, "127.0.0.2:40000", "127.0.0.1:4433");
        assert_eq!(header.len(), 16 + 12);
        let (got, rest) = read(&header);
        assert_eq!(
            got.unwrap()
                .client_address("127.0.0.1:5000".parse().unwrap()),
            "127.0.0.2:40000".parse::<SocketAddr>().unwrap()
        );
        assert_eq!(rest, TLS_HELLO_START);

        let header = v2_header(
            v2::Command::Proxy,
            "[2001:db8::7]:40001",
            "[2001:db8::1]:443",
        );
        assert_eq!(header.len(), 16 + 36);
        let (got, rest) = read(&header);
        assert_eq!(
            got.unwrap(),
            ProxyHeader::Proxied {
                source: "[2001:db8::7]:40001".parse().unwrap()
            }
        );
        assert_eq!(rest, TLS_HELLO_START);

        // An IPv4-mapped IPv6 client is counted as its IPv4 address.
        let header = v2_header(v2::Command::Proxy, "[::ffff:10.1.2.3]:1", "[::1]:443");
        assert_eq!(
            read(&header).0.unwrap(),
            ProxyHeader::Proxied {
                source: "10.1.2.3:1".parse().unwrap()
            }
        );
    }

    #[test]
    fn version_2_with_tlvs_is_read_to_its_end() {
        let addresses: v2::Addresses = (
            "192.0.2.9:1234".parse::<SocketAddr>().unwrap(),
            "192.0.2.1:4433".parse::<SocketAddr>().unwrap(),
        )
            .into();
        let header = v2::Builder::with_addresses(0x21, v2::Protocol::Stream, addresses)
            .write_tlv(v2::Type::UniqueId, b"an-id-of-the-balancer")
            .unwrap()
            .write_tlv(v2::Type::NoOp, &[0; 40])
            .unwrap()
            .build()
            .unwrap();
        let (got, rest) = read(&header);
        assert_eq!(
            got.unwrap(),
            ProxyHeader::Proxied {
                source: "192.0.2.9:1234".parse().unwrap()
            }
        );
        assert_eq!(rest, TLS_HELLO_START);
    }

    #[test]
    fn local_keeps_the_balancers_address() {
        let peer: SocketAddr = "10.0.0.5:3000".parse().unwrap();
        let header = v2_header(v2::Command::Local, "127.0.0.2:1", "127.0.0.1:2");
        let (got, rest) = read(&header);
        assert_eq!(got.unwrap().client_address(peer), peer);
        assert_eq!(rest, TLS_HELLO_START);
        // HAProxy's checks: LOCAL with no address at all.
        let bare = v2::Builder::with_addresses(
            0x20,
            v2::Protocol::Unspecified,
            v2::Addresses::Unspecified,
        )
        .build()
        .unwrap();
        assert_eq!(bare.len(), 16);
        assert_eq!(read(&bare).0.unwrap(), ProxyHeader::Local);
        assert_eq!(read(b"PROXY UNKNOWN\r\n").0.unwrap(), ProxyHeader::Local);
    }

    #[test]
    fn version_1_tcp4_and_tcp6_give_the_client() {
        let (got, rest) = read(b"PROXY TCP4 127.0.0.3 127.0.0.1 51000 8443\r\n");
        assert_eq!(
            got.unwrap(),
            ProxyHeader::Proxied {
                source: "127.0.0.3:51000".parse().unwrap()
            }
        );
        assert_eq!(rest, TLS_HELLO_START);
        let (got, _) = read(b"PROXY TCP6 2001:db8::3 2001:db8::1 51000 8443\r\n");
        assert_eq!(
            got.unwrap(),
            ProxyHeader::Proxied {
                source: "[2001:db8::3]:51000".parse().unwrap()
            }
        );
    }

    #[test]
    fn truncated_headers_are_closed_with_the_bytes_read() {
        let header = v2_header(v2::Command::Proxy, "127.0.0.2:40000", "127.0.0.1:4433");
        for cut in [0, 5, 8, 12, 16, 20, header.len() - 1] {
            let runtime = tokio::runtime::Builder::new_current_thread()
                .build()
                .unwrap();
            let mut stream = io::Cursor::new(header[..cut].to_vec());
            match runtime.block_on(read_header(&mut stream)) {
                Err(ProxyHeaderError::Closed { read }) => assert_eq!(read, cut),
                other => panic!("cut at {cut}: {other:?}"),
            }
        }
        let runtime = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        let mut stream = io::Cursor::new(b"PROXY TCP4 127.0.0.3".to_vec());
        assert!(matches!(
            runtime.block_on(read_header(&mut stream)),
            Err(ProxyHeaderError::Closed { read: 20 })
        ));
        let e = ProxyHeaderError::Closed { read: 0 }.to_string();
        assert!(e.contains("before sending a PROXY protocol header"), "{e}");
    }

    #[test]
    fn oversized_headers_are_refused_before_they_are_read() {
        // Version 2 announcing 60 000 bytes: refused on its 16 first.
        let mut header = v2_header(v2::Command::Proxy, "127.0.0.2:40000", "127.0.0.1:4433");
        header[14..16].copy_from_slice(&60_000u16.to_be_bytes());
        let (got, rest) = read(&header);
        assert!(
            matches!(got, Err(ProxyHeaderError::Oversized { bytes: 60_016 })),
            "{got:?}"
        );
        assert_eq!(rest.len(), header.len() - 16 + TLS_HELLO_START.len());
        // Version 1 without its end.
        let long = format!("PROXY TCP4 {}", "1".repeat(200));
        let (got, rest) = read(long.as_bytes());
        assert!(
            matches!(got, Err(ProxyHeaderError::Oversized { bytes: 107 })),
            "{got:?}"
        );
        assert!(!rest.is_empty());
    }

    #[test]
    fn garbage_and_a_tls_hello_are_no_header() {
        for bytes in [
            &b"GET / HTTP/1.1\r\n\r\n"[..],
            TLS_HELLO_START,
            b"PROXY\r\n\r\n\r\n",
            b"\r\n\r\n\0\r\nQUIZ\n\x21\x11\0\x0c",
        ] {
            let (got, _) = read(bytes);
            assert!(
                matches!(got, Err(ProxyHeaderError::Missing)),
                "{bytes:?}: {got:?}"
            );
        }
        for bytes in [
            &b"PROXY TCP4 300.0.0.1 127.0.0.1 1 2\r\n"[..],
            b"PROXY TCP4 127.0.0.1 127.0.0.1 1\r\n",
            b"PROXY UDP4 127.0.0.1 127.0.0.1 1 2\r\n",
            b"PROXY TCP4 127.0.0.1 127.0.0.1 1 2\n",
            // Version 2 with version nibble 1, a bad command, a bad family.
            b"\r\n\r\n\0\r\nQUIT\n\x11\x11\0\x0c\x7f\0\0\x02\x7f\0\0\x01\0\x01\0\x02",
            b"\r\n\r\n\0\r\nQUIT\n\x2f\x11\0\x0c\x7f\0\0\x02\x7f\0\0\x01\0\x01\0\x02",
            b"\r\n\r\n\0\r\nQUIT\n\x21\x41\0\x0c\x7f\0\0\x02\x7f\0\0\x01\0\x01\0\x02",
            // IPv6 announced, 12 bytes of addresses given.
            b"\r\n\r\n\0\r\nQUIT\n\x21\x21\0\x0c\x7f\0\0\x02\x7f\0\0\x01\0\x01\0\x02",
        ] {
            let (got, _) = read(bytes);
            assert!(
                matches!(got, Err(ProxyHeaderError::Malformed(_))),
                "{bytes:?}: {got:?}"
            );
        }
    }

    proptest! {
        /// Any bytes: no panic, never a read past the announced header, and a header that
        /// parses once read parses the same from its bytes alone.
        #[test]
        fn any_bytes_are_read_safely(body in proptest::collection::vec(any::<u8>(), 0..300),
                                     v2_prefix in any::<bool>(), v1_prefix in any::<bool>()) {
            let mut bytes = Vec::new();
            if v2_prefix {
                bytes.extend_from_slice(&V2_SIGNATURE);
            } else if v1_prefix {
                bytes.extend_from_slice(V1_PREFIX);
            }
            bytes.extend_from_slice(&body);
            let runtime = tokio::runtime::Builder::new_current_thread().build().unwrap();
            let mut stream = io::Cursor::new(bytes.clone());
            let got = runtime.block_on(read_header(&mut stream));
            let used = stream.position() as usize;
            prop_assert!(used <= MAX_V2_HEADER_BYTES);
            if let Ok(header) = got {
                prop_assert_eq!(parse(&bytes[..used]).unwrap(), header);
            }
        }
    }
}
