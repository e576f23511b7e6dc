//! End to end: the real binary in a pseudo-terminal.
//!
//! - A person opens the visualiser, switches to the gravity lesson, raises
//!   the wall restitution, pauses, steps and quits.
//! - An unfinished escape sequence holds the keys, not the picture.
//! - Pasted text is not keys.
//! - SIGTERM, SIGHUP, SIGINT and SIGQUIT (and SIGUSR1, SIGALRM) end it with
//!   status 128 + signal.
//! - SIGTSTP and Ctrl-Z stop it; SIGCONT brings the picture back, whole.
//!
//! Whenever lerpit leaves the screen (exit or stop) the terminal must be as
//! it was: the main screen, no mouse reporting, the cursor shown, and the
//! tty modes it started with (cooked: ICANON, ECHO, ISIG).
//!
//! A stop needs a parent that controls the job: the system discards SIGTSTP
//! sent to a process group that no shell controls, and a process started
//! straight in a pseudo-terminal leads its own session. The stop tests
//! therefore start this test binary as that parent ([`job_control_parent`],
//! reached through one of the stop tests, [`PARENT_TEST`]), which runs
//! lerpit as a shell runs a foreground job.

use crate::pty_screen::{PATIENCE, Screen};
use crate::support::{BIN, SceneFile};
use portable_pty::{Child, CommandBuilder, ExitStatus, MasterPty, PtySize, native_pty_system};
use std::io::Write;
use std::time::{Duration, Instant};

const ROWS: u16 = 40;
const COLS: u16 = 120;
/// Set when this binary runs as [`job_control_parent`]: the program to run
/// as the job.
const JOB: &str = "LERPIT_PTY_JOB";
/// Set as well when [`job_control_parent`] takes the terminal back while
/// the job is stopped, as a shell does.
const TAKES_BACK: &str = "LERPIT_PTY_TAKES_BACK";
/// Drawn only by a full redraw: the picture's title and the footer never
/// change while the ping-pong lesson runs, so a frame that only updates
/// what moved never writes them.
const TITLE: &str = "lerpit: Ping-pong";
const FOOTER: &str = "? help  q quit";
/// What the small screen adds while an unfinished escape sequence may
/// hold the keys.
const HELD_SHORT: &str = "keys held by an unfinished ESC[ sequence";

/// The tty's mode flags, read through the pseudo-terminal's master.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct TtyModes {
    input: libc::tcflag_t,
    output: libc::tcflag_t,
    control: libc::tcflag_t,
    local: libc::tcflag_t,
}

impl TtyModes {
    fn of(master: &dyn MasterPty) -> Self {
        let fd = master.as_raw_fd().expect("the pty has a descriptor");
        // SAFETY: tcgetattr fills the zeroed struct it is given.
        let mut t: libc::termios = unsafe { std::mem::zeroed() };
        assert_eq!(
            unsafe { libc::tcgetattr(fd, &mut t) },
            0,
            "the tty modes read"
        );
        TtyModes {
            input: t.c_iflag,
            output: t.c_oflag,
            control: t.c_cflag,
            local: t.c_lflag,
        }
    }

    fn cooked(&self) -> bool {
        let cooked = libc::ICANON | libc::ECHO | libc::ISIG;
        self.local & cooked == cooked
    }
}

