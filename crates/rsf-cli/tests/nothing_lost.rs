//! Nothing lost, nothing invented: the `rsf` binary on the ways a lab's only copy of a record
//! could be destroyed, and on broken records that must never give a confident number. Each
//! test is one defect of issue 20 (its number in the test's name).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BASALT: &str = "examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt";
const COLS: [&str; 6] = ["--time-col", "Time(s)", "--lp-col", "Displ(microns)", "--mu-col", "Friction"];

fn rsf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rsf"))
}
fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}
fn basalt() -> String {
    std::fs::read_to_string(repo().join(BASALT)).unwrap()
}
fn run(args: &[&str]) -> Output {
    rsf().args(args).output().unwrap()
}
fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}
fn fit(record: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["fit", s(record)];
    args.extend(COLS);
    args.extend(["--law", "slip", "--stiffness", "0.0151", "--loading", "protocol", "--starts", "1"]);
    args.extend(extra);
    run(&args)
}
fn segments(record: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["segments", s(record)];
    args.extend(COLS);
    args.extend(extra);
    run(&args)
}
fn params(json: &Path) -> serde_json::Value {
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    v["params"].clone()
}

#[test]
fn d1_an_output_that_is_an_input_is_refused_before_any_work() {
    let d = tempfile::tempdir().unwrap();
    let rec = d.path().join("rec.txt");
    std::fs::write(&rec, basalt()).unwrap();
    let other = d.path().join("out.json");
    let sub = d.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    // the same file spelled through another folder
    let spelled = sub.join("..").join("rec.txt");
    for (opt, target) in [("--json", &rec), ("--plot", &rec), ("--json", &spelled)] {
        let o = fit(&rec, &[opt, s(target)]);
        let e = stderr(&o);
        assert!(!o.status.success() && e.contains(&format!("the {opt} output")) && e.contains("is the record"), "{e}");
    }
    let o = fit(&rec, &["--json", s(&other), "--plot", s(&other)]);
    assert!(!o.status.success() && stderr(&o).contains("are one file"), "{}", stderr(&o));
    assert!(!other.exists());
    let mut args = vec!["diagnose", s(&rec), "--stiffness", "0.0151", "--report", s(&rec)];
    args.extend(COLS);
    let o = run(&args);
    assert!(!o.status.success() && stderr(&o).contains("--report output"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&rec).unwrap(), basalt(), "the record is intact");

    // simulate: -o onto the protocol, onto the record the protocol reads, and -o X --plot X
    let csv = d.path().join("lp.csv");
    std::fs::write(&csv, "time_s,load_point_um\n0,0\n10,30\n20,60\n").unwrap();
    let toml = d.path().join("p.toml");
    let protocol = "[model]\nmu0 = 0.6\nv0 = 1.0\na = 0.01\nstiffness = 0.1\n[[model.state]]\nlaw = \"slip\"\nb = 0.012\ndc = 5.0\n\
                    [loading]\nv_init = 3.0\nrecord = \"lp.csv\"\n";
    std::fs::write(&toml, protocol).unwrap();
    let out = d.path().join("o.csv");
    for args in [
        vec!["simulate", s(&toml), "-o", s(&toml)],
        vec!["simulate", s(&toml), "-o", s(&csv)],
        vec!["simulate", s(&toml), "-o", s(&out), "--plot", s(&out)],
    ] {
        let o = run(&args);
        assert!(!o.status.success(), "{args:?} succeeded");
    }
    assert_eq!(std::fs::read_to_string(&toml).unwrap(), protocol);
    assert!(std::fs::read_to_string(&csv).unwrap().starts_with("time_s,load_point_um\n0,0"));
    assert!(!out.exists());
}

