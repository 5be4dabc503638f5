//! The station's words come from the catalogues (`crates/i18n/locales`), never from string
//! literals in its source: a scan of `src/` and of the crates whose words the patient may
//! read ([`CRATES`]: the window's `crates/render/src`, named `render/…` here, the session's
//! `session/…`, the arm's `arm/…` and the measures' `measures/…`) with `syn` finds every literal that reads like a
//! sentence (two words or more) outside the places where text is for developers (logs,
//! errors, assertions, the terminal, tests) and outside the allow-list
//! (`tests/words_allowed.txt`, each entry with its reason). It also checks that every
//! message id the source passes to `tr!` is in the English catalogue.

use proc_macro2::{TokenStream, TokenTree};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use syn::punctuated::Punctuated;
use syn::visit::{self, Visit};

mod common;

fn src() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The station's crates whose words the patient may read too, scanned beside `src/`: the
/// window's, the session's, and the arm's and the measures' below the session. A file of one
/// is named `<crate>/…` here (`render/gpu.rs`, `session/lib.rs`).
const CRATES: [&str; 4] = ["render", "session", "arm", "measures"];

/// The source folder of `krate`, one of [`CRATES`].
fn crate_src(krate: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../{krate}/src"))
}

/// Where a scanned or allowed name (`front_door/mod.rs`, `render/gpu.rs`, `session/lib.rs`)
/// is on disk.
fn path_of(name: &str) -> PathBuf {
    CRATES
        .iter()
        .find_map(|krate| {
            let rest = name.strip_prefix(krate)?.strip_prefix('/')?;
            Some(crate_src(krate).join(rest))
        })
        .unwrap_or_else(|| src().join(name))
}

/// Macros whose strings are for developers (logs, errors, assertions, terminal output) or
/// are not text at all; `tr!` holds message ids, checked on their own.
const DEVELOPER_MACROS: &[&str] = &[
    "trace",
    "debug",
    "info",
    "warn",
    "error",
    "event",
    "span",
    "trace_span",
    "debug_span",
    "info_span",
    "warn_span",
    "error_span",
    "bail",
    "anyhow",
    "ensure",
    "assert",
    "assert_eq",
    "assert_ne",
    "debug_assert",
    "debug_assert_eq",
    "debug_assert_ne",
    "panic",
    "unreachable",
    "todo",
    "unimplemented",
    "println",
    "eprintln",
    "print",
    "eprint",
    "write",
    "writeln",
    "include_str",
    "include_bytes",
    "concat",
    "env",
    "option_env",
    "compile_error",
    "tr",
];

/// Methods whose string arguments are error context for developers.
const DEVELOPER_METHODS: &[&str] = &["context", "with_context", "expect", "expect_err"];

/// A literal found.
#[derive(Debug, Clone)]
struct Found {
    /// Relative to `src/`.
    file: String,
    line: usize,
    text: String,
}

#[derive(Default)]
struct Finder {
    file: String,
    sentences: Vec<Found>,
    /// Message ids passed to `tr!` (every id-like literal in its tokens).
    ids: Vec<Found>,
}

/// Reads like words for a person: two words or more of two letters or more.
fn is_sentence(s: &str) -> bool {
    s.split_whitespace()
        .filter(|w| w.chars().filter(|c| c.is_alphabetic()).count() >= 2)
        .count()
        >= 2
}

fn is_message_id(s: &str) -> bool {
    !s.is_empty()
        && s.starts_with(|c: char| c.is_ascii_lowercase())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '.')
}

fn is_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("test")
            || (a.path().is_ident("cfg")
                && a.meta.require_list().is_ok_and(|l| {
                    l.tokens
                        .to_string()
                        .split(|c: char| !c.is_alphanumeric() && c != '_')
                        .any(|t| t == "test")
                }))
    })
}

impl Finder {
    fn literal(&mut self, lit: &syn::LitStr) {
        let text = lit.value();
        if is_sentence(&text) {
            self.sentences.push(Found {
                file: self.file.clone(),
                line: lit.span().start().line,
                text,
            });
        }
    }

