//! The installed library, as a C or Fortran group uses it: `make install-files` (the copy step
//! of `make install`, with the library this test run built) into a temporary prefix; then the
//! C and Fortran hosts of `examples/` built against that prefix alone — through pkg-config
//! (the shared library for C, the static one for Fortran) and through CMake's
//! `find_package(rsf CONFIG)` — and run. The compilers see no path into this repository but
//! the example sources: headers, module source and libraries come from the prefix.
//! Each tool that is missing skips its part with a line saying so (`.ci/run` installs them).

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{crate_dir, static_lib};

fn have(tool: &str) -> bool {
    Command::new(tool).arg("--version").output().is_ok_and(|o| o.status.success())
}

/// Runs `cmd` without cargo's LD_LIBRARY_PATH (which points into this repository's target/
/// and would take precedence over the installed library's rpath).
fn run(cmd: &mut Command) -> String {
    let o = cmd.env_remove("LD_LIBRARY_PATH").output().unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{cmd:?} failed:\n{text}");
    text
}

/// A fresh temporary folder for this test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-install-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Installs into `prefix` with the repository's Makefile, from the folder that holds the
/// library this test links (cargo built its staticlib and cdylib there).
fn install(prefix: &Path) {
    let lib_dir = static_lib().parent().unwrap().to_path_buf();
    let root = crate_dir().join("../..");
    run(Command::new("make")
        .arg("-s")
        .arg("-C")
        .arg(&root)
        .arg("install-files")
        .arg(format!("PREFIX={}", prefix.display()))
        .arg(format!("LIB={}", lib_dir.display())));
}

fn pkg_config(prefix: &Path, args: &[&str]) -> Vec<String> {
    let out =
        run(Command::new("pkg-config").args(args).arg("rsf").env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig")));
    out.split_whitespace().map(String::from).collect()
}

fn example(rel: &str) -> PathBuf {
    crate_dir().join("examples").join(rel)
}

#[test]
fn installed_library_builds_c_and_fortran_hosts() {
    if !have("make") || !have("pkg-config") {
        println!("SKIP: make or pkg-config not installed; the install was not tested");
        return;
    }
    let dir = scratch("pc");
    let prefix = dir.join("prefix");
    install(&prefix);
    for f in [
        "lib/librsf_capi.a",
        "lib/librsf_capi.so",
        "include/rsf.h",
        "include/rsf.f90",
        "lib/pkgconfig/rsf.pc",
        "lib/cmake/rsf/rsfConfig.cmake",
        "lib/cmake/rsf/rsfConfigVersion.cmake",
    ] {
        assert!(prefix.join(f).is_file(), "{f} not installed");
    }
    let version = pkg_config(&prefix, &["--modversion"]);
    assert_eq!(version, vec![env!("CARGO_PKG_VERSION").to_string()]);
    let libdir = pkg_config(&prefix, &["--variable=libdir"]).remove(0);
    assert_eq!(Path::new(&libdir), prefix.join("lib"));

    if have("gcc") {
        // the three C hosts, shared library: cflags and libs from pkg-config, an rpath to the
        // prefix, and the library the executable loads is the prefix's
        for (src, line) in
            [("c/mesh.c", "mesh: ok"), ("c/spring_slider.c", "onset 5.9824 yr"), ("c/refusals.c", "accepted 0")]
        {
            let exe = dir.join(src.replace(['/', '.'], "_"));
            run(Command::new("gcc")
                .arg(example(src))
                .args(pkg_config(&prefix, &["--cflags", "--libs"]))
                .arg(format!("-Wl,-rpath,{libdir}"))
                .arg("-lm")
                .arg("-o")
                .arg(&exe));
            let out = run(&mut Command::new(&exe));
            assert!(out.contains(line), "{src}: no `{line}` in\n{out}");
            let ldd = run(Command::new("ldd").arg(&exe));
            assert!(ldd.contains(&prefix.join("lib/librsf_capi.so").display().to_string()), "{src}: {ldd}");
        }
    } else {
        println!("SKIP: gcc not installed; the C hosts were not built against the installed library");
    }
    if have("gfortran") {
        // Fortran, static library: the module source and the archive from pkg-config
        let exe = dir.join("f_element");
        let module = pkg_config(&prefix, &["--variable=fortran_module"]).remove(0);
        let archive = pkg_config(&prefix, &["--variable=staticlib"]).remove(0);
        let private: Vec<String> =
            pkg_config(&prefix, &["--static", "--libs-only-l"]).into_iter().filter(|l| l != "-lrsf_capi").collect();
        run(Command::new("gfortran")
            .arg("-J")
            .arg(&dir)
            .arg(&module)
            .arg(example("fortran/element.f90"))
            .arg(&archive)
            .args(&private)
            .arg("-o")
            .arg(&exe));
        let out = run(&mut Command::new(&exe));
        assert!(out.contains("mesh rate error"), "{out}");
    } else {
        println!("SKIP: gfortran not installed; the Fortran host was not built against the installed library");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn installed_library_is_found_by_cmake() {
    if !have("make") || !have("cmake") || !have("gcc") {
        println!("SKIP: make, cmake or gcc not installed; find_package(rsf) was not tested");
        return;
    }
    let fortran = have("gfortran");
    let dir = scratch("cmake");
    let prefix = dir.join("prefix");
    install(&prefix);
    let src = dir.join("host");
    std::fs::create_dir_all(&src).unwrap();
    let mut lists = format!(
        "cmake_minimum_required(VERSION 3.13)\nproject(host LANGUAGES C{})\n\
         find_package(rsf 0.1 CONFIG REQUIRED)\n\
         add_executable(c_mesh {})\ntarget_link_libraries(c_mesh PRIVATE rsf::rsf m)\n",
        if fortran { " Fortran" } else { "" },
        example("c/mesh.c").display()
    );
    if fortran {
        lists += &format!(
            "add_executable(f_element ${{rsf_FORTRAN_MODULE}} {})\ntarget_link_libraries(f_element PRIVATE rsf::rsf_static)\n",
            example("fortran/element.f90").display()
        );
    }
    std::fs::write(src.join("CMakeLists.txt"), lists).unwrap();
    let build = dir.join("build");
    run(Command::new("cmake")
        .arg("-S")
        .arg(&src)
        .arg("-B")
        .arg(&build)
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())));
    run(Command::new("cmake").arg("--build").arg(&build));
    let out = run(&mut Command::new(build.join("c_mesh")));
    assert!(out.contains("mesh: ok"), "{out}");
    if fortran {
        let out = run(&mut Command::new(build.join("f_element")));
        assert!(out.contains("mesh rate error"), "{out}");
    } else {
        println!("SKIP: gfortran not installed; the Fortran host was not built by CMake");
    }
    // a version the package does not provide is refused by find_package
    std::fs::write(
        src.join("CMakeLists.txt"),
        "cmake_minimum_required(VERSION 3.13)\nproject(h LANGUAGES C)\nfind_package(rsf 9.0 CONFIG REQUIRED)\n",
    )
    .unwrap();
    let o = Command::new("cmake")
        .arg("-S")
        .arg(&src)
        .arg("-B")
        .arg(dir.join("build9"))
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display()))
        .output()
        .unwrap();
    assert!(!o.status.success(), "find_package(rsf 9.0) succeeded against version {}", env!("CARGO_PKG_VERSION"));
    let _ = std::fs::remove_dir_all(&dir);
}