enum Start {
    /// lerpit straight in the pseudo-terminal, leading its own session.
    Alone,
    /// The same, with these arguments, waiting for a screen that shows
    /// the given text instead of the ping-pong lesson.
    With(Vec<String>, &'static str),
    /// lerpit as a shell's foreground job, under [`job_control_parent`].
    AsJob,
    /// The same, the parent taking the terminal back whenever the job
    /// stops, as a shell does: continued then, the job is in the
    /// background.
    AsShellJob,
}

/// lerpit running in a pseudo-terminal, shown on a vt100 screen.
struct Lerpit {
    screen: Screen,
    keys: Box<dyn Write + Send>,
    /// lerpit, or for [`Start::AsJob`] its parent.
    child: Box<dyn Child + Send + Sync>,
    master: Box<dyn MasterPty + Send>,
    /// lerpit's own process id.
    pid: libc::pid_t,
    modes_before: TtyModes,
}

impl Lerpit {
    /// Start lerpit and wait for its first screen.
    fn start(how: Start) -> Self {
        let pty = native_pty_system()
            .openpty(PtySize {
                rows: ROWS,
                cols: COLS,
                pixel_width: 0,
                pixel_height: 0,
            })
            .expect("a pseudo-terminal opens");
        let modes_before = TtyModes::of(&*pty.master);
        let lerpit = BIN;
        let mut first = TITLE;
        let mut cmd = match how {
            Start::Alone => CommandBuilder::new(lerpit),
            Start::With(args, shows) => {
                first = shows;
                let mut cmd = CommandBuilder::new(lerpit);
                cmd.args(args);
                cmd
            }
            Start::AsJob | Start::AsShellJob => {
                let mut cmd = CommandBuilder::new(std::env::current_exe().unwrap());
                if matches!(how, Start::AsShellJob) {
                    cmd.env(TAKES_BACK, "1");
                }
                cmd.args([PARENT_TEST, "--exact", "--nocapture", "--quiet"]);
                cmd.env(JOB, lerpit);
                cmd
            }
        };
        cmd.env("TERM", "xterm-256color");
        cmd.env_remove("NO_COLOR");
        let child = pty.slave.spawn_command(cmd).expect("lerpit starts");
        drop(pty.slave);

        let keys = pty.master.take_writer().unwrap();
        let mut screen = Screen::reading(&*pty.master, ROWS, COLS);
        screen.wait_for("the first screen", |s| s.contains(first));
        assert!(screen.parser.screen().alternate_screen(), "full screen");
        // The terminal's foreground process group: lerpit's own, whichever
        // way it was started.
        let pid = pty
            .master
            .process_group_leader()
            .expect("the terminal has a foreground process group");
        Lerpit {
            screen,
            keys,
            child,
            master: pty.master,
            pid,
            modes_before,
        }
    }

    fn press(&mut self, keys: &str) {
        self.keys.write_all(keys.as_bytes()).unwrap();
        self.keys.flush().unwrap();
    }

    /// Press `keys`, the last of them an Esc that does nothing here, and
    /// check lerpit still runs once its word on that Esc shows, which it
    /// draws only after taking in the keys before it (`why` says what
    /// exiting would mean).
    fn runs_on_after(&mut self, keys: &str, why: &str) {
        const DOES_NOTHING: &str = "Esc does nothing here";
        assert!(keys.ends_with('\x1b'), "{keys:?} ends with Esc");
        self.press(keys);
        let deadline = Instant::now() + PATIENCE;
        while !self.screen.contents().contains(DOES_NOTHING) {
            assert!(self.child.try_wait().unwrap().is_none(), "{why}");
            assert!(
                Instant::now() < deadline,
                "the screen never showed the word on Esc; it shows:\n{}",
                self.screen.contents()
            );
            self.screen.pump(Duration::from_millis(50));
        }
        assert!(self.child.try_wait().unwrap().is_none(), "{why}");
    }

    fn signal(&self, signal: libc::c_int) {
        // SAFETY: kill takes plain integers.
        assert_eq!(
            unsafe { libc::kill(self.pid, signal) },
            0,
            "signal {signal} sent"
        );
    }

    fn wait_exit(&mut self, after: &str) -> ExitStatus {
        let deadline = Instant::now() + PATIENCE;
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            assert!(
                Instant::now() < deadline,
                "lerpit did not exit after {after}"
            );
            self.screen.pump(Duration::from_millis(50));
        }
    }

    /// lerpit's state as the system reports it: `T` when stopped.
    fn state(&self) -> Option<char> {
        let stat = std::fs::read_to_string(format!("/proc/{}/stat", self.pid)).ok()?;
        stat.rsplit_once(')')?.1.trim_start().chars().next()
    }

