//! `rsf` with power-law aging built in: every command of rsf's CLI, with `power-aging-rs` a law
//! name like `aging` (`cargo run --features cli --bin rsf-power -- laws`).

fn main() -> std::process::ExitCode {
    if let Err(e) = my_rsf_law::register() {
        eprintln!("error: {e}");
        return std::process::ExitCode::FAILURE;
    }
    rsf_cli::main()
}
