//! The station's subcommands of `telerehab`: one file each, owning its `clap` arguments and its
//! `run()` (the `telerehab` binary crate's `cli` only names them and dispatches). A new
//! subcommand is a new file here, a variant of `telerehab::cli::Command` and one line of its
//! `dispatch`.

pub mod devices;
pub mod doctor;
pub mod pair;
pub mod recover;
pub mod render;
pub mod replay;
pub mod report;
pub mod run;
pub mod start;
pub mod sync;
pub mod therapist;
pub mod vehicle;
pub mod wheel;
pub mod window_process;

/// Parse `WIDTHxHEIGHT` (16 to 8192 pixels a side): the `--size` of `render` and `bench window`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
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
