//! The byte stream between the station and its window process, and how the window process is
//! started on it. Everything spoken over it ([`super::wire`]) is the same on both systems.
//!
//! - **Linux**: a socket pair; the window's end is its standard input. The window runs in a
//!   process group of its own, so Ctrl-C in the terminal stops the session (which then closes
//!   the window) rather than killing the window first.
//! - **Windows** (std has no socket pair there): a loopback TCP connection. The station listens
//!   on `127.0.0.1`, port chosen by the system, and gives the window the port in
//!   [`PORT_ENV`] and a one-time 256-bit token on its standard input (a pipe no other process
//!   can read). The window connects and says the token first; a connection that does not say
//!   it within `TOKEN_TIMEOUT` (2 s) is closed and the station keeps waiting, so another local
//!   program cannot take the window's place. The window gets a new process group
//!   (`CREATE_NEW_PROCESS_GROUP`) for the same reason as on Linux.

use std::io;
use std::process::{Child, Command};
use std::time::Duration;

/// The station's end of the stream (and the window's).
#[cfg(unix)]
pub type WindowSocket = std::os::unix::net::UnixStream;
/// The station's end of the stream (and the window's).
#[cfg(windows)]
pub type WindowSocket = std::net::TcpStream;

/// Windows: the environment variable that gives the window the station's loopback port.
pub const PORT_ENV: &str = "TELEREHAB_WINDOW_PORT";

/// Windows: how long a connection may take to say the token before it is closed.
#[cfg(windows)]
pub const TOKEN_TIMEOUT: Duration = Duration::from_secs(2);

/// Starts `command` as the window process, connected to the returned socket; the window
/// process takes its end with [`connect_to_station`]. `open_timeout` bounds how long the
/// window may take to connect (Windows; on Linux the socket exists before the process).
pub fn spawn_connected(
    command: &mut Command,
    open_timeout: Duration,
) -> io::Result<(Child, WindowSocket)> {
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        let _ = open_timeout;
        let (ours, theirs) = WindowSocket::pair()?;
        let child = command
            .stdin(std::process::Stdio::from(std::os::fd::OwnedFd::from(
                theirs,
            )))
            .process_group(0)
            .spawn();
        // The command holds our copy of the window's end until its stdin is set again: closed
        // now, so that the window's death reaches us as the end of the stream.
        command.stdin(std::process::Stdio::null());
        Ok((child?, ours))
    }
    #[cfg(windows)]
    {
        windows::spawn_connected(command, open_timeout)
    }
}

/// The window process's end of the stream to the station that started it.
pub fn connect_to_station() -> io::Result<WindowSocket> {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        let fd = io::stdin().as_fd().try_clone_to_owned()?;
        Ok(WindowSocket::from(fd))
    }
    #[cfg(windows)]
    {
        windows::connect_to_station()
    }
}

#[cfg(windows)]
mod windows {
    use super::{PORT_ENV, TOKEN_TIMEOUT, WindowSocket};
    use std::io::{self, BufRead as _, Read as _, Write as _};
    use std::net::{Ipv4Addr, TcpListener};
    use std::os::windows::process::CommandExt as _;
    use std::process::{Child, Command, Stdio};
    use std::time::{Duration, Instant};

    /// `CREATE_NEW_PROCESS_GROUP` (WinBase.h).
    const CREATE_NEW_PROCESS_GROUP: u32 = 0x0000_0200;
    /// The token's length in hex digits (256 bits).
    const TOKEN_HEX: usize = 64;

