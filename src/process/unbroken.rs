//! Work a termination signal does not cut in two: a study's files are
//! written with the signals that end a process held off (SIGINT, SIGTERM,
//! SIGHUP, SIGQUIT, and the others whose default action ends it without a
//! fault of its own: [`ENDING`]), so an interrupted
//! study leaves all of its files or none, and no temporary file. A signal
//! that arrives meanwhile ends the program as soon as the work is done,
//! as it would have (killed by that signal). Outside such work the signals
//! end the program at once, as without this.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The signals that end the program: those a terminal or a user sends, and
/// the others whose default action ends a process without a fault of its
/// own (SIGPIPE stays ignored, as Rust leaves it, and the headless
/// commands ignore SIGXFSZ: see `cli::main`). A study holds them off
/// while it writes; the visualiser restores the terminal on each.
#[cfg(unix)]
pub(crate) const ENDING: [libc::c_int; 11] = [
    libc::SIGTERM,
    libc::SIGHUP,
    libc::SIGINT,
    libc::SIGQUIT,
    libc::SIGUSR1,
    libc::SIGUSR2,
    libc::SIGALRM,
    libc::SIGVTALRM,
    libc::SIGPROF,
    libc::SIGXCPU,
    libc::SIGXFSZ,
];

/// The termination signals, registered for the rest of the process.
pub(crate) struct Unbroken {
    /// True: a signal ends the program at once.
    armed: Arc<AtomicBool>,
    /// The signal that arrived while disarmed (0: none).
    caught: Arc<AtomicUsize>,
}

impl Unbroken {
    /// Register the signals. Where that fails (or off Unix), the work
    /// simply runs as it would without this.
    pub(crate) fn install() -> Self {
        let unbroken = Self {
            armed: Arc::new(AtomicBool::new(true)),
            caught: Arc::new(AtomicUsize::new(0)),
        };
        #[cfg(unix)]
        {
            use signal_hook::flag::{register_conditional_default, register_usize};
            for signal in ENDING {
                // A signal the program was started ignoring (`nohup`, a
                // background job) stays ignored, as does SIGXFSZ, which
                // `cli::main` ignores so that a write past the file-size
                // limit fails with an error the command says.
                if ignored(signal) {
                    continue;
                }
                // Noted first, then (when armed) the default action.
                let _ = register_usize(signal, Arc::clone(&unbroken.caught), signal as usize);
                let _ = register_conditional_default(signal, Arc::clone(&unbroken.armed));
            }
        }
        unbroken
    }

    /// Run `work` with the signals held off; then end the program if one
    /// arrived meanwhile.
    pub(crate) fn hold<T>(&self, work: impl FnOnce() -> T) -> T {
        self.hold_then(work, || {})
    }

    /// [`Unbroken::hold`], running `before_ending` before a signal that
    /// arrived meanwhile ends the program.
    pub(crate) fn hold_then<T>(&self, work: impl FnOnce() -> T, before_ending: impl FnOnce()) -> T {
        /// Armed again however the work ends, a panic included.
        struct Rearm<'a>(&'a AtomicBool);
        impl Drop for Rearm<'_> {
            fn drop(&mut self) {
                self.0.store(true, Ordering::SeqCst);
            }
        }
        self.caught.store(0, Ordering::SeqCst);
        self.armed.store(false, Ordering::SeqCst);
        let out = {
            let _rearm = Rearm(&self.armed);
            work()
        };
        let signal = self.caught.swap(0, Ordering::SeqCst);
        #[cfg(unix)]
        if signal != 0 {
            use std::io::Write;
            before_ending();
            let _ = std::io::stdout().flush();
            let _ = signal_hook::low_level::emulate_default_handler(signal as i32);
        }
        #[cfg(not(unix))]
        let _ = (signal, before_ending);
        out
    }
}

/// Whether `signal` is set to be ignored (as `nohup` and shells starting
/// background jobs leave SIGHUP and SIGINT).
#[cfg(unix)]
pub(super) fn ignored(signal: libc::c_int) -> bool {
    // SAFETY: a null new action only reads the current one into `old`.
    unsafe {
        let mut old: libc::sigaction = std::mem::zeroed();
        libc::sigaction(signal, std::ptr::null(), &mut old) == 0
            && old.sa_sigaction == libc::SIG_IGN
    }
}
