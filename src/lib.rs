//! lerpit: learn and explore simple body dynamics.
//!
//! One folder per concept; each folder's `mod.rs` has the table of its
//! files.
//!
//! | folder   | concept                                                          |
//! |----------|------------------------------------------------------------------|
//! | [`sim`]  | the physics: bodies, the step and its stages, exact references   |
//! | [`scene`]| scenes as data: the lessons, TOML scene files, the rules of a valid value, the benchmark scene |
//! | [`study`]| the accuracy study: work-precision sweeps, goals, stability suite |
//! | [`cli`]  | the command line: flags, the headless runner, bench, study output |
//! | `tui`    | the full-screen terminal visualiser (feature `tui`)              |
//! | `process`| for both front ends: the progress line, the signals that end the program |
//!
//! Each layer uses only what lies below it in this picture, never what lies
//! above:
//!
//! ```text
//!   cli ---> tui        the front ends: the command line is the program's
//!    |   \  /  \        entry and opens the visualiser, which uses nothing
//!    |  study  process  of it; study runs scenes and measures them; process
//!    |    |   /         draws the progress line and holds off signals
//!     scene             builds worlds from data
//!       |
//!      sim              knows nothing above it
//! ```
//!
//! So `sim` imports none of `scene`, `study`, `process`, `cli`, `tui`;
//! `scene` none of `study`, `process`, `cli`, `tui`; `study` and `process`
//! none of each other, `cli` or `tui`; `tui` nothing of `cli`. A front end
//! may reach past a level (`cli` uses `sim` directly). What both front
//! ends need lives below them: the benchmark scene is [`scene::bench`],
//! not the command line's, and the progress line is `process`'s.
//!
//! The documentation is written for readers of the whole source, and its
//! links reach private items too: `cargo doc --document-private-items`
//! renders every one of them.

// Links to private items resolve in the documentation of the whole source.
#![allow(rustdoc::private_intra_doc_links)]

pub mod cli;
pub(crate) mod process;
pub mod scene;
pub mod sim;
pub mod study;
#[cfg(feature = "tui")]
pub mod tui;

#[cfg(test)]
mod tests {
    use std::path::Path;

    /// The text of the source file `path` before its tests.
    pub(crate) fn code_of(path: &Path) -> String {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        match text.find("#[cfg(test)]\nmod tests") {
            Some(end) => text[..end].to_string(),
            None => text,
        }
    }

    /// The code of every file under `src/{folder}`, each before its tests.
    fn code_under(folder: &str) -> Vec<(String, String)> {
        fn walk(dir: &Path, out: &mut Vec<(String, String)>) {
            let mut entries: Vec<_> = std::fs::read_dir(dir)
                .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
                .map(|e| e.unwrap().path())
                .collect();
            entries.sort();
            for path in entries {
                if path.is_dir() {
                    walk(&path, out);
                } else if path.extension().is_some_and(|x| x == "rs") {
                    out.push((path.display().to_string(), code_of(&path)));
                }
            }
        }
        let mut out = Vec::new();
        walk(
            &Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("src")
                .join(folder),
            &mut out,
        );
        out
    }

    #[test]
    fn each_layer_uses_only_what_lies_below_it() {
        let layers: [(&str, &[&str]); 5] = [
            ("sim", &[]),
            ("scene", &["sim"]),
            ("study", &["scene", "sim"]),
            ("process", &["scene", "sim"]),
            ("tui", &["process", "study", "scene", "sim"]),
        ];
        for (layer, below) in layers {
            let files = code_under(layer);
            assert!(!files.is_empty(), "no files under src/{layer}");
            for (path, code) in files {
                for (at, _) in code.match_indices("crate::") {
                    let used: String = code[at + "crate::".len()..]
                        .chars()
                        .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                        .collect();
                    assert!(
                        used == layer || below.contains(&used.as_str()),
                        "{path} uses crate::{used}, which does not lie below {layer}"
                    );
                }
                if layer != "tui" {
                    for terminal in ["ratatui", "crossterm"] {
                        assert!(!code.contains(terminal), "{path} uses {terminal}");
                    }
                }
            }
        }
    }
}
