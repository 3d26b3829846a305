//! The adequacy test: does a fitted model explain the record to its noise level where the
//! protocol's events are?
//!
//! A wrong evolution law, or any effect the menu lacks, leaves a misfit *locked to the
//! protocol's events*: a transient after every velocity step and reslide that the model gets
//! wrong the same way each time. Slow noise (1/f drift, AR(1)) is not locked to them: it is as
//! large anywhere in the record. So the test compares the residuals in a window after each
//! event with the residuals in windows of the same length placed where no event is (placebo
//! windows, inside sliding segments after their own transient), instead of asking a fitted
//! noise model — whose drift part can absorb the misfit it should expose.
//!
//! **Statistic.** In each window the residuals are averaged in bins of logarithmically growing
//! width in the time since its start (a transient decays in log time), and the bin means' spread
//! about their mean is taken, Q = mean over bins of (r̄_b − r̄)², after the part of it along the
//! bin means of the model's own rate of change after the event is taken out: a shift of the
//! event's time, which a noisy load point leaves uncertain by a fraction of a second and whose
//! misfit is locked to the event without being physics. Each placebo takes out the same shape at
//! the same times since its start, so event and placebos lose the same freedom. Where the load
//! point is noisy, a break's time is known only to about 3σ_x/|Δv| (`timing.rs`), and a fast
//! transient misplaced by that much is far from linear in the shift: each window also takes the
//! best of the model's own changes for break shifts within that uncertainty
//! (`windows.rs`, `break_shifts`), the event window and its placebos alike. The window's
//! mean is left out, so a slow drift's offset does not count. Event and placebos are made
//! alike in what the noise does to them: each placebo starts at the event's sampling phase (a
//! break the lab logged as a sample puts one sample at a window's start), and a window of fewer
//! than `MIN_WINDOW_SAMPLES` (`windows.rs`) is not used. The bin means are unweighted, so a window sampled
//! densely after its event is no noisier than a sparse placebo (conservative for a variably
//! sampled record). T = Σ_w Q_w over the event windows.
//!
//! **Null.** Each event window's placebos: disjoint windows of the same length tiling the quiet
//! stretches of sliding (after each segment's own transient), at least [`MIN_PLACEBOS`] of
//! them. Where ln Q of the event window stands among its placebos' ln Q is a prediction-interval
//! t (K − 1 degrees of freedom; ln Q of a window of noise is near normal); the windows' normal
//! scores are summed (Stouffer) into one p. The excess is the geometric mean over the windows of
//! Q over its placebos' typical (geometric-mean) Q: 1 for noise alone.
//!
//! **Verdict of the event test.** Inadequate when p < [`ADEQUACY_LEVEL`] *and* the excess is
//! above [`ADEQUACY_EXCESS`] (significant, and as large as the noise itself), or when p <
//! [`ADEQUACY_LEVEL_LARGE`] and the excess is above [`ADEQUACY_EXCESS_LARGE`] (a misfit twice
//! the noise in rms needs less significance). Untestable when no
//! event window has its placebos (steps too close together for a quiet stretch of sliding as
//! long as a transient).
//!
//! **The model's verdict** ([`Adequacy::verdict`]) takes the level test (`levels.rs`) too: the
//! event windows' mean is taken out, so a model that puts whole segments at the wrong level
//! passes them; the level test sees that. Inadequate when either test finds misfit; otherwise
//! the event test's verdict (a record whose events cannot be tested stays untestable even when
//! its levels fit: the shape of its transients is not judged).

use super::coherence::{Coherence, EventDirection, EventWindow, coherence};
use super::form::FormTest;
use super::levels::{LevelTest, level_test};
use super::quiet::{QuietTest, quiet_test};
#[cfg(doc)]
use super::rule::{ADEQUACY_EXCESS, ADEQUACY_EXCESS_LARGE, ADEQUACY_LEVEL_LARGE, PLACEBOS};
use super::rule::{ADEQUACY_LEVEL, AdequacyVerdict, Family, MIN_PLACEBOS, WINDOW_DC, evenly, judged, quiet_stretches};
use super::sensitivity::FitEffect;
use super::timing::TIMING_SIGMAS;
use super::windows::{bin_time_fractions, break_shifts, event_shape, least_q, model_rate, window_bins};
use rsf_fit::fit::FitResult;
use rsf_fit::segment::Segment;
use rsf_noise::NoiseModel;
use serde::Serialize;
use statrs::distribution::ContinuousCDF;

