//! The diagnosis report reads like a scientist's: a plain-language verdict first, tables of
//! formatted numbers with units, candidates in a real table, no raw JSON, no 15-digit floats.
//!
//! `RSF_REPORT_OUT=/tmp/report.html cargo test --release -p rsf-report --test report` also writes
//! the page (to look at it, e.g. with `docs/diagnose/screenshot.sh`).

use rsf_core::{Model, StateVariable};
use rsf_diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use rsf_fit::fit::{FitOptions, LoadingMode};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, record};
use rsf_laws::{Slip, law_by_name};
use rsf_report::{diagnosis_html, fit_svg};

/// A short step-and-hold record with a slip trend `g` (per µm), diagnosed with a Slip baseline.
fn diagnosis(g: f64) -> Diagnosis {
    let truth = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Slip, 0.013, 8.0)).with_slip_trend(g);
    let protocol = [
        (1.0, 60.0, 0.2),
        (10.0, 10.0, 0.2),
        (1.0, 60.0, 0.2),
        (0.1, 150.0, 1.0),
        (1.0, 60.0, 0.2),
        (0.0, 100.0, 1.0),
        (1.0, 60.0, 0.2),
        (0.0, 300.0, 2.0),
        (1.0, 60.0, 0.2),
    ];
    let rec = record(&truth, 1.0, &protocol, Noise { sigma: 2e-4, tau: 0.0 }, 11).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005);
    fit.loading = LoadingMode::Protocol;
    let mut o = DiagnoseOptions::new(fit);
    o.null_replicates = 0;
    diagnose(&rec, &segs, &o).unwrap()
}

/// The text a reader sees: tags, style and inline SVG removed.
fn visible(html: &str) -> String {
    let mut s = html.to_string();
    for (open, close) in [("<style", "</style>"), ("<svg", "</svg>")] {
        while let Some(a) = s.find(open) {
            let b = s[a..].find(close).map_or(s.len(), |b| a + b + close.len());
            s.replace_range(a..b, " ");
        }
    }
    let mut out = String::new();
    let mut in_tag = false;
    for c in s.chars() {
        match c {
            '<' => in_tag = true,
            '>' if in_tag => {
                in_tag = false;
                out.push(' ');
            }
            _ if !in_tag => out.push(c),
            _ => {}
        }
    }
    out
}

/// The text of the charts' labels, titles and legends (`<text …>…</text>` of the inline SVG).
fn chart_text(html: &str) -> String {
    let mut out = String::new();
    let mut rest = html;
    while let Some(a) = rest.find("<text") {
        let after = &rest[a..];
        let (Some(open_end), Some(close)) = (after.find('>'), after.find("</text>")) else { break };
        out += &after[open_end + 1..close];
        out.push('\n');
        rest = &after[close..];
    }
    out
}

