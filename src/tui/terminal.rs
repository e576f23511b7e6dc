//! The terminal's modes and the signals that end or suspend the program.
//!
//! Owns, for the whole process: raw mode, the alternate screen, mouse
//! reporting and the cursor's visibility ([`Screen`]); the panic hook that
//! gives them back; and the signals that end, suspend and resume the
//! visualiser ([`Signals`]). It never changes the app and never draws
//! anything but a cleared screen: the event loop decides what to do and
//! when, on the main thread, and the picture is its business.
//!
//! What each way out or pause does:
//!
//! | cause | what happens |
//! |---|---|
//! | SIGTERM, SIGHUP, SIGINT, SIGQUIT | restore the terminal, exit with 128 + the signal (143, 129, 130, 131) |
//! | SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGXFSZ | the same (138, 140, 142, ...) |
//! | SIGTSTP, or Ctrl-Z (a key in raw mode) | restore the terminal, stop as the terminal's own Ctrl-Z would; when continued, enter again and redraw everything |
//! | SIGCONT after a stop from outside (SIGSTOP; SIGTTIN and SIGTTOU, which keep their default action, the one the tty driver gives a job in the background that reads or sets the terminal) | enter again and redraw everything |
//! | SIGCONT in the background (`bg`; `kill` sends SIGTERM then SIGCONT) | leave the terminal alone: exit on an ending signal (restoring it first if a SIGSTOP left it entered), else stop again until in the foreground; where nothing can stop the program (an orphaned process group), fail as a terminal that cannot be used |
//! | a panic on the main thread | restore the terminal, then report the panic |
//! | an allocation that fails (memory ran out) | restore the terminal (without allocating), then say so and exit 1 (`cli/out_of_memory.rs`) |
//! | `q`, an error, the end of [`Screen`] | restore the terminal |
//!
//! "Restore" is one function for all of them: mouse reporting and bracketed
//! paste off, the main screen back, the cursor shown, the tty modes the
//! program started with. (Bracketed paste is on so that pasted text comes
//! as one paste, which the visualiser ignores, not as keys.)
//!
//! A signal handler may do almost nothing safely, so the signals arrive on
//! a thread of their own (signal-hook's iterator) that passes each on as a
//! [`SignalEvent`]; the event loop looks for one at least every
//! [`SIGNAL_POLL`] and acts on it on the main thread, where the terminal is
//! drawn. Should the main thread not answer an ending signal within
//! [`EXIT_GRACE`] (stuck in a long computation), or should a second ending
//! signal arrive, the signal thread restores the terminal and exits itself;
//! it exits at once on an ending signal that finds the terminal out of the
//! visualiser's modes (suspended, or waiting for the foreground after it).
//! Entering and restoring the modes hold one lock, so a signal's exit on
//! its thread never interleaves with the main thread entering them.
//!
//! Stopping sends SIGTSTP, with its default action, to the whole process
//! group, as the tty driver does for Ctrl-Z outside raw mode (and as vim
//! does): a `cargo run` or a script waiting on lerpit stops with it, so the
//! shell gets the terminal back. In a process group that no shell controls
//! (an orphaned group, such as a program started directly by a terminal
//! emulator) the system discards such a stop, and lerpit returns to the
//! screen at once rather than freeze with nobody to continue it.

use crate::process::unbroken::ENDING;
use ratatui::backend::{Backend, ClearType, CrosstermBackend};
use ratatui::crossterm;
use ratatui::crossterm::cursor;
use ratatui::crossterm::event::{
    DisableBracketedPaste, DisableMouseCapture, EnableBracketedPaste, EnableMouseCapture,
};
use ratatui::crossterm::execute;
use ratatui::crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use ratatui::layout::{Position, Rect, Size};
use ratatui::{DefaultTerminal, Terminal, TerminalOptions, Viewport};
use signal_hook::consts::signal::{SIGCONT, SIGTSTP};
use std::io;
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Mutex, MutexGuard, Once, OnceLock, PoisonError};
use std::thread::{self, JoinHandle};
use std::time::Duration;

