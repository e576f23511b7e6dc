//! The command line: `lerpit` (the visualiser), `lerpit run` (headless),
//! `lerpit scene NAME` (print a lesson's scene file), `lerpit study` (the
//! accuracy study: work-precision sweeps, conservation, stability),
//! `lerpit bench` (measurements: the simulation's speed and memory at any
//! size, and the visualiser's drawing).
//!
//! | file               | concept                                                    |
//! |--------------------|------------------------------------------------------------|
//! | `mod.rs`           | the commands and flags, the visualiser's, exit statuses    |
//! | `run.rs`           | `lerpit run`: simulate headless, print or trace            |
//! | `study.rs`         | `lerpit study`: the study's tables, charts and files       |
//! | `bench.rs`         | `lerpit bench`: speed and memory, drawing with `--render`  |
//! | `overrides.rs`     | flags that override a scene's parameters                   |
//! | `values.rs`        | flag values as typed, checked against their ranges         |
//! | `closed_output.rs` | a standard output closed before the program started        |
//! | `out_of_memory.rs` | the allocator: memory that runs out part-way ends with a message |
//!
//! Exit statuses (also in the README):
//! - 0: success; also when a reader closes standard output early
//!   (`lerpit scene gravity | head -1`);
//! - 1: a failure while running: output could not be written (a full disk,
//!   a standard output closed from the start,
//!   `/dev/full`, a study folder that cannot be written), the terminal
//!   could not be used, a settled benchmark that needs more memory than is
//!   available, memory that runs out part-way (`out_of_memory.rs`);
//! - 2: a bad command line: unknown flag, a value out of its range,
//!   contradictory flags, a run beyond the step limit, all-pairs over
//!   [`MAX_SPHERES_ALL_PAIRS`] spheres without `--allow-slow`, study files
//!   that would be replaced without `--force`;
//! - 3: a bad scene: a missing, unreadable, oversized or irregular file,
//!   malformed TOML, a field with a wrong type or value, a spawn that cannot
//!   fit, spheres crowded past the contact limit.

pub mod bench;
pub mod closed_output;
pub mod out_of_memory;
pub(crate) mod overrides;
pub(crate) mod run;
pub(crate) mod study;
pub(crate) mod values;

use crate::scene::{Lesson, Scene, SceneError};
use crate::sim::BroadPhase;
use crate::sim::broad_phase::{MAX_SPHERES_ALL_PAIRS, all_pairs_tests, grid_tests, grid_too_slow};
use crate::sim::grid::CellLayout;
use clap::{Args, Parser, Subcommand};
use serde::Serialize;
use std::ffi::OsString;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

pub use overrides::Overrides;

#[derive(Parser, Debug)]
#[command(
    name = "lerpit",
    version,
    about = "Learn and explore simple body dynamics in the terminal",
    long_about = "Learn and explore simple body dynamics: a particle and its integration \
                  step, a ping-pong ball, spheres under gravity bouncing in a 1x1x1 box, and \
                  sphere-sphere collisions.\n\nWith no command, lerpit opens the terminal \
                  visualiser. `lerpit run` simulates headless; `lerpit scene NAME` prints a \
                  lesson as a scene file to start your own from.",
    after_help = "Exit status: 0 success, 1 runtime failure, 2 bad command line (a flag a \
                  request needs, such as --allow-slow, included), 3 bad scene.",
    args_conflicts_with_subcommands = true
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub source: SourceArgs,
    #[command(flatten)]
    pub overrides: Overrides,
    #[arg(long, help = ALLOW_SLOW_HELP)]
    pub allow_slow: bool,
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    /// Simulate a lesson or scene file without a terminal and print the result.
    Run(Box<run::RunArgs>),
    /// Measure every method's speed against its accuracy, or (--stability) where each fails.
    Study(study::StudyArgs),
    /// Print a built-in lesson as a scene file.
    Scene {
        /// The lesson to print.
        #[arg(value_parser = values::choice::<Lesson>())]
        lesson: Lesson,
    },
    /// Measure the program's speed and memory (release builds give the real
    /// figures): the simulation by default, drawing with --render.
    Bench(bench::BenchArgs),
}

