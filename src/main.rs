//! The `diffract` command; everything lives in the library (`diffract::cli`).

fn main() -> std::process::ExitCode {
    diffract::cli::main()
}
