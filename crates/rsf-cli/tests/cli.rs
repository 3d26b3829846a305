//! End-to-end tests of the `rsf` binary.

use std::path::PathBuf;
use std::process::Command;

fn rsf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rsf"))
}
fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn simulate_writes_the_specified_csv_and_a_plot() {
    let (csv, svg) = (tmp("sd.csv"), tmp("sd.svg"));
    let out = rsf()
        .args(["simulate", repo().join("examples/step_down.toml").to_str().unwrap(), "-o"])
        .arg(&csv)
        .arg("--plot")
        .arg(&svg)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("time_s,load_point_um,mu,slip_rate_um_s,slip_um,theta_1_s"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    // 10 µm at 3 µm/s then 500 s: 503.333 s, samples every 0.02 s plus the end
    assert_eq!(rows.len(), 25168);
    assert_eq!(rows[0][0], 0.0);
    assert_eq!(rows[0][1], 0.0);
    assert_eq!(rows[0][4], 0.0);
    assert!((rows[1][0] - 0.02).abs() < 1e-15);
    assert!((rows.last().unwrap()[0] - 10.0 / 3.0 - 500.0).abs() < 1e-9);
    assert!((rows.last().unwrap()[1] - 11.5).abs() < 1e-9);
    let svg = std::fs::read_to_string(&svg).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("friction"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("steps") && stderr.contains("Jacobians"), "{stderr}");
}

#[test]
fn method_override_gives_the_same_answer() {
    let p = repo().join("examples/slide_hold_slide.toml");
    let run = |m: &str| {
        let out = rsf().args(["simulate", p.to_str().unwrap(), "--method", m]).output().unwrap();
        assert!(out.status.success());
        String::from_utf8(out.stdout).unwrap()
    };
    let (a, b) = (run("explicit"), run("implicit"));
    let last = |s: &str| s.lines().last().unwrap().split(',').map(|x| x.parse::<f64>().unwrap()).collect::<Vec<_>>();
    assert!((last(&a)[2] - last(&b)[2]).abs() < 1e-8);
}

#[test]
fn errors_exit_nonzero_with_a_named_cause() {
    let bad = tmp("bad.toml");
    let good = std::fs::read_to_string(repo().join("examples/step_down.toml")).unwrap();
    std::fs::write(&bad, good.replace("dc = 2.07", "dc = -2.07")).unwrap();
    let out = rsf().args(["simulate", bad.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("bad.toml:12") && e.contains("model.state[1].dc"), "{e}");
    assert!(out.stdout.is_empty(), "no partial CSV on error");

    // an unstable quasi-static step: reported as a blow-up with its time, not garbage rows
    let unstable = good
        .replace("a = 0.013", "a = 0.005")
        .replace("b = 0.016", "b = 0.01")
        .replace("dc = 2.07", "dc = 10.0")
        .replace("stiffness = 0.065", "stiffness = 0.001")
        .replace("v = 0.003", "v = 30.0")
        .replace("v_init = 3.0", "v_init = 3.0\n");
    std::fs::write(&bad, unstable).unwrap();
    let out = rsf().args(["simulate", bad.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("blew up at t =") && e.contains("eta"), "{e}");

    let out = rsf().args(["simulate", "/nonexistent.toml"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read"));
}

#[test]
fn help_documents_every_field() {
    let out = rsf().args(["simulate", "--help"]).output().unwrap();
    let h = String::from_utf8(out.stdout).unwrap();
    for f in [
        "mu0",
        "v0",
        "a =",
        "stiffness",
        "eta",
        "form",
        "law",
        "b =",
        "dc",
        "vc",
        "c =",
        "v_init",
        "segment",
        "duration",
        "displacement",
        "record",
        "time_column",
        "load_point_column",
        "dt",
        "method",
        "rtol",
        "atol",
        "max_slip_rate",
    ] {
        assert!(h.contains(f), "--help lacks `{f}`");
    }
}