/// Longest the event loop may wait for input before it looks for a signal.
pub(crate) const SIGNAL_POLL: Duration = Duration::from_millis(100);
/// How long the main thread has to answer an ending signal before the
/// signal thread restores the terminal and exits itself.
pub(crate) const EXIT_GRACE: Duration = Duration::from_secs(1);

/// What a signal asks of the event loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SignalEvent {
    /// Restore the terminal and exit with 128 + this signal
    /// ([`Screen::exit`]).
    Exit(i32),
    /// SIGTSTP: restore the terminal and stop ([`Screen::suspend`]).
    Suspend,
    /// SIGCONT: enter the terminal again and redraw ([`Screen::resume`]).
    Resume,
}

impl SignalEvent {
    /// The event for one of the signals [`Signals`] listens to.
    fn of(signal: i32) -> Self {
        match signal {
            SIGTSTP => SignalEvent::Suspend,
            SIGCONT => SignalEvent::Resume,
            ending => SignalEvent::Exit(ending),
        }
    }
}

/// Linux's own signals whose default action ends a process: an I/O
/// readiness signal, power failure, a coprocessor stack fault. The
/// visualiser restores the terminal on them as on [`ENDING`]. A study
/// leaves them their default action: signal-hook cannot act it out for
/// them (it takes SIGIO as ignored, as BSD does, and knows no other).
#[cfg(any(target_os = "linux", target_os = "android"))]
const ENDING_ON_LINUX: [libc::c_int; 3] = [libc::SIGIO, libc::SIGPWR, libc::SIGSTKFLT];
#[cfg(not(any(target_os = "linux", target_os = "android")))]
const ENDING_ON_LINUX: [libc::c_int; 0] = [];

/// The exit status after an ending signal, as shells report a process
/// that the signal ended.
pub(crate) fn exit_status(signal: i32) -> i32 {
    128 + signal
}

/// The listening end of the signals: the ending ones ([`ENDING`],
/// [`ENDING_ON_LINUX`]), SIGTSTP and SIGCONT, caught from
/// [`Signals::install`] until drop (their default actions no longer happen
/// meanwhile: the event loop acts instead).
pub(crate) struct Signals {
    events: Receiver<SignalEvent>,
    handle: signal_hook::iterator::Handle,
    listener: Option<JoinHandle<()>>,
}

impl Signals {
    /// Catch the signals and start the thread that passes them on. Install
    /// before [`Screen::enter`], so that no signal finds the terminal
    /// changed and nobody listening.
    pub(crate) fn install() -> io::Result<Self> {
        let mut caught = signal_hook::iterator::Signals::new(
            ENDING
                .iter()
                .chain(&ENDING_ON_LINUX)
                .chain(&[SIGTSTP, SIGCONT]),
        )?;
        let handle = caught.handle();
        let (sender, events) = mpsc::channel();
        let listener = thread::Builder::new()
            .name("signals".into())
            .spawn(move || pass_on(&mut caught, &sender))?;
        Ok(Signals {
            events,
            handle,
            listener: Some(listener),
        })
    }

    /// The next signal's event, if one arrived; never waits.
    pub(crate) fn poll(&self) -> Option<SignalEvent> {
        self.events.try_recv().ok()
    }

    /// The next signal's event, waiting at most `wait` for it.
    pub(crate) fn wait(&self, wait: Duration) -> Option<SignalEvent> {
        self.events.recv_timeout(wait).ok()
    }
}

impl Drop for Signals {
    fn drop(&mut self) {
        self.handle.close();
        if let Some(listener) = self.listener.take() {
            let _ = listener.join();
        }
    }
}