/// Numbers printed with nine or more decimals (`2.833121483939129e-6`, `0.60000000001`).
fn long_floats(text: &str) -> Vec<String> {
    let b: Vec<char> = text.chars().collect();
    let mut hits = Vec::new();
    for i in 1..b.len() {
        if b[i] == '.' && b[i - 1].is_ascii_digit() {
            let n = b[i + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
            if n >= 9 {
                hits.push(b[i.saturating_sub(3)..(i + 1 + n).min(b.len())].iter().collect());
            }
        }
    }
    hits
}

#[test]
fn the_report_is_something_a_scientist_would_show() {
    let d = diagnosis(1e-5);
    println!("cause {}: {}", d.cause, d.reason);
    let html = diagnosis_html(&d, "synthetic <slip trend>.txt");
    if let Ok(p) = std::env::var("RSF_REPORT_OUT") {
        std::fs::write(&p, &html).unwrap();
        std::fs::write(std::path::Path::new(&p).with_extension("svg"), fit_svg(&d.baseline, "baseline").unwrap())
            .unwrap();
    }
    assert!(html.starts_with("<!doctype html>") && !html.contains("src=\"http") && html.contains("<svg"));
    assert!(html.contains("synthetic &lt;slip trend&gt;.txt"), "the name is escaped");
    // the noise model, with the residual spectrum against the fitted model's
    assert!(html.contains("<h2>Noise</h2>") && html.contains("residual spectrum of the baseline"), "no noise section");
    assert!(html.contains("white noise rms") && html.contains("n_eff for a slow effect"));
    let text = visible(&html);
    // the verdict is the first paragraph, in words
    let body = &html[html.find("<body>").unwrap()..];
    let first_p = body.find("<p").unwrap();
    assert!(body[first_p..].starts_with("<p class=\"verdict"), "{}", &body[first_p..first_p + 80]);
    let verdict = &body[first_p..first_p + body[first_p..].find("</p>").unwrap()];
    if d.cause.as_str() == "none" {
        assert!(verdict.contains("explains the record"), "{verdict}");
    } else {
        assert!(verdict.contains("The data need") && verdict.contains("ΔBIC"), "{verdict}");
    }
    assert_eq!(d.cause.as_str(), "slip_trend", "{}", d.reason);
    assert!(verdict.contains("slip trend") && verdict.contains("×10⁻⁶"), "g formatted: {verdict}");
    // candidates in a real table, one row each
    let cand = &html[html.find("<h2>Candidates</h2>").expect("a candidates section")..];
    let cand = &cand[..cand.find("</table>").unwrap()];
    assert!(cand.contains("<table"));
    assert_eq!(cand.matches("<tr").count(), d.candidates.len() + 1, "a header and a row per candidate");
    // no raw JSON, no unformatted floats, in the text or in the charts' labels
    let labels = chart_text(&html);
    assert!(labels.contains("friction μ") && labels.contains("load-point displacement (µm)"), "{labels}");
    assert!(!text.contains("{\"") && !text.contains("\":"), "raw JSON in the report");
    let long = long_floats(&(text.clone() + &labels));
    assert!(long.is_empty(), "unformatted numbers: {long:?}");
    // units where they belong
    assert!(text.contains("µm") && text.contains("/µm"));
}

#[test]
fn with_nothing_hidden_the_verdict_says_the_baseline_stands() {
    let d = diagnosis(0.0);
    assert_eq!(d.cause.as_str(), "none", "{}", d.reason);
    let html = diagnosis_html(&d, "no effect");
    let body = &html[html.find("<p class=\"verdict").expect("a verdict")..];
    let verdict = &body[..body.find("</p>").unwrap()];
    println!("{verdict}");
    assert!(verdict.contains("explains the record") && verdict.contains("best was"), "{verdict}");
    assert!(long_floats(&(visible(&html) + &chart_text(&html))).is_empty());
    assert!(!html.contains("<h2>Effect</h2>"), "no effect table without an effect");
}

/// The visible text of a report's verdict paragraph (printed, for a failing test's log).
fn verdict_text(html: &str) -> String {
    let body = &html[html.find("<p class=\"verdict").expect("a verdict")..];
    let verdict = visible(&body[..body.find("</p>").unwrap()]);
    println!("{verdict}");
    verdict
}

/// The diagnosis of `tests/data/{rel}` with a Slip baseline at stiffness `k` and protocol
/// loading, as `rsf diagnose` has it.
fn diagnosed_record(rel: &str, k: f64) -> rsf_diagnose::Diagnosis {
    use rsf_fit::data::{ReadOptions, read_record};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data").join(rel);
    let rec = read_record(&path, &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], k);
    fit.loading = LoadingMode::Protocol;
    diagnose(&rec, &segs, &DiagnoseOptions { threads: 2, ..DiagnoseOptions::new(fit) }).unwrap()
}

/// `undecided` (a small second state the record cannot tell from a slip trend,
/// tests/data/detection/second_state_or_trend.csv): the verdict names neither, gives both with
/// their scores, and says what decides; both rows are shaded in the candidates' table.
#[test]
fn an_undecided_verdict_names_both_and_neither() {
    let d = diagnosed_record("detection/second_state_or_trend.csv", 0.03275739878830749);
    assert_eq!(d.cause.as_str(), "undecided", "{}", d.reason);
    assert_eq!(d.apart, Some(rsf_diagnose::Apart::Margin));
    let html = diagnosis_html(&d, "undecided");
    let verdict = verdict_text(&html);
    for words in
        ["does not tell which of two extensions", "a slip trend", "a second state variable", "No cause is named"]
    {
        assert!(verdict.contains(words), "{words}: {verdict}");
    }
    let table = &html[html.find("<h2>Candidates</h2>").expect("the candidates")..];
    assert_eq!(table.matches("<tr class=\"chosen\"").count(), 2);
    assert!(long_floats(&(visible(&html) + &chart_text(&html))).is_empty());
}

#[test]
fn long_floats_are_caught() {
    assert_eq!(long_floats("g = 2.833121483939129e-6, k = 0.0073").len(), 1);
    assert!(long_floats("0.00965 ± 0.00012, 1.23456789").is_empty());
    assert_eq!(visible("<p>a<b>b</b></p><svg><text>x</text></svg>").split_whitespace().collect::<String>(), "ab");
}

