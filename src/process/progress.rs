//! Progress of the long headless commands (`run`, `study`, `bench`): one
//! indicatif bar on standard error, drawn only when standard error is a
//! terminal. A script, a pipe or a log file gets nothing, and standard
//! output never carries progress.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// The message comes last and is cut to the terminal's width, so that the
/// line does not wrap (a signal's handler clears one line).
const BAR: &str =
    "{prefix} [{bar:20}] {human_pos}/{human_len} ({elapsed}, about {eta} left) {wide_msg}";
/// [`BAR`] for a terminal too narrow for it.
const NARROW_BAR: &str = "{prefix} {percent}% ({eta} left) {wide_msg}";
/// [`NARROW_BAR`] for a terminal too narrow for it: the time left, without
/// the command's name.
const SHORT_BAR: &str = "{percent}% ({eta} left)";
/// [`SHORT_BAR`] for a terminal too narrow for it.
const TINY_BAR: &str = "{percent}%";
/// [`BAR`], [`NARROW_BAR`] and [`SHORT_BAR`] for work whose parts take
/// very different times (`study`): the time taken, where a time left from
/// the parts done would mislead (it said "about 1s left" for ten seconds).
const UNEVEN_BAR: &str = "{prefix} [{bar:20}] {human_pos}/{human_len} ({elapsed}) {wide_msg}";
const UNEVEN_NARROW_BAR: &str = "{prefix} {percent}% ({elapsed}) {wide_msg}";
const UNEVEN_SHORT_BAR: &str = "{percent}% ({elapsed})";
const SPINNER: &str = "{prefix} {spinner} {pos} done: {msg} ({elapsed})";
/// The wait for a large scene to be built.
/// The message comes last, cut to the terminal's width, so that the line
/// does not wrap (a signal's handler clears one line).
const WAITING: &str = "{prefix} {spinner} ({elapsed}) {wide_msg}";

fn target() -> ProgressDrawTarget {
    if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    }
}

/// A progress display. Hidden, it costs one branch a call: `run` may
/// report every step of a one-sphere scene.
pub(crate) struct Progress {
    bar: ProgressBar,
    shown: bool,
    /// A bar's length, label and parts, to fit its line to the terminal
    /// again after a resize ([`RESIZED`]).
    fits: Option<(u64, String, Parts)>,
    /// Handlers that clear the line on a signal, for as long as the
    /// display is shown ([`Progress::waiting_cleared_on_signals`]).
    clearing: Vec<signal_hook_registry::SigId>,
    /// The handlers of [`clear_line_while_shown`] act while it is shown.
    gated: bool,
}

/// Scenes of at least this many spheres say that they are being built:
/// placing them and checking them for overlaps takes seconds.
pub(crate) const BUILD_NOTICE_BODIES: usize = 100_000;

/// While a scene of [`BUILD_NOTICE_BODIES`] or more is built, on a
/// terminal: a line saying so, labelled `prefix`, cleared when dropped,
/// and by the signals that end the program as `clearing` says.
pub(crate) fn building(prefix: &str, bodies: usize, clearing: Clearing) -> Option<Progress> {
    (bodies >= BUILD_NOTICE_BODIES).then(|| {
        let spinner = match clearing {
            Clearing::ForGood => {
                if std::io::stderr().is_terminal() {
                    clear_line_on_signals();
                }
                Progress::waiting(prefix)
            }
            Clearing::WhileShown => Progress::waiting(prefix).cleared_while_shown(),
            #[cfg(feature = "tui")]
            Clearing::UntilDropped => Progress::waiting_cleared_on_signals(prefix),
        };
        spinner.message(format!(
            "building the scene: placing {} spheres and checking them for overlaps",
            crate::scene::thousands(bodies as u64)
        ));
        spinner
    })
}

/// How [`building`]'s line is taken off the screen by a signal that ends
/// the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Clearing {
    /// By handlers that stay for the rest of the process (`run`).
    ForGood,
    /// By those of [`clear_line_while_shown`], installed first (`run`
    /// writing rows to a file with the signals held off at times).
    WhileShown,
    /// By handlers that go with the line (the visualiser, whose own
    /// handling must then be in place).
    #[cfg(feature = "tui")]
    UntilDropped,
}