/// The signal thread: pass each signal on; back an ending one with a
/// watchdog, and end at once on a second.
fn pass_on(caught: &mut signal_hook::iterator::Signals, events: &Sender<SignalEvent>) {
    let mut ending = false;
    for signal in caught.forever() {
        let event = SignalEvent::of(signal);
        if let SignalEvent::Exit(signal) = event {
            // A second ending signal ends at once; so does one that finds
            // the terminal out of the visualiser's modes (suspended, or
            // waiting for the foreground after it), where there is
            // nothing to restore and the main thread may be about to stop
            // again. (After a SIGSTOP the modes stay entered: the main
            // thread acts, from the background too.)
            if ending || !ENTERED.load(Ordering::SeqCst) {
                restore_and_exit(signal);
            }
            ending = true;
            let _ = thread::Builder::new()
                .name("exit watchdog".into())
                .spawn(move || {
                    thread::sleep(EXIT_GRACE);
                    restore_and_exit(signal)
                });
        }
        if events.send(event).is_err() {
            break;
        }
    }
}

/// The terminal in the visualiser's modes: raw, on the alternate screen,
/// reporting the mouse. Restored on drop, before a
/// stop ([`Screen::suspend`]) and before an exit ([`Screen::exit`]).
pub(crate) struct Screen {
    /// Never dropped: ratatui's drop shows the cursor and, should that
    /// fail (a terminal that went away), reports it with `eprintln!`,
    /// which panics when standard error went with it. The drop of the
    /// screen shows the cursor itself, ignoring failure.
    terminal: ManuallyDrop<DefaultTerminal>,
    /// The area drawn in: the terminal's, at most [`MAX_SIZE`].
    area: Rect,
    /// The terminal's own size when the area was last set.
    found: Size,
}

/// The most cells the visualiser draws in, across and down; a larger
/// terminal gets its top-left corner of this size. Each cell takes about
/// 40 bytes in each of the two frames kept: a pseudo-terminal of
/// 65535x65535 had asked for 206 GB and aborted.
pub(crate) const MAX_SIZE: Size = Size {
    width: 1200,
    height: 600,
};

impl Screen {
    /// Install the panic hook (once per process), then enter raw mode, the
    /// alternate screen and mouse reporting. On failure the terminal is
    /// restored before the error returns.
    pub(crate) fn enter(signals: &Signals) -> io::Result<Self> {
        install_panic_hook();
        wait_for_foreground(signals)?;
        let found: Size = crossterm::terminal::size()?.into();
        let area = Rect::from((Position::ORIGIN, drawn_size(found)));
        let terminal = enter_modes()
            .and_then(|()| {
                // A fixed area, not ratatui's full screen, which would
                // take the terminal's whole size, however large.
                let viewport = Viewport::Fixed(area);
                Terminal::with_options(
                    CrosstermBackend::new(io::stdout()),
                    TerminalOptions { viewport },
                )
            })
            .inspect_err(|_| restore_modes())?;
        Ok(Screen {
            terminal: ManuallyDrop::new(terminal),
            area,
            found,
        })
    }

    /// The terminal, drawing in the area [`Screen::fit`] last set.
    pub(crate) fn terminal(&mut self) -> &mut DefaultTerminal {
        &mut self.terminal
    }

    /// The size the visualiser draws in now: the terminal's, at most
    /// [`MAX_SIZE`].
    pub(crate) fn size(&mut self) -> io::Result<Size> {
        Ok(drawn_size(self.terminal.size()?))
    }

    /// The terminal's own size, however large.
    pub(crate) fn found_size(&mut self) -> io::Result<Size> {
        self.terminal.size()
    }

    /// Draw in the area of [`Screen::size`] from now on; a terminal
    /// resized since (beyond [`MAX_SIZE`] too, where the area stays)
    /// clears the screen and forgets the last frame. Returns the area's
    /// size.
    pub(crate) fn fit(&mut self) -> io::Result<Size> {
        let found = self.terminal.size()?;
        if found != self.found || drawn_size(found) != self.area.as_size() {
            self.resize(found)?;
        }
        Ok(self.area.as_size())
    }

    fn resize(&mut self, found: Size) -> io::Result<()> {
        self.found = found;
        self.area = Rect::from((Position::ORIGIN, drawn_size(found)));
        // The whole screen, beyond the area too (a terminal larger than
        // [`MAX_SIZE`]), then the area's frame forgotten.
        self.terminal.backend_mut().clear_region(ClearType::All)?;
        self.terminal.resize(self.area)
    }