/// `undecided` by the lead's chance spread (a power-law-aging truth that a cut-off and an
/// Aging–Slip law both bend towards, 27 apart in ΔBIC, tests/data/outside/power_aging_or_cutoff.csv):
/// the verdict says the gap is beyond the fixed margin and why it still decides nothing.
#[test]
fn a_lead_the_noise_could_reverse_is_said_so() {
    let d = diagnosed_record("outside/power_aging_or_cutoff.csv", 0.03530547554472882);
    assert_eq!(d.cause.as_str(), "undecided", "{}", d.reason);
    assert_eq!(d.apart, Some(rsf_diagnose::Apart::Lead));
    let html = diagnosis_html(&d, "undecided by its lead");
    let verdict = verdict_text(&html);
    for words in ["does not tell which of two extensions", "more than the margin", "another draw of the noise"] {
        assert!(verdict.contains(words), "{words}: {verdict}");
    }
    assert!(!verdict.contains("within 10 of each other"), "{verdict}");
    assert!(long_floats(&(visible(&html) + &chart_text(&html))).is_empty());
}

/// `undecided` beside a better-scoring rival whose fit did not converge (a slip trend whose fit
/// ran out of budget, tests/data/detection/unconverged_rival_slip_trend.csv): the verdict says
/// so, and that the fit shown is the one chosen first, not the better-scoring one.
#[test]
fn a_rival_that_did_not_converge_is_said_so() {
    let d = diagnosed_record("detection/unconverged_rival_slip_trend.csv", 0.004560632516018635);
    if d.apart != Some(rsf_diagnose::Apart::Unconverged) {
        // a fit that reaches the trend's optimum names it (`diagnose_unconverged.rs`)
        assert_eq!(d.cause.as_str(), "slip_trend", "{}", d.reason);
        return;
    }
    let html = diagnosis_html(&d, "undecided beside a rival that did not converge");
    let verdict = verdict_text(&html);
    for words in ["does not tell which of two extensions", "its fit did not converge", "the first one's"] {
        assert!(verdict.contains(words), "{words}: {verdict}");
    }
    assert!(!verdict.contains("within 10 of each other"), "{verdict}");
}

/// `undecided` because a rival's law, reshaped, explains the record as well as the cause chosen
/// (power-law aging that a cut-off led, tests/data/outside/power_aging_reshaped_rival.csv): the
/// verdict says which law, reshaped, does as well, and that the fit shown is the first one's.
#[test]
fn a_rival_law_reshaped_that_does_as_well_is_said_so() {
    let d = diagnosed_record("outside/power_aging_reshaped_rival.csv", 0.05558273592187484);
    assert_eq!(d.apart, Some(rsf_diagnose::Apart::Form), "{}", d.reason);
    let html = diagnosis_html(&d, "undecided beside a rival law reshaped");
    let verdict = verdict_text(&html);
    for words in ["does not tell which of two extensions", "(aging-slip) read at a reshaped state", "the first one's"] {
        assert!(verdict.contains(words), "{words}: {verdict}");
    }
    assert!(!verdict.contains("within 10 of each other"), "{verdict}");
}

/// `unexplained` where no cause was chosen (a rate-dependent direct effect that no candidate
/// mimics, tests/data/outside/rate_a_none_baseline.csv): the form test judged the baseline, and
/// the report says so — the baseline, not a "model named", has the wrong direct effect.
#[test]
fn a_baseline_that_misfits_in_form_is_named_as_the_baseline() {
    let d = diagnosed_record("outside/rate_a_none_baseline.csv", 0.06881918692627965);
    assert_eq!(d.cause.as_str(), "unexplained", "{}", d.reason);
    let html = diagnosis_html(&d, "unexplained baseline");
    let verdict = verdict_text(&html);
    assert!(!verdict.contains("model named"), "{verdict}");
    // the misfit as the test that found it says: not an event test's numbers it did not measure
    assert!(verdict.contains("its direct effect is not the record's"), "{verdict}");
    assert!(!verdict.contains("event-locked misfit of rms –"), "{verdict}");
    let text = visible(&html);
    let form = &text[text.find("Form:").expect("the form test's paragraph")..];
    let form = &form[..form.find("explains nothing").expect("its verdict")];
    println!("{form}");
    for words in [
        "the baseline with a rate-dependent direct effect",
        "against the baseline",
        "the baseline has the wrong direct effect",
    ] {
        assert!(form.contains(words), "{words}: {form}");
    }
    assert!(!form.contains("model named"), "{form}");
    // the baseline's tests share the level, and the page says how
    let m = d.adequacy.family.tests;
    assert!(m >= 2, "{:?}", d.adequacy.family);
    assert!(text.contains(&format!("The baseline's {m} tests")) && text.contains("share the 1 % level"), "{text}");
    assert!(long_floats(&(text + &chart_text(&html))).is_empty());
}
