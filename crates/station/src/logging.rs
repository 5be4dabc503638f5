//! The `tracing` subscriber: set up once, here, for the whole process (DESIGN.md, house style 4).

use tracing_subscriber::EnvFilter;

/// Log to stderr with `filter` (e.g. `info`, `station=trace`), else `RUST_LOG`, else `info`.
pub fn init(filter: Option<&str>) {
    let filter = match filter {
        Some(f) => EnvFilter::new(f),
        None => EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
    };
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .try_init();
}