    /// Ctrl-Z: restore the terminal, stop the process group (see the
    /// module's notes) and, once continued, enter again with the screen
    /// cleared, so the next frame draws everything. Call on the main
    /// thread.
    pub(crate) fn suspend(&mut self, signals: &Signals) -> io::Result<()> {
        restore_modes();
        let stopped = stop_process_group();
        self.resume(signals)?;
        stopped
    }

    /// Enter raw mode, the alternate screen and mouse reporting again, and
    /// clear the screen so the next frame draws everything. Safe to call
    /// while entered: after a stop from outside, whoever held the terminal
    /// meanwhile may have changed its modes or its screen. Continued in
    /// the background (a shell's `bg`, or `kill`, which sends SIGCONT
    /// after SIGTERM), it first waits for the terminal
    /// ([`wait_for_foreground`]).
    pub(crate) fn resume(&mut self, signals: &Signals) -> io::Result<()> {
        wait_for_foreground(signals)?;
        enter_modes()?;
        // `resize` to the present size clears the screen and forgets the
        // last frame, as `Terminal::clear` does, without `clear`'s question
        // to the terminal (where is the cursor?), which waits for an answer
        // and fails where none comes. It also catches a resize made while
        // stopped.
        let found = self.terminal.size()?;
        self.resize(found)
    }

    /// Restore the terminal and exit with 128 + `signal`.
    pub(crate) fn exit(&mut self, signal: i32) -> ! {
        restore_and_exit(signal)
    }
}

impl Drop for Screen {
    fn drop(&mut self) {
        restore_modes();
    }
}

/// A terminal of `size` draws in at most [`MAX_SIZE`].
fn drawn_size(size: impl Into<Size>) -> Size {
    let size = size.into();
    Size {
        width: size.width.min(MAX_SIZE.width),
        height: size.height.min(MAX_SIZE.height),
    }
}

/// Whether the terminal is in the visualiser's modes. One flag for the
/// process, as the modes themselves are: the panic hook and the signal
/// thread read it too.
static ENTERED: AtomicBool = AtomicBool::new(false);
/// Set by the first thread on its way out through [`restore_and_exit`].
static EXITING: AtomicBool = AtomicBool::new(false);

/// The terminal raw mode is set on: standard input when it is one (as
/// crossterm), else standard output, which always is here.
fn terminal_fd() -> libc::c_int {
    // SAFETY: `isatty` only asks.
    if unsafe { libc::isatty(libc::STDIN_FILENO) } == 1 {
        libc::STDIN_FILENO
    } else {
        libc::STDOUT_FILENO
    }
}

/// Whether our process group is the terminal's foreground group (also when
/// the terminal cannot say: the system then decides).
fn in_foreground() -> bool {
    // SAFETY: both only ask.
    let owner = unsafe { libc::tcgetpgrp(terminal_fd()) };
    owner < 0 || owner == unsafe { libc::getpgrp() }
}

/// Return once our process group holds the terminal, so that entering the
/// visualiser's modes cannot stop the program. A background group that
/// sets the tty's modes is stopped by the system (SIGTTOU), and an ending
/// signal that came with the SIGCONT (a shell's `kill` on a stopped job)
/// then waited for `fg`. Meanwhile an ending signal exits at once (after
/// giving back the modes a SIGSTOP left entered; otherwise the terminal is
/// left as it is, the shell's); anything else stops the process group as
/// the system would (SIGTTOU), to look again when continued. An error
/// where no stop comes: nothing will ever hand this group the terminal.
fn wait_for_foreground(signals: &Signals) -> io::Result<()> {
    while !in_foreground() {
        // Every signal of the next moment: the SIGCONT that came with a
        // SIGTERM may be passed on first.
        signals_of_the_moment(signals, SIGNAL_POLL);
        if in_foreground() {
            break;
        }
        // SAFETY: `kill` takes plain integers; SIGTTOU keeps its default
        // action (stop), as nothing here catches it.
        unsafe { libc::kill(0, libc::SIGTTOU) };
        // Stopped, then continued: SIGCONT says so. Not stopped (an
        // orphaned process group, whose stops the system discards, or
        // SIGTTOU ignored from the start): nothing will hand this group
        // the terminal.
        if !signals_of_the_moment(signals, CONTINUED_WAIT) {
            return Err(io::Error::other(
                "the terminal belongs to another process group, and this one cannot wait \
                 for it (started in the background of a shell that has gone, or with \
                 SIGTTOU ignored)",
            ));
        }
    }
    Ok(())
}

