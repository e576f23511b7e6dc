//! The terminal visualiser: an orthographic braille view of the box, live
//! controls, stepping forward and back (feature `tui`).
//!
//! | file               | concept                                                   |
//! |--------------------|-----------------------------------------------------------|
//! | `session.rs`       | the simulation session: scene, world, history, ghost      |
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
//! | `energy_chart.rs`  | the energy log and its chart                              |
//! | `ghost.rs`         | the exact reference drawn over the spheres, anchored      |
//! | `work_chart.rs`    | the work-precision chart screen, computed in the background |
//! | `help.rs`          | the help overlay                                          |
//! | `history.rs`       | the ring buffer of states for stepping back               |
//! | `accumulator.rs`   | fixed-dt stepping, clamped against the spiral of death    |
//! | `event_loop.rs`    | the terminal session and the event loop                   |
//! | `render_bench.rs`  | `lerpit bench --render`: drawing cost, headless           |
//!
//! Drawing never steps physics; physics (`crate::sim`) never draws. The
//! session and what it owns (`session`, `history`, `ghost`, the energy
//! log) run on the worker thread; the view (`app`, `view`, `panel`,
//! `box_view`, `help`, charts) reads only published frames.

pub mod accumulator;
pub mod action;
pub mod app;
pub mod box_view;
pub mod camera;
pub mod dot_buffer;
pub mod energy_chart;
pub mod event_loop;
pub mod frame;
pub mod ghost;
pub mod help;
pub mod history;
pub mod keymap;
pub mod palette;
pub mod panel;
pub mod render_bench;
pub mod session;
pub mod view;
pub mod work_chart;
pub mod worker;

pub use action::Action;
pub use app::App;

use crate::cli::{Failure, Overrides, SourceArgs};
use crate::scene::Lesson;
use std::io::IsTerminal;

/// Open the visualiser on the chosen scene, with the command line's
/// overrides applied.
pub fn open(source: &SourceArgs, overrides: &Overrides) -> Result<(), Failure> {
    let mut scene = source.load()?;
    overrides.apply(&mut scene).map_err(Failure::Usage)?;
    let lesson = match source.scene {
        Some(_) => None,
        None => Some(source.lesson.unwrap_or(Lesson::Pingpong)),
    };
    let mut app = App::new(scene, lesson)?;
    if !std::io::stdout().is_terminal() {
        return Err(Failure::Runtime(
            "standard output is not a terminal, and the visualiser needs one. \
             To simulate without a terminal, use `lerpit run` (see `lerpit run --help`)."
                .into(),
        ));
    }
    app.colour = palette::colour_allowed();
    event_loop::run_in_terminal(app)
        .map_err(|e| Failure::Runtime(format!("the terminal failed: {e}")))
}
