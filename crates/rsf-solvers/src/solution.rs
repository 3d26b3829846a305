//! The solution of a forward problem and its CSV forms.

use crate::ode::{StepStats, Tolerances};
use crate::watch::SlipEvent;
use serde::Serialize;

/// A solved forward problem: columns at the output times, and the work done.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Solution {
    /// Time, s.
    pub time: Vec<f64>,
    /// Load-point displacement, µm.
    pub load_point: Vec<f64>,
    /// Friction τ (shear stress over normal stress carried by the spring; = f(V, θ) + ηV).
    pub mu: Vec<f64>,
    /// Slip rate V, µm/s.
    pub slip_rate: Vec<f64>,
    /// Slip δ, µm (0 at the start).
    pub slip: Vec<f64>,
    /// θ_i, s: `theta[i][row]`.
    pub theta: Vec<Vec<f64>>,
    /// Integrator work.
    pub stats: StepStats,
    /// Integrator name.
    pub method: String,
    /// Tolerances used.
    pub tolerances: Option<Tolerances>,
    /// The largest slip rate since the previous row, µm/s, per row (empty unless
    /// [`crate::WatchOptions::peak_slip_rate`]).
    pub peak_slip_rate: Vec<f64>,
    /// Slip events (empty unless [`crate::WatchOptions::event_slip_rate`]).
    pub events: Vec<SlipEvent>,
    /// Normal stress σ, MPa, per row (empty when σ is constant).
    pub normal_stress: Vec<f64>,
}

impl Solution {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.time.len()
    }
    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Writes the CSV `time_s,load_point_um,mu,slip_rate_um_s,slip_um,theta_1_s[,theta_2_s…]`,
    /// then `peak_slip_rate_um_s` when watched and `normal_stress_mpa` when σ varies, with
    /// shortest round-trip number formatting (`zmij`: exact, and fast enough that writing
    /// does not dominate a solve).
    pub fn write_csv<W: std::io::Write>(&self, w: W) -> std::io::Result<()> {
        use std::io::Write;
        let mut w = std::io::BufWriter::with_capacity(1 << 16, w);
        write!(w, "time_s,load_point_um,mu,slip_rate_um_s,slip_um")?;
        for i in 0..self.theta.len() {
            write!(w, ",theta_{}_s", i + 1)?;
        }
        let peak = self.peak_slip_rate.len() == self.len() && !self.peak_slip_rate.is_empty();
        if peak {
            write!(w, ",peak_slip_rate_um_s")?;
        }
        let sigma = self.normal_stress.len() == self.len() && !self.normal_stress.is_empty();
        if sigma {
            write!(w, ",normal_stress_mpa")?;
        }
        writeln!(w)?;
        let mut buf = zmij::Buffer::new();
        let mut ibuf = itoa::Buffer::new();
        let mut line: Vec<u8> = Vec::with_capacity(256);
        let mut num = |line: &mut Vec<u8>, x: f64| {
            // integers print without a fraction (0 rather than 0.0)
            if x == x.trunc() && x.abs() < 1e15 {
                line.extend_from_slice(ibuf.format(x as i64).as_bytes());
            } else {
                line.extend_from_slice(buf.format(x).as_bytes());
            }
        };
        for r in 0..self.len() {
            line.clear();
            for (j, x) in [self.time[r], self.load_point[r], self.mu[r], self.slip_rate[r], self.slip[r]]
                .into_iter()
                .chain(self.theta.iter().map(|t| t[r]))
                .chain(peak.then(|| self.peak_slip_rate[r]))
                .chain(sigma.then(|| self.normal_stress[r]))
                .enumerate()
            {
                if j > 0 {
                    line.push(b',');
                }
                num(&mut line, x);
            }
            line.push(b'\n');
            w.write_all(&line)?;
        }
        w.flush()
    }
}

impl Solution {
    /// The event catalogue as CSV: `onset_s,end_s,peak_slip_rate_um_s,peak_time_s,slip_um`
    /// (an event still running at the end has an empty `end_s`).
    pub fn write_events_csv<W: std::io::Write>(&self, mut w: W) -> std::io::Result<()> {
        writeln!(w, "onset_s,end_s,peak_slip_rate_um_s,peak_time_s,slip_um")?;
        for e in &self.events {
            let end = e.end_s.map(|t| format!("{t:?}")).unwrap_or_default();
            writeln!(w, "{:?},{end},{:?},{:?},{:?}", e.onset_s, e.peak_slip_rate, e.peak_time_s, e.slip_um)?;
        }
        Ok(())
    }
}
