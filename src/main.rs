//! The `geoslip` program; see [`geoslip::cli`].

fn main() -> std::process::ExitCode {
    geoslip::cli::main()
}
