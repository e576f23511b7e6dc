//! When memory runs out part-way: the program's allocator ends it with a
//! message and status 1, where Rust would print the size and abort (134,
//! with a backtrace under `RUST_BACKTRACE`).
//!
//! The commands check what a scene and its first step need before they
//! start, but a pile grows: its contacts, and the support pass's rows,
//! outgrow an address-space limit (`ulimit -v`) many steps in (`run
//! --support` of 300,000 falling spheres under 400 MB did at its sixth
//! second of running). No caller can be told of it there, so the
//! allocator says so itself: the terminal given back first (the
//! visualiser's), then one line on standard error, written and ended
//! without allocating (`write`, `_exit`).
//!
//! A reader told of a failure instead (`read_to_end` reading a scene file
//! gives an error, which names the file) holds a
//! [`Recoverable`](crate::scene::memory::Recoverable) while it reads
//! (`scene::memory`): the allocation's failure is then returned to
//! it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::fmt::Write;

use crate::scene::memory::{told_of_failure, write_memory_size};

/// The system's allocator, which ends the program with a message and
/// status 1 when an allocation fails (and gives the visualiser's terminal
/// back first), unless a [`Recoverable`](crate::scene::memory::Recoverable)
/// is held.
pub struct Allocator;

// SAFETY: every call is the system allocator's, with the same arguments; a
// failure only also writes to the terminal and may end the process,
// without allocating.
unsafe impl GlobalAlloc for Allocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's promises are the system allocator's.
        checked(unsafe { System.alloc(layout) }, layout.size())
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `alloc`.
        checked(unsafe { System.alloc_zeroed(layout) }, layout.size())
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as `alloc`.
        checked(unsafe { System.realloc(ptr, layout, new_size) }, new_size)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as `alloc`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// `ptr`; if it is null (an allocation of `size` bytes failed), the
/// terminal is given back, and unless a reader is told of it, the program
/// ends with the message.
#[inline]
fn checked(ptr: *mut u8, size: usize) -> *mut u8 {
    if ptr.is_null() {
        ran_out(size);
    }
    ptr
}

#[cold]
fn ran_out(size: usize) {
    // A thread-local of `const` initial value and no destructor: reading
    // it never allocates.
    if told_of_failure() {
        return;
    }
    #[cfg(feature = "tui")]
    crate::tui::restore_without_allocating();
    let mut text = Line::default();
    // A progress line on a terminal is cleared first.
    // SAFETY: `isatty` only asks about the descriptor.
    if unsafe { libc::isatty(libc::STDERR_FILENO) } == 1 {
        let _ = text.write_str("\r\x1b[2K");
    }
    let _ = message(&mut text, size, limits());
    // SAFETY: `write` reads the bytes of `text`; `_exit` ends the process
    // at once, every thread with it, and runs nothing that could allocate.
    unsafe {
        libc::write(libc::STDERR_FILENO, text.bytes.as_ptr().cast(), text.len);
        libc::_exit(1);
    }
}

/// The address-space and data-size limits (`ulimit -v`, `ulimit -d`),
/// bytes, where set.
fn limits() -> [Option<u64>; 2] {
    let limit = |resource| {
        let mut l = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: `getrlimit` writes the one struct it is given.
        let read = unsafe { libc::getrlimit(resource, &mut l) } == 0;
        (read && l.rlim_cur != libc::RLIM_INFINITY).then_some(l.rlim_cur)
    };
    [limit(libc::RLIMIT_AS), limit(libc::RLIMIT_DATA)]
}

/// The line said when an allocation of `size` bytes fails under the
/// address-space and data-size `limits`.
fn message(out: &mut impl Write, size: usize, limits: [Option<u64>; 2]) -> std::fmt::Result {
    write!(out, "lerpit: error: memory ran out: an allocation of ")?;
    write_memory_size(out, size as f64)?;
    write!(out, " failed")?;
    let named = [
        (limits[0], "the address-space limit (ulimit -v)"),
        (limits[1], "the data-size limit (ulimit -d)"),
    ];
    let mut any = false;
    for (limit, what) in named {
        if let Some(bytes) = limit {
            write!(out, "{}{what} is ", if any { " and " } else { "; " })?;
            write_memory_size(out, bytes as f64)?;
            any = true;
        }
    }
    writeln!(
        out,
        ". Use fewer spheres{}",
        if any { ", or raise the limit" } else { "" }
    )
}

/// A line of text on the stack; what does not fit is left out.
struct Line {
    bytes: [u8; 400],
    len: usize,
}

impl Default for Line {
    fn default() -> Self {
        Self {
            bytes: [0; 400],
            len: 0,
        }
    }
}

impl Write for Line {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let room = self.bytes.len() - self.len;
        let n = s.len().min(room);
        self.bytes[self.len..self.len + n].copy_from_slice(&s.as_bytes()[..n]);
        self.len += n;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{Line, message};

    fn said(size: usize, limits: [Option<u64>; 2]) -> String {
        let mut line = Line::default();
        message(&mut line, size, limits).expect("fits");
        String::from_utf8(line.bytes[..line.len].to_vec()).expect("text")
    }

    #[test]
    fn the_message_names_the_size_and_each_limit_set() {
        assert_eq!(
            said(115_200_000, [Some(409_600_000), None]),
            "lerpit: error: memory ran out: an allocation of 115 MB failed; the address-space \
             limit (ulimit -v) is 410 MB. Use fewer spheres, or raise the limit\n"
        );
        assert_eq!(
            said(2_500_000_000, [Some(8 << 30), Some(3 << 30)]),
            "lerpit: error: memory ran out: an allocation of 2.5 GB failed; the address-space \
             limit (ulimit -v) is 8.6 GB and the data-size limit (ulimit -d) is 3.2 GB. Use \
             fewer spheres, or raise the limit\n"
        );
        assert_eq!(
            said(640, [None, None]),
            "lerpit: error: memory ran out: an allocation of 640 bytes failed. Use fewer spheres\n"
        );
    }

    #[test]
    fn a_line_longer_than_its_room_is_cut_not_overrun() {
        use std::fmt::Write;
        let mut line = Line::default();
        for _ in 0..50 {
            line.write_str("0123456789").expect("never fails");
        }
        assert_eq!(line.len, line.bytes.len());
    }
}