/// Where a scene comes from: a built-in lesson or a file.
#[derive(Args, Debug, Clone, Default)]
pub(crate) struct SourceArgs {
    /// A built-in lesson (without --scene, the ping-pong lesson by default).
    #[arg(long, value_parser = values::choice::<Lesson>(), conflicts_with = "scene", global = false)]
    pub lesson: Option<Lesson>,
    /// A scene file (TOML; see `lerpit scene pingpong` for the format).
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
}

impl SourceArgs {
    /// Load the chosen scene; the ping-pong lesson when none is named.
    pub(crate) fn load(&self) -> Result<Scene, SceneError> {
        match (&self.scene, self.lesson) {
            (Some(path), _) => Scene::from_file(path),
            (None, lesson) => Ok(lesson.unwrap_or(Lesson::Pingpong).scene()),
        }
    }
}

/// Why a command failed, and so its exit status.
#[derive(Debug)]
pub enum Failure {
    /// Status 1.
    Runtime(String),
    /// Standard output could not be written. Status 1, except a closed
    /// pipe (the reader has all it wanted): status 0, quietly.
    Output(std::io::Error),
    /// Status 2.
    Usage(String),
    /// Status 3.
    Scene(SceneError),
}

impl Failure {
    pub(crate) fn status(&self) -> u8 {
        match self {
            Failure::Output(e) if e.kind() == std::io::ErrorKind::BrokenPipe => 0,
            Failure::Runtime(_) | Failure::Output(_) => 1,
            Failure::Usage(_) => 2,
            Failure::Scene(_) => 3,
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Runtime(m) | Failure::Usage(m) => write!(f, "{m}"),
            Failure::Output(e) => write!(f, "cannot write the output: {e}"),
            Failure::Scene(e) => write!(f, "{e}"),
        }
    }
}

impl From<SceneError> for Failure {
    fn from(e: SceneError) -> Self {
        Failure::Scene(e)
    }
}

/// Errors writing standard output.
impl From<std::io::Error> for Failure {
    fn from(e: std::io::Error) -> Self {
        Failure::Output(e)
    }
}

/// Errors writing JSON to standard output (serde_json keeps the I/O error).
impl From<serde_json::Error> for Failure {
    fn from(e: serde_json::Error) -> Self {
        Failure::Output(e.into())
    }
}

/// Errors writing CSV: the I/O error when there is one (a closed pipe is
/// then no failure), else a failure to run.
impl From<csv::Error> for Failure {
    fn from(e: csv::Error) -> Self {
        match e.into_kind() {
            csv::ErrorKind::Io(e) => Failure::Output(e),
            other => Failure::Runtime(format!("cannot write CSV: {other:?}")),
        }
    }
}

/// Write `rows` to `out` as CSV: a header of the rows' field names, then a
/// line a row.
pub(crate) fn write_csv<T: Serialize>(
    out: impl Write,
    rows: impl IntoIterator<Item = T>,
) -> Result<(), Failure> {
    let mut writer = csv::Writer::from_writer(out);
    for row in rows {
        writer.serialize(row)?;
    }
    writer.flush()?;
    Ok(())
}

/// The command line with a non-finite negative number (`-inf`, `-NaN`)
/// given as its option's value joined to the option (`--dt=-nan`): clap
/// takes such a word for a cluster of short flags and names neither the
/// option nor the value, while joined, the option's own check refuses it.
fn joined_non_finite(args: impl IntoIterator<Item = OsString>) -> Vec<OsString> {
    let mut out: Vec<OsString> = Vec::new();
    for arg in args {
        // A negative fraction (`-1/60`) is no number to clap either.
        let non_finite = arg
            .to_str()
            .and_then(|a| a.strip_prefix('-'))
            .is_some_and(|a| {
                a.parse::<f64>().is_ok_and(|x| !x.is_finite())
                    || (a.contains('/') && values::decimal_or_fraction(a).is_some())
            });
        if let Some(option) = out.last_mut().filter(|_| non_finite)
            && let Some(name) = option.to_str()
            && name.starts_with("--")
            && !name.contains('=')
        {
            let joined = format!("{name}={}", arg.to_string_lossy());
            *option = joined.into();
            continue;
        }
        out.push(arg);
    }
    out
}

