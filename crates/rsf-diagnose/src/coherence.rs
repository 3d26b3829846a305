//! The coherence test: does a fitted model misfit the same way at every event of a kind?
//!
//! The event test (`adequacy.rs`) ranks each event window against placebo windows in the
//! quiet stretches of sliding. A record whose transients are as long as its segments has no
//! quiet stretch, and that test cannot run. Its events can still be compared with each other:
//! a wrong law misfits every step up (every step down, every reslide) with the same shape in
//! log time since the event, while noise — white, AR(1), 1/f — gives each window a shape of its
//! own, as likely one sign as the other. So the null comes from the events themselves.
//!
//! **Profiles.** Each event window (the event test's window: [`crate::WINDOW_DC`] Dc of slip,
//! at most the segment) is averaged in the event test's log-time bins. From its bin means the
//! window's mean, the bin means of the time since the window's start (a drift's slope: a 1/f
//! noise slow against the window is a line across it, and a slow drift has the same sign in
//! neighbouring windows) and, in a window of five bins or more, the model's own rate of change
//! (a shift of the event's time) are taken out by least squares, after the best of the event
//! test's break shifts (`windows.rs`). What is left is the window's profile.
//!
//! **Statistic and null.** Events are grouped by kind ([`speeds_up`]: steps up and reslides,
//! and steps down); each profile is scaled to unit length, so a noisy window does not outweigh
//! the others, and
//! T = Σ_groups |Σ_events s_e u_e|² with every s_e = +1. Under noise with no event-locked part the
//! profiles are independent and as likely of either sign, so every pattern of signs s is as
//! likely as the observed one: p is the share of sign patterns whose T reaches the observed T
//! (all patterns when they are few, else [`SIGN_PATTERNS`] drawn with a fixed seed). Exact
//! without a model of the noise. The fit's own residuals are orthogonal to its parameters'
//! effects, so a parameter error cannot make them agree (conservative).
//!
//! **Excess.** Each group's profiles about their mean scatter as the noise does; their mean
//! square about zero holds the common part too. Their ratio is 1 for noise alone and
//! 1 + (common misfit's variance)/(noise's) otherwise, as the event test's excess.
//!
//! **Verdict.** The event test's rule ([`crate::ADEQUACY_LEVEL`], [`crate::ADEQUACY_EXCESS`] and
//! the pair for a larger misfit). Untestable when even the most extreme sign pattern could not
//! reach p < [`crate::ADEQUACY_LEVEL`] (too few events of a kind). It is used where the event
//! test cannot run; where it can, the placebos measure the misfit against the noise itself.

use super::rule::{ADEQUACY_LEVEL, AdequacyVerdict, Family, judged, p_words};
use super::windows::{BIN_EDGES, BINS, Bins, least_shift_profile};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// Sign patterns drawn when there are more than this many (2^14): enough for a p of 0.01 to
/// be known to ±0.0008 (its binomial standard error), so the verdict at the level is stable.
pub const SIGN_PATTERNS: usize = 1 << 14;
/// The seed of the drawn sign patterns: the same record gives the same p on any machine.
const SIGN_SEED: u64 = 0x5eed_c0de;
/// A window's profile needs this many filled bins: the mean and the slope are taken out, so
/// two or more remain to have a shape (a window sampled coarsely against its length fills only
/// its later bins).
const MIN_PROFILE_BINS: usize = 4;

/// What happened at an event, for grouping: a wrong law misfits each kind its own way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventDirection {
    /// A step to a faster sliding velocity.
    StepUp,
    /// A step to a slower sliding velocity.
    StepDown,
    /// Sliding again after a hold.
    Reslide,
}

/// The outcome of the coherence test.
#[derive(Clone, Debug, Serialize)]
pub struct Coherence {
    /// Adequate, inadequate, or untestable (too few events of a kind to reach the level).
    pub verdict: AdequacyVerdict,
    /// The share of sign patterns whose agreement reaches the observed one (NaN if untestable).
    pub p_value: f64,
    /// Mean square of the profiles over their scatter about their kind's mean: 1 for noise.
    pub excess: f64,
    /// Event windows with a profile.
    pub windows: usize,
    /// Of them, in kinds with at least two events (the ones that can agree).
    pub compared: usize,
    /// Each window's profile, in time order.
    pub profiles: Vec<EventProfile>,
}

impl EventDirection {
    /// The event in words.
    pub fn words(self) -> &'static str {
        match self {
            Self::StepUp => "step up",
            Self::StepDown => "step down",
            Self::Reslide => "reslide",
        }
    }
}

impl EventProfile {
    /// The profile as (time since the event over the window's length, value) at each filled
    /// bin's middle (geometric; the first bin's at half its edge), for a plot in log time.
    pub fn points(&self) -> Vec<(f64, f64)> {
        (0..BINS)
            .filter(|&b| self.profile[b] != 0.0)
            .map(|b| {
                let (lo, hi) = (BIN_EDGES[b], BIN_EDGES[b + 1]);
                (if lo > 0.0 { (lo * hi).sqrt() } else { hi / 2.0 }, self.profile[b])
            })
            .collect()
    }

