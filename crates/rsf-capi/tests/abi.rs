//! The C ABI from C and Fortran: the examples in `examples/` are compiled against the static
//! library and run (gcc and gfortran from the system packages; `.ci/run` installs gfortran if
//! missing), and the committed header is checked against cbindgen's output when cbindgen is
//! installed. The C host integrates the BP1-like spring-slider (regularized friction, aging law,
//! radiation damping, k = k_c/2) with its own RK4 through the kernels; its recurrence interval
//! is compared with an independent integration by rsf's own solver (`rsf_solvers::Auto` on the
//! spring-slider model in µm units, started off steady state by `Problem::initial_theta`).

use rsf_core::{FrictionForm, Loading, Model, Segment, StateVariable};
use rsf_laws::Aging;
use rsf_solvers::{Auto, OutputTimes, Problem, solve};
use std::process::Command;

const YEAR: f64 = 3.1536e7;

mod common;
use common::{crate_dir, static_lib};

fn have(tool: &str) -> bool {
    Command::new(tool).arg("--version").output().is_ok_and(|o| o.status.success())
}

fn compile_and_run(compiler: &str, source: &str, out: &str) -> String {
    let lib = static_lib();
    let exe = std::env::temp_dir().join(out);
    let src = crate_dir().join("examples").join(source);
    let mut cmd = Command::new(compiler);
    if compiler == "gfortran" {
        // the module include/rsf.f90 first; its compiled module file goes to the temporary
        // directory, not the source tree
        let tmp = std::env::temp_dir();
        cmd.arg("-J").arg(&tmp).arg(format!("-I{}", tmp.display())).arg(crate_dir().join("include/rsf.f90"));
    }
    let status = cmd
        .arg(&src)
        .arg(format!("-I{}", crate_dir().join("include").display()))
        .arg("-o")
        .arg(&exe)
        .arg(&lib)
        .args(["-lpthread", "-ldl", "-lm"])
        .status()
        .unwrap();
    assert!(status.success(), "{compiler} failed on {}", src.display());
    let o = Command::new(&exe).output().unwrap();
    assert!(
        o.status.success(),
        "{out} failed:\n{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn value(text: &str, key: &str) -> f64 {
    let line = text.lines().find(|l| l.starts_with(key)).unwrap_or_else(|| panic!("no `{key}` in\n{text}"));
    line[key.len()..].split_whitespace().next().unwrap().parse().unwrap()
}

/// The same spring-slider by rsf's own solver: onset of the first event, interval between the
/// second and third onsets (years), peak slip rate (m/s).
fn independent() -> (f64, f64, f64) {
    let sigma = 50e6;
    // SI → µm, s, friction units: k and η per σ, lengths × 1e6
    let k = 0.5 * sigma * (0.015 - 0.010) / 0.008 / sigma * 1e-6;
    let eta = 2670.0 * 3464.0 / 2.0 / sigma * 1e-6;
    let model = Model { form: FrictionForm::Regularized, ..Model::new(0.6, 1.0, 0.010, k) }
        .with_eta(eta)
        .with_state(StateVariable::new(Aging, 0.015, 8000.0));
    let mut p = Problem::new(model, Loading::Segments(vec![Segment::for_duration(1e-3, 60.0 * YEAR)]), 0.9e-3, 2000.0);
    p.initial_theta = Some(vec![8000.0 / 1e-3]);
    let alg = Auto::new(1e-10, 1e-9);
    // events last seconds: a 2000 s grid finds them by their slip (0.45 m each), a second solve
    // samples those intervals every 0.05 s
    let coarse = solve(&p, &alg).unwrap();
    let mut times = coarse.time.clone();
    for i in 1..coarse.len() {
        if coarse.slip[i] - coarse.slip[i - 1] > 1e5 {
            let (a, b) = (coarse.time[i - 1], coarse.time[i]);
            times.extend((1..((b - a) / 0.05) as usize).map(|k| a + 0.05 * k as f64));
        }
    }
    times.sort_by(f64::total_cmp);
    times.dedup();
    p.output = OutputTimes::Times(times);
    let sol = solve(&p, &alg).unwrap();
    let mut onsets = vec![];
    let mut seismic = false;
    for i in 1..sol.len() {
        let (v0, v1) = (sol.slip_rate[i - 1], sol.slip_rate[i]);
        if !seismic && v1 >= 1e3 {
            // interpolated in ln V between samples
            let w = ((1e3f64).ln() - v0.ln()) / (v1.ln() - v0.ln());
            onsets.push(sol.time[i - 1] + w * (sol.time[i] - sol.time[i - 1]));
            seismic = true;
        } else if seismic && v1 < 1e3 {
            seismic = false;
        }
    }
    let peak = sol.slip_rate.iter().cloned().fold(0.0, f64::max) * 1e-6;
    (onsets[0] / YEAR, (onsets[2] - onsets[1]) / YEAR, peak)
}

#[test]
fn c_host_reproduces_an_independent_integration() {
    if !have("gcc") {
        println!("SKIP: gcc not installed (.ci/run installs it); the C example was not run");
        return;
    }
    let out = compile_and_run("gcc", "c/spring_slider.c", "rsf_capi_spring_slider");
    println!("{out}");
    let (onset, interval, peak) = (value(&out, "onset"), value(&out, "interval"), value(&out, "peak"));
    let (onset_r, interval_r, peak_r) = independent();
    println!("independent: onset {onset_r:.4} yr, interval {interval_r:.4} yr, peak {peak_r:.4} m/s");
    assert!((onset - onset_r).abs() < 2e-3, "onset {onset} vs {onset_r}");
    assert!((interval / interval_r - 1.0).abs() < 2e-4, "interval {interval} vs {interval_r}");
    assert!((peak / peak_r - 1.0).abs() < 0.01, "peak {peak} vs {peak_r}");
    // the notes' anchors: T = 14.1784 yr (QDYN, years of 365 days) and 14.1687 yr (scipy and
    // rsf): the same period, 4.4713e8 s, in years of 365 and 365.25 days
    assert!((interval_r - 14.1784).abs() < 0.002, "independent interval {interval_r}");
    assert!((interval_r * YEAR / (365.25 * 86400.0) - 14.1687).abs() < 0.002);
    assert!(out.contains("unknown law -> 2: unknown law id 42"), "{out}");
    assert!(out.contains("negative stress -> 3: "), "{out}");
}

/// Each refusal that rsf.h promises, from C: non-finite and out-of-range inputs to every entry
/// point give RSF_BAD_INPUT with a message naming the input (and the element of a batch).
#[test]
fn c_host_sees_every_bad_input_refused() {
    if !have("gcc") {
        println!("SKIP: gcc not installed (.ci/run installs it); the C refusals were not run");
        return;
    }
    let out = compile_and_run("gcc", "c/refusals.c", "rsf_capi_refusals");
    println!("{out}");
    assert!(out.contains("refused 27 accepted 0"), "{out}");
    assert!(!out.contains("ACCEPTED"), "{out}");
    for (call, says) in [
        ("psi v0=nan ->", "rsf_psi: v0 = NaN is not finite"),
        ("psi v0=-1 ->", "v0 = -1 must be positive"),
        ("psi v0=0 ->", "v0 = 0 must be positive"),
        ("psi ln_theta=inf ->", "ln_theta = inf is not finite"),
        ("batch_rates ln_v[2]=nan ->", "element 2: rsf_batch_rates: ln_v = NaN is not finite"),
        ("batch_rates ln_theta[2]=inf ->", "element 2: rsf_batch_rates: ln_theta = inf"),
        ("batch_rates version[2] ->", "element 2: RsfStateParams.version 99"),
        ("batch_solve sigma[2]=nan ->", "element 2: rsf_batch_solve_slip_rate: sigma = NaN"),
        ("batch_solve ln_v[3]=nan ->", "element 3:"),
        ("friction null output ->", "rsf_friction: f is null"),
        ("state_term cutoff vc=0 ->", "needs each state's vc = V2 > 0 (got 0)"),
        ("state_term cutoff kato-tullis ->", "a Kato-Tullis state"),
        ("solve cutoff ->", "rsf_solve_slip_rate: the cut-off form (2) has no slip-rate solve"),
        ("state_term ln_theta=nan ->", "rsf_state_term: ln_theta = NaN is not finite"),
        ("batch_partials cutoff vc[1]=0 ->", "element 1: the cut-off form needs each state's vc = V2 > 0"),
        ("batch_partials ln_v[3]=nan ->", "element 3: rsf_batch_partials: ln_v = NaN"),
    ] {
        let line = out.lines().find(|l| l.starts_with(call)).unwrap_or_else(|| panic!("no `{call}` in\n{out}"));
        assert!(line.contains(" -> 1: ") && line.contains(says), "{line}");
    }
    assert!(out.contains("good batch -> 0"), "{out}");
    assert!(out.contains("good cutoff batch -> 0"), "{out}");
}

#[test]
fn fortran_host_through_iso_c_binding() {
    if !have("gfortran") {
        println!("SKIP: gfortran not installed (.ci/run installs it); the Fortran example was not run");
        return;
    }
    let out = compile_and_run("gfortran", "fortran/element.f90", "rsf_capi_element_f90");
    println!("{out}");
    assert!(value(&out, "friction error") < 1e-14, "{out}");
    assert!(value(&out, "rate at steady state") < 1e-12, "{out}");
    assert!(value(&out, "solve error") < 1e-10, "{out}");
    assert!(out.contains("batch status 0"), "{out}");
    // the cut-off form (QDYN's law 1) against its closed form, written in the host
    assert!(value(&out, "cutoff friction error") < 1e-15, "{out}");
    assert!(value(&out, "cutoff dmu/dV error") < 1e-13, "{out}");
    assert!(value(&out, "cutoff dmu/dtheta error") < 1e-13, "{out}");
    assert!(value(&out, "slip rate error") < 1e-13, "{out}");
    assert!(value(&out, "batch partials error") == 0.0, "{out}");
    let refused = out.lines().find(|l| l.starts_with("cutoff with kato-tullis")).unwrap();
    assert!(refused.contains("-> 1: element 2:") && refused.contains("Kato-Tullis"), "{refused}");
    // a mesh (an element at V < 0 continued as QDYN's own formulas, one without healing)
    assert!(value(&out, "mesh partials error") < 1e-15, "{out}");
    assert!(value(&out, "mesh rate error") < 1e-15, "{out}");
}

/// A host with a mesh: the fault's parameters checked once, partials and rates in V and θ
/// equal to the host's own closed forms, and V < 0 refused or continued by the policy.
#[test]
fn c_host_with_a_mesh() {
    if !have("gcc") {
        println!("SKIP: gcc not installed; the C example was not run");
        return;
    }
    let out = compile_and_run("gcc", "c/mesh.c", "rsf_capi_mesh");
    println!("{out}");
    assert!(out.contains("mesh: ok"), "{out}");
    assert!(value(&out, "largest relative difference from the host's closed forms:") < 1e-13, "{out}");
    assert!(out.contains("refuse at V < 0: 1: element 5:"), "{out}");
}

#[test]
fn committed_header_is_what_cbindgen_makes() {
    if !have("cbindgen") {
        println!("SKIP: cbindgen not installed (cargo install cbindgen); the header was not regenerated");
        return;
    }
    let tmp = std::env::temp_dir().join("rsf_capi_header.h");
    let root = crate_dir().join("../..");
    let status = Command::new("cbindgen")
        .current_dir(&root)
        .args(["--config", "crates/rsf-capi/cbindgen.toml", "--crate", "rsf-capi", "--quiet", "--output"])
        .arg(&tmp)
        .status()
        .unwrap();
    assert!(status.success());
    let fresh = std::fs::read_to_string(&tmp).unwrap();
    let committed = std::fs::read_to_string(crate_dir().join("include/rsf.h")).unwrap();
    assert!(fresh == committed, "include/rsf.h is stale: regenerate it with the command in cbindgen.toml");
}

/// The C enum and the law registry's ids are one numbering.
#[test]
fn c_law_ids_are_the_registry_ids() {
    for &law in rsf_laws::Law::ALL {
        if let Some(c) = rsf_capi::RsfLaw::of(law) {
            assert_eq!(c as i32, law.c_id(), "{law}");
        }
    }
}
