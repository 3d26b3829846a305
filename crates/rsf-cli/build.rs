//! Links GCC's unwinder into the `rsf` binary on Linux with glibc, instead of loading
//! `libgcc_s.so` at every start.
//!
//! Why: `rsf simulate` on a lab protocol runs for a few milliseconds, so process start is a
//! large part of it. Loading one more shared library costs a file lookup, five mappings,
//! relocations and, on virtual machines, the `cpuid` instructions of its CPU-feature
//! constructor; measured here, a Rust binary without `libgcc_s` starts 0.1 ms sooner (0.74
//! against 0.85 ms). Rust's standard library needs only the unwinder from it, which GCC ships
//! as the static `libgcc_eh.a` (what `gcc -static-libgcc` links). With it linked whole, no
//! symbol is left for `libgcc_s`, and `--as-needed` (rustc's default) drops the library.
//! Panics unwind as before. Elsewhere, when cross-compiling, or when the toolchain has no
//! `libgcc_eh.a` (a clang-only system), nothing changes; `RSF_DYNAMIC_LIBGCC=1` turns it off.

use std::path::Path;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-env-changed=RSF_DYNAMIC_LIBGCC");
    println!("cargo:rerun-if-env-changed=CC");
    let linux_gnu = std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux")
        && std::env::var("CARGO_CFG_TARGET_ENV").as_deref() == Ok("gnu");
    let static_crt = std::env::var("CARGO_CFG_TARGET_FEATURE").is_ok_and(|f| f.split(',').any(|x| x == "crt-static"));
    // the probe below asks the host's C compiler, so only a native build uses it
    let native = std::env::var("HOST").ok() == std::env::var("TARGET").ok();
    if !linux_gnu || !native || static_crt || std::env::var_os("RSF_DYNAMIC_LIBGCC").is_some() {
        return;
    }
    // the C compiler rustc links with (`cc` by default) tells where its libgcc_eh.a is; it
    // prints the bare name when it has none
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let found = Command::new(cc)
        .arg("-print-file-name=libgcc_eh.a")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|p| Path::new(p).is_absolute() && Path::new(p).exists());
    if let Some(path) = found {
        let dir = Path::new(&path).parent().expect("an absolute path has a parent");
        println!("cargo:rustc-link-search=native={}", dir.display());
        println!("cargo:rustc-link-lib=static:+whole-archive=gcc_eh");
    }
}
