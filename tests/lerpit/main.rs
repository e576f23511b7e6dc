//! lerpit's integration tests, one binary: a module per area, with the
//! helpers they share in `support`.

mod support;

mod analytic;
mod choices;
mod cli;
mod cli_bench;
#[cfg(unix)]
mod cli_pty;
mod continuous;
mod determinism;
mod grid_contacts;
mod grid_physics;
mod invariants;
mod piles;
#[cfg(unix)]
mod pty_screen;
mod references;
mod scene_text;
mod stability;
mod study_cli;
#[cfg(feature = "tui")]
mod tui_cli;
#[cfg(feature = "tui")]
mod tui_props;
#[cfg(all(feature = "tui", unix))]
mod tui_pty;
#[cfg(feature = "tui")]
mod tui_render;
