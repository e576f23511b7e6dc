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
//!
//! Each layer uses only what lies below it in this picture, never what lies
//! above:
//!
//! ```text
//!   cli ---> tui      the front ends: the command line is the program's
//!     \      /        entry and opens the visualiser; the visualiser
//!      study          uses nothing of the command line
//!        |            runs scenes and measures them
//!      scene          builds worlds from data
//!        |
//!       sim           knows nothing above it
//! ```
//!
//! So `sim` imports none of `scene`, `study`, `cli`, `tui`; `scene` none of
//! `study`, `cli`, `tui`; `study` none of `cli`, `tui`; `tui` nothing of
//! `cli`. A front end may reach past a level (`cli` uses `sim` directly).
//! What both front ends need lives below them: the benchmark scene is
//! [`scene::bench`], not the command line's.

pub mod cli;
pub mod scene;
pub mod sim;
pub mod study;
#[cfg(feature = "tui")]
pub mod tui;
