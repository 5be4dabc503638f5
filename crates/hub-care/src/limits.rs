//! The hub's file-descriptor budget: `hub serve` raises its soft `RLIMIT_NOFILE` to the hard
//! limit, then fits its connection caps under it so that connections nobody has authenticated
//! can never take the descriptors paired stations, logged-in therapists and the database need.
//!
//! ```text
//! FD_RESERVE                                   database pool, store files, replays, runtime
//! + FDS_PER_STATION × stations                 admitted stations (socket + session/upload file)
//! + stations_unauthenticated                   station port, before the Hello is admitted
//! + web_connections                            console port (of which web_unanswered at most
//!                                              before their first answer)
//! ≤ the descriptor limit
//! ```

/// Descriptors kept for everything but connections: the database pool, session and upload
/// files, replays, the runtime, stdio.
pub const FD_RESERVE: u64 = 256;

/// Descriptors one admitted station may hold: its socket and an open session or upload file.
pub const FDS_PER_STATION: u64 = 2;

/// No cap is shrunk below this many.
pub const MIN_CAP: usize = 8;

/// Raises the soft limit on open files to the hard limit; the soft limit now in force
/// (`None`: unlimited).
pub fn raise_fd_limit() -> Result<Option<u64>, String> {
    use rustix::process::{Resource, getrlimit, setrlimit};
    let limit = getrlimit(Resource::Nofile);
    if limit.current != limit.maximum {
        let raised = rustix::process::Rlimit {
            current: limit.maximum,
            maximum: limit.maximum,
        };
        if let Err(e) = setrlimit(Resource::Nofile, raised) {
            return Err(format!(
                "cannot raise the open-file limit from {:?} to {:?}: {e}",
                limit.current, limit.maximum
            ));
        }
    }
    Ok(getrlimit(Resource::Nofile).current)
}

/// The soft limit on open files now (`None`: unlimited).
pub fn fd_limit() -> Option<u64> {
    rustix::process::getrlimit(rustix::process::Resource::Nofile).current
}

/// Connection caps that consume descriptors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConnectionBudget {
    /// Stations admitted at once (station port `max_connections`).
    pub stations: usize,
    /// Station-port connections not admitted yet (`max_unauthenticated`).
    pub stations_unauthenticated: usize,
    /// Console connections in all (0: no console).
    pub web_connections: usize,
    /// Console connections with no answered request yet (at most `web_connections`).
    pub web_unanswered: usize,
}

impl ConnectionBudget {
    /// Descriptors these caps may use at most, [`FD_RESERVE`] included.
    pub fn descriptors(&self) -> u64 {
        let n = |x: usize| u64::try_from(x).unwrap_or(u64::MAX);
        FD_RESERVE
            .saturating_add(FDS_PER_STATION.saturating_mul(n(self.stations)))
            .saturating_add(n(self.stations_unauthenticated))
            .saturating_add(n(self.web_connections))
    }

    /// These caps shrunk in proportion (none below [`MIN_CAP`]) until they fit `fd_limit`
    /// (`None`: unlimited), and a warning saying so if they had to shrink.
    pub fn fit(self, fd_limit: Option<u64>) -> (Self, Option<String>) {
        let Some(limit) = fd_limit else {
            return (self, None);
        };
        let wanted = self.descriptors();
        if wanted <= limit {
            return (self, None);
        }
        let available = limit.saturating_sub(FD_RESERVE);
        let need = wanted - FD_RESERVE;
        let scale = |cap: usize| -> usize {
            if cap == 0 {
                return 0;
            }
            let scaled = u128::from(u64::try_from(cap).unwrap_or(u64::MAX)) * u128::from(available)
                / u128::from(need.max(1));
            usize::try_from(scaled).unwrap_or(usize::MAX).max(MIN_CAP)
        };
        let web_connections = scale(self.web_connections);
        let fitted = Self {
            stations: scale(self.stations),
            stations_unauthenticated: scale(self.stations_unauthenticated),
            web_connections,
            web_unanswered: scale(self.web_unanswered).min(web_connections),
        };
        let warning = format!(
            "the open-file limit is {limit} but the connection caps need {wanted} descriptors; \
             shrunk to {} stations, {} unauthenticated station connections, {} console \
             connections ({} unanswered); raise the hard limit (ulimit -Hn, LimitNOFILE=) to \
             serve more",
            fitted.stations,
            fitted.stations_unauthenticated,
            fitted.web_connections,
            fitted.web_unanswered
        );
        (fitted, Some(warning))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WANTED: ConnectionBudget = ConnectionBudget {
        stations: 2048,
        stations_unauthenticated: 1024,
        web_connections: 1024,
        web_unanswered: 512,
    };

    #[test]
    fn caps_that_fit_the_descriptor_limit_are_kept() {
        assert_eq!(WANTED.descriptors(), 256 + 4096 + 1024 + 1024);
        assert_eq!(WANTED.fit(Some(20_000)), (WANTED, None));
        assert_eq!(WANTED.fit(None), (WANTED, None));
    }

    #[test]
    fn caps_shrink_under_a_small_descriptor_limit_and_leave_the_reserve() {
        let (fitted, warning) = WANTED.fit(Some(1024));
        assert!(fitted.descriptors() <= 1024, "{fitted:?}");
        assert!(fitted.stations_unauthenticated < 1024 && fitted.stations >= MIN_CAP);
        assert!(fitted.web_unanswered <= fitted.web_connections);
        let warning = warning.unwrap();
        assert!(warning.contains("open-file limit is 1024"), "{warning}");
    }
}