/// Parse the command line, run it, and turn the outcome into an exit status.
pub fn main() -> ExitCode {
    crate::scene::memory::one_arena_under_a_limit();
    // A write past the file-size limit (`ulimit -f`) then fails with its
    // error, which the command says (status 1), where the signal would end
    // the program part-way through a file with nothing said.
    // SAFETY: setting a signal's disposition to "ignore" runs no code.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let args = joined_non_finite(std::env::args_os());
    let outcome = match Cli::try_parse_from(&args) {
        Ok(_) if closed_output::closed_at_start() => Err(Failure::Output(closed_output::error())),
        Ok(cli) => dispatch(cli),
        Err(e) if let Some(flag) = run_flag_without_run(&e, &args) => {
            let _ = writeln!(
                std::io::stderr(),
                "lerpit: error: {flag} is for `lerpit run`, which simulates without the \
                 visualiser: lerpit run {flag} ... (the visualiser takes the flags that \
                 shape the scene; see lerpit --help)"
            );
            return ExitCode::from(2);
        }
        Err(e) => {
            // `--help` and `--version` come this way too, for standard
            // output; a bad command line is status 2 even if its message
            // cannot be written.
            if e.use_stderr() {
                // The values quoted may hold control characters, line
                // breaks among them, and be any length: the message is that
                // of the same command line with each argument escaped and
                // cut as lerpit's own messages quote a value (on one line),
                // without styles, so that it reads the same on a terminal
                // as off it and keeps its own lines.
                use clap::CommandFactory;
                let quoted: Vec<String> = args
                    .iter()
                    .map(|a| printable_line(&a.to_string_lossy(), ARG_CHARS))
                    .collect();
                let plain = Cli::command()
                    .styles(clap::builder::Styles::plain())
                    .try_get_matches_from(&quoted)
                    .err()
                    .unwrap_or(e);
                let message = printable(&plain.render().ansi().to_string(), MESSAGE_CHARS);
                let _ = write!(std::io::stderr(), "{message}");
                return ExitCode::from(2);
            }
            if closed_output::closed_at_start() {
                Err(Failure::Output(closed_output::error()))
            } else {
                e.print().map_err(Failure::Output)
            }
        }
    };
    // What a command left in the standard output's buffer must reach it too.
    let outcome = outcome.and_then(|()| Ok(std::io::stdout().flush()?));
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let status = failure.status();
            if status != 0 {
                // Nothing more can be done when standard error fails too.
                let message = printable(&failure.to_string(), MESSAGE_CHARS);
                let _ = writeln!(std::io::stderr(), "lerpit: error: {message}");
            }
            ExitCode::from(status)
        }
    }
}

/// The flag of `lerpit run` that `error` found unexpected, when `args`
/// name no command: given to the visualiser, which does not take it.
fn run_flag_without_run(error: &clap::Error, args: &[std::ffi::OsString]) -> Option<String> {
    use clap::CommandFactory;
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if error.kind() != ErrorKind::UnknownArgument {
        return None;
    }
    let Some(ContextValue::String(given)) = error.get(ContextKind::InvalidArg) else {
        return None;
    };
    let flag = given.split('=').next().unwrap_or_default();
    let cli = Cli::command();
    let commands: Vec<&str> = cli
        .get_subcommands()
        .map(|c| c.get_name())
        .chain(["help"])
        .collect();
    let no_command = !args.iter().skip(1).any(|a| commands.iter().any(|c| a == c));
    let run = cli.find_subcommand("run")?;
    let of_run = run
        .get_arguments()
        .filter_map(|a| a.get_long())
        .any(|long| flag.strip_prefix("--") == Some(long));
    (no_command && of_run).then(|| flag.to_string())
}

/// Most characters of an error message printed: a message quotes a line of
/// the user's file, which may be any length.
pub(crate) const MESSAGE_CHARS: usize = 2000;

/// Characters of one argument a message of a bad command line quotes.
const ARG_CHARS: usize = 200;

/// `text` as it may reach a terminal: control characters other than line
/// breaks and tabs escaped (a scene file's line cannot set the terminal's
/// title or clear it), and at most `most` characters, saying how many more
/// there were.
pub(crate) fn printable(text: &str, most: usize) -> String {
    escaped(text, most, |c| c != '\n' && c != '\t')
}

