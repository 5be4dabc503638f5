//! How the long-running servers (`hub serve`, `therapist`) stop: on SIGINT or SIGTERM, within
//! a bounded time whatever they are doing (a flood of connections, an upload, a replay, a
//! pairing), with everything acknowledged already stored.
//!
//! The signal listeners are installed once, before serving, so a signal that arrives while
//! the server is busy is kept rather than lost (a listener made afresh each loop turn misses
//! one delivered in between: `therapist` once ignored SIGINT for 36 minutes under a flood).

use std::future::Future;
use std::io;
use std::time::Duration;

/// Longest the runtime waits for its blocking tasks (a replay's decoding, a file's hash) once
/// the server has stopped: they hold nothing that is not already stored.
pub const BLOCKING_GRACE: Duration = Duration::from_millis(500);

/// Resolves at the first SIGINT or SIGTERM after this call (on Windows: Ctrl-C, Ctrl-Break or
/// the console closing), with the signal's name.
pub fn stop_signal() -> io::Result<impl Future<Output = &'static str> + Send> {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        let mut interrupt = signal(SignalKind::interrupt())
            .map_err(|e| named(e, "cannot install the SIGINT handler"))?;
        let mut terminate = signal(SignalKind::terminate())
            .map_err(|e| named(e, "cannot install the SIGTERM handler"))?;
        Ok(async move {
            tokio::select! {
                _ = interrupt.recv() => "SIGINT",
                _ = terminate.recv() => "SIGTERM",
            }
        })
    }
    #[cfg(windows)]
    {
        use tokio::signal::windows::{ctrl_break, ctrl_c, ctrl_close};
        let mut interrupt = ctrl_c().map_err(|e| named(e, "cannot install the Ctrl-C handler"))?;
        let mut brk =
            ctrl_break().map_err(|e| named(e, "cannot install the Ctrl-Break handler"))?;
        let mut close =
            ctrl_close().map_err(|e| named(e, "cannot install the console-close handler"))?;
        Ok(async move {
            tokio::select! {
                _ = interrupt.recv() => "Ctrl-C",
                _ = brk.recv() => "Ctrl-Break",
                _ = close.recv() => "console closed",
            }
        })
    }
}

/// Runs `server` to its end on `runtime`, then shuts the runtime down waiting at most
/// [`BLOCKING_GRACE`] for blocking tasks still running.
pub fn run_to_stop<T, E>(
    runtime: tokio::runtime::Runtime,
    server: impl Future<Output = Result<T, E>>,
) -> Result<T, E> {
    let result = runtime.block_on(server);
    runtime.shutdown_timeout(BLOCKING_GRACE);
    result
}

/// `e` with what could not be done in front of it.
fn named(e: io::Error, what: &str) -> io::Error {
    io::Error::new(e.kind(), format!("{what}: {e}"))
}