/// How long [`wait_for_foreground`] waits for the SIGCONT after its stop.
const CONTINUED_WAIT: Duration = Duration::from_secs(1);

/// The signals that arrive within `wait`, and then within [`SIGNAL_POLL`]
/// of each other: an ending one exits; returns whether a SIGCONT came.
fn signals_of_the_moment(signals: &Signals, wait: Duration) -> bool {
    let mut continued = false;
    while let Some(event) = signals.wait(if continued { SIGNAL_POLL } else { wait }) {
        match event {
            SignalEvent::Exit(signal) => restore_and_exit(signal),
            SignalEvent::Resume => continued = true,
            SignalEvent::Suspend => {}
        }
    }
    continued
}

/// Held while the modes change: entering and restoring never interleave
/// (a signal's exit, on its own thread, meets a main thread entering
/// them), and an exit holds it to the end, so nothing enters after.
static MODES: Mutex<()> = Mutex::new(());

fn modes_held() -> MutexGuard<'static, ()> {
    MODES.lock().unwrap_or_else(PoisonError::into_inner)
}

fn enter_modes() -> io::Result<()> {
    let _modes = modes_held();
    FOUND_MODES.get_or_init(|| {
        let fd = terminal_fd();
        let mut modes = std::mem::MaybeUninit::<libc::termios>::uninit();
        // SAFETY: `tcgetattr` fills the struct it is given, or fails and
        // leaves it alone (then not read).
        let found = unsafe { libc::tcgetattr(fd, modes.as_mut_ptr()) == 0 };
        // SAFETY: filled, as `tcgetattr` succeeded.
        found.then(|| (fd, unsafe { modes.assume_init() }))
    });
    // Entered from before the modes change: a signal meanwhile restores
    // them rather than leave them half set.
    ENTERED.store(true, Ordering::SeqCst);
    // crossterm remembers the modes it found before raw mode and does
    // nothing while it thinks raw mode is on; after a stop from outside
    // that may no longer be true, so give them back and enter afresh.
    disable_raw_mode()?;
    enable_raw_mode()?;
    execute!(
        io::stdout(),
        EnterAlternateScreen,
        EnableMouseCapture,
        EnableBracketedPaste
    )
}

/// The terminal's file descriptor and its tty modes before the program
/// first entered raw mode (`None`: not read), for
/// [`restore_without_allocating`].
static FOUND_MODES: OnceLock<Option<(libc::c_int, libc::termios)>> = OnceLock::new();

/// What [`restore_modes`] does, where nothing may allocate or take a lock:
/// the escape sequences written straight to standard output, the modes
/// found first set again on the terminal.
pub(crate) fn restore_without_allocating() {
    if ENTERED.swap(false, Ordering::SeqCst) {
        // Mouse reporting (every mode crossterm enables), bracketed paste,
        // the alternate screen off; the cursor shown.
        const OFF: &[u8] =
            b"\x1b[?1006l\x1b[?1015l\x1b[?1003l\x1b[?1002l\x1b[?1000l\x1b[?2004l\x1b[?1049l\x1b[?25h";
        // SAFETY: `write` reads `OFF` only; `tcsetattr` reads the modes.
        unsafe {
            libc::write(libc::STDOUT_FILENO, OFF.as_ptr().cast(), OFF.len());
            if let Some(Some((fd, modes))) = FOUND_MODES.get() {
                libc::tcsetattr(*fd, libc::TCSANOW, modes);
            }
        }
    }
}

