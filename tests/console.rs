//! The therapist console's HTTPS API as a browser reaches it, for the end-to-end tests: one
//! request a connection, trusting the clinic's CA only.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::sync::Arc;

/// The console's HTTPS API, one request a connection, trusting the clinic's CA only.
pub struct Console {
    addr: String,
    tls: Arc<rustls::ClientConfig>,
    /// The local address its connections come from (`None`: the system's choice).
    source: Option<std::net::IpAddr>,
}

/// An answer: status, headers (lowercase names) and body.
pub struct Answer {
    /// The status code.
    pub status: u16,
    /// The headers, names lowercase.
    pub headers: Vec<(String, String)>,
    /// The body (de-chunked).
    pub body: Vec<u8>,
    /// How long after the request the body's first line of replay frames (`{"frames"`) had
    /// arrived, if one did (a streamed replay's time to its first frames).
    pub first_frames_after: Option<std::time::Duration>,
}

impl Answer {
    /// The body as JSON (panics, showing it, if it is not).
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|_| panic!("{} {}", self.status, String::from_utf8_lossy(&self.body)))
    }

    /// The first header `name` (lowercase).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }
}

impl Console {
    /// The console of the clinic in `data` at `addr` (`127.0.0.1:PORT`).
    pub fn new(data: &Path, addr: &str) -> Self {
        use rustls::pki_types::CertificateDer;
        use rustls::pki_types::pem::PemObject;
        let mut roots = rustls::RootCertStore::empty();
        for cert in CertificateDer::pem_file_iter(data.join("tls").join("ca.crt")).unwrap() {
            roots.add(cert.unwrap()).unwrap();
        }
        let provider = Arc::new(rustls::crypto::ring::default_provider());
        let tls = rustls::ClientConfig::builder_with_provider(provider)
            .with_safe_default_protocol_versions()
            .unwrap()
            .with_root_certificates(roots)
            .with_no_client_auth();
        Self {
            addr: addr.to_owned(),
            tls: Arc::new(tls),
            source: None,
        }
    }

    /// The same console, reached from the local address `source` (a loopback address such as
    /// `127.0.0.2`: another client for the hub's per-address guards).
    pub fn from_source(mut self, source: std::net::IpAddr) -> Self {
        self.source = Some(source);
        self
    }

