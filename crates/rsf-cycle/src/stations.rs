//! The SEAS on-fault station files `fltst_dpXXX`: t (s), slip (m), log10 V (m/s), shear
//! stress (MPa), log10 θ (s), sampled about every 0.1 yr between events and every 0.1 s in
//! them (the benchmark's guidance), at the 12 depths of BP1-QD.

use std::io::Write;

/// BP1-QD station depths, m.
pub const DEPTHS: [f64; 12] = [0.0, 2.5e3, 5e3, 7.5e3, 10e3, 12.5e3, 15e3, 17.5e3, 20e3, 25e3, 30e3, 35e3];

/// Sampling interval between events, s (0.1 yr).
pub const INTERSEISMIC_DT: f64 = 0.1 * crate::YEAR;
/// Sampling interval in events, s.
pub const SEISMIC_DT: f64 = 0.1;

/// Rows of every station, in memory until written.
#[derive(Clone, Debug, Default)]
pub struct Stations {
    rows: Vec<Vec<[f64; 5]>>,
    last: Option<f64>,
}

/// The value at depth `z` from cell-centre values `f(i)` (cells of size `dz`): linear between
/// centres, extrapolated linearly from the two shallowest cells above the first centre.
pub fn at_depth(z: f64, dz: f64, n: usize, f: impl Fn(usize) -> f64) -> f64 {
    let s = (z / dz - 0.5).clamp(0.0 - 0.5, (n - 1) as f64);
    let i = (s.floor().max(0.0) as usize).min(n - 2);
    let w = s - i as f64;
    (1.0 - w) * f(i) + w * f(i + 1)
}

impl Stations {
    /// Empty files for the 12 depths.
    pub fn new() -> Self {
        Self { rows: vec![Vec::new(); DEPTHS.len()], last: None }
    }

    /// Whether a row is due at `t`.
    pub fn due(&self, t: f64, seismic: bool) -> bool {
        self.last.is_none_or(|l| t - l >= if seismic { SEISMIC_DT } else { INTERSEISMIC_DT })
    }

    /// Records a row per station: `value(z)` returns (slip, ln V, shear stress Pa, ln θ) at depth z.
    pub fn record(&mut self, t: f64, value: impl Fn(f64) -> (f64, f64, f64, f64)) {
        for (rows, &z) in self.rows.iter_mut().zip(&DEPTHS) {
            let (slip, ln_v, tau, ln_theta) = value(z);
            rows.push([t, slip, ln_v / std::f64::consts::LN_10, tau / 1e6, ln_theta / std::f64::consts::LN_10]);
        }
        self.last = Some(t);
    }

    /// Writes `dir/fltst_dpXXX` (XXX: depth in hundreds of metres).
    pub fn write(&self, dir: &std::path::Path, header: &str) -> std::io::Result<()> {
        for (rows, &z) in self.rows.iter().zip(&DEPTHS) {
            let name = format!("fltst_dp{:03}", (z / 100.0).round() as i64);
            let mut w = std::io::BufWriter::new(std::fs::File::create(dir.join(name))?);
            writeln!(w, "# {header}")?;
            writeln!(w, "# location = on-fault, {:.1} km depth", z / 1e3)?;
            writeln!(w, "t slip slip_rate shear_stress state")?;
            for r in rows {
                writeln!(w, "{:.15e} {:.15e} {:.15e} {:.15e} {:.15e}", r[0], r[1], r[2], r[3], r[4])?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_interpolation_and_surface_extrapolation() {
        // f linear in depth: exact everywhere, the surface included
        let (dz, n) = (100.0, 50);
        let f = |i: usize| 3.0 + 0.01 * (i as f64 + 0.5) * dz;
        for z in [0.0, 50.0, 123.0, 2500.0, 4950.0] {
            assert!((at_depth(z, dz, n, f) - (3.0 + 0.01 * z)).abs() < 1e-9, "z {z}");
        }
    }
}