/// A run killed while it writes leaves the old output or the new one, never a mix; no
/// temporary file is left beside it once a later run completes.
#[test]
fn d2_a_killed_run_leaves_the_old_or_the_new_file() {
    let d = tempfile::tempdir().unwrap();
    let toml = |dt: f64| {
        format!(
            "[model]\nmu0 = 0.65\nv0 = 1.0\na = 0.013\nstiffness = 0.065\n[[model.state]]\nlaw = \"slip\"\nb = 0.016\n\
             dc = 2.07\n[loading]\nv_init = 3.0\n[[loading.segment]]\nv = 3.0\ndisplacement = 10.0\n\
             [[loading.segment]]\nv = 0.003\nduration = 500.0\n[output]\ndt = {dt}\n"
        )
    };
    let (old_p, new_p) = (d.path().join("old.toml"), d.path().join("new.toml"));
    std::fs::write(&old_p, toml(0.0004)).unwrap();
    std::fs::write(&new_p, toml(0.001)).unwrap();
    let (old_csv, new_csv, out) = (d.path().join("old.csv"), d.path().join("new.csv"), d.path().join("out.csv"));
    assert!(run(&["simulate", s(&old_p), "-o", s(&old_csv)]).status.success());
    let started = std::time::Instant::now();
    assert!(run(&["simulate", s(&new_p), "-o", s(&new_csv)]).status.success());
    let full = started.elapsed().as_secs_f64();
    let (old, new) = (std::fs::read(&old_csv).unwrap(), std::fs::read(&new_csv).unwrap());
    assert!(old.len() > new.len() && new.len() > 10_000_000);
    let mut outcomes = (0, 0);
    for k in 0..10 {
        std::fs::copy(&old_csv, &out).unwrap();
        let mut child =
            rsf().args(["simulate", s(&new_p), "-o", s(&out)]).stderr(std::process::Stdio::null()).spawn().unwrap();
        std::thread::sleep(std::time::Duration::from_secs_f64(full * (0.3 + 0.08 * k as f64)));
        let _ = child.kill();
        child.wait().unwrap();
        let now = std::fs::read(&out).unwrap();
        assert!(now == old || now == new, "attempt {k}: a mix of two runs ({} bytes)", now.len());
        if now == old { outcomes.0 += 1 } else { outcomes.1 += 1 }
    }
    println!("killed runs: {} left the old file, {} the new", outcomes.0, outcomes.1);
    // the killed runs' temporary files are named as such; none is an output
    for e in std::fs::read_dir(d.path()).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with('.') || name.ends_with(".rsf-partial"), "{name}");
    }
}