/// What [`building`]'s line says once `placed` of the scene's `spawned`
/// random spheres are placed (the percentage rounded down: 100% only
/// once all are), and whether they are then `checked` for overlaps.
pub(crate) fn placing(placed: usize, spawned: usize, checked: bool) -> String {
    let percent = (100 * placed).checked_div(spawned).unwrap_or(100);
    let then = if checked {
        ", then checked for overlaps"
    } else {
        ""
    };
    format!(
        "building the scene: {} of {} spheres placed ({percent}%){then}",
        crate::scene::thousands(placed as u64),
        crate::scene::thousands(spawned as u64)
    )
}

/// Whether a bar's parts take about the same time each, so that the time
/// left can be told from those done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Parts {
    Even,
    Uneven,
}

/// Set when the terminal is resized (SIGWINCH) while a bar is shown.
static RESIZED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

impl Progress {
    fn new(bar: ProgressBar, template: &str, prefix: &str) -> Self {
        bar.set_style(style(template));
        bar.set_prefix(prefix.to_string());
        let shown = !bar.is_hidden();
        Self {
            bar,
            shown,
            fits: None,
            clearing: Vec::new(),
            gated: false,
        }
    }

    /// A bar of `len` units of work, labelled `prefix` (`run`, `study`, ...),
    /// of the kind `parts` says: the time left, or for uneven parts the
    /// time taken. On a terminal too narrow for the whole line, the
    /// percentage and the time, then what of the message fits; narrower,
    /// without the command's name; below 20 columns, the percentage alone.
    /// Fitted again when the terminal is resized, so that the line never
    /// wraps (a signal's handler clears one line).
    fn bar_of(len: u64, prefix: &str, parts: Parts) -> Self {
        let mut bar = Self::new(
            ProgressBar::with_draw_target(Some(len), target()),
            bar_template(columns(), len, prefix, parts),
            prefix,
        );
        if bar.shown {
            static ONCE: std::sync::Once = std::sync::Once::new();
            ONCE.call_once(|| {
                // SAFETY: the action stores to an atomic, which is
                // async-signal-safe.
                let _ = unsafe {
                    signal_hook_registry::register(libc::SIGWINCH, || {
                        RESIZED.store(true, std::sync::atomic::Ordering::Relaxed);
                    })
                };
            });
            bar.fits = Some((len, prefix.to_string(), parts));
        }
        bar
    }

    /// A bar of even parts ([`Progress::bar_of`]) for a command that ends
    /// by the default action of SIGINT, SIGQUIT, SIGTERM and SIGHUP (`run`,
    /// `bench`): on a terminal, it takes itself off the screen first, so
    /// the shell's prompt does not start on a stale line. The handlers are
    /// in place before the bar is drawn.
    pub(crate) fn bar_cleared_on_signals(len: u64, prefix: &str) -> Self {
        if std::io::stderr().is_terminal() {
            clear_line_on_signals();
        }
        Self::bar_of(len, prefix, Parts::Even)
    }

    /// [`Progress::bar_of`] for a command whose signals are held off at
    /// times (`study`, see `unbroken.rs`): while it is on the screen, the
    /// handlers of [`clear_line_while_shown`] take it off before the
    /// signal ends the program.
    pub(crate) fn bar_of_cleared_while_shown(len: u64, prefix: &str, parts: Parts) -> Self {
        Self::bar_of(len, prefix, parts).cleared_while_shown()
    }

    /// Work of no known length: a count of the parts done and the current
    /// one.
    pub(crate) fn spinner(prefix: &str) -> Self {
        Self::ticking(SPINNER, prefix)
    }

    /// [`Progress::spinner`], cleared as [`Progress::bar_of_cleared_while_shown`] is.
    pub(crate) fn spinner_cleared_while_shown(prefix: &str) -> Self {
        Self::spinner(prefix).cleared_while_shown()
    }

    fn cleared_while_shown(mut self) -> Self {
        if self.shown {
            CLEAR_WHILE_SHOWN.store(true, std::sync::atomic::Ordering::SeqCst);
            self.gated = true;
        }
        self
    }

    /// One piece of work of unknown length, labelled `prefix`: what it is
    /// (`message`), a spinner and the time taken.
    pub(crate) fn waiting(prefix: &str) -> Self {
        Self::ticking(WAITING, prefix)
    }

