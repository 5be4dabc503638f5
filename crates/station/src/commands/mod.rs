//! Subcommands of `telerehab`: one file each, owning its `clap` arguments and its `run()`
//! ([`crate::cli`] only names them and dispatches). A new subcommand is a new file here, a
//! variant of [`crate::cli::Command`] and one line of [`crate::cli::dispatch`].

pub mod bench;
pub mod devices;
pub mod docs;
pub mod doctor;
#[cfg(unix)]
pub mod hub;
#[cfg(unix)]
pub mod hub_chaos;
#[cfg(unix)]
pub mod hub_cohort;
pub mod pair;
pub mod recover;
pub mod render;
pub mod replay;
pub mod report;
pub mod run;
mod server_stop;
pub mod start;
pub mod sync;
pub mod therapist;
pub mod vehicle;
pub mod wheel;
pub mod window_process;

/// Parse `WIDTHxHEIGHT` (16 to 8192 pixels a side): the `--size` of `render` and `bench window`.
pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size `{s}` is not WIDTHxHEIGHT"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|e| format!("size `{s}`: {e}"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(format!("size `{s}`: each side must be 16 to 8192 pixels"));
    }
    Ok((w, h))
}
