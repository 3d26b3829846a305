//! Protocol files with errors are rejected with a message naming the field and line.

use rsf_solvers::protocol::parse;

const GOOD: &str = r#"[model]
mu0 = 0.65
v0 = 1.0
a = 0.013
stiffness = 0.065

[[model.state]]
law = "slip"
b = 0.016
dc = 2.07

[loading]
v_init = 3.0

[[loading.segment]]
v = 0.003
duration = 500.0

[output]
dt = 0.02

[solver]
method = "implicit"
rtol = 1e-9
atol = 1e-12
"#;

/// Replaces `from` (which must occur once) and expects an error whose text contains all `needles`.
fn bad(from: &str, to: &str, needles: &[&str]) {
    assert_eq!(GOOD.matches(from).count(), 1, "fixture: `{from}`");
    let text = GOOD.replace(from, to);
    let e = parse(&text, None, "p.toml").err().unwrap_or_else(|| panic!("`{to}` was accepted"));
    let msg = e.to_string();
    for n in needles {
        assert!(msg.contains(n), "message `{msg}` lacks `{n}`");
    }
}

#[test]
fn the_schema_example_parses_and_solves() {
    let p = parse(GOOD, None, "p.toml").unwrap();
    let sol = p.method.solve(&p.problem).unwrap();
    assert_eq!(sol.len(), 25001);
    assert_eq!(sol.time[0], 0.0);
    assert_eq!(*sol.time.last().unwrap(), 500.0);
}

#[test]
fn errors_name_field_and_line() {
    bad(
        "law = \"slip\"",
        "law = \"dieterich\"",
        &["p.toml:8", "model.state[1].law", "unknown law `dieterich`", "aging"],
    );
    bad("dc = 2.07", "dc = -2.07", &["p.toml:10", "model.state[1].dc", "positive"]);
    bad("stiffness = 0.065", "stiffness = -0.065", &["p.toml:5", "model.stiffness", "positive"]);
    bad("a = 0.013", "a = nan", &["p.toml:4", "model.a"]);
    bad("dc = 2.07\n", "", &["p.toml", "missing field `dc`"]);
    bad("duration = 500.0", "duration = 500.0\ndisplacement = 3.0", &["p.toml:18", "loading.segment[1]", "not both"]);
    bad("v = 0.003\nduration = 500.0", "v = 0.0\ndisplacement = 3.0", &["p.toml:15", "loading.segment[1]", "hold"]);
    bad("v = 0.003\nduration = 500.0", "v = 0.003", &["p.toml:15", "loading.segment[1]", "duration"]);
    bad("duration = 500.0", "duration = -1.0", &["p.toml:15", "duration"]);
    bad("b = 0.016", "b = 0.016\nvc = 1e-3", &["p.toml:10", "model.state[1].vc", "does not apply"]);
    bad("law = \"slip\"", "law = \"kato-tullis\"", &["p.toml:8", "needs parameter `vc`"]);
    bad("law = \"slip\"", "law = \"kato-tullis\"\nvc = -1.0", &["p.toml:9", "model.state[1].vc", "outside its range"]);
    // a law's own parameter that the built-in list never had: the registry names the law's
    bad("b = 0.016", "b = 0.016\nn = 1.5", &["p.toml:10", "model.state[1].n", "does not apply to law `slip`"]);
    bad(
        "law = \"slip\"\nb = 0.016",
        "law = \"nagata\"\nc = 2.0\nb = 0.0",
        &["p.toml:10", "model.state[1].b", "divides by b"],
    );
    bad("method = \"implicit\"", "method = \"rk4\"", &["p.toml:23", "solver.method", "rk4"]);
    bad("rtol = 1e-9", "rtol = 2.0", &["p.toml:24", "solver.rtol"]);
    bad("dt = 0.02", "dt = 0.0", &["p.toml:20", "output.dt"]);
    bad("v_init = 3.0", "v_init = 0.0", &["p.toml:13", "loading.v_init"]);
    bad("mu0 = 0.65", "mu0 = 0.65\nmuu = 1", &["p.toml:3", "unknown field `muu`"]);
    bad("[output]\ndt = 0.02\n", "", &["output.dt", "required"]);
    bad("v = 0.003\nduration = 500.0", "v = 0.003\nduration = 500.0\n[loading.x]", &["p.toml"]);
    bad(
        "[[loading.segment]]\nv = 0.003\nduration = 500.0\n",
        "record = \"/nonexistent/run.csv\"\n",
        &["loading.record", "cannot read"],
    );
    bad("mu0 = 0.65", "mu0 = \"high\"", &["p.toml:2", "invalid type"]);
}