/// The test needs at least this many event windows with placebos: one suffices, since each
/// window is ranked against its own placebos (one step or one hold is a test of one event).
pub const MIN_WINDOWS: usize = 1;

/// One event window's misfit.
#[derive(Clone, Debug, Serialize)]
pub struct EventMisfit {
    /// The segment after the event (1-based, as in `rsf segments`).
    pub segment: usize,
    /// Time of the event, s.
    pub t: f64,
    /// What happened: `step` (a change of sliding velocity) or `reslide` (after a hold).
    pub event: &'static str,
    /// Window length, s.
    pub window_s: f64,
    /// rms of the window's bin means about their mean (friction).
    pub rms: f64,
    /// That rms over the median of its placebos' (1: like noise).
    pub ratio: f64,
}

/// The adequacy of one fitted model.
#[derive(Clone, Debug, Serialize)]
pub struct Adequacy {
    /// The verdict: inadequate when the event test or the level test finds misfit beyond the
    /// noise, else the event test's ([`Adequacy::event_verdict`]).
    pub verdict: AdequacyVerdict,
    /// The event test's verdict alone (the fields below down to `events` are the event test's).
    pub event_verdict: AdequacyVerdict,
    /// T over the median placebo T: 1 for noise alone; the event-locked misfit's variance
    /// over the noise's, plus one.
    pub excess: f64,
    /// The probability of so large a T under noise with no event-locked part.
    pub p_value: f64,
    /// rms of the event windows' bin means (friction).
    pub event_rms: f64,
    /// The same in the median placebo set (the noise band).
    pub noise_rms: f64,
    /// Event windows tested.
    pub windows: usize,
    /// The record's events (steps and reslides): `windows` of them were tested, the others'
    /// windows had too few samples or no placebos (a transient longer than every quiet
    /// stretch of sliding).
    pub events_total: usize,
    /// Each tested window, worst first.
    pub events: Vec<EventMisfit>,
    /// The level test (`levels.rs`): each step's change of level against its placebos and the
    /// fit's own uncertainty; part of the verdict.
    pub levels: LevelTest,
    /// The coherence test (`coherence.rs`): do the events' misfits agree with each other beyond
    /// the noise? Part of the verdict where the event test cannot run.
    pub coherence: Coherence,
    /// The quiet test (`quiet.rs`): is the wander the noise model counts as noise there inside
    /// the quiet stretches of sliding? Part of the verdict.
    pub quiet: QuietTest,
    /// The form test (`form.rs`): does the law named fit better reshaped in state? Run on the
    /// model of a named cause whose other tests found no misfit; part of the verdict.
    pub form: Option<FormTest>,
    /// The tests that share the level (`rule.rs`): the tests alone for a named model, the
    /// tests that ran for the baseline of a `none` verdict ([`Adequacy::baseline_family`]).
    pub family: Family,
}

/// A test of the adequacy verdict that can find misfit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdequacyTest {
    /// Event windows against quiet placebos.
    Events,
    /// Each step's change of level (`levels.rs`).
    Levels,
    /// The wander inside the quiet stretches against the noise model (`quiet.rs`).
    Quiet,
    /// The events' misfits against each other, where the event test could not run
    /// (`coherence.rs`).
    Coherence,
    /// The model reshaped (`form.rs`).
    Form,
}

impl Adequacy {
    /// The tests that found misfit, in the order the verdict reads them: the model is
    /// inadequate exactly when this is not empty.
    pub fn misfits(&self) -> Vec<AdequacyTest> {
        let coherence =
            self.event_verdict == AdequacyVerdict::Untestable && self.coherence.verdict == AdequacyVerdict::Inadequate;
        [
            (self.event_verdict == AdequacyVerdict::Inadequate, AdequacyTest::Events),
            (self.levels.inadequate(), AdequacyTest::Levels),
            (self.quiet.inadequate(), AdequacyTest::Quiet),
            (coherence, AdequacyTest::Coherence),
            (self.form.as_ref().is_some_and(FormTest::inadequate), AdequacyTest::Form),
        ]
        .into_iter()
        .filter_map(|(found, t)| found.then_some(t))
        .collect()
    }

    /// The family of the baseline's tests: each test that ran (the event test, or the
    /// coherence test where it could not run; the level and quiet tests), and the form test,
    /// which runs when they find nothing.
    pub fn baseline_family(&self) -> Family {
        let events = match self.event_verdict {
            AdequacyVerdict::Untestable => self.coherence.verdict != AdequacyVerdict::Untestable,
            AdequacyVerdict::Adequate | AdequacyVerdict::Inadequate => true,
        };
        let ran = [events, self.levels.ran(), self.quiet.ran(), true];
        Family { tests: ran.into_iter().filter(|r| *r).count() }
    }

