//! `telerehab docs` writes a man page for the program and every subcommand a person may run,
//! and the bash, zsh and fish completions, all from the command line itself (for the package).

use clap::CommandFactory;
use telerehab_tests::run_ok;

/// The man page names of `cmd` and its visible subcommands, `telerehab-hub-serve` style.
fn pages(cmd: &clap::Command, prefix: &str, out: &mut Vec<String>) {
    out.push(prefix.to_owned());
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        pages(sub, &format!("{prefix}-{}", sub.get_name()), out);
    }
}

#[test]
fn every_visible_subcommand_has_a_man_page_and_the_shells_complete_them() {
    let dir = tempfile::tempdir().unwrap();
    run_ok(&["docs", "--out", dir.path().to_str().unwrap()]);
    let mut expected = Vec::new();
    pages(&telerehab::cli::Cli::command(), "telerehab", &mut expected);
    assert!(expected.len() >= 25, "{expected:?}");
    for name in &expected {
        let page = dir.path().join("man1").join(format!("{name}.1"));
        let text = std::fs::read_to_string(&page).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            text.starts_with(".ie") || text.contains(".TH"),
            "{name}: not roff"
        );
    }
    let written = std::fs::read_dir(dir.path().join("man1")).unwrap().count();
    assert_eq!(
        written,
        expected.len(),
        "a page for a hidden command, or one too many"
    );
    let run = std::fs::read_to_string(dir.path().join("man1/telerehab-run.1")).unwrap();
    assert!(run.contains("\\-\\-sim") || run.contains("--sim"), "{run}");
    for file in ["telerehab.bash", "_telerehab", "telerehab.fish"] {
        let text = std::fs::read_to_string(dir.path().join("completions").join(file)).unwrap();
        assert!(text.contains("replay"), "{file}");
    }
}