    pub(super) fn spawn_connected(
        command: &mut Command,
        open_timeout: Duration,
    ) -> io::Result<(Child, WindowSocket)> {
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, 0))?;
        let port = listener.local_addr()?.port();
        let mut token_bytes = [0u8; TOKEN_HEX / 2];
        getrandom::fill(&mut token_bytes).map_err(io::Error::other)?;
        let token: String = token_bytes.iter().map(|b| format!("{b:02x}")).collect();
        let mut child = command
            .env(PORT_ENV, port.to_string())
            .stdin(Stdio::piped())
            .creation_flags(CREATE_NEW_PROCESS_GROUP)
            .spawn()?;
        let told = child
            .stdin
            .take()
            .map(|mut stdin| writeln!(stdin, "{token}"))
            .unwrap_or_else(|| Err(io::ErrorKind::BrokenPipe.into()));
        let accepted = told.and_then(|()| accept_with_token(&listener, &token, open_timeout));
        match accepted {
            Ok(socket) => Ok((child, socket)),
            Err(e) => {
                let _ = child.kill();
                let _ = child.wait();
                Err(e)
            }
        }
    }

    /// The first connection that says `token` within [`TOKEN_TIMEOUT`], before `timeout`.
    fn accept_with_token(
        listener: &TcpListener,
        token: &str,
        timeout: Duration,
    ) -> io::Result<WindowSocket> {
        let deadline = Instant::now() + timeout;
        listener.set_nonblocking(true)?;
        loop {
            match listener.accept() {
                Ok((socket, _)) => {
                    socket.set_nonblocking(false)?;
                    socket.set_read_timeout(Some(TOKEN_TIMEOUT))?;
                    let mut said = [0u8; TOKEN_HEX];
                    let proved = (&socket).read_exact(&mut said).is_ok()
                        && said
                            .iter()
                            .zip(token.as_bytes())
                            .fold(0u8, |d, (a, b)| d | (a ^ b))
                            == 0;
                    if proved {
                        socket.set_read_timeout(None)?;
                        socket.set_nodelay(true)?;
                        return Ok(socket);
                    }
                    tracing::warn!("a local connection to the window's port did not prove itself");
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    if Instant::now() >= deadline {
                        return Err(io::Error::new(
                            io::ErrorKind::TimedOut,
                            format!("it did not connect within {} s", timeout.as_secs()),
                        ));
                    }
                    std::thread::sleep(Duration::from_millis(5));
                }
                Err(e) => return Err(e),
            }
        }
    }

    pub(super) fn connect_to_station() -> io::Result<WindowSocket> {
        let port: u16 = std::env::var(PORT_ENV)
            .ok()
            .and_then(|p| p.parse().ok())
            .ok_or_else(|| {
                io::Error::new(
                    io::ErrorKind::NotFound,
                    format!("{PORT_ENV} does not name the station's port"),
                )
            })?;
        let mut token = String::new();
        io::stdin().lock().read_line(&mut token)?;
        let token = token.trim();
        if token.len() != TOKEN_HEX {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                "the station's token on standard input is not 64 hex digits",
            ));
        }
        let mut socket = WindowSocket::connect((Ipv4Addr::LOCALHOST, port))?;
        socket.write_all(token.as_bytes())?;
        socket.set_nodelay(true)?;
        Ok(socket)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read as _, Write as _};

    /// The test binary run as the window process: [`child_echo`] echoes one byte back,
    /// upper-cased, over [`connect_to_station`].
    #[test]
    fn a_window_process_started_on_the_channel_talks_both_ways() {
        let mut command = Command::new(std::env::current_exe().unwrap());
        command.args(["--exact", "window::channel::tests::child_echo", "--ignored"]);
        let (mut child, mut socket) =
            spawn_connected(&mut command, Duration::from_secs(30)).unwrap();
        socket.write_all(b"x").unwrap();
        let mut back = [0u8; 1];
        socket.read_exact(&mut back).unwrap();
        assert_eq!(&back, b"X");
        drop(socket);
        assert!(child.wait().unwrap().success());
    }

    #[test]
    fn a_window_process_that_dies_ends_the_stream() {
        // The test binary listing its tests exits at once without touching the stream: its
        // death must reach the station as the end of the stream (no other copy of the
        // window's end left open), not as a silence the station takes for a hang.
        let mut command = Command::new(std::env::current_exe().unwrap());
        command.arg("--list").stdout(std::process::Stdio::null());
        let (mut child, mut socket) =
            spawn_connected(&mut command, Duration::from_secs(30)).unwrap();
        assert!(child.wait().unwrap().success());
        socket
            .set_read_timeout(Some(Duration::from_secs(10)))
            .unwrap();
        let mut byte = [0u8; 1];
        assert_eq!(socket.read(&mut byte).unwrap(), 0, "the end of the stream");
    }

    #[test]
    #[ignore = "the window process of a_window_process_started_on_the_channel_talks_both_ways"]
    fn child_echo() {
        let mut socket = connect_to_station().unwrap();
        let mut byte = [0u8; 1];
        socket.read_exact(&mut byte).unwrap();
        socket.write_all(&byte.to_ascii_uppercase()).unwrap();
        let mut rest = Vec::new();
        socket.read_to_end(&mut rest).unwrap();
    }
}
