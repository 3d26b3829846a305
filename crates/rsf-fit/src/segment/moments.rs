//! Centred moments of runs of samples: exact, stable merging (Chan et al.) for line fits.

/// Centred moments of a run of samples (t, x).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Moments {
    pub(super) n: f64,
    pub(super) mt: f64,
    pub(super) mx: f64,
    pub(super) stt: f64,
    pub(super) sxx: f64,
    pub(super) stx: f64,
}

impl Moments {
    pub(super) fn of(t: &[f64], x: &[f64]) -> Self {
        let mut m = Moments::default();
        for (&ti, &xi) in t.iter().zip(x) {
            m = m.merge(&Moments { n: 1.0, mt: ti, mx: xi, ..Default::default() });
        }
        m
    }
    pub(super) fn merge(&self, o: &Moments) -> Moments {
        if self.n == 0.0 {
            return *o;
        }
        let n = self.n + o.n;
        let (dt, dx) = (o.mt - self.mt, o.mx - self.mx);
        let f = self.n * o.n / n;
        Moments {
            n,
            mt: self.mt + dt * o.n / n,
            mx: self.mx + dx * o.n / n,
            stt: self.stt + o.stt + dt * dt * f,
            sxx: self.sxx + o.sxx + dx * dx * f,
            stx: self.stx + o.stx + dt * dx * f,
        }
    }
    /// Residual sum of squares of the least-squares line.
    pub(super) fn sse(&self) -> f64 {
        if self.stt > 0.0 { (self.sxx - self.stx * self.stx / self.stt).max(0.0) } else { self.sxx }
    }
    pub(super) fn slope(&self) -> f64 {
        if self.stt > 0.0 { self.stx / self.stt } else { 0.0 }
    }
    /// Standard error of the slope given noise variance `s2`.
    pub(super) fn slope_se(&self, s2: f64) -> f64 {
        if self.stt > 0.0 { (s2 / self.stt).sqrt() } else { f64::INFINITY }
    }
}
