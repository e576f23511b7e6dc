/// Allocation through the system's allocator, which, should an allocation
/// fail, gives the visualiser's terminal back and ends the program with a
/// message and status 1 (`cli/out_of_memory.rs`).
#[global_allocator]
static ALLOCATOR: lerpit::cli::out_of_memory::Allocator = lerpit::cli::out_of_memory::Allocator;

/// Before Rust's runtime opens `/dev/null` in place of a closed standard
/// output: whether it was closed (`cli/closed_output.rs`).
#[ctor::ctor(unsafe)]
fn note_closed_output() {
    lerpit::cli::closed_output::note_at_start();
}

fn main() -> std::process::ExitCode {
    lerpit::cli::main()
}