    /// The context switches of all of lerpit's threads so far: a thread
    /// that runs and stops again adds at least one.
    fn context_switches(&self) -> u64 {
        let tasks = std::fs::read_dir(format!("/proc/{}/task", self.pid)).unwrap();
        tasks
            .filter_map(|task| {
                let status = std::fs::read_to_string(task.ok()?.path().join("status")).ok()?;
                Some(
                    status
                        .lines()
                        .filter(|l| l.contains("ctxt_switches:"))
                        .filter_map(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
                        .sum::<u64>(),
                )
            })
            .sum()
    }

    fn wait_stopped(&mut self, after: &str) {
        let deadline = Instant::now() + PATIENCE;
        while self.state() != Some('T') {
            assert!(
                Instant::now() < deadline,
                "lerpit did not stop after {after} (state {:?}); the screen shows:\n{}",
                self.state(),
                self.screen.parser.screen().contents()
            );
            self.screen.pump(Duration::from_millis(50));
        }
    }

    /// The terminal is as it was before lerpit started. Call once lerpit
    /// has exited or stopped, when everything it wrote is on its way.
    fn assert_restored(&mut self, when: &str) {
        // The cursor is shown last of what lerpit writes to restore.
        self.screen
            .wait_until(&format!("the main screen and the cursor {when}"), |s| {
                !s.alternate_screen() && !s.hide_cursor()
            });
        let s = self.screen.parser.screen();
        assert_eq!(
            s.mouse_protocol_mode(),
            vt100::MouseProtocolMode::None,
            "mouse reporting is off {when}"
        );
        assert!(!s.bracketed_paste(), "bracketed paste is off {when}");
        let modes = TtyModes::of(&*self.master);
        assert!(
            modes.cooked(),
            "ICANON, ECHO and ISIG are on {when}: {modes:?}"
        );
        assert_eq!(
            modes, self.modes_before,
            "the tty modes are as before {when}"
        );
    }

    /// Under [`Start::AsShellJob`], stopped: the parent has taken the
    /// terminal back, as a shell does once it sees the stop.
    fn wait_taken_back(&mut self) {
        let deadline = Instant::now() + PATIENCE;
        while self.master.process_group_leader() == Some(self.pid) {
            assert!(
                Instant::now() < deadline,
                "the parent took the terminal back"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// A shell's `kill` on a job it put in the background: SIGTERM, then
    /// SIGCONT. lerpit ends with 143, the terminal as it was.
    fn killed_in_the_background(&mut self) {
        self.signal(libc::SIGTERM);
        self.signal(libc::SIGCONT);
        let status = self.wait_exit("SIGTERM and SIGCONT in the background");
        assert_eq!(status.exit_code(), 143, "exit status 128 + SIGTERM");
        self.assert_restored("after SIGTERM in the background");
    }

    /// The whole picture is back, in raw mode with mouse reporting.
    fn wait_redrawn(&mut self, after: &str) {
        self.screen
            .wait_until(&format!("the whole picture after {after}"), |s| {
                let text = s.contents();
                s.alternate_screen() && text.contains(TITLE) && text.contains(FOOTER)
            });
        assert_ne!(
            self.screen.parser.screen().mouse_protocol_mode(),
            vt100::MouseProtocolMode::None,
            "mouse reporting is on again after {after}"
        );
        assert!(
            !TtyModes::of(&*self.master).cooked(),
            "raw mode again after {after}"
        );
    }

    /// Resize the terminal (and the screen that reads it) to `cols` x `rows`.
    fn resize(&mut self, cols: u16, rows: u16) {
        self.master
            .resize(PtySize {
                rows,
                cols,
                pixel_width: 0,
                pixel_height: 0,
            })
            .expect("the pseudo-terminal resizes");
        self.screen.parser.set_size(
            std::num::NonZeroU16::new(rows).unwrap(),
            std::num::NonZeroU16::new(cols).unwrap(),
        );
    }

    fn quit(&mut self) {
        self.press("q");
        let status = self.wait_exit("q");
        assert!(status.success(), "exit status {status:?}");
        self.assert_restored("after q");
    }
}

impl Drop for Lerpit {
    /// A failed test leaves no lerpit behind, stopped or running.
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            // SAFETY: kill takes plain integers.
            unsafe { libc::kill(self.pid, libc::SIGKILL) };
            let _ = self.child.kill();
        }
    }
}

/// When a stop test starts this binary in a pseudo-terminal with [`JOB`]
/// set (as [`PARENT_TEST`], which comes here first), run lerpit as a shell
/// runs a foreground job (a process group of its own that owns the
/// terminal, with this process as its parent in the same session) and exit
/// with lerpit's status.
#[cfg(target_os = "linux")]
fn job_control_parent(program: std::ffi::OsString) -> ! {
    use std::os::unix::process::CommandExt;
    let mut job = std::process::Command::new(program);
    // SAFETY: between fork and exec, only async-signal-safe calls.
    unsafe {
        job.pre_exec(|| {
            if libc::setpgid(0, 0) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            // A background group taking the terminal is sent SIGTTOU:
            // ignore it for the call, as shells do.
            libc::signal(libc::SIGTTOU, libc::SIG_IGN);
            let taken = libc::tcsetpgrp(0, libc::getpid());
            libc::signal(libc::SIGTTOU, libc::SIG_DFL);
            if taken != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    if std::env::var_os(TAKES_BACK).is_none() {
        let status = job.status().expect("lerpit starts as a job");
        let code = status
            .code()
            .unwrap_or_else(|| panic!("lerpit did not exit by itself: {status}"));
        std::process::exit(code);
    }
    let pid = job.spawn().expect("lerpit starts as a job").id() as libc::pid_t;
    loop {
        let mut status = 0;
        // SAFETY: waitpid writes the status it is given.
        let got = unsafe { libc::waitpid(pid, &mut status, libc::WUNTRACED) };
        assert_eq!(got, pid, "waiting for lerpit");
        if libc::WIFEXITED(status) {
            std::process::exit(libc::WEXITSTATUS(status));
        }
        assert!(
            libc::WIFSTOPPED(status),
            "lerpit did not exit by itself: wait status {status}"
        );
        // The job stopped: take the terminal back, as a shell does.
        // SAFETY: plain integers; SIGTTOU ignored for the call, as above.
        unsafe {
            libc::signal(libc::SIGTTOU, libc::SIG_IGN);
            libc::tcsetpgrp(0, libc::getpgrp());
            libc::signal(libc::SIGTTOU, libc::SIG_DFL);
        }
    }
}

/// The step number the readouts show ("step N").
fn shown_step(screen: &str) -> Option<u64> {
    let at = screen.find(" s, step ")?;
    let rest = &screen[at + " s, step ".len()..];
    rest.split(|c: char| !c.is_ascii_digit())
        .next()?
        .parse()
        .ok()
}

#[test]
fn a_person_switches_lesson_tunes_steps_and_quits() {
    let mut lerpit = Lerpit::start(Start::Alone);
    lerpit.press("2");
    lerpit.screen.wait_for("the gravity lesson", |s| {
        s.contains("lerpit: Gravity") && s.contains("c_r = 0.95")
    });
    lerpit.press(" ");
    lerpit.screen.wait_for("the pause", |s| {
        s.contains(" paused ") && s.contains("paused, x1")
    });
    // The pause shows at once, and the world may still take the steps it
    // owed: the frame that carries a change made after the pause comes
    // from the paused world, so its step is the one `n` goes on from.
    lerpit.press("E");
    lerpit.screen.wait_for("the raised restitution", |s| {
        s.contains("c_r = 1.00") && s.contains(" paused ")
    });
    // That frame may arrive in pieces, its step below the restitution:
    // the footer's word on a key typed after it is drawn after all of it.
    lerpit.press("\x1b");
    let shown = lerpit
        .screen
        .wait_for("the word on Esc", |s| s.contains("Esc does nothing here"));
    let step = shown_step(&shown).expect("the readouts show the step");
    lerpit.press("n");
    lerpit
        .screen
        .wait_for("one step more", |s| shown_step(s) == Some(step + 1));
    lerpit.quit();
}

/// An escape sequence that does not end (here the start of a mouse report)
/// holds the keys typed after it, but not the picture: the simulation
/// draws on, the footer says why keys do nothing and how to end the
/// sequence, and once it has ended `q` quits.
#[test]
fn an_unfinished_escape_sequence_freezes_neither_the_picture_nor_the_way_out() {
    const HELD: &str = "an escape sequence (ESC[...) may be unfinished";
    let mut lerpit = Lerpit::start(Start::Alone);
    lerpit.press("\x1b[<0;5");
    let held = lerpit
        .screen
        .wait_for("that input is held", |s| s.contains(HELD));
    let step = shown_step(&held).expect("the readouts show the step");
    lerpit.screen.wait_for("the simulation drawn on", |s| {
        s.contains(HELD) && shown_step(s).is_some_and(|n| n > step + 10)
    });
    // Too small to draw, it still says so, beside the way out.
    lerpit.resize(70, 20);
    lerpit.screen.wait_for("the short word on held keys", |s| {
        s.contains("q to quit") && s.contains("keys held by an unfinished ESC[ sequence")
    });
    // `q` goes into the sequence; `m` ends it, as a mouse report ends.
    lerpit.press("q");
    lerpit.press("m");
    lerpit.quit();
}

/// Pasted text (bracketed, as the visualiser asks the terminal to send
/// it) is not keys: a `q` in it does not quit, and nothing in it acts.
#[test]
fn pasted_text_is_not_taken_as_keys() {
    let mut lerpit = Lerpit::start(Start::Alone);
    lerpit
        .screen
        .wait_until("bracketed paste asked for", |s| s.bracketed_paste());
    lerpit.runs_on_after("\x1b[200~q 2 i\x1b[201~\x1b", "a pasted q quit");
    let screen = lerpit.screen.parser.screen().contents();
    assert!(
        screen.contains("lerpit: Ping-pong") && !screen.contains(" paused "),
        "the paste acted:\n{screen}"
    );
    lerpit.quit();
}

/// Send `signal`; lerpit restores the terminal and exits with 128 + signal.
fn ends_on(signal: libc::c_int, name: &str) {
    let mut lerpit = Lerpit::start(Start::Alone);
    lerpit.signal(signal);
    let status = lerpit.wait_exit(name);
    assert_eq!(
        status.signal(),
        None,
        "lerpit exited rather than died of {name}"
    );
    assert_eq!(
        status.exit_code(),
        128 + signal as u32,
        "exit status 128 + {name}"
    );
    lerpit.assert_restored(&format!("after {name}"));
}

#[test]
fn sigterm_restores_the_terminal_and_exits_143() {
    ends_on(libc::SIGTERM, "SIGTERM");
}

#[test]
fn sighup_restores_the_terminal_and_exits_129() {
    ends_on(libc::SIGHUP, "SIGHUP");
}

#[test]
fn sigint_restores_the_terminal_and_exits_130() {
    ends_on(libc::SIGINT, "SIGINT");
}

#[test]
fn sigquit_restores_the_terminal_and_exits_131() {
    ends_on(libc::SIGQUIT, "SIGQUIT");
}

#[test]
fn sigusr1_and_sigalrm_restore_the_terminal_and_exit_138_and_142() {
    // Signals no terminal sends, whose default action would end the
    // program with the terminal as it was.
    ends_on(libc::SIGUSR1, "SIGUSR1");
    ends_on(libc::SIGALRM, "SIGALRM");
}

#[cfg(target_os = "linux")]
#[test]
fn linux_signals_that_end_a_process_restore_the_terminal_too() {
    // Linux's own: power failure, an I/O readiness signal, a coprocessor
    // stack fault. Each would otherwise end the program with the screen
    // left alternate, the cursor hidden and the mouse reporting.
    ends_on(libc::SIGPWR, "SIGPWR");
    ends_on(libc::SIGIO, "SIGIO");
    ends_on(libc::SIGSTKFLT, "SIGSTKFLT");
}

/// Stop lerpit with `stop`: restored while stopped; SIGCONT brings the
/// whole picture back; `q` still quits with status 0.
#[cfg(target_os = "linux")]
fn stops_and_continues(lerpit: &mut Lerpit, stop: impl FnOnce(&mut Lerpit), name: &str) {
    stop(lerpit);
    lerpit.wait_stopped(name);
    lerpit.assert_restored(&format!("while stopped by {name}"));
    lerpit.signal(libc::SIGCONT);
    lerpit.wait_redrawn(&format!("{name} and SIGCONT"));
    lerpit.quit();
}

/// The test this binary runs as the stop tests' parent: with [`JOB`] set
/// it is [`job_control_parent`], and otherwise a stop test of its own.
const PARENT_TEST: &str = "tui_pty::sigtstp_stops_with_the_terminal_restored_and_sigcont_redraws";

#[cfg(target_os = "linux")]
#[test]
fn sigtstp_stops_with_the_terminal_restored_and_sigcont_redraws() {
    if let Some(program) = std::env::var_os(JOB) {
        job_control_parent(program);
    }
    let mut lerpit = Lerpit::start(Start::AsJob);
    stops_and_continues(&mut lerpit, |l| l.signal(libc::SIGTSTP), "SIGTSTP");
}

#[cfg(target_os = "linux")]
#[test]
fn ctrl_z_stops_with_the_terminal_restored_and_sigcont_redraws() {
    let mut lerpit = Lerpit::start(Start::AsJob);
    stops_and_continues(&mut lerpit, |l| l.press("\x1a"), "Ctrl-Z");
}

/// Paused and idle, the loop still looks for signals.
#[cfg(target_os = "linux")]
#[test]
fn a_paused_visualiser_stops_on_sigtstp() {
    let mut lerpit = Lerpit::start(Start::AsJob);
    lerpit.press(" ");
    lerpit
        .screen
        .wait_for("the pause", |s| s.contains("paused, x1"));
    stops_and_continues(
        &mut lerpit,
        |l| l.signal(libc::SIGTSTP),
        "SIGTSTP while paused",
    );
}

/// A shell takes the terminal back from a stopped job; `bg` then continues
/// it in the background, and `kill` sends SIGTERM, then SIGCONT. In the
/// background lerpit leaves the terminal alone: `bg` stops it again, and
/// `kill` ends it with 143. It had set its modes there, so the system
/// stopped it again with the SIGTERM unanswered until `fg`.
#[cfg(target_os = "linux")]
#[test]
fn a_stopped_job_continued_in_the_background_stops_again_or_ends() {
    let mut lerpit = Lerpit::start(Start::AsShellJob);
    lerpit.press("\x1a");
    lerpit.wait_stopped("Ctrl-Z");
    lerpit.assert_restored("while stopped by Ctrl-Z");
    lerpit.wait_taken_back();
    // Stopped again once it has run: not the stop it was in before.
    let switched = lerpit.context_switches();
    lerpit.signal(libc::SIGCONT);
    let deadline = Instant::now() + PATIENCE;
    while lerpit.context_switches() == switched {
        assert!(Instant::now() < deadline, "lerpit never ran after SIGCONT");
        std::thread::sleep(Duration::from_millis(5));
    }
    lerpit.wait_stopped("SIGCONT in the background");
    lerpit.assert_restored("stopped again in the background");
    lerpit.killed_in_the_background();
}

/// Stopped from outside (SIGSTOP, which leaves the terminal in lerpit's
/// modes), then `kill` from the shell, which has taken the terminal back:
/// SIGTERM and SIGCONT in the background. lerpit gives the terminal back
/// and ends with 143; setting the tty's modes from the background had
/// stopped it again, the SIGTERM unanswered until `fg`.
#[cfg(target_os = "linux")]
#[test]
fn a_job_stopped_from_outside_and_killed_in_the_background_restores_and_ends() {
    let mut lerpit = Lerpit::start(Start::AsShellJob);
    lerpit.signal(libc::SIGSTOP);
    lerpit.wait_stopped("SIGSTOP");
    lerpit.wait_taken_back();
    lerpit.killed_in_the_background();
}

/// SIGSTOP cannot be caught, so the terminal stays as it is while
/// stopped; whatever happened to the screen meanwhile, SIGCONT redraws it
/// all.
#[cfg(target_os = "linux")]
#[test]
fn sigcont_after_an_outside_sigstop_redraws_everything() {
    let mut lerpit = Lerpit::start(Start::Alone);
    lerpit.signal(libc::SIGSTOP);
    lerpit.wait_stopped("SIGSTOP");
    // Another program clears the screen while lerpit is stopped.
    lerpit.screen.parser.process(b"\x1b[H\x1b[2J");
    lerpit.signal(libc::SIGCONT);
    lerpit.wait_redrawn("SIGSTOP and SIGCONT");
    lerpit.quit();
}

/// A left click at the 0-based terminal cell `(column, row)`, as a
/// terminal reports it with SGR mouse encoding: press, then release.
fn click(lerpit: &mut Lerpit, column: u16, row: u16) {
    let (c, r) = (column + 1, row + 1);
    lerpit.press(&format!("\x1b[<0;{c};{r}M\x1b[<0;{c};{r}m"));
}

#[test]
fn q_quits_at_once_while_one_step_takes_far_longer() {
    // 30,000 spheres, every pair tested, ten thousand sub-steps: one step
    // is 4.5e12 pair tests, hours of work here and minutes at the least on
    // any machine, far beyond the patience of `wait_exit`. An exit within
    // it is an exit that did not wait for the step.
    let scene = SceneFile::named(
        "slow.toml",
        "[world]\nbroad_phase = \"all-pairs\"\nsubsteps = 10000\n\n\
         [[spawn]]\ncount = 30000\nradius = [0.004, 0.004]\n",
    );
    let args = vec![
        "--allow-slow".to_string(),
        "--scene".to_string(),
        scene.path.display().to_string(),
    ];
    let mut lerpit = Lerpit::start(Start::With(args, "lerpit: slow"));
    lerpit
        .screen
        .wait_for("a step in progress", |s| s.contains("one step has taken"));
    lerpit.press("q");
    let status = lerpit.wait_exit("q during a long step");
    assert!(status.success(), "exit status {status:?}");
    lerpit.assert_restored("after q");
}

#[test]
fn o_pauses_on_a_collision_with_the_pairs_numbers_and_steps_walk_through_it() {
    let args = vec!["--lesson".to_string(), "collisions".to_string()];
    let mut lerpit = Lerpit::start(Start::With(args, "lerpit: Collisions"));
    lerpit.press("o");
    // A frame may arrive in pieces: wait for the footer's message too, the
    // last row drawn.
    let screen = lerpit
        .screen
        .wait_for("a collision, and the message says so", |s| {
            s.contains(" paused ")
                && s.contains("V1, V2")
                && s.contains(": found in contact")
                && s.contains("collide at t =")
        });
    let step = shown_step(&screen).expect("the readouts show the step");
    lerpit.press("n");
    lerpit
        .screen
        .wait_for("the step after", |s| shown_step(s) == Some(step + 1));
    lerpit.press(",");
    // A frame may arrive in pieces: wait for the panel's last rows too.
    let back = lerpit.screen.wait_for("the collision again", |s| {
        shown_step(s) == Some(step) && s.contains(": found in contact") && s.contains("V1, V2")
    });
    assert!(back.contains("V1, V2"), "the same numbers:\n{back}");
    lerpit.quit();
}

#[test]
fn a_click_picks_a_sphere_and_esc_forgets_it_without_quitting() {
    use lerpit::tui::view::Areas;
    use ratatui::layout::Rect;
    let mut lerpit = Lerpit::start(Start::Alone);
    // Paused at the start, the ball is at the box's centre, which every
    // view draws at the middle of the canvas.
    lerpit.press(" r");
    lerpit.screen.wait_for("the restart", |s| {
        shown_step(s) == Some(0) && s.contains(" paused ")
    });
    let canvas = Areas::of(Rect::new(0, 0, COLS, ROWS), true)
        .canvas()
        .unwrap();
    click(
        &mut lerpit,
        canvas.x + canvas.width / 2,
        canvas.y + canvas.height / 2,
    );
    lerpit.screen.wait_for("the ball selected", |s| {
        s.contains("Sphere 0") && s.contains("r, m")
    });
    // A click beside the box picks nothing and says so.
    click(&mut lerpit, 0, ROWS - 2);
    lerpit
        .screen
        .wait_for("the message", |s| s.contains("click on a sphere"));
    lerpit.press("\x1b");
    lerpit
        .screen
        .wait_for("no selection", |s| !s.contains("Sphere 0"));
    lerpit.runs_on_after("\x1b", "Esc never quits");
    assert!(lerpit.screen.parser.screen().contents().contains(TITLE));
    lerpit.quit();
}

#[test]
fn a_huge_terminal_gets_its_top_left_corner_drawn_and_q_quits() {
    // 65535x65535 cells would take 206 GB in ratatui's frames: lerpit
    // draws in the top-left 1200x600, which the screen here reads.
    let mut lerpit = Lerpit::start(Start::Alone);
    lerpit
        .master
        .resize(PtySize {
            rows: u16::MAX,
            cols: u16::MAX,
            pixel_width: 0,
            pixel_height: 0,
        })
        .expect("the pseudo-terminal resizes");
    lerpit.screen.parser.set_size(
        std::num::NonZeroU16::new(600).unwrap(),
        std::num::NonZeroU16::new(1200).unwrap(),
    );
    lerpit.press(" ");
    let drawn = lerpit.screen.wait_for("the pause, drawn", |s| {
        s.contains(" paused ") && s.contains("pace      paused")
    });
    // The frame's right border is the 1200th column.
    let top = drawn.lines().next().unwrap_or_default();
    assert!(top.starts_with('┌') && top.ends_with('┐'), "{top}");
    assert_eq!(top.chars().count(), 1200);
    lerpit.resize(COLS, ROWS);
    lerpit.quit();
}

#[test]
fn keys_do_nothing_unseen_while_the_terminal_is_too_small_but_q_quits() {
    let mut lerpit = Lerpit::start(Start::Alone);
    lerpit.press(" ");
    lerpit.screen.wait_for("the pause", |s| {
        s.contains(" paused ") && s.contains("Ping-pong")
    });
    lerpit.resize(60, 20);
    lerpit
        .screen
        .wait_for("the small screen", |s| s.contains("too small"));
    // Space would run on, 3 would open another lesson, where no one sees.
    // Then the start of a paste, which holds what comes after it: once a
    // read of the terminal brings only more of the paste, the small
    // screen says the keys are held. The event loop has the two keys
    // then, and has carried them out by the time it draws the small
    // screen again without that word, once the paste has ended (a paste
    // does nothing, on either screen).
    lerpit.press(" 3\x1b[200~");
    let deadline = Instant::now() + PATIENCE;
    while !lerpit.screen.contents().contains(HELD_SHORT) {
        assert!(
            Instant::now() < deadline,
            "the small screen never said the keys are held; it shows:\n{}",
            lerpit.screen.contents()
        );
        lerpit.press("x");
        let look = Instant::now() + Duration::from_millis(1500);
        while Instant::now() < look && !lerpit.screen.contents().contains(HELD_SHORT) {
            lerpit.screen.pump(Duration::from_millis(50));
        }
    }
    lerpit.press("\x1b[201~");
    lerpit
        .screen
        .wait_for("the keys freed on the small screen", |s| {
            s.contains("too small") && !s.contains(HELD_SHORT)
        });
    lerpit.resize(COLS, ROWS);
    let back = lerpit
        .screen
        .wait_for("the full screen again", |s| s.contains("lerpit: "));
    assert!(
        back.contains(" paused ") && back.contains("Ping-pong"),
        "the keys acted unseen:\n{back}"
    );
    lerpit.resize(60, 20);
    lerpit
        .screen
        .wait_for("the small screen", |s| s.contains("too small"));
    lerpit.quit();
}

#[test]
fn a_key_typed_as_the_window_resizes_acts_at_once() {
    // crossterm's default reader, told of the resize and the key in one
    // look, returned the resize and lost the key's readiness: the key
    // waited for the next one (about one time in two here).
    let mut lerpit = Lerpit::start(Start::Alone);
    for (k, (cols, rows)) in [(200, 60), (COLS, ROWS), (150, 50), (COLS, ROWS)]
        .into_iter()
        .enumerate()
    {
        lerpit.resize(cols, rows);
        lerpit.press(" ");
        let (now, state) = if k % 2 == 0 {
            ("paused", "pace      paused")
        } else {
            ("running", "pace      running")
        };
        lerpit.screen.wait_for(now, |s| {
            s.contains(state) && s.lines().count() == rows as usize
        });
    }
    lerpit.resize(100, 30);
    lerpit.quit();
}