    /// The string literals anywhere in `tokens` (a macro whose arguments are not
    /// expressions).
    fn literals_in(&mut self, tokens: TokenStream, ids: bool) {
        for tree in tokens {
            match tree {
                TokenTree::Group(g) => self.literals_in(g.stream(), ids),
                TokenTree::Literal(l) => {
                    if let Ok(lit) = syn::parse_str::<syn::LitStr>(&l.to_string()) {
                        if ids {
                            let text = lit.value();
                            if is_message_id(&text) {
                                self.ids.push(Found {
                                    file: self.file.clone(),
                                    line: l.span().start().line,
                                    text,
                                });
                            }
                        } else {
                            let lit = syn::LitStr::new(&lit.value(), l.span());
                            self.literal(&lit);
                        }
                    }
                }
                _ => {}
            }
        }
    }
}

impl<'ast> Visit<'ast> for Finder {
    fn visit_attribute(&mut self, _: &'ast syn::Attribute) {
        // Doc comments, clap's and serde's attributes: not on the patient's screen.
    }

    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        if !is_test(&m.attrs) {
            visit::visit_item_mod(self, m);
        }
    }

    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        if !is_test(&f.attrs) {
            visit::visit_item_fn(self, f);
        }
    }

    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        if !is_test(&f.attrs) {
            visit::visit_impl_item_fn(self, f);
        }
    }

    fn visit_expr_method_call(&mut self, call: &'ast syn::ExprMethodCall) {
        if DEVELOPER_METHODS.contains(&call.method.to_string().as_str()) {
            self.visit_expr(&call.receiver);
        } else {
            visit::visit_expr_method_call(self, call);
        }
    }

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        let name = mac
            .path
            .segments
            .last()
            .map(|s| s.ident.to_string())
            .unwrap_or_default();
        if name == "tr" {
            self.literals_in(mac.tokens.clone(), true);
            return;
        }
        if DEVELOPER_MACROS.contains(&name.as_str()) {
            return;
        }
        match mac.parse_body_with(Punctuated::<syn::Expr, syn::Token![,]>::parse_terminated) {
            Ok(args) => args.iter().for_each(|e| self.visit_expr(e)),
            Err(_) => self.literals_in(mac.tokens.clone(), false),
        }
    }

    fn visit_lit_str(&mut self, lit: &'ast syn::LitStr) {
        self.literal(lit);
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Every sentence-like literal and every `tr!` id of the station's source.
fn scan() -> Finder {
    let root = src();
    let roots: Vec<(&str, PathBuf)> = CRATES.iter().map(|&k| (k, crate_src(k))).collect();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    for (_, krate_root) in &roots {
        rust_files(krate_root, &mut files);
    }
    let mut finder = Finder::default();
    let parsed: Vec<(PathBuf, syn::File)> = files
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path).unwrap();
            let ast = syn::parse_file(&text)
                .unwrap_or_else(|e| panic!("{}: does not parse: {e}", path.display()));
            (path, ast)
        })
        .collect();
    // Test modules in their own files (`mod tests;`, `mod shots;` under `#[cfg(test)]`):
    // their files, and their folders.
    let test_modules: Vec<PathBuf> = parsed
        .iter()
        .flat_map(|(path, ast)| test_module_paths(path, ast))
        .collect();
    let is_test_file = |p: &Path| {
        test_modules
            .iter()
            .any(|m| p == m.with_extension("rs") || p.starts_with(m))
    };
    for (path, ast) in parsed.iter().filter(|(p, _)| !is_test_file(p)) {
        finder.file = roots
            .iter()
            .find_map(|(krate, krate_root)| {
                let rest = path.strip_prefix(krate_root).ok()?;
                Some(format!("{krate}/{}", rest.to_string_lossy()))
            })
            .unwrap_or_else(|| {
                path.strip_prefix(&root)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned()
            });
        finder.visit_file(ast);
    }
    finder
}

/// Where the `#[cfg(test)] mod name;` declarations of `file` live, without extension: the
/// module `name` is `<dir>/name.rs` or the folder `<dir>/name/`.
fn test_module_paths(file: &Path, ast: &syn::File) -> Vec<PathBuf> {
    let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    let dir = if matches!(stem, "mod" | "lib" | "main") {
        file.parent().unwrap().to_path_buf()
    } else {
        file.with_extension("")
    };
    ast.items
        .iter()
        .filter_map(|item| match item {
            syn::Item::Mod(m) if m.content.is_none() && is_test(&m.attrs) => {
                Some(dir.join(m.ident.to_string()))
            }
            _ => None,
        })
        .collect()
}

/// The allow-list: `path  # reason` (a file or folder under `src/`, every literal in it) or
/// `path: text  # reason` (one literal of that file).
#[derive(Debug)]
struct Allowed {
    paths: Vec<String>,
    literals: Vec<(String, String)>,
}