    /// One request on its own connection; the answer.
    pub fn request(&self, method: &str, path: &str, cookie: Option<&str>, body: &str) -> Answer {
        let name = rustls::pki_types::ServerName::try_from("localhost").unwrap();
        let conn = rustls::ClientConnection::new(self.tls.clone(), name).unwrap();
        let tcp = connect_from(self.source, &self.addr);
        let mut tls = rustls::StreamOwned::new(conn, tcp);
        let mut head = format!(
            "{method} {path} HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\
             Content-Length: {}\r\n",
            body.len()
        );
        if !body.is_empty() {
            head.push_str("Content-Type: application/json\r\n");
        }
        if let Some(c) = cookie {
            head.push_str(&format!("Cookie: {c}\r\n"));
        }
        head.push_str("\r\n");
        tls.write_all(head.as_bytes()).unwrap();
        tls.write_all(body.as_bytes()).unwrap();
        let sent = std::time::Instant::now();
        let mut raw = Vec::new();
        let mut first_frames_after = None;
        let mut buf = vec![0u8; 64 << 10];
        // The server closes after the answer (some TLS stacks skip close_notify).
        loop {
            match tls.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    let from = raw.len().saturating_sub(16);
                    raw.extend_from_slice(&buf[..n]);
                    let frames = b"{\"frames\"";
                    if first_frames_after.is_none()
                        && raw[from..].windows(frames.len()).any(|w| w == frames)
                    {
                        first_frames_after = Some(sent.elapsed());
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    assert_eq!(e.kind(), std::io::ErrorKind::UnexpectedEof, "{e}");
                    break;
                }
            }
        }
        let split = raw
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .expect("an HTTP answer");
        let head = String::from_utf8_lossy(&raw[..split]).into_owned();
        let mut lines = head.lines();
        let status = lines
            .next()
            .unwrap()
            .split(' ')
            .nth(1)
            .unwrap()
            .parse()
            .unwrap();
        let headers: Vec<(String, String)> = lines
            .filter_map(|l| l.split_once(':'))
            .map(|(n, v)| (n.trim().to_lowercase(), v.trim().to_owned()))
            .collect();
        let mut body = raw[split + 4..].to_vec();
        if headers
            .iter()
            .any(|(n, v)| n == "transfer-encoding" && v.contains("chunked"))
        {
            body = unchunk(&body);
        }
        Answer {
            status,
            headers,
            body,
            first_frames_after,
        }
    }

    /// Logs in; the `Cookie` header value. A one-time password (`hub init`, `hub therapist
    /// add`) is changed first, as the console makes a therapist do at first login.
    pub fn login(&self, email: &str, password: &str) -> String {
        let body = serde_json::json!({"email": email, "password": password}).to_string();
        let answer = self.request("POST", "/api/login", None, &body);
        assert_eq!(
            answer.status,
            200,
            "{}",
            String::from_utf8_lossy(&answer.body)
        );
        let cookie = session_cookie(&answer);
        if answer.json()["must_change_password"] != true {
            return cookie;
        }
        let change = serde_json::json!({"current": password, "new": format!("{password} renewed")});
        let changed = self.request(
            "POST",
            "/api/me/password",
            Some(&cookie),
            &change.to_string(),
        );
        assert!(
            changed.status < 300,
            "{} {}",
            changed.status,
            String::from_utf8_lossy(&changed.body)
        );
        session_cookie(&changed)
    }

    /// `GET path` (Server-Sent Events) with the login `cookie`, read on a thread of its own:
    /// each event as (its name, its data), as it arrives, until the server ends the stream.
    pub fn events(&self, path: &str, cookie: &str) -> std::sync::mpsc::Receiver<(String, String)> {
        use std::io::BufRead;
        let name = rustls::pki_types::ServerName::try_from("localhost").unwrap();
        let conn = rustls::ClientConnection::new(self.tls.clone(), name).unwrap();
        let tcp = connect_from(self.source, &self.addr);
        let mut tls = rustls::StreamOwned::new(conn, tcp);
        let head = format!(
            "GET {path} HTTP/1.1\r\nHost: localhost\r\nAccept: text/event-stream\r\n\
             Cookie: {cookie}\r\n\r\n"
        );
        tls.write_all(head.as_bytes()).unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            // Chunk-size lines of the chunked body come between events; only `event:` and
            // `data:` lines are read (the hub writes each event in one chunk).
            let mut event = String::new();
            for line in std::io::BufReader::new(tls).lines() {
                let Ok(line) = line else { return };
                if let Some(name) = line.strip_prefix("event: ") {
                    event = name.to_owned();
                } else if let Some(data) = line.strip_prefix("data: ")
                    && tx.send((event.clone(), data.to_owned())).is_err()
                {
                    return;
                }
            }
        });
        rx
    }

    /// `GET path` with the login `cookie`.
    pub fn get(&self, path: &str, cookie: &str) -> Answer {
        self.request("GET", path, Some(cookie), "")
    }
}

/// A chunked HTTP/1.1 body joined.
fn unchunk(mut raw: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line_end = raw.windows(2).position(|w| w == b"\r\n").unwrap();
        let size_text = String::from_utf8_lossy(&raw[..line_end]).into_owned();
        let size = usize::from_str_radix(size_text.split(';').next().unwrap().trim(), 16).unwrap();
        raw = &raw[line_end + 2..];
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&raw[..size]);
        raw = &raw[size + 2..];
    }
}

/// The login cookie an answer sets (`name=value`).
fn session_cookie(answer: &Answer) -> String {
    answer
        .headers
        .iter()
        .filter(|(n, _)| n == "set-cookie")
        .map(|(_, v)| v.split(';').next().unwrap().to_owned())
        .find(|c| c.starts_with("telerehab_session="))
        .expect("a login cookie")
}

/// A TCP connection to `addr` (`127.0.0.1:PORT`) from the local address `source` (any port),
/// or from the system's choice without one.
pub fn connect_from(source: Option<std::net::IpAddr>, addr: &str) -> TcpStream {
    let Some(source) = source else {
        return TcpStream::connect(addr).unwrap();
    };
    let to: std::net::SocketAddr = addr.parse().unwrap();
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .build()
        .unwrap();
    runtime.block_on(async {
        let socket = if source.is_ipv4() {
            tokio::net::TcpSocket::new_v4()
        } else {
            tokio::net::TcpSocket::new_v6()
        }
        .unwrap();
        socket.bind(std::net::SocketAddr::new(source, 0)).unwrap();
        let tcp = socket.connect(to).await.unwrap();
        let tcp = tcp.into_std().unwrap();
        tcp.set_nonblocking(false).unwrap();
        tcp
    })
}
