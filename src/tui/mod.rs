//! The terminal visualiser: an orthographic braille view of the box, live
//! controls, stepping forward and back (feature `tui`).
//!
//! | file               | concept                                                   |
//! |--------------------|-----------------------------------------------------------|
//! | `session.rs`       | the simulation session: scene, world, history, ghost      |
//! | `selection.rs`     | the picked sphere or pair and its numbers, replayed exactly |
//! | `frame.rs`         | the copy of the session's state that the view draws       |
//! | `worker.rs`        | the session on its own thread: commands in, frames out    |
//! | `app.rs`           | the view state and `App::apply`, testable without a terminal |
//! | `action.rs`        | what a person can ask for                                 |
//! | `keymap.rs`        | the key table: dispatch, footer and help from one list    |
//! | `camera.rs`        | orbit camera and orthographic projection to braille dots  |
//! | `box_view.rs`      | the canvas shape: box, floor, spheres, overlays, in order |
//! | `dot_buffer.rs`    | braille dots lit and cleared, then painted                |
//! | `palette.rs`       | colour by speed or depth, NO_COLOR                        |
//! | `view.rs`          | `impl Widget for &App`: layout, view, legend, footer      |
//! | `panel.rs`         | lesson, parameters, readouts                              |
//! | `energy_log.rs`    | energies and momentum after each step, the newest kept    |
//! | `energy_chart.rs`  | the chart of the energy log                               |
//! | `numbers.rs`       | the text of the figures shown: digits, energies, dt       |
//! | `ghost.rs`         | the exact reference drawn over the spheres, anchored      |
//! | `work_chart.rs`    | the work-precision chart screen, computed in the background |
//! | `help.rs`          | the help overlay                                          |
//! | `history.rs`       | the ring buffer of states for stepping back               |
//! | `accumulator.rs`   | fixed-dt stepping, clamped against the spiral of death    |
//! | `draw_rate.rs`     | frames a second: fewer while the steps need the cores     |
//! | `terminal.rs`      | raw mode, alternate screen, mouse; signals, Ctrl-Z        |
//! | `input.rs`         | keys and mouse read on their own thread; input held       |
//! | `event_loop.rs`    | the event loop                                            |
//! | `render_bench.rs`  | `lerpit bench --render`: drawing cost, headless           |
//!
//! Drawing never steps physics; physics (`crate::sim`) never draws. The
//! session and what it owns (`session`, `history`, `ghost`, `energy_log`)
//! run on the worker thread, and import nothing that draws; the view (`app`, `view`, `panel`,
//! `box_view`, `help`, charts) reads only published frames.

pub(crate) mod accumulator;
pub mod action;
pub mod app;
pub(crate) mod box_view;
pub mod camera;
pub(crate) mod dot_buffer;
pub(crate) mod draw_rate;
pub(crate) mod energy_chart;
pub(crate) mod energy_log;
pub(crate) mod event_loop;
pub(crate) mod frame;
pub(crate) mod ghost;
pub mod help;
pub(crate) mod history;
pub(crate) mod input;
pub mod keymap;
pub mod numbers;
pub(crate) mod palette;
pub mod panel;
pub(crate) mod render_bench;
pub mod selection;
pub mod session;
pub(crate) mod terminal;
pub mod view;
pub mod work_chart;
pub(crate) mod worker;

pub use action::Action;
pub use app::App;
pub(crate) use terminal::restore_without_allocating;

use crate::scene::{Lesson, Scene, SceneError};
use std::io::IsTerminal;

/// Why the visualiser could not run.
#[derive(Debug)]
pub(crate) enum OpenError {
    /// The scene does not build.
    Scene(SceneError),
    /// Standard output is not a terminal.
    NotATerminal,
    /// The terminal failed.
    Terminal(std::io::Error),
}

impl std::fmt::Display for OpenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OpenError::Scene(e) => write!(f, "{e}"),
            OpenError::NotATerminal => f.write_str(
                "standard output is not a terminal, and the visualiser needs one. \
                 To simulate without a terminal, use `lerpit run` (see `lerpit run --help`).",
            ),
            OpenError::Terminal(e) => write!(f, "the terminal failed: {e}"),
        }
    }
}

/// Open the visualiser on `scene` (the lesson `lesson`'s, or a scene
/// file's when `None`) until the person quits.
pub(crate) fn open(scene: Scene, lesson: Option<Lesson>) -> Result<(), OpenError> {
    // A large scene takes seconds to place and check: said on a terminal's
    // standard error until the screen opens.
    // It goes once the visualiser's own signal handling is in place.
    // Without a terminal there is nothing to place the scene for (a
    // large one takes seconds and gigabytes).
    if !std::io::stdout().is_terminal() {
        return Err(OpenError::NotATerminal);
    }
    let building = crate::process::progress::building(
        "lerpit",
        scene.body_count(),
        crate::process::progress::Clearing::UntilDropped,
    );
    let (spawned, checked) = (scene.spawned(), scene.world.pair_collisions);
    let session = session::Session::new_telling(scene, lesson, &|placed| {
        if let Some(line) = &building {
            line.message(crate::process::progress::placing(placed, spawned, checked));
        }
    })
    .map_err(OpenError::Scene)?;
    let mut app = App::with_session(session);
    app.colour = palette::colour_allowed();
    event_loop::run_in_terminal(app, building).map_err(OpenError::Terminal)
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    /// The text of `src/tui/{name}.rs` before its tests.
    fn code_of(name: &str) -> String {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("src/tui/{name}.rs"));
        crate::tests::code_of(&path)
    }

    /// The modules of `src/tui` that `code` names as `super::name`.
    fn siblings(code: &str) -> Vec<String> {
        code.match_indices("super::")
            .map(|(at, _)| {
                code[at + "super::".len()..]
                    .chars()
                    .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '_')
                    .collect::<String>()
            })
            .filter(|name| !name.is_empty() && name != "super")
            .collect()
    }

    #[test]
    fn the_session_and_what_it_reaches_import_nothing_that_draws() {
        let mut seen = BTreeSet::new();
        let mut next = vec!["session".to_string()];
        while let Some(name) = next.pop() {
            if !seen.insert(name.clone()) {
                continue;
            }
            let code = code_of(&name);
            for terminal in ["ratatui", "crossterm"] {
                assert!(
                    !code.contains(terminal),
                    "{name}.rs, which the session reaches, uses {terminal}"
                );
            }
            next.extend(siblings(&code));
        }
        // The walk reached what the session owns.
        for owned in ["history", "ghost", "energy_log", "selection", "frame"] {
            assert!(seen.contains(owned), "{seen:?}");
        }
    }
}
