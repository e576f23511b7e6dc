//! Standard output closed before the program started (`lerpit run >&-`).
//! Rust's runtime opens `/dev/null` in place of a closed standard stream
//! before `main`, so every write would then succeed into nothing and the
//! command exit 0. The binary notes whether the descriptor was open before
//! the runtime starts ([`note_at_start`], called from a constructor), and
//! a command that would write finds it here ([`closed_at_start`]).

use std::sync::atomic::{AtomicBool, Ordering};

static CLOSED: AtomicBool = AtomicBool::new(false);

/// Note whether standard output (descriptor 1) is open. Called before the
/// runtime starts, so it only asks the system and stores a flag.
pub fn note_at_start() {
    // SAFETY: F_GETFD only reads the descriptor's flags.
    let open = unsafe { libc::fcntl(libc::STDOUT_FILENO, libc::F_GETFD) } != -1;
    CLOSED.store(!open, Ordering::Relaxed);
}

/// Whether standard output was closed when the program started.
pub(crate) fn closed_at_start() -> bool {
    CLOSED.load(Ordering::Relaxed)
}

/// The failure of a command whose standard output was closed.
pub(crate) fn error() -> std::io::Error {
    std::io::Error::other(
        "standard output was closed when lerpit started (as by `>&-`), so nothing it prints \
         would reach anyone; give it a file or /dev/null instead",
    )
}
