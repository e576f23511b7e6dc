//! The headless commands on a terminal: `run`'s progress line leaves no
//! trace when a signal ends it, whether Ctrl-C or Ctrl-\\ typed at the
//! terminal (which the terminal echoes as `^C` or `^\`) or SIGTERM sent from
//! outside; so does the visualiser's line while it builds a large scene.
//! SIGTERM ends `run` while the terminal's output is stopped (Ctrl-S).

use crate::pty_screen::{PATIENCE, Screen};
use crate::support::BIN;
use portable_pty::{Child, CommandBuilder, PtySize, native_pty_system};
use std::io::Write;
use std::time::{Duration, Instant};

/// A long `run` on a terminal, its output on a vt100 screen.
struct LongRun {
    screen: Screen,
    keys: Box<dyn Write + Send>,
    child: Box<dyn Child + Send + Sync>,
}

impl LongRun {
    /// Start it and wait for its progress line.
    fn start() -> Self {
        Self::start_at(100)
    }

    /// [`LongRun::start`] on a terminal `cols` wide.
    fn start_at(cols: u16) -> Self {
        Self::start_with(
            &["run", "--lesson", "collisions", "--steps", "1e9"],
            cols,
            |s| s.contains("run [") || s.contains("% ("),
        )
    }

    /// `lerpit args` on a terminal `cols` wide, once `shown` holds of its
    /// screen.
    fn start_with(args: &[&str], cols: u16, shown: fn(&str) -> bool) -> Self {
        let pty = native_pty_system()
            .openpty(PtySize {
                rows: 10,
                cols,
                pixel_width: 0,
                pixel_height: 0,
            })
            .expect("a pseudo-terminal opens");
        let mut cmd = CommandBuilder::new(BIN);
        cmd.args(args);
        cmd.env("TERM", "xterm-256color");
        let child = pty.slave.spawn_command(cmd).expect("lerpit starts");
        drop(pty.slave);
        let keys = pty.master.take_writer().unwrap();
        let mut run = LongRun {
            screen: Screen::reading(&*pty.master, 10, cols),
            keys,
            child,
        };
        run.screen.wait_for("the progress line", shown);
        run
    }

    /// Wait for the end, then for all it wrote (up to the end of the
    /// terminal's output, which comes once lerpit has closed it); the
    /// screen after.
    fn screen_after_exit(&mut self, after: &str) -> String {
        self.wait_for_exit(after);
        self.screen.read_to_end(after);
        self.screen.contents()
    }

    /// Wait for the end (reading what it writes meanwhile); its status.
    fn wait_for_exit(&mut self, after: &str) -> portable_pty::ExitStatus {
        let deadline = Instant::now() + PATIENCE;
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            assert!(
                Instant::now() < deadline,
                "lerpit did not end after {after}"
            );
            self.screen.pump(Duration::from_millis(50));
        }
    }
}

impl Drop for LongRun {
    fn drop(&mut self) {
        let _ = self.child.kill();
    }
}

/// Type `key` (`name`, which the terminal echoes as `echo`) at a long
/// run: neither its progress line nor the echo is left.
fn typed_key_leaves_no_trace(key: &[u8], name: &str, echo: &str) {
    let mut run = LongRun::start();
    run.keys.write_all(key).unwrap();
    run.keys.flush().unwrap();
    let screen = run.screen_after_exit(name);
    assert!(
        !screen.contains("run [") && !screen.contains(echo),
        "{name}: the progress line or the echo is left:\n{screen}"
    );
}

#[test]
fn ctrl_c_typed_at_the_terminal_leaves_neither_the_progress_line_nor_its_echo() {
    // The terminal's interrupt key: the tty sends SIGINT and echoes ^C.
    typed_key_leaves_no_trace(b"\x03", "Ctrl-C", "^C");
}

#[test]
fn ctrl_backslash_typed_at_the_terminal_leaves_neither_the_progress_line_nor_its_echo() {
    // The terminal's quit key: the tty sends SIGQUIT and echoes ^\.
    typed_key_leaves_no_trace(b"\x1c", "Ctrl-\\", "^\\");
}