    /// The same adequacy with its tests' level shared by `family`: each test's verdict, and
    /// the model's, again.
    pub(super) fn held_to(mut self, family: Family) -> Self {
        self.family = family;
        self.levels.family = family;
        self.quiet.family = family;
        self.coherence = self.coherence.held_to(family);
        if self.event_verdict != AdequacyVerdict::Untestable {
            self.event_verdict = judged(self.p_value, self.excess, family);
        }
        self.verdict = verdict_of(self.event_verdict, &self.levels, &self.quiet, &self.coherence);
        self
    }

    /// How many of the record's events were tested, when not all: `; 2 of 8 events tested`.
    pub fn untested_words(&self) -> String {
        if self.windows < self.events_total {
            format!("; {} of {} events tested", self.windows, self.events_total)
        } else {
            String::new()
        }
    }

    /// The verdict in words, for the diagnosis's reason: the event test's (the coherence
    /// test's where the event test could not run), the level test's when it ran, and the form
    /// test's (first when it found misfit).
    pub fn words(&self) -> String {
        let base = self.event_and_level_words();
        let base = match self.quiet.words() {
            Some(q) => format!("{q}; {base}"),
            None => base,
        };
        let words = match &self.form {
            Some(f) if f.inadequate() => format!("{}; {base}", f.words()),
            Some(f) => format!("{base}; {}", f.words()),
            None => base,
        };
        match self.family_words() {
            Some(f) => format!("{words}; {f}"),
            None => words,
        }
    }

    /// The shared level in words, when the tests share it (the baseline's): `its 4 tests share
    /// the 1 % level, each held to 0.25 %`.
    pub fn family_words(&self) -> Option<String> {
        (self.family.tests > 1).then(|| {
            format!(
                "its {} tests share the {} % level, each held to {} %",
                self.family.tests,
                100.0 * ADEQUACY_LEVEL,
                format!("{:.3}", 100.0 * self.family.level()).trim_end_matches('0')
            )
        })
    }

    /// The same adequacy with the form test's outcome: inadequate when it finds misfit.
    pub(super) fn with_form(mut self, form: Option<FormTest>) -> Self {
        if form.as_ref().is_some_and(FormTest::inadequate) {
            self.verdict = AdequacyVerdict::Inadequate;
        }
        self.form = form;
        self
    }

    /// The event and level tests' verdicts in words.
    fn event_and_level_words(&self) -> String {
        let levels = self.levels.words();
        match (self.event_verdict, levels) {
            (AdequacyVerdict::Inadequate, Some(l)) if self.levels.inadequate() => {
                format!("{}; and {l}", self.event_words())
            }
            (_, Some(l)) if self.levels.inadequate() => format!("{l}; {}", self.event_words()),
            (_, Some(l)) => format!("{}; {l}", self.event_words()),
            (_, None) => self.event_words(),
        }
    }

    /// The event test's verdict in words.
    fn event_words(&self) -> String {
        match self.event_verdict {
            AdequacyVerdict::Untestable => format!(
                "its events could not be tested against the noise (too few with a quiet stretch as long as their \
                 transient); compared with each other, {}",
                self.coherence.words()
            ),
            AdequacyVerdict::Adequate => format!(
                "it explains the events to the noise level (event-locked misfit {:.2}× the noise's variance, p = {:.2}{})",
                self.excess,
                self.p_value,
                self.untested_words()
            ),
            AdequacyVerdict::Inadequate => {
                let worst: Vec<String> = self
                    .events
                    .iter()
                    .take(3)
                    .map(|e| format!("{} at t = {:.0} s ({:.1}×)", e.event, e.t, e.ratio))
                    .collect();
                format!(
                    "it still misfits where the events are: event-locked misfit rms {:.1e} against a noise band of \
                     {:.1e} ({:.1}× the noise's variance, p = {:.3}), worst {}",
                    self.event_rms,
                    self.noise_rms,
                    self.excess,
                    self.p_value,
                    worst.join(", ")
                )
            }
        }
    }
}