    /// [`Progress::waiting`] whose line, on a terminal, SIGINT, SIGQUIT,
    /// SIGTERM and SIGHUP take off the screen before they end the program,
    /// as [`Progress::bar_cleared_on_signals`] does; its handlers go when
    /// it is dropped. Those signals are then caught with nothing to do
    /// (the registry keeps its handler), so drop it only once other
    /// handling is in place: the visualiser drops it after installing its
    /// own.
    #[cfg(feature = "tui")]
    pub(crate) fn waiting_cleared_on_signals(prefix: &str) -> Self {
        let clearing = if std::io::stderr().is_terminal() {
            register_clearing(None)
        } else {
            Vec::new()
        };
        let mut spinner = Self::waiting(prefix);
        spinner.clearing = clearing;
        spinner
    }

    /// A spinner drawn by `template`, kept moving on its own: parts may
    /// each take seconds, and the clock and the spinner move between them.
    fn ticking(template: &str, prefix: &str) -> Self {
        let spinner = Self::new(
            ProgressBar::with_draw_target(None, target()),
            template,
            prefix,
        );
        if spinner.shown {
            spinner
                .bar
                .enable_steady_tick(std::time::Duration::from_millis(200));
        }
        spinner
    }

    /// Never drawn.
    pub(crate) fn hidden() -> Self {
        Self {
            bar: ProgressBar::hidden(),
            shown: false,
            fits: None,
            clearing: Vec::new(),
            gated: false,
        }
    }

    /// `n` more units done.
    pub(crate) fn inc(&self, n: u64) {
        if self.shown {
            if let Some((len, prefix, parts)) = &self.fits
                && RESIZED.swap(false, std::sync::atomic::Ordering::Relaxed)
            {
                self.bar
                    .set_style(style(bar_template(columns(), *len, prefix, *parts)));
            }
            self.bar.inc(n);
        }
    }

    /// What is being done now.
    pub(crate) fn message(&self, what: impl Into<String>) {
        if self.shown {
            self.bar.set_message(what.into());
        }
    }

    /// Run `write` with the display off the screen, then draw it again:
    /// for output on the same terminal.
    pub(crate) fn suspend<R>(&self, write: impl FnOnce() -> R) -> R {
        if self.shown {
            self.bar.suspend(write)
        } else {
            write()
        }
    }

    /// Run `work` with the signals that end the program held off
    /// (`unbroken`); one that arrived meanwhile takes the display off the
    /// screen and ends the program once the work is done. A display of
    /// [`Progress::bar_of_cleared_while_shown`] leaves such a signal to
    /// the hold meanwhile.
    pub(crate) fn held<R>(
        &self,
        unbroken: &super::unbroken::Unbroken,
        work: impl FnOnce() -> R,
    ) -> R {
        use std::sync::atomic::Ordering::SeqCst;
        unbroken.hold_then(
            || {
                if self.gated {
                    gate_off();
                }
                let out = work();
                if self.gated {
                    CLEAR_WHILE_SHOWN.store(true, SeqCst);
                }
                out
            },
            || {
                if self.shown {
                    // SAFETY: only system calls (see `clear_line_now`).
                    unsafe { clear_line_now(HELD_ECHOED.load(SeqCst)) };
                }
            },
        )
    }

    /// Take the display off the screen.
    pub(crate) fn finish(&self) {
        if self.shown {
            self.bar.finish_and_clear();
        }
        // Off the screen first: a signal in between clears an empty line.
        if self.gated {
            gate_off();
        }
    }
}

impl Drop for Progress {
    /// A command that fails part way leaves no stale bar above its message.
    fn drop(&mut self) {
        self.finish();
        for id in self.clearing.drain(..) {
            signal_hook_registry::unregister(id);
        }
    }
}

/// On SIGINT, SIGQUIT, SIGTERM or SIGHUP, clear the terminal line standard
/// error is on, then end as the signal's default action does (status
/// 128 + n). Installed once.
///
/// The bar leaves the cursor at the right edge of its line (indicatif's
/// way, so that whatever is written next starts a line of its own). Ctrl-C
/// (or Ctrl-\\) typed at the terminal is echoed there as `^C` (`^\`), which
/// therefore wraps onto the next line: for a SIGINT (SIGQUIT) from the
/// terminal with that echo on, the handler waits for the echo, then clears
/// its line and the bar's.
fn clear_line_on_signals() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    // The handlers stay for the rest of the process.
    ONCE.call_once(|| drop(register_clearing(None)));
}

