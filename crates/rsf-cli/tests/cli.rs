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

/// The binary has its own entry point (see main.rs); it still ignores SIGPIPE, so a reader
/// that stops early ends a long CSV on stdout with success and no message.
#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let mut child = rsf()
        .args(["simulate", repo().join("examples/step_down.toml").to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut header = String::new();
    // 25,168 rows (2 MB) cannot fit in the pipe: the writer meets the closed end
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut header).unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !stderr.contains("error"), "{:?}: {stderr}", out.status);
    assert!(header.starts_with("time_s,"), "{header}");
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

const BASALT: &str = "examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt";

fn fit_args() -> Vec<String> {
    [
        "fit",
        repo().join(BASALT).to_str().unwrap(),
        "--time-col",
        "Time(s)",
        "--lp-col",
        "Displ(microns)",
        "--mu-col",
        "Friction",
        "--law",
        "slip",
        "--stiffness",
        "0.0151",
        "--fit-stiffness",
        "--loading",
        "protocol",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

#[test]
fn fit_writes_the_specified_json_and_plot() {
    let (json, svg) = (tmp("fit.json"), tmp("fit.svg"));
    let out = rsf()
        .args(fit_args())
        .args(["--mcmc", "2000", "--chains", "2", "--seed", "5", "--per-segment", "--json"])
        .arg(&json)
        .arg("--plot")
        .arg(&svg)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let p = &v["params"];
    for key in ["mu0", "a", "k"] {
        assert!(p[key].as_f64().is_some(), "params.{key}");
    }
    assert_eq!(p["b"].as_array().unwrap().len(), 1);
    assert_eq!(p["dc"].as_array().unwrap().len(), 1);
    for free in ["mu0", "a", "b1", "dc1", "k"] {
        let ci = v["ci95"][free].as_array().unwrap_or_else(|| panic!("ci95.{free}"));
        assert!(ci[0].as_f64().unwrap() < ci[1].as_f64().unwrap());
    }
    for key in ["rms", "n", "log_likelihood", "aic", "bic"] {
        assert!(v[key].as_f64().is_some(), "{key}");
    }
    assert_eq!(v["segments"].as_array().unwrap().len(), 2);
    assert!(v["mcmc"]["params"]["a"]["rhat"].as_f64().is_some());
    assert!(!v["per_segment"].as_array().unwrap().is_empty());
    // a and Dc near the record's values (see docs/fit.md); the fit is reproducible
    let a = p["a"].as_f64().unwrap();
    assert!((0.008..0.012).contains(&a), "a = {a}");
    let svg = std::fs::read_to_string(&svg).unwrap();
    assert!(svg.contains("residual"));
    let again = rsf()
        .args(fit_args())
        .args(["--mcmc", "2000", "--chains", "2", "--seed", "5", "--json"])
        .arg(tmp("fit2.json"))
        .output()
        .unwrap();
    assert!(again.status.success());
    let w: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(tmp("fit2.json")).unwrap()).unwrap();
    assert_eq!(
        v["mcmc"]["params"]["a"]["median"], w["mcmc"]["params"]["a"]["median"],
        "--seed makes MCMC reproducible"
    );
}

#[test]
fn fit_errors_are_named() {
    let run = |extra: &[&str]| {
        let out = rsf().args(fit_args()).args(extra).output().unwrap();
        assert_eq!(out.status.code(), Some(1));
        String::from_utf8_lossy(&out.stderr).to_string()
    };
    assert!(run(&["--fix", "a-q=1"]).contains("unknown parameter `q`"));
    // a constraint that does not parse is refused with the arguments (exit 2), before any work
    let out = rsf().args(fit_args()).args(["--fix", "a-b=x"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("`x` is not a number"));
    let args: Vec<String> = fit_args().into_iter().map(|a| if a == "slip" { "dieterich".into() } else { a }).collect();
    let out = rsf().args(args).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown law `dieterich`"));
    let out = rsf().args(["fit", repo().join(BASALT).to_str().unwrap(), "--stiffness=-1"]).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("--stiffness -1 must be positive"));
    // a closed option's bad value is a usage error (clap: exit 2) naming the option and the names
    let out = rsf().args(fit_args()).args(["--weights", "heavy"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--weights") && err.contains("unknown weights `heavy`: use equal-segments or uniform"),
        "{err}"
    );
    let out = rsf().args(["fit", "/nonexistent.csv", "--stiffness", "0.01"]).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read"));
    let bad = tmp("bad.csv");
    std::fs::write(&bad, "time_s,load_point_um,mu\n0,0,0.6\n1,1,0.6\n0.5,2,0.6\n").unwrap();
    let out = rsf().args(["fit", bad.to_str().unwrap(), "--stiffness", "0.01"]).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.csv:4: column `time_s`: time 0.5 does not increase"));
    // a repeated time names the option that drops such rows
    std::fs::write(&bad, "time_s,load_point_um,mu\n0,0,0.6\n1,1,0.6\n1,2,0.6\n").unwrap();
    let out = rsf().args(["fit", bad.to_str().unwrap(), "--stiffness", "0.01"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.csv:4: column `time_s`: time 1 repeats the previous row's")
            && err.contains("--duplicate-times drop"),
        "{err}"
    );
}

#[test]
fn fixing_a_minus_b_holds_the_difference() {
    let json = tmp("fix.json");
    let out = rsf().args(fit_args()).args(["--fix", "a-b=0.0005", "--json"]).arg(&json).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let (a, b) = (v["params"]["a"].as_f64().unwrap(), v["params"]["b"][0].as_f64().unwrap());
    assert!((a - b - 0.0005).abs() < 1e-12, "a − b = {}", a - b);
    assert_eq!(v["n_free"].as_u64(), Some(4));
}

#[test]
fn a_segments_file_overrides_detection() {
    let seg = tmp("segs.json");
    let out = rsf()
        .args([
            "segments",
            repo().join(BASALT).to_str().unwrap(),
            "--time-col",
            "Time(s)",
            "--lp-col",
            "Displ(microns)",
            "--mu-col",
            "Friction",
            "--json",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    std::fs::write(&seg, &out.stdout).unwrap();
    let json = tmp("segfit.json");
    let out = rsf().args(fit_args()).arg("--segments").arg(&seg).arg("--json").arg(&json).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["segments"].as_array().unwrap().len(), 2);
    // a broken file is named
    std::fs::write(&seg, r#"[{"t0": 11700, "t1": 11600, "v": 3}]"#).unwrap();
    let out = rsf().args(fit_args()).arg("--segments").arg(&seg).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("segment 1: needs t1 > t0"));
}

/// `rsf COMMAND` on the bundled basalt step with its columns and nominal stiffness.
fn on_basalt(command: &str) -> Command {
    let mut c = rsf();
    c.args([command, repo().join(BASALT).to_str().unwrap()]);
    c.args(["--time-col", "Time(s)", "--lp-col", "Displ(microns)", "--mu-col", "Friction", "--stiffness", "0.0151"]);
    c
}

#[test]
fn diagnose_writes_json_and_a_self_contained_report() {
    let (json, html) = (tmp("diag.json"), tmp("diag.html"));
    let out = on_basalt("diagnose").arg("--json").arg(&json).arg("--report").arg(&html).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let causes = ["none", "evolution_law", "second_state_variable", "cutoff_velocity", "slip_trend", "stiffness"];
    assert!(causes.contains(&v["cause"].as_str().unwrap()));
    assert_eq!(v["candidates"].as_array().unwrap().len(), 5);
    for key in ["delta_bic", "delta_aic", "rms_ratio", "heldout_rms_before", "heldout_rms_after"] {
        assert!(v["gain"][key].as_f64().is_some(), "gain.{key}");
    }
    assert!(v["baseline"]["params"]["a"].as_f64().is_some() && v["extended"]["params"]["a"].as_f64().is_some());
    let report = std::fs::read_to_string(&html).unwrap();
    assert!(report.starts_with("<!doctype html>") && report.contains("<svg") && !report.contains("src=\"http"));
}

fn design_basalt() -> Command {
    let mut c = on_basalt("design");
    c.args(["--threads", "2"]);
    c
}

#[test]
fn design_refuses_bad_constraints_before_any_work() {
    for (args, words) in [
        (vec!["--v-range", "300,0.001"], "needs 0 < LOW ≤ HIGH"),
        (vec!["--v-range", "0.001"], "expected LOW,HIGH"),
        (vec!["--v-range", "a,b"], "must be numbers"),
        (vec!["--max-time=-1"], "--max-time -1 must be positive"),
        (vec!["--max-hold", "nan"], "--max-hold NaN must be zero or positive"),
        (vec!["--max-sigma-change", "1.5"], "--max-sigma-change 1.5 must be a fraction"),
    ] {
        let out = design_basalt().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(words), "{args:?}: {err}");
        assert!(!err.contains("diagnosing"), "{args:?} refused only after the diagnosis: {err}");
    }
}

/// The basalt step: a slip trend, decisively, and no other model credible. The cause is
/// decided, its effect (g) is not measured yet: the design proposes the segment that best
/// measures it, with g's standard error now and expected after (before issue 41 it refused:
/// "one credible model … no next segment is needed").
#[test]
fn design_measures_the_effect_when_the_record_already_decides() {
    let json = tmp("design_basalt.json");
    let out = design_basalt().arg("--json").arg(&json).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("one credible model (slip_trend): the segment that best measures its effect"), "{text}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let top = &v["proposals"][0];
    let g = &top["effect"]["parameters"][0];
    assert_eq!(g["name"], "g");
    assert!(g["stderr_expected"].as_f64().unwrap() < g["stderr_now"].as_f64().unwrap(), "{g}");
    assert!(!v["standards"].as_array().unwrap().is_empty());
    // a protocol asked for where no proposal fits the constraints is an error, and nothing is
    // written
    let toml = tmp("design_basalt.toml");
    let out = design_basalt().args(["--max-time", "5"]).arg("--protocol").arg(&toml).output().unwrap();
    assert!(!out.status.success(), "{}", String::from_utf8_lossy(&out.stdout));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no proposal fits the constraints"));
    assert!(!toml.exists());
}

/// The bundled hidden cut-off (examples/data/design): a long hold is proposed, and the protocol,
/// figure and page are written; the protocol runs in `rsf simulate`.
#[test]
fn design_proposes_a_long_hold_for_a_hidden_cutoff_and_writes_its_outputs() {
    let (json, toml, svg, html, csv) =
        (tmp("hc.json"), tmp("hc.toml"), tmp("hc.svg"), tmp("hc.html"), tmp("hc_next.csv"));
    let out = rsf()
        .args(["design", repo().join("examples/data/design/hidden_cutoff.csv").to_str().unwrap()])
        .args(["--stiffness", "0.0026919553456917138", "--threads", "2", "--json"])
        .arg(&json)
        .arg("--protocol")
        .arg(&toml)
        .arg("--plot")
        .arg(&svg)
        .arg("--report")
        .arg(&html)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["cause"], "none");
    assert!(v["models"].as_array().unwrap().iter().any(|m| m["name"] == "cutoff_velocity"));
    let best = &v["proposals"][0];
    let holds: Vec<f64> = best["segments"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s[0].as_f64() == Some(0.0))
        .map(|s| s[1].as_f64().unwrap())
        .collect();
    assert!(holds.iter().any(|&h| h >= 3000.0), "{}", best["description"]);
    assert!(best["score"].as_f64().unwrap() > v["standard"]["score"].as_f64().unwrap());
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.starts_with("<!doctype html>") && page.contains("<svg") && !page.contains("src=\"http"));
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    let sim = rsf().arg("simulate").arg(&toml).arg("-o").arg(&csv).output().unwrap();
    assert!(sim.status.success(), "{}", String::from_utf8_lossy(&sim.stderr));
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
    assert!(rows > 1000, "{rows}");
}

/// `rsf design --from`: the diagnosis's JSON of the same record is designed from without
/// diagnosing again (here with normal-stress changes, whose protocol runs in `rsf simulate`);
/// the JSON of another record, a cut JSON and `--diagnosis-json` beside it are refused.
#[test]
fn design_from_a_diagnosis_json() {
    let hc = repo().join("examples/data/design/hidden_cutoff.csv");
    let k = ["--stiffness", "0.0026919553456917138", "--threads", "2"];
    let diag = tmp("hc_from_diag.json");
    let out = rsf().arg("diagnose").arg(&hc).args(k).arg("--json").arg(&diag).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (json, toml, csv) = (tmp("hc_from.json"), tmp("hc_from.toml"), tmp("hc_from_next.csv"));
    let out = rsf()
        .arg("design")
        .arg(&hc)
        .args(k)
        .args(["--max-sigma-change", "0.2", "--from"])
        .arg(&diag)
        .arg("--json")
        .arg(&json)
        .arg("--protocol")
        .arg(&toml)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("refitting the models") && !err.contains("diagnosing first"), "{err}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("[from "));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!(v["models"].as_array().unwrap().iter().any(|m| m["name"] == "cutoff_velocity"));
    assert!(v["models"].as_array().unwrap().iter().any(|m| m["name"] == "normal_stress_coupling"));
    let best = &v["proposals"][0];
    let ratios: Vec<f64> =
        best["normal_stress_ratio"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(ratios.iter().any(|&r| r != 1.0), "{}", best["description"]);
    let sim = rsf().arg("simulate").arg(&toml).arg("-o").arg(&csv).output().unwrap();
    assert!(sim.status.success(), "{}", String::from_utf8_lossy(&sim.stderr));
    // another record's diagnosis
    let basalt = tmp("basalt_diag_for_from.json");
    let out = on_basalt("diagnose").arg("--json").arg(&basalt).output().unwrap();
    assert!(out.status.success());
    let out = rsf()
        .arg("design")
        .arg(&hc)
        .args(["--stiffness", "0.0151", "--threads", "2", "--from"])
        .arg(&basalt)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("basalt_diag_for_from.json") && err.contains("not the record"),
        "{err}"
    );
    // the same record's diagnosis with another stiffness than it was made with
    let out = rsf().arg("design").arg(&hc).args(["--stiffness", "0.003", "--from"]).arg(&diag).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("give the stiffness it was made with"), "{err}");
    // a cut file, named with its line and column
    let cut = tmp("hc_from_cut.json");
    let text = std::fs::read_to_string(&diag).unwrap();
    std::fs::write(&cut, &text[..text.len() / 3]).unwrap();
    let out = rsf().arg("design").arg(&hc).args(k).arg("--from").arg(&cut).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("line ") && err.contains("column "), "{err}");
    // --diagnosis-json writes the diagnosis the design runs: with --from there is none
    let mut both = rsf();
    both.arg("design").arg(&hc).args(k).arg("--from").arg(&diag).arg("--diagnosis-json").arg(tmp("x.json"));
    let out = both.output().unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("cannot be used with"));
}