/// Mouse reporting off first, so that no report arrives to be echoed once
/// the tty is cooked again; then the main screen, the cursor and the tty
/// modes. Does nothing if not entered; errors are ignored (a hung-up
/// terminal refuses everything, and there is nothing better to do).
fn restore_modes() {
    let _modes = modes_held();
    restore_entered();
}

/// [`restore_modes`], its lock already held (or not to be waited for).
fn restore_entered() {
    if ENTERED.swap(false, Ordering::SeqCst) {
        let _ = execute!(
            io::stdout(),
            DisableMouseCapture,
            DisableBracketedPaste,
            LeaveAlternateScreen,
            cursor::Show
        );
        let _ = disable_raw_mode();
    }
}

/// Restore the terminal and exit with 128 + `signal`. The first thread to
/// get here does it; any later one waits for the end.
fn restore_and_exit(signal: i32) -> ! {
    if EXITING.swap(true, Ordering::SeqCst) {
        loop {
            thread::park();
        }
    }
    // On the way out the terminal is given back even from the background
    // (stopped from outside, then `bg` and `kill`), where setting its
    // modes would otherwise stop the program, SIGTERM unanswered.
    // SAFETY: `signal` with SIG_IGN touches no memory of ours.
    unsafe { libc::signal(libc::SIGTTOU, libc::SIG_IGN) };
    let _modes = modes_held();
    restore_entered();
    std::process::exit(exit_status(signal))
}

/// Send SIGTSTP with its default action (stop) to our process group, and
/// return once continued, or at once where the system discards the stop.
///
/// Our own SIGTSTP handler (signal-hook's) is set aside for the duration.
/// Sent from the main thread, the signal stops the process before `kill`
/// returns: the kernel gives a process-directed signal to the thread group
/// leader first when it is the sender.
fn stop_process_group() -> io::Result<()> {
    // SAFETY: `sigaction` with zeroed structs naming SIG_DFL, and `kill`,
    // touch no memory of ours beyond the two structs here.
    unsafe {
        let mut default: libc::sigaction = std::mem::zeroed();
        default.sa_sigaction = libc::SIG_DFL;
        let mut ours: libc::sigaction = std::mem::zeroed();
        if libc::sigaction(libc::SIGTSTP, &default, &mut ours) != 0 {
            return Err(io::Error::last_os_error());
        }
        let sent = libc::kill(0, libc::SIGTSTP);
        let error = io::Error::last_os_error();
        libc::sigaction(libc::SIGTSTP, &ours, std::ptr::null_mut());
        if sent != 0 {
            return Err(error);
        }
    }
    Ok(())
}

/// A panic on the thread that entered the session ends the program:
/// restore the terminal, then report the panic through the hook that was
/// there before. A panic on another thread is caught there and shown as
/// that thread's result, so the screen stays as it is and nothing is
/// printed over it.
fn install_panic_hook() {
    static INSTALLED: Once = Once::new();
    INSTALLED.call_once(|| {
        let main = thread::current().id();
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if thread::current().id() == main {
                // As on any way out (`restore_and_exit`): never stopped
                // for setting the modes from the background.
                // SAFETY: `signal` with SIG_IGN touches no memory of ours.
                unsafe { libc::signal(libc::SIGTTOU, libc::SIG_IGN) };
                // Not waited for: the panic may come from inside a change
                // of the modes, on this thread.
                let _modes = MODES.try_lock();
                restore_entered();
                previous(info);
            }
        }));
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ending_signals_exit_with_128_plus_the_signal() {
        for signal in ENDING.into_iter().chain(ENDING_ON_LINUX) {
            assert_eq!(SignalEvent::of(signal), SignalEvent::Exit(signal));
        }
        let statuses = ENDING.map(exit_status);
        assert_eq!(statuses[..4], [143, 129, 130, 131]);
        assert_eq!(statuses[4..7], [138, 140, 142], "SIGUSR1, SIGUSR2, SIGALRM");
    }

    #[test]
    fn stop_and_continue_suspend_and_resume() {
        assert_eq!(SignalEvent::of(SIGTSTP), SignalEvent::Suspend);
        assert_eq!(SignalEvent::of(SIGCONT), SignalEvent::Resume);
    }
}