/// Set while a display made by [`Progress::bar_of_cleared_while_shown`]
/// or [`Progress::spinner_cleared_while_shown`] is on the screen.
static CLEAR_WHILE_SHOWN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Take the terminal line standard error is on off the screen, and with
/// `echoed` the line above it too (a Ctrl-C typed while the bar was drawn,
/// whose echo wrapped onto a line of its own, is waited for first): the
/// handlers' clearing, before a signal ends the program. From here on,
/// what anything else writes to standard error goes to /dev/null.
///
/// The clearing never waits on the terminal: where its output is stopped
/// (Ctrl-S), the line stays and the program ends all the same.
///
/// # Safety
/// Async-signal-safe: dup(2), open(2), dup2(2), nanosleep(2) and write(2).
unsafe fn clear_line_now(echoed: bool) {
    const CLEAR: &[u8] = b"\r\x1b[2K";
    const CLEAR_ECHO_AND_BAR: &[u8] = b"\r\x1b[2K\x1b[1A\r\x1b[2K";
    let out = if echoed { CLEAR_ECHO_AND_BAR } else { CLEAR };
    // SAFETY: the calls named above, on descriptors this owns.
    unsafe {
        // The terminal standard error is on, opened afresh so that the
        // write cannot block without the shell's own descriptor turning
        // non-blocking too (a copy of standard error where that fails).
        let flags = libc::O_WRONLY | libc::O_NONBLOCK | libc::O_NOCTTY | libc::O_CLOEXEC;
        let fresh = libc::open(c"/proc/self/fd/2".as_ptr(), flags);
        let terminal = if fresh >= 0 {
            fresh
        } else {
            libc::dup(libc::STDERR_FILENO)
        };
        // Another thread may be drawing the bar: from here on its writes
        // go to /dev/null, and the clearing goes to the terminal through
        // the descriptor above.
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_WRONLY);
        if terminal >= 0 && null >= 0 {
            libc::dup2(null, libc::STDERR_FILENO);
        }
        let fd = if terminal >= 0 {
            terminal
        } else {
            libc::STDERR_FILENO
        };
        if echoed {
            // The terminal echoes after it sends the signal.
            let wait = libc::timespec {
                tv_sec: 0,
                tv_nsec: 20_000_000,
            };
            libc::nanosleep(&wait, std::ptr::null_mut());
        }
        libc::write(fd, out.as_ptr().cast(), out.len());
    }
}

/// End the program with status 0, as a command whose reader has gone does
/// (`reader_watch.rs`), taking a display of [`clear_line_while_shown`]
/// shown at the time off the terminal first, as its handlers do.
pub(crate) fn end_for_a_gone_reader() -> ! {
    if CLEAR_WHILE_SHOWN.load(std::sync::atomic::Ordering::SeqCst) {
        // SAFETY: see `clear_line_now`, which is safe anywhere.
        unsafe { clear_line_now(false) };
    }
    std::process::exit(0)
}

