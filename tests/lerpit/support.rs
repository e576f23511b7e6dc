//! What several test modules use: the real binary and its output, scene
//! files in a temporary folder, spheres and worlds, runs on a thread pool
//! of a given size, and the visualiser drawn into a test backend.

use lerpit::sim::threads::thread_pool;
use lerpit::sim::{Bodies, Body, Vec3, World, WorldConfig};
use std::path::PathBuf;
use std::process::{Command, Output};

/// The lerpit binary cargo built for these tests.
pub const BIN: &str = env!("CARGO_BIN_EXE_lerpit");

/// The README, whose example scene and key table the tests check.
pub const README: &str = include_str!("../../README.md");

/// A scene file's one body, in the middle of the box.
pub const BODY: &str = "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n";

/// Whether the clock that times a step's stages (the monotonic clock,
/// which `Instant` reads) counts microseconds or finer: a stage that ran
/// for longer than a tick of it reads more than 0 s. On a coarse clock
/// (ticks of milliseconds) a short stage may read 0 s, as one that did
/// not run does.
pub fn stage_clock_is_fine() -> bool {
    #[cfg(unix)]
    {
        // SAFETY: clock_getres writes the resolution it is given.
        let mut res: libc::timespec = unsafe { std::mem::zeroed() };
        let read = unsafe { libc::clock_getres(libc::CLOCK_MONOTONIC, &mut res) } == 0;
        read && res.tv_sec == 0 && res.tv_nsec <= 1_000
    }
    #[cfg(not(unix))]
    {
        true
    }
}

/// Run the binary with `args`, standard input closed, its output captured.
pub fn lerpit(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("the lerpit binary runs")
}

/// [`lerpit`] under an address-space limit of `kb` kilobytes (`ulimit
/// -v`, set by a shell that then becomes lerpit; the arguments pass
/// through unquoted).
pub fn lerpit_within(kb: u64, args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg("ulimit -v \"$0\" && exec \"$@\"")
        .arg(kb.to_string())
        .arg(BIN)
        .args(args)
        .output()
        .expect("sh runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A successful run's standard output, one JSON object.
#[track_caller]
pub fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "lerpit failed: {}", stderr(o));
    serde_json::from_slice(&o.stdout).expect("stdout is one JSON object")
}

/// Run with `args`; expect exit 2 and every fragment in the message.
#[track_caller]
pub fn refused_flags(args: &[&str], fragments: &[&str]) {
    refused(args, 2, fragments);
}

/// Run with `args`; expect exit `code` and every fragment in the message.
/// Returns the output, for what else the caller checks.
#[track_caller]
pub fn refused(args: &[&str], code: i32, fragments: &[&str]) -> Output {
    let o = lerpit(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    for f in fragments {
        assert!(err.contains(f), "message for {args:?} lacks {f:?}:\n{err}");
    }
    o
}

/// A scene file in a temporary folder, removed with it.
pub struct SceneFile {
    _dir: tempfile::TempDir,
    pub path: PathBuf,
}

impl SceneFile {
    /// `text` written to a file called `name` (the scene's name is the
    /// file's stem).
    pub fn named(name: &str, text: &str) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        SceneFile { _dir: dir, path }
    }
}

/// `text` as `scene.toml`.
pub fn scene_file(text: &str) -> SceneFile {
    SceneFile::named("scene.toml", text)
}

pub fn sphere(
    position: impl Into<Vec3>,
    velocity: impl Into<Vec3>,
    radius: f64,
    mass: f64,
) -> Body {
    Body {
        position: position.into(),
        velocity: velocity.into(),
        radius,
        mass,
    }
}

pub fn world(config: WorldConfig, bodies: &[Body]) -> World {
    World::new(config, bodies.iter().copied().collect::<Bodies>())
}

/// Step `world` `steps` times on a pool of `threads` threads.
pub fn run_on_threads(world: &mut World, steps: u64, threads: usize) {
    let pool = thread_pool(Some(threads)).expect("a small pool starts");
    pool.install(|| world.run(steps));
}

/// `app` drawn whole into a `width` x `height` test terminal.
#[cfg(feature = "tui")]
pub fn draw(app: &lerpit::tui::App, width: u16, height: u16) -> ratatui::backend::TestBackend {
    use ratatui::Terminal;
    use ratatui::backend::TestBackend;
    let mut terminal = Terminal::new(TestBackend::new(width, height)).unwrap();
    terminal.draw(|f| f.render_widget(app, f.area())).unwrap();
    terminal.backend().clone()
}