#[test]
fn record_errors_name_line_and_column() {
    let dir = std::env::temp_dir().join(format!("rsf-proto-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let proto = GOOD.replace("[[loading.segment]]\nv = 0.003\nduration = 500.0\n", "record = \"run.csv\"\n");
    for (csv, needles) in [
        ("time_s,load_point_um\n0,0\n1,x\n", vec!["run.csv:3", "`load_point_um`", "`x` is not a number"]),
        ("time_s,load_point_um\n0,0\n0,1\n", vec!["run.csv:3", "repeats the previous row's"]),
        ("time_s,load_point_um\n1,0\n0,1\n", vec!["run.csv:3", "does not increase"]),
        ("time_s,lp\n0,0\n1,1\n", vec!["column `load_point_um`: no such column"]),
        ("time_s,load_point_um\n0,0\n1,nan\n", vec!["run.csv:3", "not finite"]),
        ("time_s,load_point_um\n0,0\n", vec!["1 data rows; at least 2"]),
    ] {
        std::fs::write(dir.join("run.csv"), csv).unwrap();
        let e = parse(&proto, Some(&dir), "p.toml").unwrap_err().to_string();
        for n in needles {
            assert!(e.contains(n), "`{e}` lacks `{n}`");
        }
    }
    // a good record, with a comment line, drives the model; output at the record's times
    std::fs::write(dir.join("run.csv"), "# lab run\ntime_s,load_point_um\n10,0\n20,30\n30,30\n40,31\n").unwrap();
    let p = parse(&proto.replace("[output]\ndt = 0.02\n", ""), Some(&dir), "p.toml").unwrap();
    let sol = p.method.solve(&p.problem).unwrap();
    assert_eq!(sol.time, vec![10.0, 20.0, 30.0, 40.0]);
    assert_eq!(sol.load_point, vec![0.0, 30.0, 30.0, 31.0]);
    assert!(sol.slip_rate[2] < 0.1, "the hold between 20 and 30 s relaxes V");
}

/// `[initial]` starts off steady state: at t = 0 the slip rate and θ are the given ones, and a
/// bad table names its field.
#[test]
fn an_initial_state_off_steady_state() {
    let text = format!("{GOOD}\n[initial]\nv = 0.5\ntheta = [10.0]\n");
    let p = parse(&text, None, "p.toml").unwrap();
    let sol = p.method.solve(&p.problem).unwrap();
    assert!(
        (sol.slip_rate[0] - 0.5).abs() < 1e-12 && (sol.theta[0][0] - 10.0).abs() < 1e-9,
        "{} {}",
        sol.slip_rate[0],
        sol.theta[0][0]
    );
    // steady state at 3 µm/s would have θ = Dc/V = 0.69 s
    let steady =
        parse(GOOD, None, "p.toml").unwrap().method.solve(&parse(GOOD, None, "p.toml").unwrap().problem).unwrap();
    assert!((steady.theta[0][0] - 2.07 / 3.0).abs() < 1e-9);
    for (tail, needle) in [
        ("[initial]\nv = 0.5\ntheta = [10.0, 3.0]\n", "initial.theta"),
        ("[initial]\nv = -1\ntheta = [10.0]\n", "initial.v"),
    ] {
        let Err(e) = parse(&format!("{GOOD}\n{tail}"), None, "p.toml") else { panic!("`{tail}` was accepted") };
        let e = e.to_string();
        assert!(e.contains(needle), "{e}");
    }
}

/// A table built in memory (the Python objects' path, `from_table`) is checked by the same rules
/// as the text: every bad case of `errors_name_field_and_line` that is expressible as values
/// gives the same field and message, without a line; the good table solves to the same result.
#[test]
fn tables_in_memory_are_checked_by_the_same_rules() {
    use rsf_solvers::protocol::from_table;
    let table = |text: &str| -> toml::Table { toml::from_str(text).unwrap() };
    let a = parse(GOOD, None, "p.toml").unwrap();
    let b = from_table(table(GOOD), None, "objects").unwrap();
    let (sa, sb) = (a.method.solve(&a.problem).unwrap(), b.method.solve(&b.problem).unwrap());
    assert_eq!(sa.mu, sb.mu);
    for (from, to, field, what) in [
        ("law = \"slip\"", "law = \"dieterich\"", "model.state[1].law", "unknown law `dieterich`"),
        ("dc = 2.07", "dc = -2.07", "model.state[1].dc", "positive"),
        ("stiffness = 0.065", "stiffness = -0.065", "model.stiffness", "positive"),
        ("duration = 500.0", "duration = 500.0\ndisplacement = 3.0", "loading.segment[1]", "not both"),
        ("b = 0.016", "b = 0.016\nvc = 1e-3", "model.state[1].vc", "does not apply"),
        ("method = \"implicit\"", "method = \"rk4\"", "solver.method", "rk4"),
        ("dt = 0.02", "dt = 0.0", "output.dt", "positive"),
        ("mu0 = 0.65", "mu0 = 0.65\nmuu = 1", "", "unknown field `muu`"),
    ] {
        let text = GOOD.replace(from, to);
        let from_text = parse(&text, None, "p.toml").unwrap_err();
        let e = from_table(table(&text), None, "objects").unwrap_err();
        assert_eq!(e.line, None, "{e}");
        assert_eq!(e.field, from_text.field, "{e}");
        assert_eq!(e.message, from_text.message, "{e}");
        assert!(e.to_string().starts_with("objects: ") && e.to_string().contains(what), "{e}");
        if !field.is_empty() {
            assert!(e.to_string().contains(field), "{e}");
        }
    }
}

/// A protocol that registers a law file uses the law like a built-in one: at n = 1 power-law
/// aging is the Aging law, so the two protocols give the same friction.
#[test]
fn a_law_file_in_a_protocol_is_used_like_a_built_in_law() {
    let examples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let text = std::fs::read_to_string(examples.join("power_aging_steps.toml")).unwrap();
    let power = parse(&text.replace("n = 1.5", "n = 1.0"), Some(&examples), "power.toml").unwrap();
    let aging = parse(
        &text
            .replace("law = \"power-aging\"\nn = 1.5", "law = \"aging\"")
            .replace("law_files = [\"laws/power_aging.toml\"]", ""),
        Some(&examples),
        "aging.toml",
    )
    .unwrap();
    let (p, a) = (power.method.solve(&power.problem).unwrap(), aging.method.solve(&aging.problem).unwrap());
    assert_eq!(p.len(), a.len());
    let worst = p.mu.iter().zip(&a.mu).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-8, "power-aging at n = 1 differs from aging by {worst:e}");
    // and n = 1.5 heals differently over the hold
    let p15 = parse(&text, Some(&examples), "power.toml").unwrap();
    let s15 = p15.method.solve(&p15.problem).unwrap();
    let d = s15.mu.iter().zip(&a.mu).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(d > 1e-4, "n = 1.5 should differ from Aging (max difference {d:e})");
    // a missing file names itself
    let e = parse(&text.replace("laws/power_aging.toml", "laws/none.toml"), Some(&examples), "p.toml").unwrap_err();
    assert!(e.to_string().contains("none.toml") && e.to_string().contains("law_files"), "{e}");
}