/// Whether the last signal a closed gate left to a hold was typed at the
/// terminal and echoed there (see [`clear_line_now`]).
static HELD_ECHOED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Handlers of [`clear_line_while_shown`] that found their display shown
/// and are ending the program (one waits up to 20 ms for the terminal's
/// echo first).
static ENDING: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// Close the gate of [`clear_line_while_shown`]'s handlers: from here on
/// they leave a signal to the handlers after them (a hold notes it). One
/// that found the gate open ends the program: wait for that, so that no
/// work it would cut in two (a file's write) begins.
fn gate_off() {
    use std::sync::atomic::Ordering::SeqCst;
    CLEAR_WHILE_SHOWN.store(false, SeqCst);
    while ENDING.load(SeqCst) > 0 {
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

/// For a command that holds the signals off at times (`study`): handlers
/// that, while such a display is on the screen, do what those of
/// [`clear_line_on_signals`] do, and otherwise nothing, leaving the signal
/// to the handlers registered after them. Installed once, on a terminal,
/// before those others: a registered handler that ends the program runs
/// before the handlers registered after it.
pub(crate) fn clear_line_while_shown() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    if std::io::stderr().is_terminal() {
        ONCE.call_once(|| drop(register_clearing(Some(&CLEAR_WHILE_SHOWN))));
    }
}

/// Register the handlers of [`clear_line_on_signals`] (with a `gate`, only
/// while it is set); they stay until unregistered by the ids returned.
fn register_clearing(
    gate: Option<&'static std::sync::atomic::AtomicBool>,
) -> Vec<signal_hook_registry::SigId> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
    let mut ids = Vec::new();
    for signal in [SIGINT, SIGQUIT, SIGTERM, SIGHUP] {
        let clear = move |info: &libc::siginfo_t| {
            use std::sync::atomic::Ordering::SeqCst;
            let echoed = (signal == SIGINT || signal == SIGQUIT) && typed_and_echoed(info);
            // Counted as ending before the gate is read, so that
            // `gate_off` either is seen here or waits for the end.
            if let Some(g) = gate {
                ENDING.fetch_add(1, SeqCst);
                if !g.load(SeqCst) {
                    // Left to a hold, which clears the line as this
                    // would have once its work is done.
                    HELD_ECHOED.store(echoed, SeqCst);
                    ENDING.fetch_sub(1, SeqCst);
                    return;
                }
            }
            // SAFETY: see `clear_line_now`; emulate_default_handler is
            // async-signal-safe too (its documentation says so).
            unsafe { clear_line_now(echoed) };
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            if gate.is_some() {
                ENDING.fetch_sub(1, SeqCst);
            }
        };
        // SAFETY: the action only reads the terminal's modes, moves
        // file descriptors, sleeps, writes and re-raises (see above).
        // A signal left ignored (nohup) stays ignored.
        if !super::unbroken::ignored(signal)
            && let Ok(id) = unsafe { signal_hook_registry::register_sigaction(signal, clear) }
        {
            ids.push(id);
        }
    }
    ids
}

/// The style of `template`.
fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template)
        .expect("the templates are valid (tested)")
        .progress_chars("=> ")
}

/// The template of a bar of `len` units labelled `prefix` on a terminal
/// `width` columns wide (`None`: not a terminal).
fn bar_template(width: Option<u16>, len: u64, prefix: &str, parts: Parts) -> &'static str {
    let [bar, narrow, short] = match parts {
        Parts::Even => [BAR, NARROW_BAR, SHORT_BAR],
        Parts::Uneven => [UNEVEN_BAR, UNEVEN_NARROW_BAR, UNEVEN_SHORT_BAR],
    };
    match width.map(usize::from) {
        Some(w) if w < SHORT_BAR_WIDTH => TINY_BAR,
        Some(w) if w < narrow_bar_width(prefix) => short,
        Some(w) if w < bar_width(len, prefix) => narrow,
        _ => bar,
    }
}

/// The columns [`NARROW_BAR`] takes labelled `prefix`, its message aside,
/// at its widest.
/// Columns [`SHORT_BAR`] takes at most, with one to spare.
const SHORT_BAR_WIDTH: usize = "100% (59m 59s left) ".len();

fn narrow_bar_width(prefix: &str) -> usize {
    prefix.chars().count() + " 100% (59m 59s left) ".len()
}

/// The columns [`BAR`] takes for `len` units labelled `prefix`, its message
/// aside, at its widest: a count as long as `len`, and the longest times
/// indicatif writes (`59m 59s`, `99h`).
fn bar_width(len: u64, prefix: &str) -> usize {
    let digits = len.max(1).ilog10() as usize + 1;
    let count = digits + (digits - 1) / 3;
    prefix.chars().count() + " [] ".len() + 20 + 2 * count + 1 + " (59m 59s, about 99h left) ".len()
}

/// Columns of the terminal standard error is on; `None` when it is not one.
fn columns() -> Option<u16> {
    // SAFETY: TIOCGWINSZ fills the zeroed winsize it is given.
    unsafe {
        let mut size: libc::winsize = std::mem::zeroed();
        let got = libc::ioctl(libc::STDERR_FILENO, libc::TIOCGWINSZ, &mut size) == 0;
        (got && size.ws_col > 0).then_some(size.ws_col)
    }
}