#[test]
fn on_a_narrow_terminal_the_progress_line_fits_and_ctrl_c_leaves_none() {
    // 50 columns: the whole line (81 at 10^9 steps) would wrap onto a
    // second row, which the clearing of one line leaves behind.
    let mut run = LongRun::start_at(50);
    let shown = run.screen.contents();
    let line = shown
        .lines()
        .find(|l| l.contains("% ("))
        .unwrap_or_default();
    assert!(
        line.starts_with("run ") && line.trim_end().ends_with("left)"),
        "not the short line:\n{shown}"
    );
    run.keys.write_all(b"\x03").unwrap();
    run.keys.flush().unwrap();
    let screen = run.screen_after_exit("Ctrl-C");
    assert!(screen.trim().is_empty(), "something is left:\n{screen}");
}

#[test]
fn sigterm_leaves_no_progress_line() {
    let mut run = LongRun::start();
    let pid = run.child.process_id().expect("lerpit has a process id");
    // SAFETY: kill takes plain integers.
    assert_eq!(unsafe { libc::kill(pid as libc::pid_t, libc::SIGTERM) }, 0);
    let screen = run.screen_after_exit("SIGTERM");
    assert!(
        !screen.contains("run ["),
        "the progress line is left:\n{screen}"
    );
}

#[test]
fn sigterm_ends_a_run_whose_terminal_output_is_stopped() {
    // Ctrl-S stops the terminal's output, and the progress line's next
    // draw waits for Ctrl-Q: SIGTERM still ends the program, without
    // waiting to clear the line.
    let mut run = LongRun::start();
    run.keys.write_all(b"\x13").unwrap();
    run.keys.flush().unwrap();
    // Long enough for the line to be drawn again (and block).
    let drawn_again = Instant::now() + Duration::from_millis(500);
    while Instant::now() < drawn_again {
        run.screen.pump(Duration::from_millis(50));
    }
    let pid = run.child.process_id().expect("lerpit has a process id");
    // SAFETY: kill takes plain integers.
    assert_eq!(unsafe { libc::kill(pid as libc::pid_t, libc::SIGTERM) }, 0);
    let status = run.wait_for_exit("SIGTERM, with the output stopped");
    assert!(!status.success(), "{status:?}");
    run.keys.write_all(b"\x11").unwrap();
    run.keys.flush().unwrap();
    run.screen.read_to_end("SIGTERM");
}

#[test]
fn ctrl_c_while_a_large_scene_is_built_leaves_no_line() {
    // A million spheres take seconds to place: the visualiser and `run`
    // say so on standard error meanwhile, and Ctrl-C then ends them
    // without the line or the echo left, at 80 columns too, where the
    // whole line would wrap.
    let visualiser = [
        "--lesson",
        "collisions",
        "--particles",
        "1000000",
        "--broadphase",
        "grid",
    ];
    let run = [&["run"][..], &visualiser, &["--steps", "1"]].concat();
    for (args, cols) in [
        (&visualiser[..], 100),
        (&visualiser[..], 80),
        (&run[..], 80),
    ] {
        let mut long = LongRun::start_with(args, cols, |s| s.contains("building the scene"));
        long.keys.write_all(b"\x03").unwrap();
        long.keys.flush().unwrap();
        let screen = long.screen_after_exit("Ctrl-C");
        assert!(
            screen.trim().is_empty(),
            "{args:?} at {cols} columns, something is left:\n{screen}"
        );
    }
}

#[cfg(feature = "tui")]
#[test]
fn bench_render_shows_its_frames_on_a_terminal_and_ctrl_c_leaves_no_line() {
    // Drawing many frames of many spheres takes minutes: the bar counts
    // the frames drawn, and Ctrl-C takes it off the screen.
    let mut long = LongRun::start_with(
        &[
            "bench",
            "--render",
            "--particles",
            "20000",
            "--frames",
            "100000",
        ],
        140,
        |s| s.contains("bench --render") && s.contains("drawing 20,000 spheres"),
    );
    long.keys.write_all(b"\x03").unwrap();
    long.keys.flush().unwrap();
    let screen = long.screen_after_exit("Ctrl-C");
    assert!(screen.trim().is_empty(), "something is left:\n{screen}");
}
