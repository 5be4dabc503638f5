//! `telerehab docs --out DIR` (hidden; for packaging): a man page for the program and one for
//! every subcommand, generated from the command line itself (clap_mangen), and the shell
//! completions for bash, zsh and fish (clap_complete), so neither can drift from the CLI.

use anyhow::Context;
use clap_complete::Shell;
use std::path::PathBuf;

/// Arguments of `telerehab docs`.
#[derive(Debug, clap::Args)]
pub struct DocsArgs {
    /// Directory to write into: `man1/` (man pages) and `completions/` (created if need be).
    #[arg(long)]
    pub out: PathBuf,
}

/// Write the man pages and completions of the command line `cmd` (the program's clap tree,
/// `Cli::with_version`) under `args.out`.
pub fn run(args: &DocsArgs, cmd: clap::Command) -> anyhow::Result<()> {
    let man = args.out.join("man1");
    let completions = args.out.join("completions");
    for dir in [&man, &completions] {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    clap_mangen::generate_to(cmd.clone(), &man)
        .with_context(|| format!("cannot write the man pages to {}", man.display()))?;
    for shell in [Shell::Bash, Shell::Zsh, Shell::Fish] {
        clap_complete::generate_to(shell, &mut cmd.clone(), "telerehab", &completions)
            .with_context(|| format!("cannot write the {shell} completions"))?;
    }
    let pages = std::fs::read_dir(&man)?.count();
    println!(
        "{pages} man pages in {}, completions for bash, zsh and fish in {}",
        man.display(),
        completions.display()
    );
    Ok(())
}
