/// Allocation through the system's allocator, which gives the
/// visualiser's terminal back should an allocation fail (the program then
/// aborts, and nothing else would).
#[cfg(feature = "tui")]
#[global_allocator]
static ALLOCATOR: lerpit::tui::RestoringAllocator = lerpit::tui::RestoringAllocator;

/// Before Rust's runtime opens `/dev/null` in place of a closed standard
/// output: whether it was closed (`cli/closed_output.rs`).
#[ctor::ctor(unsafe)]
fn note_closed_output() {
    lerpit::cli::closed_output::note_at_start();
}

fn main() -> std::process::ExitCode {
    lerpit::cli::main()
}
