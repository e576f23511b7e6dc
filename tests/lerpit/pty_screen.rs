//! What a program in a pseudo-terminal shows: its output read on a thread
//! of its own and kept on a vt100 screen (the pty tests' shared part).

use portable_pty::MasterPty;
use std::io::Read;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

/// A guard against a test that would otherwise wait for ever; no check
/// depends on it.
pub const PATIENCE: Duration = Duration::from_secs(60);

pub struct Screen {
    pub parser: vt100::Parser,
    output: mpsc::Receiver<Vec<u8>>,
}

impl Screen {
    /// A `rows` x `cols` screen of what the program behind `master` writes.
    pub fn reading(master: &dyn MasterPty, rows: u16, cols: u16) -> Self {
        let mut reader = master.try_clone_reader().unwrap();
        let (tx, output) = mpsc::channel();
        std::thread::spawn(move || {
            let mut buf = [0u8; 8192];
            while let Ok(n) = reader.read(&mut buf) {
                if n == 0 || tx.send(buf[..n].to_vec()).is_err() {
                    break;
                }
            }
        });
        Screen {
            parser: vt100::Parser::new(
                std::num::NonZeroU16::new(rows).unwrap(),
                std::num::NonZeroU16::new(cols).unwrap(),
                0,
            ),
            output,
        }
    }

    /// Take in what arrived, waiting up to `wait` for the first of it.
    pub fn pump(&mut self, wait: Duration) {
        if let Ok(bytes) = self.output.recv_timeout(wait) {
            self.parser.process(&bytes);
        }
        while let Ok(bytes) = self.output.try_recv() {
            self.parser.process(&bytes);
        }
    }

    /// Take in all the program wrote, up to the end of the terminal's
    /// output: once every process that had the terminal open has closed it
    /// (ended), reading it fails and the reading thread ends.
    pub fn read_to_end(&mut self, what: &str) {
        let deadline = Instant::now() + PATIENCE;
        loop {
            match self.output.recv_timeout(Duration::from_millis(50)) {
                Ok(bytes) => self.parser.process(&bytes),
                Err(RecvTimeoutError::Disconnected) => return,
                Err(RecvTimeoutError::Timeout) => assert!(
                    Instant::now() < deadline,
                    "the terminal's output never ended after {what}; the screen shows:\n{}",
                    self.parser.screen().contents()
                ),
            }
        }
    }

    /// The screen's text.
    pub fn contents(&self) -> String {
        self.parser.screen().contents()
    }

    /// Wait until the screen satisfies `ok`; panic with the screen if not.
    pub fn wait_until(&mut self, what: &str, ok: impl Fn(&vt100::Screen) -> bool) -> String {
        let deadline = Instant::now() + PATIENCE;
        loop {
            let screen = self.parser.screen();
            if ok(screen) {
                return screen.contents();
            }
            assert!(
                Instant::now() < deadline,
                "the screen never showed {what}; it shows:\n{}",
                screen.contents()
            );
            self.pump(Duration::from_millis(50));
        }
    }

    /// Wait until the screen's text satisfies `ok`.
    pub fn wait_for(&mut self, what: &str, ok: impl Fn(&str) -> bool) -> String {
        self.wait_until(what, |s| ok(&s.contents()))
    }
}