fn allowed() -> Allowed {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/words_allowed.txt");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut out = Allowed {
        paths: Vec::new(),
        literals: Vec::new(),
    };
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let Some((entry, reason)) = line.rsplit_once("  # ") else {
            panic!("words_allowed.txt line {}: no `  # reason`: {line}", n + 1);
        };
        assert!(
            !reason.trim().is_empty(),
            "words_allowed.txt line {}: empty reason",
            n + 1
        );
        match entry.split_once(": ") {
            Some((file, literal)) => out
                .literals
                .push((file.trim().to_owned(), literal.trim().to_owned())),
            None => out.paths.push(entry.trim().to_owned()),
        }
    }
    out
}

impl Allowed {
    fn allows(&self, f: &Found) -> bool {
        self.paths
            .iter()
            .any(|p| f.file == *p || (p.ends_with('/') && f.file.starts_with(p.as_str())))
            || self
                .literals
                .iter()
                .any(|(file, text)| *file == f.file && text.trim() == f.text.trim())
    }
}

#[test]
fn no_patient_facing_sentence_is_a_string_literal_outside_the_catalogues() {
    let found = scan();
    let allowed = allowed();
    let offending: Vec<String> = found
        .sentences
        .iter()
        .filter(|f| !allowed.allows(f))
        .map(|f| format!("src/{}:{}: {:?}", f.file, f.line, f.text))
        .collect();
    assert!(
        offending.is_empty(),
        "{} sentence(s) in the station's source, not in a catalogue \
         (crates/i18n/locales/*/*.ftl; use i18n::tr!), or add them to \
         tests/words_allowed.txt with the reason they are not the patient's:\n{}",
        offending.len(),
        offending.join("\n")
    );
}

#[test]
fn the_scanner_finds_a_sentence_in_code_and_ignores_logs_errors_and_tests() {
    let code = r#"
        fn page() -> String {
            tracing::info!("the window opened at last");
            let _ = std::fs::read("x").context("cannot read the file");
            let title = format!("Exercise {} of {}", 1, 2);
            i18n::tr!("card-get-ready");
            "Press Space to start".into()
        }
        #[cfg(test)]
        mod tests { fn t() { let _ = "a sentence in a test"; } }
    "#;
    let mut finder = Finder::default();
    finder.visit_file(&syn::parse_file(code).unwrap());
    let texts: Vec<&str> = finder.sentences.iter().map(|f| f.text.as_str()).collect();
    assert_eq!(texts, ["Exercise {} of {}", "Press Space to start"]);
    let ids: Vec<&str> = finder.ids.iter().map(|f| f.text.as_str()).collect();
    assert_eq!(ids, ["card-get-ready"]);
}

#[test]
fn every_message_id_the_station_asks_for_is_in_the_english_catalogue() {
    let english = i18n::Catalogue::load(i18n::FALLBACK).unwrap();
    let found = scan();
    assert!(!found.ids.is_empty());
    let missing: Vec<String> = found
        .ids
        .iter()
        .filter(|f| !english.has(&f.text))
        .map(|f| format!("src/{}:{}: {}", f.file, f.line, f.text))
        .collect();
    assert!(
        missing.is_empty(),
        "tr! ids with no English message:\n{}",
        missing.join("\n")
    );
}

#[test]
fn every_allow_list_entry_names_a_file_or_folder_that_exists() {
    let a = allowed();
    let mut by_file: BTreeMap<&str, usize> = BTreeMap::new();
    for p in a.paths.iter().chain(a.literals.iter().map(|(f, _)| f)) {
        *by_file.entry(p.as_str()).or_default() += 1;
        assert!(path_of(p).exists(), "words_allowed.txt: no src/{p}");
    }
}

// ---------------------------------------------------------------------------------------
// The words on each screen, counted (English), in docs/WORDS.md.

mod per_screen {
    use record::{ArmSample, ArmSetup};
    use regimen::Regimen;
    use render::{ScreenState, StatusLine};
    use session::config::StationConfig;
    use session::{BreakKind, BreakNow};
    use station::screen::{CourseView, WindowState, cannot_start_page, confirm_end_card};

    use super::common::tick;

