//! Output that a signal does not cut mid-row: `run --trace` and `run
//! --trajectory` hand their rows on as they go, and a run stopped by a
//! signal ends its output after a whole row.
//!
//! Rows wait in memory and are handed on whole: to a regular file with
//! the signals that end the program held off ([`Unbroken`]), which a
//! file's write never keeps waiting; to anything else (a pipe, a
//! terminal) in writes of at most [`PIPE_BUF`] bytes of whole rows, which
//! a pipe takes whole or not at all, so that a reader that has stopped
//! never holds the signals off.

use super::progress::Progress;
use super::unbroken::Unbroken;
use std::io::{self, IsTerminal, Write};

/// The most a pipe takes in one piece (`PIPE_BUF`: Linux's, else the
/// least POSIX allows).
#[cfg(target_os = "linux")]
pub(crate) const PIPE_BUF: usize = 4096;
#[cfg(not(target_os = "linux"))]
pub(crate) const PIPE_BUF: usize = 512;
/// Bytes of rows that wait before they are handed on, besides a flush.
const WAITING: usize = 1 << 20;

/// A writer of rows (each ending in a newline, none within) to `out`.
pub(crate) struct WholeRows<'a, W: Write> {
    out: W,
    /// What was written and not yet handed on: whole rows, then perhaps
    /// the start of the next.
    pending: Vec<u8>,
    /// Set for a regular file: its writes are made with the signals held.
    unbroken: Option<&'a Unbroken>,
    /// The progress display, taken off the screen while rows are written
    /// to the terminal it is on.
    progress: &'a Progress,
    on_terminal: bool,
}

impl<'a, W: Write> WholeRows<'a, W> {
    /// Rows to `out`; `unbroken` when it is a regular file.
    pub(crate) fn new(out: W, unbroken: Option<&'a Unbroken>, progress: &'a Progress) -> Self {
        Self {
            out,
            pending: Vec::new(),
            unbroken,
            progress,
            on_terminal: std::io::stdout().is_terminal(),
        }
    }

    /// Hand on every whole row waiting.
    fn hand_on(&mut self) -> io::Result<()> {
        let Some(last) = self.pending.iter().rposition(|&b| b == b'\n') else {
            return Ok(());
        };
        let (rows, out, progress) = (&self.pending[..=last], &mut self.out, self.progress);
        let on_terminal = self.on_terminal;
        let most = if self.unbroken.is_some() {
            rows.len()
        } else {
            PIPE_BUF
        };
        let mut write = || -> io::Result<()> {
            for piece in pieces(rows, most) {
                out.write_all(piece)?;
                out.flush()?;
            }
            Ok(())
        };
        // A signal during a hold takes the display off once the rows are
        // written; rows to the terminal take it off while they are.
        let written = match self.unbroken {
            Some(unbroken) => progress.held(unbroken, write),
            None if on_terminal => progress.suspend(write),
            None => write(),
        };
        // Written or failed, they are not handed on again.
        self.pending.drain(..=last);
        written
    }
}

impl<W: Write> Write for WholeRows<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.pending.extend_from_slice(buf);
        if self.pending.len() >= WAITING {
            self.hand_on()?;
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.hand_on()
    }
}

/// `rows` (whole rows) cut into pieces of whole rows of at most `most`
/// bytes each, but a row longer than that alone.
fn pieces(rows: &[u8], most: usize) -> impl Iterator<Item = &[u8]> {
    let mut rest = rows;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let window = &rest[..most.min(rest.len())];
        let end = match window.iter().rposition(|&b| b == b'\n') {
            Some(k) if window.len() < rest.len() => k + 1,
            _ if window.len() == rest.len() => rest.len(),
            // A row longer than a piece: up to its end.
            _ => rest
                .iter()
                .position(|&b| b == b'\n')
                .map_or(rest.len(), |k| k + 1),
        };
        let (piece, after) = rest.split_at(end);
        rest = after;
        Some(piece)
    })
}

/// Whether standard output is a regular file.
pub(crate) fn stdout_is_regular_file() -> bool {
    #[cfg(unix)]
    {
        // SAFETY: `fstat` writes the one struct it is given.
        unsafe {
            let mut st: libc::stat = std::mem::zeroed();
            libc::fstat(libc::STDOUT_FILENO, &mut st) == 0
                && st.st_mode & libc::S_IFMT == libc::S_IFREG
        }
    }
    #[cfg(not(unix))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::pieces;

    #[test]
    fn pieces_are_whole_rows_within_the_bound() {
        let rows = b"ab\ncde\nf\nghijklmn\no\n";
        let cut: Vec<&[u8]> = pieces(rows, 7).collect();
        assert_eq!(
            cut,
            [&b"ab\ncde\n"[..], b"f\n", b"ghijklmn\n", b"o\n"],
            "a row longer than the bound goes alone"
        );
        assert_eq!(cut.concat(), rows);
        assert_eq!(pieces(b"", 7).count(), 0);
        let one: Vec<&[u8]> = pieces(b"ab\n", 512).collect();
        assert_eq!(one, [&b"ab\n"[..]]);
    }
}
