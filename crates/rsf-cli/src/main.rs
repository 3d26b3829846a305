//! The `rsf` binary: the CLI of [`rsf_cli`] with rsf's own laws.
#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    rsf_cli::main()
}
