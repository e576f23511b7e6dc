//! Whether the reader of standard output has gone: a command whose output
//! goes to a pipe ends (status 0, as a write finding the pipe closed does)
//! once the reader has stopped, not at its next row or its end, which may
//! be days away (`run --steps 1e12 --trace 1e9 | head -c 10`, `bench
//! --steps 1e9 | true`).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How often [`ReaderWatch`] looks at standard output.
const READER_LOOK: Duration = Duration::from_millis(250);

/// Looks at standard output every [`READER_LOOK`] on a thread of its own,
/// until dropped.
pub(crate) struct ReaderWatch {
    gone: Arc<AtomicBool>,
    done: Arc<AtomicBool>,
}

impl ReaderWatch {
    /// A watch the command asks ([`ReaderWatch::gone`]) between pieces of
    /// its work.
    pub(crate) fn start() -> Self {
        Self::start_then(|| {})
    }

    /// For a command whose only output is what it prints at its end (the
    /// study without `--out`): a watch that ends the program, with status
    /// 0, once the reader has gone, whatever it is in the middle of (a
    /// progress line shown is taken off the terminal first).
    pub(crate) fn ending_the_program() -> Self {
        Self::start_then(|| crate::process::progress::end_for_a_gone_reader())
    }

    fn start_then(when_gone: impl FnOnce() + Send + 'static) -> Self {
        let (gone, done) = (
            Arc::new(AtomicBool::new(false)),
            Arc::new(AtomicBool::new(false)),
        );
        let (g, d) = (Arc::clone(&gone), Arc::clone(&done));
        // Without the thread (none could start) the command only ends later.
        let _ = std::thread::Builder::new()
            .name("reader watch".into())
            .spawn(move || {
                while !d.load(Ordering::Relaxed) {
                    if reader_gone() {
                        g.store(true, Ordering::Relaxed);
                        when_gone();
                        return;
                    }
                    std::thread::sleep(READER_LOOK);
                }
            });
        Self { gone, done }
    }

    /// Whether the reader has gone, as last looked.
    pub(crate) fn gone(&self) -> bool {
        self.gone.load(Ordering::Relaxed)
    }

    /// A broken pipe, once the reader has gone.
    pub(crate) fn check(&self) -> std::io::Result<()> {
        if self.gone() {
            return Err(std::io::ErrorKind::BrokenPipe.into());
        }
        Ok(())
    }
}

impl Drop for ReaderWatch {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
    }
}

/// Whether standard output is a pipe with no reader left (the system
/// reports an error condition on its writing end).
fn reader_gone() -> bool {
    #[cfg(unix)]
    {
        let mut fd = libc::pollfd {
            fd: libc::STDOUT_FILENO,
            events: 0,
            revents: 0,
        };
        // SAFETY: `poll` reads and writes the one struct it is given.
        let ready = unsafe { libc::poll(&mut fd, 1, 0) };
        ready > 0 && fd.revents & libc::POLLERR != 0
    }
    #[cfg(not(unix))]
    {
        false
    }
}
