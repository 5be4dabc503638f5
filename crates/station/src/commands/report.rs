//! `telerehab report`: recorded sessions → one self-contained HTML report
//! (the `report` crate's `report::html`).

use anyhow::bail;
use std::path::PathBuf;

/// `telerehab report`.
#[derive(Debug, clap::Args)]
pub struct ReportArgs {
    /// Session recordings (MCAP); several give a progress section with trends.
    #[arg(required = true)]
    pub recordings: Vec<PathBuf>,
    /// The HTML file to write.
    #[arg(long)]
    pub out: PathBuf,
}

/// Write the report and say where.
pub fn run(args: &ReportArgs) -> anyhow::Result<()> {
    if args.out.extension().is_none_or(|e| e != "html") {
        bail!("--out {} must name an .html file", args.out.display());
    }
    let progress = indicatif::ProgressBar::new(args.recordings.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {wide_msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let written = report::html::write(&args.recordings, &args.out, &progress)?;
    progress.finish_and_clear();
    println!(
        "report: {} session{} → {} ({} kB; open it in any browser, it needs no network)",
        written.sessions,
        if written.sessions == 1 { "" } else { "s" },
        args.out.display(),
        written.bytes / 1000
    );
    Ok(())
}
