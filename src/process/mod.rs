//! What both front ends need of the program as a process, outside the
//! screen: the progress line on standard error while a long piece of work
//! runs, and the signals that end the program.
//!
//! | file          | concept                                                        |
//! |---------------|----------------------------------------------------------------|
//! | `progress.rs` | the progress line: drawn only on a terminal, never on standard output |
//! | `unbroken.rs` | the signals that end the program, held off while files are written |
//! | `reader_watch.rs` | whether the reader of standard output has gone      |
//! | `whole_rows.rs` | rows that a signal does not cut: handed on whole        |

pub(crate) mod progress;
pub(crate) mod reader_watch;
pub(crate) mod unbroken;
pub(crate) mod whole_rows;