/// A law that runs away on a reslide is reported with what the solver saw (the piece, the
/// load-point change, the last accepted θ and its law), and no normal-stress change is guessed
/// where σ never changed.
#[test]
fn a_run_away_names_the_piece_the_states_and_what_the_protocol_did() {
    let examples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let text = std::fs::read_to_string(examples.join("power_aging_steps.toml"))
        .unwrap()
        .replace("stiffness = 0.02 ", "stiffness = 0.005")
        .replace("duration = 100.0", "duration = 1000.0");
    let p = parse(&text, Some(&examples), "p.toml").unwrap();
    let e = p.method.solve(&p.problem).unwrap_err();
    let rsf_solvers::SolveError::BlowUp { at, .. } = &e else { panic!("expected a run-away, got {e}") };
    assert_eq!(at.piece, 5, "{e}");
    let msg = e.to_string();
    for needle in ["in piece 5", "restarted at 1 µm/s after a hold", "θ1 = ", "(power-aging)"] {
        assert!(msg.contains(needle), "`{msg}` lacks `{needle}`");
    }
    assert!(!msg.contains("normal stress") && !msg.contains("normal-stress"), "{msg}");
}

/// `a_slope` in `[model]` makes the direct effect rate dependent, ∂f/∂ln V = a + a₁ ln(V/V0):
/// after a step to 10 µm/s (a hundred Dc of slip) friction is at the bent steady state
/// μ0 + (a − b) X + ½ a₁ X², X = ln(V/V0), which is not the straight one; with radiation damping
/// it is refused, naming the field.
#[test]
fn a_rate_dependent_direct_effect_bends_the_steady_state() {
    let text = |a_slope: &str, eta: &str| {
        format!(
            "[model]\nmu0 = 0.65\nv0 = 1.0\na = 0.013\nstiffness = 0.065\n{a_slope}{eta}\n\
             [[model.state]]\nlaw = \"slip\"\nb = 0.016\ndc = 2.07\n\n\
             [loading]\nv_init = 1.0\n\n[[loading.segment]]\nv = 10.0\nduration = 30.0\n\n\
             [output]\ndt = 0.1\n\n[solver]\nrtol = 1e-10\natol = 1e-12\n"
        )
    };
    let last_mu = |t: &str| {
        let p = parse(t, None, "p.toml").unwrap();
        *p.method.solve(&p.problem).unwrap().mu.last().unwrap()
    };
    let x = 10f64.ln();
    let straight = last_mu(&text("", ""));
    let bent = last_mu(&text("a_slope = 0.002\n", ""));
    assert!((straight - (0.65 + (0.013 - 0.016) * x)).abs() < 1e-8, "{straight}");
    assert!((bent - (0.65 + (0.013 - 0.016) * x + 0.5 * 0.002 * x * x)).abs() < 1e-8, "{bent}");
    let Err(e) = parse(&text("a_slope = 0.002\n", "eta = 1e-3\n"), None, "p.toml") else {
        panic!("a_slope with radiation damping was accepted")
    };
    let e = e.to_string();
    assert!(e.contains("a_slope") && e.contains("radiation damping"), "{e}");
}