    /// The text a screen state shows, line by line.
    fn lines_of(state: &ScreenState) -> Vec<String> {
        match state {
            ScreenState::Next(c) => [c.heading.clone(), c.title.clone(), c.what.clone()]
                .into_iter()
                .chain(c.keys.iter().cloned())
                .chain(c.message.clone())
                .collect(),
            ScreenState::Instruction { title, lines }
            | ScreenState::Pictured { title, lines, .. } => std::iter::once(title.clone())
                .chain(lines.iter().cloned())
                .collect(),
            ScreenState::Welcome(w) => std::iter::once(w.title.clone())
                .chain(w.lines.iter().map(|l| l.text.clone()))
                .chain(w.choices.iter().cloned())
                .chain(w.keys.iter().cloned())
                .collect(),
            other => panic!("no words counted for {other:?}"),
        }
    }

    /// Words: runs of characters with a letter in them.
    fn count(lines: &[String]) -> usize {
        lines
            .iter()
            .flat_map(|l| l.split_whitespace())
            .filter(|w| w.chars().any(char::is_alphabetic))
            .count()
    }

    /// (screen, its lines) for the session's screens in the language in force.
    fn screens() -> Vec<(&'static str, Vec<String>)> {
        let text = "[[exercise]]\nkind = \"sine\"\nduration_s = 30.0\nrest_s = 20.0\n\n\
                    [[exercise]]\nkind = \"dial\"\nduration_s = 30.0\n";
        let r = Regimen::from_toml(text, "words").unwrap();
        let view = CourseView::new(&StationConfig::default(), Some(&r)).unwrap();
        let plain = WindowState::default();
        let rest = WindowState {
            brk: BreakNow {
                kind: BreakKind::Prescribed,
                left_s: 17.0,
                ..BreakNow::default()
            },
            ..plain
        };
        let mut hold = tick(500, 0, 0.0, true);
        hold.arm = Some(ArmSample {
            setup: ArmSetup::HoldStill,
            setup_remaining_s: 3.0,
            ..ArmSample::default()
        });
        let running = tick(9000, 0, 8.0, false);
        let hud = view.scene(&running, ScreenState::Running).hud;
        let no_wheel = cannot_start_page(&[StatusLine {
            ok: Some(false),
            text: String::new(),
        }]);
        vec![
            (
                "Next exercise (before the start)",
                lines_of(&view.screen_state(&tick(0, 0, 0.0, true), &plain)),
            ),
            (
                "Rest, then the next exercise",
                lines_of(&view.screen_state(&tick(40_000, 1, 30.0, true), &rest)),
            ),
            (
                "Pause",
                lines_of(&view.screen_state(&tick(9000, 0, 8.0, true), &plain)),
            ),
            ("End the session?", lines_of(&confirm_end_card())),
            (
                "Arm sensors: hold still",
                lines_of(&view.screen_state(&hold, &plain)),
            ),
            (
                "During a road exercise (besides the numbers)",
                std::iter::once(hud.exercise)
                    .chain(hud.devices)
                    .chain([
                        i18n::tr!("hud-time-left"),
                        i18n::tr!("hud-in-lane", percent = 96),
                        i18n::tr!("hud-middle-close"),
                        i18n::tr!("hud-help", percent = 40),
                    ])
                    .collect(),
            ),
            (
                "The session cannot start (besides the check's lines)",
                lines_of(&ScreenState::Welcome(no_wheel)),
            ),
        ]
    }

    fn table() -> String {
        i18n::use_language("en").unwrap();
        let mut out = String::from(
            "# Words per screen\n\n\
             The words a patient reads on each of the session's screens, in English (a word: a \
             run of characters with a letter). Written by `crates/station/tests/words.rs`; \
             after changing the session's words, run \
             `UPDATE_SNAPSHOTS=1 cargo test -p station --test words` and commit the diff. \
             The rules (docs/DESIGN.md, \"Words and languages\"): at most 12 words a sentence, \
             one idea a page.\n\n\
             | Screen | Words | What it says |\n|---|---:|---|\n",
        );
        for (name, lines) in screens() {
            let said = lines
                .iter()
                .filter(|l| !l.trim().is_empty())
                .cloned()
                .collect::<Vec<_>>()
                .join(" / ");
            out.push_str(&format!("| {name} | {} | {said} |\n", count(&lines)));
        }
        out
    }

    #[test]
    fn the_words_per_screen_in_the_docs_are_those_the_station_shows() {
        super::common::assert_generated_doc_current("WORDS.md", &table(), "words");
    }
}
