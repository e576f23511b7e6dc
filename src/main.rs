fn main() -> std::process::ExitCode {
    lerpit::cli::main()
}
