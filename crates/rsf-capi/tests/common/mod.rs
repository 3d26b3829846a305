//! What the tests that build hosts against the C ABI share.

use std::path::PathBuf;

/// The static library the hosts link: cargo builds the library with all its crate types
/// (rlib, staticlib, cdylib) into `target/<profile>/deps/`, beside the test's own binary, for
/// `cargo test` alone; `cargo build` also copies it one folder up.
pub fn static_lib() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    [deps.join("librsf_capi.a"), deps.parent().unwrap().join("librsf_capi.a")]
        .into_iter()
        .find(|p| p.exists())
        .unwrap_or_else(|| panic!("librsf_capi.a is in neither {} nor its parent", deps.display()))
}

/// This crate's folder.
pub fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}
