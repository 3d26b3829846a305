//! What a diverging quasi-static run reports: where it ran away, what the protocol did there,
//! and why a quasi-static model cannot follow it ([`SolveError::BlowUp`](crate::SolveError)).

/// Where a quasi-static run diverged: the piece of the loading, what the protocol did at its
/// start, and the states the solver last accepted.
#[derive(Debug, Clone, PartialEq)]
pub struct RunAway {
    /// 1-based piece (segment or record interval) in which it diverged.
    pub piece: usize,
    /// Start of that piece, s.
    pub t0: f64,
    /// Load-point velocity in that piece and in the one before it (`None` for the first),
    /// µm/s.
    pub v_lp: (Option<f64>, f64),
    /// Normal stress at the end of the piece before and at the start of this one, MPa.
    pub sigma: (Option<f64>, f64),
    /// Each state's law and θ (s) at the last accepted step.
    pub states: Vec<(String, f64)>,
}

impl RunAway {
    /// What the protocol did at the start of the piece, in words; a cause is guessed only from
    /// that.
    fn trigger(&self) -> String {
        let (v_before, v) = self.v_lp;
        let (s_before, s) = self.sigma;
        let mut what = vec![];
        if let Some(sb) = s_before.filter(|sb| s < *sb) {
            what.push(format!("the normal stress dropped from {sb} to {s} MPa at t = {} s", self.t0));
        }
        match v_before {
            Some(0.0) if v > 0.0 => what.push(format!("the load point restarted at {v} µm/s after a hold")),
            Some(vb) if v > vb => what.push(format!("the load point stepped up from {vb} to {v} µm/s")),
            _ => {}
        }
        if what.is_empty() {
            format!("nothing changed in the protocol at the start of piece {} (t = {} s)", self.piece, self.t0)
        } else {
            format!("at the start of piece {}, {}", self.piece, what.join(" and "))
        }
    }
}

impl std::fmt::Display for RunAway {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let states: Vec<String> =
            self.states.iter().enumerate().map(|(i, (law, th))| format!("θ{} = {th:.3e} s ({law})", i + 1)).collect();
        write!(
            f,
            "in piece {} (V_lp = {} µm/s; last accepted {}); {}",
            self.piece,
            self.v_lp.1,
            states.join(", "),
            self.trigger()
        )
    }
}

/// Why a quasi-static run diverges, in words.
pub(crate) fn blow_up_reason(k: f64, kc: f64) -> String {
    if k < kc {
        format!(
            "the quasi-static system is unstable (stiffness {k} < critical stiffness ≈ {kc:.3e} 1/µm); \
             add radiation damping (eta) to follow the slip event"
        )
    } else {
        format!(
            "friction rose past what sliding can carry although the stiffness {k} is above the critical ≈ {kc:.3e} \
             1/µm (a linear estimate: a law whose state collapses faster than the Aging law's can run away above \
             it); a quasi-static model cannot follow it: add radiation damping (eta), or soften what the protocol \
             does there"
        )
    }
}
