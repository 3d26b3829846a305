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
    /// then `peak_slip_rate_um_s` when watched and `normal_stress_mpa` when σ varies: shortest
    /// round-trip numbers (every value reads back exactly), integers without a fraction, in
    /// blocks of rows through one buffer.
    pub fn write_csv<W: std::io::Write>(&self, mut w: W) -> std::io::Result<()> {
        let layout = CsvLayout::of(self);
        let mut buf = Vec::with_capacity(1 << 16);
        layout.header(&mut buf);
        const BLOCK: usize = 512;
        for start in (0..self.len()).step_by(BLOCK) {
            layout.rows(self, start..(start + BLOCK).min(self.len()), &mut buf);
            w.write_all(&buf)?;
            buf.clear();
        }
        w.write_all(&buf)?;
        w.flush()
    }
}

/// The columns of a solution's CSV and their formatting: shortest round-trip numbers
/// (`zmij`: exact, and fast enough that writing does not dominate a solve), integers without
/// a fraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CsvLayout {
    /// Number of θ columns.
    pub(crate) n_theta: usize,
    /// Whether there is a `peak_slip_rate_um_s` column.
    pub(crate) peak: bool,
    /// Whether there is a `normal_stress_mpa` column.
    pub(crate) normal_stress: bool,
}

impl CsvLayout {
    /// The layout of `sol`'s rows.
    pub(crate) fn of(sol: &Solution) -> Self {
        let full = |v: &Vec<f64>| !v.is_empty() && v.len() == sol.len();
        Self { n_theta: sol.theta.len(), peak: full(&sol.peak_slip_rate), normal_stress: full(&sol.normal_stress) }
    }

    /// Appends the header line.
    pub(crate) fn header(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(b"time_s,load_point_um,mu,slip_rate_um_s,slip_um");
        for i in 0..self.n_theta {
            out.extend_from_slice(format!(",theta_{}_s", i + 1).as_bytes());
        }
        if self.peak {
            out.extend_from_slice(b",peak_slip_rate_um_s");
        }
        if self.normal_stress {
            out.extend_from_slice(b",normal_stress_mpa");
        }
        out.push(b'\n');
    }

    /// Appends rows `range` of `sol` (which must have this layout).
    pub(crate) fn rows(&self, sol: &Solution, range: std::ops::Range<usize>, out: &mut Vec<u8>) {
        let mut buf = zmij::Buffer::new();
        let mut ibuf = itoa::Buffer::new();
        let mut line = Line { buf: [0; 512], len: 0 };
        // the columns in order, sliced to the range once (no per-value bounds checks or
        // iterator chains in the row loop)
        let mut cols: Vec<&[f64]> = vec![&sol.time, &sol.load_point, &sol.mu, &sol.slip_rate, &sol.slip];
        cols.extend(sol.theta.iter().map(|t| t.as_slice()));
        if self.peak {
            cols.push(&sol.peak_slip_rate);
        }
        if self.normal_stress {
            cols.push(&sol.normal_stress);
        }
        let cols: Vec<&[f64]> = cols.into_iter().map(|c| &c[range.clone()]).collect();
        for r in 0..range.len() {
            for (j, col) in cols.iter().enumerate() {
                if j > 0 {
                    line.put(b",", out);
                }
                let x = col[r];
                // integers print without a fraction (0 rather than 0.0); the round trip through
                // i64 tests integrality without a call to `trunc` (a libm call on baseline x86-64)
                let i = x as i64;
                if i as f64 == x && x.abs() < 1e15 {
                    line.put(ibuf.format(i).as_bytes(), out);
                } else {
                    line.put(buf.format(x).as_bytes(), out);
                }
            }
            line.put(b"\n", out);
            out.extend_from_slice(&line.buf[..line.len]);
            line.len = 0;
        }
    }
}

/// A CSV row assembled on the stack and appended to the output in one copy. Why: appending
/// each number with `extend_from_slice` is a `memcpy` call per number, 5% of `rsf simulate` on
/// the seed protocol; the short fixed-size copies below compile to plain moves.
struct Line {
    buf: [u8; 512],
    len: usize,
}

impl Line {
    /// Appends `s`, handing the row so far to `out` when the buffer would overflow.
    #[inline(always)]
    fn put(&mut self, s: &[u8], out: &mut Vec<u8>) {
        let n = s.len();
        if self.len + n.max(32) > self.buf.len() {
            out.extend_from_slice(&self.buf[..self.len]);
            self.len = 0;
        }
        let d = &mut self.buf[self.len..];
        // two overlapping copies of a fixed size cover any length in their range
        match n {
            0 => {}
            1..=3 => {
                d[0] = s[0];
                d[n / 2] = s[n / 2];
                d[n - 1] = s[n - 1];
            }
            4..=7 => {
                d[..4].copy_from_slice(&s[..4]);
                d[n - 4..n].copy_from_slice(&s[n - 4..]);
            }
            8..=15 => {
                d[..8].copy_from_slice(&s[..8]);
                d[n - 8..n].copy_from_slice(&s[n - 8..]);
            }
            16..=32 => {
                d[..16].copy_from_slice(&s[..16]);
                d[n - 16..n].copy_from_slice(&s[n - 16..]);
            }
            _ => {
                // longer than any number: hand over the row so far first, to keep the order
                out.extend_from_slice(&self.buf[..self.len]);
                self.len = 0;
                out.extend_from_slice(s);
                return;
            }
        }
        self.len += n;
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
