//! The keyboard and mouse, read on a thread of their own.
//!
//! crossterm reads the terminal until it holds a whole event. In the middle
//! of an escape sequence that does not end (Alt-[ sends `ESC [`; a stray
//! `ESC [ <` waits for a mouse report's `m`, `ESC [ ?` for a `c`,
//! `ESC [ 200 ~` for the end of a paste) its read waits for the next byte,
//! and the bytes typed meanwhile go into the sequence. Read on the main
//! thread, that wait stopped the drawing until the sequence ended.
//!
//! Here the wait holds only this thread: the event loop draws on, handles
//! signals, and, once a look for input has overrun its time by
//! [`HELD_AFTER`], tells the person that the keys may be held and how to
//! free them ([`Input::held`]). A sequence that ends without making an
//! event (`ESC [` then `m`) leaves the read waiting for the next byte as
//! before, so the look goes on overrunning: "may be" is all it can say,
//! until the next event.

use ratatui::crossterm::event::{self, Event};
use std::io;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::thread;
use std::time::{Duration, Instant};

/// How long one look for input may wait before the thread looks again.
const LOOK: Duration = Duration::from_millis(100);
/// A look that has run this much past [`LOOK`] may be waiting inside an
/// unfinished sequence.
pub(crate) const HELD_AFTER: Duration = Duration::from_millis(700);

/// The input thread's events, in order, and whether it is held.
pub(crate) struct Input {
    events: Receiver<io::Result<Event>>,
    shared: Arc<Shared>,
}

/// What the event loop and the input thread both see.
struct Shared {
    /// When the thread's present look for input began, in milliseconds
    /// after `start` plus one; zero while it is not looking.
    looking_since: AtomicU64,
    start: Instant,
    /// Set when the `Input` is dropped: the thread ends after its look.
    closed: AtomicBool,
}

impl Input {
    /// Start the thread. It ends on its own when this `Input` is dropped
    /// and its look returns, or on a read error, which it passes on.
    pub(crate) fn start() -> io::Result<Self> {
        let (sender, events) = mpsc::channel();
        let shared = Arc::new(Shared {
            looking_since: AtomicU64::new(0),
            start: Instant::now(),
            closed: AtomicBool::new(false),
        });
        let theirs = Arc::clone(&shared);
        thread::Builder::new()
            .name("input".into())
            .spawn(move || read_events(&sender, &theirs))?;
        Ok(Input { events, shared })
    }

    /// The next event, waiting at most `timeout`; `None` if none came. A
    /// read error ends the thread, and comes here as its last event.
    pub(crate) fn next(&self, timeout: Duration) -> Option<io::Result<Event>> {
        match self.events.recv_timeout(timeout) {
            Ok(event) => Some(event),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => Some(Err(io::Error::other(
                "the input thread ended without saying why",
            ))),
        }
    }

    /// The next event if one is waiting.
    pub(crate) fn ready(&self) -> Option<io::Result<Event>> {
        self.events.try_recv().ok()
    }

    /// Whether the keys may be held by an unfinished escape sequence: the
    /// present look for input has overrun its time by [`HELD_AFTER`].
    pub(crate) fn held(&self) -> bool {
        let since = self.shared.looking_since.load(Ordering::Acquire);
        since > 0 && {
            let began = self.shared.start + Duration::from_millis(since - 1);
            began.elapsed() >= LOOK + HELD_AFTER
        }
    }
}

impl Drop for Input {
    fn drop(&mut self) {
        self.shared.closed.store(true, Ordering::Release);
    }
}

/// The input thread: look, read, pass on, until nobody listens.
fn read_events(sender: &Sender<io::Result<Event>>, shared: &Shared) {
    while !shared.closed.load(Ordering::Acquire) {
        let began = shared.start.elapsed().as_millis() as u64 + 1;
        shared.looking_since.store(began, Ordering::Release);
        let looked = event::poll(LOOK);
        shared.looking_since.store(0, Ordering::Release);
        let passed = match looked {
            Ok(false) => Ok(()),
            Ok(true) => match event::read() {
                Ok(event) => sender.send(Ok(event)),
                Err(error) => {
                    let _ = sender.send(Err(error));
                    return;
                }
            },
            Err(error) => {
                let _ = sender.send(Err(error));
                return;
            }
        };
        if passed.is_err() {
            return;
        }
    }
}