/// Whether a signal came from a key typed at the terminal (the kernel
/// sends those) and the terminal on standard error echoes it (`^C`, `^\`).
fn typed_and_echoed(info: &libc::siginfo_t) -> bool {
    #[cfg(any(target_os = "linux", target_os = "android"))]
    let typed = info.si_code == libc::SI_KERNEL;
    #[cfg(not(any(target_os = "linux", target_os = "android")))]
    let typed = {
        let _ = info;
        false
    };
    if !typed {
        return false;
    }
    // SAFETY: tcgetattr fills the zeroed struct it is given.
    unsafe {
        let mut modes: libc::termios = std::mem::zeroed();
        libc::tcgetattr(libc::STDERR_FILENO, &mut modes) == 0
            && modes.c_lflag & libc::ECHO != 0
            && modes.c_lflag & libc::ECHOCTL != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_placing_line_says_100_percent_only_once_all_are_placed() {
        assert_eq!(
            placing(999_424, 1_000_000, true),
            "building the scene: 999,424 of 1,000,000 spheres placed (99%), then checked for \
             overlaps"
        );
        assert_eq!(
            placing(1_000_000, 1_000_000, false),
            "building the scene: 1,000,000 of 1,000,000 spheres placed (100%)"
        );
    }

    #[test]
    fn the_templates_are_valid() {
        assert!(ProgressStyle::with_template(BAR).is_ok());
        assert!(ProgressStyle::with_template(NARROW_BAR).is_ok());
        assert!(ProgressStyle::with_template(SHORT_BAR).is_ok());
        assert!(ProgressStyle::with_template(TINY_BAR).is_ok());
        assert!(ProgressStyle::with_template(SPINNER).is_ok());
        #[cfg(feature = "tui")]
        assert!(ProgressStyle::with_template(WAITING).is_ok());
    }

    #[test]
    fn the_bar_s_width_counts_its_digits_and_separators() {
        // "run [", 20 cells, "] ", "1,000,000,000/1,000,000,000", " (59m 59s, about 99h left) "
        assert_eq!(bar_width(1_000_000_000, "run"), 3 + 4 + 20 + 27 + 27);
        assert_eq!(bar_width(1, "bench"), 5 + 4 + 20 + 3 + 27);
    }

    #[test]
    fn the_bar_takes_the_widest_template_the_terminal_fits() {
        let (len, full) = (1000, bar_width(1000, "run"));
        let narrow = narrow_bar_width("run");
        assert_eq!(narrow, 3 + 21);
        assert_eq!(bar_template(None, len, "run", Parts::Even), BAR);
        assert_eq!(
            bar_template(Some(full as u16), len, "run", Parts::Even),
            BAR
        );
        assert_eq!(
            bar_template(Some(full as u16 - 1), len, "run", Parts::Even),
            NARROW_BAR
        );
        assert_eq!(
            bar_template(Some(narrow as u16), len, "run", Parts::Even),
            NARROW_BAR
        );
        assert_eq!(
            bar_template(Some(narrow as u16 - 1), len, "run", Parts::Even),
            SHORT_BAR
        );
        assert_eq!(bar_template(Some(20), len, "run", Parts::Even), SHORT_BAR);
        assert_eq!(bar_template(Some(19), len, "run", Parts::Even), TINY_BAR);
        assert_eq!(bar_template(Some(12), len, "run", Parts::Even), TINY_BAR);
        // Uneven parts: the same widths, the time taken for the time left.
        let uneven = |w: Option<u16>| bar_template(w, len, "run", Parts::Uneven);
        assert_eq!(uneven(None), UNEVEN_BAR);
        assert_eq!(uneven(Some(full as u16 - 1)), UNEVEN_NARROW_BAR);
        assert_eq!(uneven(Some(20)), UNEVEN_SHORT_BAR);
        assert_eq!(uneven(Some(19)), TINY_BAR);
        for t in [UNEVEN_BAR, UNEVEN_NARROW_BAR, UNEVEN_SHORT_BAR] {
            assert!(!t.contains("eta") && t.contains("{elapsed}"), "{t}");
        }
    }

    #[test]
    fn a_hidden_display_is_never_drawn() {
        let p = Progress::hidden();
        p.inc(3);
        p.message("x");
        assert!(!p.shown && p.bar.is_hidden());
    }
}