/// A record cut in the middle of its last row: the row is dropped with a warning and the fit
/// equals the fit of the record without that row.
#[test]
fn d3_a_record_cut_mid_row_is_not_used() {
    let d = tempfile::tempdir().unwrap();
    let text = basalt();
    let (cut, whole) = (d.path().join("cut.txt"), d.path().join("whole.txt"));
    // the last row `…\t0.608734\t19.974…` cut to `…\t0`
    let last = text.trim_end().rfind('\n').unwrap() + 1;
    let friction_at = last + text[last..].match_indices('\t').nth(1).unwrap().0 + 1;
    std::fs::write(&cut, &text[..friction_at + 1]).unwrap();
    std::fs::write(&whole, &text[..last]).unwrap();
    let (jc, jw) = (d.path().join("c.json"), d.path().join("w.json"));
    let o = fit(&cut, &["--json", s(&jc)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("taken for a cut line and dropped"), "{}", stderr(&o));
    assert!(fit(&whole, &["--json", s(&jw)]).status.success());
    assert_eq!(params(&jc), params(&jw));
}

/// One over-range friction cell: an error naming line and column, or with --drop-invalid the
/// row dropped and counted — never the starting guess as a "result".
#[test]
fn d4_an_over_range_cell_is_refused_or_dropped() {
    let d = tempfile::tempdir().unwrap();
    let text = basalt();
    let line: Vec<&str> = text.lines().collect();
    for bad in ["9.9e37", "1e300", "-999999"] {
        let mut rows: Vec<String> = line.iter().map(|l| l.to_string()).collect();
        let mut cells: Vec<&str> = line[500].split('\t').collect();
        cells[2] = bad;
        rows[500] = cells.join("\t");
        let p = d.path().join("over.txt");
        std::fs::write(&p, rows.join("\n") + "\n").unwrap();
        let o = fit(&p, &[]);
        let e = stderr(&o);
        assert!(!o.status.success(), "{bad}: exit 0");
        assert!(e.contains("over.txt:501: column `Friction`:") && e.contains(bad.trim_start_matches('-')), "{e}");
        let j = d.path().join("f.json");
        let o = fit(&p, &["--drop-invalid", "--json", s(&j)]);
        assert!(
            o.status.success() && stderr(&o).contains("dropped 1 rows with an invalid value (lines 501)"),
            "{}",
            stderr(&o)
        );
        assert!(params(&j)["a"].as_f64().unwrap() > 0.005);
    }
}

/// Data rows ending in a delimiter that the header lacks: read as they are (a trailing empty
/// field), not shifted; on some rows only, an error naming the line.
#[test]
fn d5_ragged_rows_never_shift_columns() {
    let d = tempfile::tempdir().unwrap();
    let text = basalt();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let trailing: String = std::iter::once(format!("{header}\n")).chain(lines.map(|l| format!("{l}\t\n"))).collect();
    let p = d.path().join("trailing.txt");
    std::fs::write(&p, &trailing).unwrap();
    let (a, b) = (segments(&repo().join(BASALT), &["--json"]), segments(&p, &["--json"]));
    assert!(b.status.success(), "{}", stderr(&b));
    assert_eq!(a.stdout, b.stdout, "the same protocol");
    let some: String =
        text.lines().enumerate().map(|(i, l)| if i == 300 { format!("{l}\t\n") } else { format!("{l}\n") }).collect();
    std::fs::write(&p, some).unwrap();
    let o = segments(&p, &[]);
    assert!(
        !o.status.success()
            && stderr(&o).contains("trailing.txt:301: 5 fields where the header and the rows before have 4"),
        "{}",
        stderr(&o)
    );
}

/// A Latin-1 header, UTF-16 and old-Mac line ends are read (and named), not "no header".
#[test]
fn d6_encodings_and_line_ends_are_read() {
    let d = tempfile::tempdir().unwrap();
    let text = basalt().replacen("Displ(microns)", "Displ(µm)", 1);
    let want = segments(&repo().join(BASALT), &["--json"]).stdout;
    let latin: Vec<u8> = text.chars().map(|c| if c == 'µ' { 0xB5 } else { c as u8 }).collect();
    let utf16: Vec<u8> = [0xFF, 0xFE].into_iter().chain(text.encode_utf16().flat_map(u16::to_le_bytes)).collect();
    let cr = text.replace('\n', "\r").into_bytes();
    for (what, bytes) in [("latin1", latin), ("utf16", utf16), ("cr", cr)] {
        let p = d.path().join(format!("{what}.txt"));
        std::fs::write(&p, bytes).unwrap();
        let o = run(&[
            "segments",
            s(&p),
            "--time-col",
            "Time(s)",
            "--lp-col",
            "Displ(µm)",
            "--mu-col",
            "Friction",
            "--json",
        ]);
        assert!(o.status.success(), "{what}: {}", stderr(&o));
        assert_eq!(o.stdout, want, "{what}");
    }
}

/// `rsf simulate` reads a protocol's record with the same reader as `rsf fit`: the lab formats
/// give the same simulation as plain CSV.
#[test]
fn d7_simulate_reads_records_as_fit_does() {
    let d = tempfile::tempdir().unwrap();
    let rows: Vec<(f64, f64, f64)> =
        (0..40).map(|i| (i as f64 * 0.5, i as f64 * 1.5, 0.6 + 0.001 * i as f64)).collect();
    let variants: Vec<(&str, String)> = vec![
        (
            "plain",
            rows.iter().fold("time_s,load_point_um,mu\n".into(), |a, r| a + &format!("{},{},{}\n", r.0, r.1, r.2)),
        ),
        (
            "eu",
            rows.iter().fold("time_s;load_point_um;mu\n".into(), |a, r| {
                a + &format!("{};{};{}\n", r.0, r.1, r.2).replace('.', ",")
            }),
        ),
        (
            "bom+units",
            rows.iter().fold("\u{feff}time_s,load_point_um,mu\ns,um,-\n".into(), |a, r| {
                a + &format!("{},{},{}\n", r.0, r.1, r.2)
            }),
        ),
        (
            "quoted",
            rows.iter().fold("\"time_s\",\"load_point_um\",\"mu\"\n".into(), |a, r| {
                a + &format!("\"{}\",\"{}\",\"{}\"\n", r.0, r.1, r.2)
            }),
        ),
        (
            "spaces",
            rows.iter()
                .fold("time_s   load_point_um   mu\n".into(), |a, r| a + &format!("{}   {}   {}\n", r.0, r.1, r.2)),
        ),
    ];
    let mut outs = vec![];
    for (what, text) in variants {
        std::fs::write(d.path().join("r.txt"), text).unwrap();
        let toml = d.path().join("p.toml");
        std::fs::write(
            &toml,
            "[model]\nmu0 = 0.6\nv0 = 1.0\na = 0.01\nstiffness = 0.1\n[[model.state]]\nlaw = \"slip\"\nb = 0.012\ndc = 5.0\n\
             [loading]\nv_init = 3.0\nrecord = \"r.txt\"\nfriction_column = \"mu\"\n",
        )
        .unwrap();
        let o = run(&["simulate", s(&toml)]);
        assert!(o.status.success(), "{what}: {}", stderr(&o));
        outs.push((what, o.stdout));
    }
    for (what, out) in &outs[1..] {
        assert_eq!(out, &outs[0].1, "{what}");
    }
}

/// The smaller defects: tolerances, long cells, NaN in the first data row, huge times,
/// /dev/zero, and events beside `-o /dev/null`.
#[test]
fn d9_smaller_defects() {
    let d = tempfile::tempdir().unwrap();
    let step = repo().join("examples/step_down.toml");
    let o = run(&["simulate", s(&step), "--atol", "0", "-o", "/dev/null"]);
    assert!(!o.status.success() && stderr(&o).contains("atol = 0 must be positive"), "{}", stderr(&o));
    let o = run(&["simulate", s(&step), "--rtol", "2", "-o", "/dev/null"]);
    assert!(!o.status.success() && stderr(&o).contains("0 < rtol < 1"), "{}", stderr(&o));

    let text = basalt();
    let p = d.path().join("r.txt");
    // an 8 MB cell is not echoed whole; 1e-300 is not three hundred zeros
    std::fs::write(&p, text.replacen("0.607142", &"7".repeat(8_000_000), 1)).unwrap();
    let e = stderr(&segments(&p, &[]));
    assert!(e.len() < 400 && e.contains("r.txt:3: a line longer than 1 MiB"), "{}", &e[..e.len().min(400)]);
    std::fs::write(&p, text.replacen("0.607142", &"x".repeat(100_000), 1)).unwrap();
    let e = stderr(&segments(&p, &[]));
    assert!(
        e.len() < 400 && e.contains("r.txt:3: column `Friction`: `xxxx") && e.contains("(100000 characters)"),
        "{}",
        &e[..e.len().min(400)]
    );
    std::fs::write(&p, text.replacen("0.607142", "1e-300", 1).replacen("\t8503.847000", "\t-1e-300", 1)).unwrap();
    let o = segments(&p, &[]);
    assert!(stderr(&o).len() < 400, "{}", stderr(&o));
    // NaN time in the first data row is an error, not a unit row
    std::fs::write(&p, text.replacen("11607.700000", "NaN", 1)).unwrap();
    let o = segments(&p, &[]);
    assert!(
        !o.status.success() && stderr(&o).contains("r.txt:2: column `Time(s)`: NaN is not finite"),
        "{}",
        stderr(&o)
    );
    // times × 1e300: refused, not NaN velocities
    let huge: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                return format!("{l}\n");
            }
            let mut c: Vec<String> = l.split('\t').map(str::to_string).collect();
            c[0] = format!("{:e}", c[0].parse::<f64>().unwrap() * 1e300);
            c.join("\t") + "\n"
        })
        .collect();
    std::fs::write(&p, huge).unwrap();
    let o = segments(&p, &[]);
    assert!(!o.status.success() && stderr(&o).contains("out of range"), "{}", stderr(&o));
    // /dev/zero: refused at once, memory bounded
    let o = run(&["segments", "/dev/zero"]);
    assert!(!o.status.success() && stderr(&o).contains("NUL byte"), "{}", stderr(&o));
    // events with -o /dev/null go to stderr, not to /dev/null_events.csv
    let _ = std::fs::remove_file("/dev/null_events.csv");
    let o = run(&["simulate", s(&repo().join("examples/stick_slip_cycle.toml")), "-o", "/dev/null"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!Path::new("/dev/null_events.csv").exists());
}