/// The model's verdict from the event test's, the level, quiet and coherence tests:
/// inadequate when the levels are off ([`LevelTest::inadequate`]) or the noise model's wander
/// is not in the quiet stretches ([`QuietTest::inadequate`]), or when the events could
/// not be tested against placebos and their misfits agree with each other beyond the noise
/// (`coherence.rs`); else the event test's. Where the coherence test finds nothing the record
/// stays untestable: it compares the events with each other, not with the noise's own size.
fn verdict_of(
    events: AdequacyVerdict,
    levels: &LevelTest,
    quiet: &QuietTest,
    coherence: &Coherence,
) -> AdequacyVerdict {
    match events {
        _ if levels.inadequate() || quiet.inadequate() => AdequacyVerdict::Inadequate,
        AdequacyVerdict::Untestable if coherence.verdict == AdequacyVerdict::Inadequate => AdequacyVerdict::Inadequate,
        AdequacyVerdict::Untestable | AdequacyVerdict::Adequate | AdequacyVerdict::Inadequate => events,
    }
}

/// A tested event window: its segment index, start, what happened, length, Q, and its
/// placebos' Q.
type Tested = (usize, f64, &'static str, f64, f64, Vec<f64>);

/// The adequacy of the fit `f` on the record's `segments` (those the fit used), with the
/// load point's noise about the protocol's lines `load_point_sigma_um` (µm; 0 for a clean one),
/// which sets how far each break's time is uncertain, and the fit's own uncertainty `effect`
/// (`sensitivity.rs`; evaluated only when the record has a step to test the levels of). With
/// `effect` `None` the level test does not run (a candidate's excess needs only the event test);
/// with `noise` (the noise model fitted to `f`'s residuals) or the fit's effect `None`, the quiet
/// test does not.
pub fn adequacy(
    f: &FitResult,
    segments: &[Segment],
    load_point_sigma_um: f64,
    effect: Option<&dyn Fn() -> Option<FitEffect>>,
    noise: Option<&NoiseModel>,
) -> Adequacy {
    // the fit's effect, evaluated at most once, and only when a test needs it
    let cached = std::cell::OnceCell::new();
    let fit_effect = || cached.get_or_init(|| effect.and_then(|e| e())).clone();
    let levels = match effect {
        Some(_) => level_test(f, segments, load_point_sigma_um, &fit_effect),
        None => LevelTest { p_value: f64::NAN, excess: f64::NAN, steps: vec![], family: Family::ALONE },
    };
    let quiet_wander = match (noise, effect.is_some().then(fit_effect).flatten()) {
        (Some(m), Some(e)) => quiet_test(f, segments, m, &e),
        _ => QuietTest::untested(),
    };
    let c = &f.curve;
    let res: Vec<f64> = c.data.iter().zip(&c.model).map(|(d, m)| d - m).collect();
    let rate = model_rate(&c.time, &c.model);
    let dc_max = f.params.dc.iter().copied().fold(0.0f64, f64::max);
    let time = &c.time;
    // each sliding segment's transient window after the event that starts it
    let window_of = |s: &Segment| (WINDOW_DC * dc_max / s.v).min(s.t1 - s.t0);
    let mut events = vec![];
    for (j, s) in segments.iter().enumerate().skip(1) {
        if !(s.v > 0.0) {
            continue;
        }
        let reslide = segments[j - 1].v <= 0.0;
        // the break's time is known to about σ_x/|Δv| (timing.rs), taken TIMING_SIGMAS wide
        let uncertainty = TIMING_SIGMAS * load_point_sigma_um / (s.v - segments[j - 1].v).abs();
        let direction = if reslide {
            EventDirection::Reslide
        } else if s.v > segments[j - 1].v {
            EventDirection::StepUp
        } else {
            EventDirection::StepDown
        };
        events.push((j, s.t0, window_of(s), direction, uncertainty));
    }
    let quiet = quiet_stretches(segments, dc_max);
    // an event window's placebos: disjoint windows of its length tiling the quiet stretches
    // (disjoint, so that each is a comparison of its own), at most PLACEBOS of them spread
    // evenly over all the tiles
    let tiles = |len: f64| -> Vec<(f64, f64)> {
        let mut starts = vec![];
        for &(a, b) in &quiet {
            let n = ((b - a) / len).floor() as usize;
            starts.extend((0..n).map(|i| (a + i as f64 * len, b)));
        }
        evenly(starts)
    };
    let mut tested: Vec<Tested> = vec![];
    let mut compared: Vec<EventWindow> = vec![];
    for &(j, t0, len, direction, uncertainty) in &events {
        let what = match direction {
            EventDirection::Reslide => "reslide",
            EventDirection::StepUp | EventDirection::StepDown => "step",
        };
        let shape = event_shape(time, &rate, t0, len);
        let Some(bins) = window_bins(time, &res, &shape, t0, len) else { continue };
        // the event window and each placebo alike take the break shift that fits them best
        let shifts = break_shifts(time, &c.model, t0, len, uncertainty);
        let q = least_q(&bins, &shifts);
        // each placebo starts at the event window's sampling phase: as far before a sample as
        // the event is before its first (0 where the break is a sample, as a lab's logged
        // change of velocity is). A placebo placed between samples would lack the single-sample
        // bin at its start that the event window has, and the noise alone would then make the
        // event windows look worse.
        let phase = time.get(time.partition_point(|&t| t < t0)).map_or(0.0, |&t| t - t0);
        let placebo: Vec<f64> = tiles(len)
            .into_iter()
            .filter_map(|(s, end)| {
                let first = *time.get(time.partition_point(|&t| t < s + phase))?;
                let start = first - phase;
                (start + len <= end).then_some(start)
            })
            .filter_map(|s| window_bins(time, &res, &shape, s, len))
            .map(|b| least_q(&b, &shifts))
            .filter(|q| *q > 0.0)
            .collect();
        if placebo.len() >= MIN_PLACEBOS && q > 0.0 {
            tested.push((j, t0, what, len, q, placebo));
        }
        compared.push(EventWindow { t: t0, direction, bins, shifts, time_fraction: bin_time_fractions(time, t0, len) });
    }
    let coherence = coherence(&compared);
    if tested.len() < MIN_WINDOWS {
        return Adequacy {
            verdict: verdict_of(AdequacyVerdict::Untestable, &levels, &quiet_wander, &coherence),
            event_verdict: AdequacyVerdict::Untestable,
            excess: f64::NAN,
            p_value: f64::NAN,
            event_rms: f64::NAN,
            noise_rms: f64::NAN,
            windows: tested.len(),
            events_total: events.len(),
            events: vec![],
            levels,
            coherence,
            quiet: quiet_wander,
            form: None,
            family: Family::ALONE,
        };
    }
    // per window: where ln Q stands among its placebos' ln Q, as a prediction-interval t with
    // K − 1 degrees of freedom, turned into a normal score; Stouffer's sum over the windows
    let normal = statrs::distribution::Normal::standard();
    let mut z_sum = 0.0;
    let mut ln_excess = 0.0;
    let (mut t_real, mut t_noise) = (0.0, 0.0);
    let mut per_event = vec![];
    for (j, t0, what, len, q, placebo) in &tested {
        let k = placebo.len() as f64;
        let ln: Vec<f64> = placebo.iter().map(|x| x.ln()).collect();
        let m = ln.iter().sum::<f64>() / k;
        let sd = (ln.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (k - 1.0)).sqrt().max(1e-12);
        let t = (q.ln() - m) / (sd * (1.0 + 1.0 / k).sqrt());
        let p_one = match statrs::distribution::StudentsT::new(0.0, 1.0, k - 1.0) {
            Ok(d) => 1.0 - d.cdf(t),
            Err(_) => 0.5,
        };
        z_sum += normal.inverse_cdf(1.0 - p_one.clamp(1e-300, 1.0 - 1e-16));
        ln_excess += q.ln() - m;
        let typical = m.exp();
        t_real += q;
        t_noise += typical;
        per_event.push(EventMisfit {
            segment: j + 1,
            t: *t0,
            event: what,
            window_s: *len,
            rms: q.sqrt(),
            ratio: (q / typical).sqrt(),
        });
    }
    let n = tested.len() as f64;
    let z = z_sum / n.sqrt();
    let p_value = 1.0 - normal.cdf(z);
    // the typical window's: the geometric mean over the windows of Q over its placebos' typical Q
    let excess = (ln_excess / n).exp();
    per_event.sort_by(|a, b| b.ratio.total_cmp(&a.ratio));
    let event_verdict = judged(p_value, excess, Family::ALONE);
    Adequacy {
        verdict: verdict_of(event_verdict, &levels, &quiet_wander, &coherence),
        event_verdict,
        excess,
        p_value,
        event_rms: (t_real / n).sqrt(),
        noise_rms: (t_noise / n).sqrt(),
        windows: tested.len(),
        events_total: events.len(),
        events: per_event,
        levels,
        coherence,
        quiet: quiet_wander,
        form: None,
        family: Family::ALONE,
    }
}
