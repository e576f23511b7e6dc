/// Allocation through the system's allocator, which gives the
/// visualiser's terminal back should an allocation fail (the program then
/// aborts, and nothing else would).
#[cfg(feature = "tui")]
#[global_allocator]
static ALLOCATOR: lerpit::tui::RestoringAllocator = lerpit::tui::RestoringAllocator;

fn main() -> std::process::ExitCode {
    lerpit::cli::main()
}