/// [`printable`] for one line of output: line breaks and tabs escaped too.
pub(crate) fn printable_line(text: &str, most: usize) -> String {
    escaped(text, most, |_| true)
}

/// `text` with the control characters `escape` picks escaped, cut after
/// `most` characters.
fn escaped(text: &str, most: usize, escape: impl Fn(char) -> bool) -> String {
    let mut out = String::new();
    let mut chars = text.chars();
    for c in chars.by_ref().take(most) {
        if c.is_control() && escape(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    let rest = chars.count();
    if rest > 0 {
        out.push_str(&format!("... ({rest} more characters)"));
    }
    out
}

/// `--allow-slow` (`run`, `bench` and the visualiser): what [`check_all_pairs`] and [`check_grid`] let
/// through. The number is [`MAX_SPHERES_ALL_PAIRS`] (tested to agree).
pub(crate) const ALLOW_SLOW_HELP: &str = "Run all-pairs with pair collisions above 5,000 spheres \
    (n (n - 1) / 2 pair tests a step), or a grid whose cells, sized by one large sphere, would \
    hold so many small ones that it tests more pairs, which are otherwise refused";

/// `bench --allow-slow`: its spheres share one radius, so only all-pairs
/// can be refused.
pub(crate) const BENCH_ALLOW_SLOW_HELP: &str = "Run all-pairs with pair collisions above 5,000 \
    spheres (n (n - 1) / 2 pair tests a step), which is otherwise refused";

/// Refuse all-pairs over [`MAX_SPHERES_ALL_PAIRS`] spheres with pair
/// collisions unless `allow_slow`: half a trillion pair tests a step at a
/// million spheres. `chosen` says where all-pairs came from, for the message.
pub(crate) fn check_all_pairs(
    broad_phase: BroadPhase,
    pair_collisions: bool,
    spheres: usize,
    allow_slow: bool,
    chosen: &str,
) -> Result<(), Failure> {
    if allow_slow
        || !pair_collisions
        || broad_phase.resolve(spheres) != BroadPhase::AllPairs
        || spheres <= MAX_SPHERES_ALL_PAIRS
    {
        return Ok(());
    }
    Err(Failure::Usage(format!(
        "{chosen} with {} would test {} pairs a step; all-pairs is limited \
         to {} with pair collisions. Use --broadphase grid \
         (the same motion, a few tests a sphere), or add --allow-slow to run it anyway",
        crate::scene::spheres(spheres),
        crate::scene::thousands(all_pairs_tests(spheres)),
        crate::scene::spheres(MAX_SPHERES_ALL_PAIRS),
    )))
}

/// Refuse a grid that would test more pairs than all-pairs is allowed,
/// and over 100 a sphere ([`grid_too_slow`]), unless `allow_slow`: its cells are sized by
/// the largest sphere, so one large sphere among many small ones puts them
/// all in a few cells.
pub(crate) fn check_grid(scene: &Scene, allow_slow: bool) -> Result<(), Failure> {
    let n = scene.body_count();
    let w = &scene.world;
    let r = scene.max_radius();
    if allow_slow || !w.pair_collisions || w.broad_phase.resolve(n) != BroadPhase::Grid {
        return Ok(());
    }
    if !grid_too_slow(n, r) {
        return Ok(());
    }
    let tests = grid_tests(n, r);
    let cells = CellLayout::new(r, n).n;
    Err(Failure::Usage(format!(
        "the grid with {} would test about {} pairs a step ({} a sphere): its \
         cells are sized by the largest sphere (radius {} m), so {cells}x{cells}x{cells} \
         cells hold them all. Use fewer spheres or a smaller largest sphere, or add \
         --allow-slow to run it anyway",
        crate::scene::spheres(n),
        crate::scene::thousands(tests),
        crate::scene::thousands(tests / n as u64),
        crate::scene::rules::show(r)
    )))
}

/// [`check_all_pairs`] and [`check_grid`] for `scene`. A scene whose
/// spheres may start piled on one another ([`Scene::may_start_crowded`])
/// and that either would refuse is built first: spheres piled on one
/// another are the scene's fault (status 3), which `--allow-slow` would
/// not mend.
pub(crate) fn check_cost(scene: &Scene, allow_slow: bool, chosen: &str) -> Result<(), Failure> {
    let w = &scene.world;
    let cost = check_all_pairs(
        w.broad_phase,
        w.pair_collisions,
        scene.body_count(),
        allow_slow,
        chosen,
    )
    .and_then(|()| check_grid(scene, allow_slow));
    if cost.is_err() && scene.may_start_crowded() {
        scene.build()?;
    }
    cost
}

fn dispatch(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Some(Command::Run(args)) => run::run(&args),
        Some(Command::Study(args)) => study::run(&args),
        Some(Command::Scene { lesson }) => {
            std::io::stdout()
                .lock()
                .write_all(lesson.source().as_bytes())?;
            Ok(())
        }
        Some(Command::Bench(args)) => bench::bench(&args),
        None => open_visualiser(&cli.source, &cli.overrides, cli.allow_slow),
    }
}

#[cfg(feature = "tui")]
fn open_visualiser(
    source: &SourceArgs,
    overrides: &Overrides,
    allow_slow: bool,
) -> Result<(), Failure> {
    use crate::tui::OpenError;
    let mut scene = source.load()?;
    overrides.apply(&mut scene).map_err(Failure::Usage)?;
    scene.check_packing()?;
    check_cost(
        &scene,
        allow_slow,
        match overrides.broadphase {
            Some(_) => "--broadphase all-pairs",
            None => "the scene's broad phase all-pairs",
        },
    )?;
    let lesson = match source.scene {
        Some(_) => None,
        None => Some(source.lesson.unwrap_or(Lesson::Pingpong)),
    };
    crate::tui::open(scene, lesson).map_err(|e| match e {
        OpenError::Scene(e) => Failure::Scene(e),
        other => Failure::Runtime(other.to_string()),
    })
}

#[cfg(not(feature = "tui"))]
fn open_visualiser(
    _source: &SourceArgs,
    _overrides: &Overrides,
    _allow_slow: bool,
) -> Result<(), Failure> {
    Err(Failure::Usage(
        "this build of lerpit has no visualiser (built without the `tui` feature); \
         use `lerpit run` to simulate without a terminal"
            .into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_non_finite_negative_value_is_joined_to_its_option() {
        let joined = |args: &[&str]| -> Vec<String> {
            joined_non_finite(args.iter().map(OsString::from))
                .into_iter()
                .map(|a| a.into_string().unwrap())
                .collect()
        };
        assert_eq!(
            joined(&["lerpit", "run", "--steps", "-inf", "--dt", "-NaN"]),
            ["lerpit", "run", "--steps=-inf", "--dt=-NaN"]
        );
        // Finite numbers, words and options are left as they are.
        let left = [
            "lerpit",
            "run",
            "--gravity",
            "-5",
            "--lesson",
            "-x",
            "-infinite",
        ];
        assert_eq!(joined(&left), left);
        assert_eq!(joined(&["lerpit", "-inf"]), ["lerpit", "-inf"]);
        // A negative fraction, which clap would take for a short flag.
        assert_eq!(
            joined(&["lerpit", "--dt", "-1/60", "-a/b"]),
            ["lerpit", "--dt=-1/60", "-a/b"]
        );
    }

    #[test]
    fn the_allow_slow_help_names_the_all_pairs_limit() {
        let limit = MAX_SPHERES_ALL_PAIRS.to_string();
        let (thousands, rest) = limit.split_at(limit.len() - 3);
        for help in [ALLOW_SLOW_HELP, BENCH_ALLOW_SLOW_HELP] {
            assert!(help.contains(&format!(" {thousands},{rest}")), "{help}");
        }
    }
}

#[cfg(test)]
mod printable_tests {
    #[test]
    fn messages_reach_the_terminal_without_its_control_codes_and_cut_to_length() {
        assert_eq!(
            super::printable("a\u{1b}]0;x\u{7}b\nc\td", 100),
            "a\\u{1b}]0;x\\u{7}b\nc\td"
        );
        assert_eq!(super::printable("abcdef", 4), "abcd... (2 more characters)");
        assert_eq!(super::printable("abc", 3), "abc");
    }
}