    /// rms of the profile over the bins it fills (friction).
    pub fn rms(&self) -> f64 {
        let filled: Vec<f64> = self.profile.iter().copied().filter(|x| *x != 0.0).collect();
        if filled.is_empty() { 0.0 } else { (filled.iter().map(|x| x * x).sum::<f64>() / filled.len() as f64).sqrt() }
    }
}

/// One event window's profile: what the test compares.
#[derive(Clone, Debug, Serialize)]
pub struct EventProfile {
    /// Time of the event, s.
    pub t: f64,
    /// What happened.
    pub direction: EventDirection,
    /// The window's bin means after the nuisances are taken out (friction; 0 in an empty bin),
    /// in the event test's log-time bins.
    pub profile: [f64; BINS],
}

impl Coherence {
    /// A record with nothing to compare.
    fn untestable(compared: usize, profiles: Vec<EventProfile>) -> Self {
        Coherence {
            verdict: AdequacyVerdict::Untestable,
            p_value: f64::NAN,
            excess: f64::NAN,
            windows: profiles.len(),
            compared,
            profiles,
        }
    }

    /// The same test with its level shared by `family` (`rule.rs`): the verdict again, where it
    /// could be tested.
    pub(super) fn held_to(mut self, family: Family) -> Self {
        if self.verdict != AdequacyVerdict::Untestable {
            self.verdict = judged(self.p_value, self.excess, family);
        }
        self
    }

    /// The verdict in words, for the diagnosis's reason.
    pub fn words(&self) -> String {
        match self.verdict {
            AdequacyVerdict::Untestable => format!(
                "too few events of a kind with their shape sampled ({} of {}) for their misfits' agreement to reach \
                 the level",
                self.compared, self.windows
            ),
            AdequacyVerdict::Adequate => format!(
                "its misfits at the {} events do not agree more than noise does (excess {:.2}, p = {})",
                self.compared,
                self.excess,
                p_words(self.p_value)
            ),
            AdequacyVerdict::Inadequate => {
                // the largest profiles, where the shared misfit shows most
                let mut by_size: Vec<&EventProfile> = self.profiles.iter().collect();
                by_size.sort_by(|a, b| b.rms().total_cmp(&a.rms()));
                let worst: Vec<String> = by_size
                    .iter()
                    .take(3)
                    .map(|e| format!("{} at t = {:.0} s ({:.1e})", e.direction.words(), e.t, e.rms()))
                    .collect();
                format!(
                    "it misfits alike at the events of each kind: across {} events the part their misfits share \
                     carries {:.2}× the noise's variance (excess {:.2}, p = {} against every pattern of their signs), \
                     largest after the {}",
                    self.compared,
                    self.excess - 1.0,
                    self.excess,
                    p_words(self.p_value),
                    worst.join(", ")
                )
            }
        }
    }
}

/// The events compared with each other: those that speed the sliding up (steps up and
/// reslides, each with a peak a wrong law gets wrong the same way) and those that slow it
/// down. Two groups, not three: each group's overall sign is no evidence (a pattern and its
/// flip give the same agreement), so every group costs the test a factor 2 in its least p, and
/// nine events in three groups could never reach the level.
fn speeds_up(d: EventDirection) -> bool {
    match d {
        EventDirection::StepUp | EventDirection::Reslide => true,
        EventDirection::StepDown => false,
    }
}

/// One event window for the test: its direction, its bins (the event test's) and its break
/// shifts' bin-mean changes of the model, and the bin means of the time since its start over
/// its length.
pub(super) struct EventWindow {
    pub t: f64,
    pub direction: EventDirection,
    pub bins: Bins,
    pub shifts: Vec<[f64; BINS]>,
    pub time_fraction: [f64; BINS],
}

