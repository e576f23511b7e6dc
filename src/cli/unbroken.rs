//! Work a termination signal does not cut in two: a study's files are
//! written with SIGINT, SIGTERM and SIGHUP held off, so an interrupted
//! study leaves all of its files or none, and no temporary file. A signal
//! that arrives meanwhile ends the program as soon as the work is done,
//! as it would have (killed by that signal). Outside such work the signals
//! end the program at once, as without this.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

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
            use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
            use signal_hook::flag::{register_conditional_default, register_usize};
            for signal in [SIGINT, SIGTERM, SIGHUP] {
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
        self.caught.store(0, Ordering::SeqCst);
        self.armed.store(false, Ordering::SeqCst);
        let out = work();
        self.armed.store(true, Ordering::SeqCst);
        let signal = self.caught.swap(0, Ordering::SeqCst);
        #[cfg(unix)]
        if signal != 0 {
            use std::io::Write;
            let _ = std::io::stdout().flush();
            let _ = signal_hook::low_level::emulate_default_handler(signal as i32);
        }
        #[cfg(not(unix))]
        let _ = signal;
        out
    }
}