/// The coherence test over the record's event windows.
pub(super) fn coherence(windows: &[EventWindow]) -> Coherence {
    // each window's profile (full length BINS, zeros where a bin is empty)
    let profiles: Vec<EventProfile> = windows
        .iter()
        .filter(|w| w.bins.len() >= MIN_PROFILE_BINS)
        .filter_map(|w| {
            least_shift_profile(&w.bins, &w.shifts, &w.time_fraction).map(|profile| EventProfile {
                t: w.t,
                direction: w.direction,
                profile,
            })
        })
        .collect();
    let groups: Vec<Vec<[f64; BINS]>> = [true, false]
        .iter()
        .map(|faster| {
            profiles.iter().filter(|p| speeds_up(p.direction) == *faster).map(|p| p.profile).collect::<Vec<_>>()
        })
        .filter(|g| g.len() >= 2)
        .collect();
    let compared: usize = groups.iter().map(Vec::len).sum();
    // the smallest p any pattern can give: the observed one and its flips within each group
    // give the same T, so at least 2^groups of the 2^compared patterns reach it
    let least_p = 2f64.powi(groups.len() as i32 - compared as i32);
    if !(least_p < ADEQUACY_LEVEL) {
        return Coherence::untestable(compared, profiles);
    }
    // unit profiles, flattened with their group index
    let unit: Vec<(usize, [f64; BINS])> = groups
        .iter()
        .enumerate()
        .flat_map(|(g, ps)| {
            ps.iter().filter_map(move |p| {
                let norm = p.iter().map(|x| x * x).sum::<f64>().sqrt();
                (norm > 0.0).then(|| (g, p.map(|x| x / norm)))
            })
        })
        .collect();
    let t_of = |signs: &dyn Fn(usize) -> f64| -> f64 {
        let mut sums = vec![[0.0; BINS]; groups.len()];
        for (e, (g, u)) in unit.iter().enumerate() {
            let s = signs(e);
            for b in 0..BINS {
                sums[*g][b] += s * u[b];
            }
        }
        sums.iter().map(|s| s.iter().map(|x| x * x).sum::<f64>()).sum()
    };
    let observed = t_of(&|_| 1.0);
    // a pattern reaches the observed T when it is not below it by more than round-off
    let reaches = |t: f64| t >= observed * (1.0 - 1e-12);
    let n = unit.len();
    let (hits, total) = if n < 64 && (1usize << n) <= SIGN_PATTERNS {
        let total = 1usize << n;
        let hits = (0..total).filter(|&m| reaches(t_of(&|e| if m >> e & 1 == 1 { -1.0 } else { 1.0 }))).count();
        (hits, total)
    } else {
        let mut rng = ChaCha8Rng::seed_from_u64(SIGN_SEED);
        let mut hits = 1; // the observed pattern itself
        for _ in 1..SIGN_PATTERNS {
            let flips: Vec<bool> = (0..n).map(|_| rng.random::<bool>()).collect();
            if reaches(t_of(&|e| if flips[e] { -1.0 } else { 1.0 })) {
                hits += 1;
            }
        }
        (hits, SIGN_PATTERNS)
    };
    let p_value = hits as f64 / total as f64;
    // excess: mean square about zero over the scatter about each kind's mean
    let (mut about_zero, mut about_mean) = (0.0, 0.0);
    for g in &groups {
        let k = g.len() as f64;
        let mut mean = [0.0; BINS];
        for p in g {
            for b in 0..BINS {
                mean[b] += p[b] / k;
            }
        }
        for p in g {
            about_zero += p.iter().map(|x| x * x).sum::<f64>();
            about_mean += p.iter().zip(&mean).map(|(x, m)| (x - m).powi(2)).sum::<f64>() * k / (k - 1.0);
        }
    }
    let excess = if about_mean > 0.0 { about_zero / about_mean } else { f64::NAN };
    let verdict = judged(p_value, excess, Family::ALONE);
    Coherence { verdict, p_value, excess, windows: profiles.len(), compared, profiles }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_distr::{Distribution, StandardNormal};

    /// Windows of noise, and of noise plus one shape in every window of a kind.
    fn windows(n: usize, common: f64, seed: u64) -> Vec<EventWindow> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let shape = [0.0, 1.0, 0.8, -0.3, -0.9, -0.2, 0.4];
        let frac = [5e-4, 2e-3, 6.5e-3, 2e-2, 6.5e-2, 0.2, 0.65];
        (0..n)
            .map(|i| {
                let bins: Bins = (0..BINS)
                    .map(|b| {
                        let e: f64 = StandardNormal.sample(&mut rng);
                        (b, common * shape[b] + e, 0.0)
                    })
                    .collect();
                EventWindow {
                    t: i as f64,
                    direction: if i % 2 == 0 { EventDirection::StepUp } else { EventDirection::StepDown },
                    bins,
                    shifts: vec![[0.0; BINS]],
                    time_fraction: frac,
                }
            })
            .collect()
    }

    /// Noise alone: p is spread over (0, 1] — at the 1 % level about 1 % of records.
    #[test]
    fn noise_alone_rarely_agrees() {
        let ps: Vec<f64> = (0..200).map(|s| coherence(&windows(12, 0.0, s)).p_value).collect();
        let below = ps.iter().filter(|p| **p < 0.05).count();
        assert!(below <= 20, "{below} of 200 below 0.05");
        assert!(ps.iter().filter(|p| **p > 0.5).count() > 70);
    }

    /// The same shape in every window, twice the noise in each bin: found.
    #[test]
    fn a_shape_repeated_at_every_event_is_found() {
        let c = coherence(&windows(12, 2.0, 7));
        assert_eq!(c.verdict, AdequacyVerdict::Inadequate, "{c:?}");
        assert!(c.p_value < 0.01 && c.excess > 2.0, "{c:?}");
    }

    /// Too few events of a kind to reach the level: untestable, never a verdict.
    #[test]
    fn a_few_events_are_untestable() {
        let c = coherence(&windows(6, 3.0, 1));
        assert_eq!(c.verdict, AdequacyVerdict::Untestable, "{c:?}");
    }
}
