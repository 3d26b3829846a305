//! Friction forms and state laws by their C ids, checked once per call.

use crate::{RSF_ABI_VERSION, RsfFrictionParams, RsfLaw, RsfStateParams, RsfStatus, fail};
use rsf_core::element::{Friction, cutoff_friction, cutoff_psi_term, friction, psi_term};
use rsf_core::{FrictionForm, LnArgs, StateArgs, StateLaw};
use rsf_laws::{Aging, AgingNoHealing, KatoTullis, Law, Prz, Slip};

/// A friction form of this ABI: one of rsf-core's, or the cut-off form (whose parameters,
/// V1 and each state's V2, travel in the existing fields).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Form {
    Core(FrictionForm),
    Cutoff,
}

impl Form {
    /// Friction and its partials at `x = ln V` for the state contribution `psi`.
    pub(crate) fn friction(self, p: &RsfFrictionParams, x: f64, psi: f64) -> Friction {
        match self {
            Form::Core(form) => friction(form, p.f0, p.a, p.v0, x, psi),
            Form::Cutoff => cutoff_friction(p.f0, p.a, p.v0, x, psi),
        }
    }

    /// One state's contribution to Ψ at `z = ln θ` and its partial ∂/∂ln θ (`scale` is the
    /// law's θ scale).
    pub(crate) fn state_term(self, p: &RsfFrictionParams, s: &RsfStateParams, scale: f64, z: f64) -> (f64, f64) {
        match self {
            Form::Core(_) => (psi_term(s.b, p.v0, s.dc, scale, z), s.b),
            Form::Cutoff => cutoff_psi_term(s.b, s.vc, s.dc, scale, z),
        }
    }

    /// Refuses a state this form cannot read: under the cut-off form, `vc` is the state's
    /// V2, so it must be positive and cannot also be a Kato–Tullis cut-off.
    pub(crate) fn check_state(self, s: &RsfStateParams) -> Result<(), RsfStatus> {
        match self {
            Form::Core(_) => Ok(()),
            Form::Cutoff if s.law == RsfLaw::RsfLawKatoTullis as i32 => Err(fail(
                RsfStatus::RsfBadInput,
                "the cut-off form reads each state's vc as its V2; a Kato-Tullis state (whose vc is its own) cannot \
                 be used with it"
                    .into(),
            )),
            Form::Cutoff if !(s.vc.is_finite() && s.vc > 0.0) => Err(fail(
                RsfStatus::RsfBadInput,
                format!("the cut-off form needs each state's vc = V2 > 0 (got {})", s.vc),
            )),
            Form::Cutoff => Ok(()),
        }
    }

    /// The rsf-core form for the slip-rate solve; the cut-off form has none.
    pub(crate) fn core(self, call: &str) -> Result<FrictionForm, RsfStatus> {
        match self {
            Form::Core(form) => Ok(form),
            Form::Cutoff => Err(fail(
                RsfStatus::RsfBadInput,
                format!("{call}: the cut-off form (2) has no slip-rate solve in this ABI version"),
            )),
        }
    }
}

pub(crate) fn form_of(p: &RsfFrictionParams) -> Result<Form, RsfStatus> {
    if p.version != RSF_ABI_VERSION {
        return Err(fail(
            RsfStatus::RsfBadInput,
            format!("RsfFrictionParams.version {} (expected {RSF_ABI_VERSION})", p.version),
        ));
    }
    if ![p.f0, p.a, p.v0].iter().all(|x| x.is_finite()) || p.a <= 0.0 || p.v0 <= 0.0 {
        return Err(fail(
            RsfStatus::RsfBadInput,
            format!("friction parameters need finite f0, a > 0, v0 > 0 (got {p:?})"),
        ));
    }
    match p.form {
        0 => Ok(Form::Core(FrictionForm::Classic)),
        1 => Ok(Form::Core(FrictionForm::Regularized)),
        2 => Ok(Form::Cutoff),
        id => Err(fail(
            RsfStatus::RsfUnknownId,
            format!("unknown friction form id {id} (0 classic, 1 regularized, 2 cut-off)"),
        )),
    }
}

/// A state law of this ABI, checked once, dispatched without a virtual call.
#[derive(Clone, Copy, Debug)]
pub(crate) enum AbiLaw {
    Aging,
    Slip,
    KatoTullis { vc: f64 },
    Prz,
    NoHealing,
}

impl AbiLaw {
    /// The law of `s`, after checking the struct's version, b, Dc and the law's own parameter.
    pub(crate) fn of(s: &RsfStateParams) -> Result<Self, RsfStatus> {
        if s.version != RSF_ABI_VERSION {
            return Err(fail(
                RsfStatus::RsfBadInput,
                format!("RsfStateParams.version {} (expected {RSF_ABI_VERSION})", s.version),
            ));
        }
        if !(s.b.is_finite() && s.dc.is_finite() && s.dc > 0.0) {
            return Err(fail(RsfStatus::RsfBadInput, format!("state parameters need finite b and dc > 0 (got {s:?})")));
        }
        let Some(law) = Law::from_c_id(s.law) else {
            let known: Vec<String> = Law::ALL.iter().map(|l| format!("{} {}", l.c_id(), l.name())).collect();
            return Err(fail(RsfStatus::RsfUnknownId, format!("unknown law id {} ({})", s.law, known.join(", "))));
        };
        match law {
            Law::Aging => Ok(AbiLaw::Aging),
            Law::Slip => Ok(AbiLaw::Slip),
            Law::KatoTullis if s.vc.is_finite() && s.vc > 0.0 => Ok(AbiLaw::KatoTullis { vc: s.vc }),
            Law::KatoTullis => Err(fail(RsfStatus::RsfBadInput, format!("Kato–Tullis needs vc > 0 (got {})", s.vc))),
            Law::Prz => Ok(AbiLaw::Prz),
            Law::AgingNoHealing => Ok(AbiLaw::NoHealing),
            // this ABI's rates take no shear-stress rate, which Nagata's law needs
            Law::Nagata => Err(fail(
                RsfStatus::RsfUnknownId,
                "law id 4 (nagata) needs the shear-stress rate, which this ABI version does not carry".into(),
            )),
            Law::AgingSlip => {
                Err(fail(RsfStatus::RsfUnknownId, "law id 5 (aging-slip) is not carried by this ABI version".into()))
            }
        }
    }

    /// The law's θ scale s in Ψ = b ln(V0 θ/(s Dc)).
    pub(crate) fn theta_scale(self) -> f64 {
        match self {
            AbiLaw::Aging => Aging.theta_scale(),
            AbiLaw::Slip => Slip.theta_scale(),
            AbiLaw::KatoTullis { vc } => KatoTullis { vc }.theta_scale(),
            AbiLaw::Prz => Prz.theta_scale(),
            AbiLaw::NoHealing => AgingNoHealing.theta_scale(),
        }
    }

    /// d ln θ/dt at prepared arguments.
    #[inline]
    pub(crate) fn ln_rate(self, a: &LnArgs) -> f64 {
        match self {
            AbiLaw::Aging => Aging.ln_theta_rate(a),
            AbiLaw::Slip => Slip.ln_theta_rate(a),
            AbiLaw::KatoTullis { vc } => KatoTullis { vc }.ln_theta_rate(a),
            AbiLaw::Prz => Prz.ln_theta_rate(a),
            AbiLaw::NoHealing => AgingNoHealing.ln_theta_rate(a),
        }
    }

    /// dθ/dt in the plain variables, V and θ of either sign: each law's closed form as written
    /// (`StateLaw::theta_rate`), so outside V > 0, θ > 0 it is the formula's continuation where
    /// the formula is defined (Aging's 1 − Vθ/Dc) and NaN where it is not (Slip's ln Ω).
    #[inline]
    pub(crate) fn rate(self, v: f64, theta: f64, dc: f64, b: f64) -> f64 {
        let s = StateArgs::new(v, theta, dc, b);
        match self {
            AbiLaw::Aging => Aging.theta_rate(&s),
            AbiLaw::Slip => Slip.theta_rate(&s),
            AbiLaw::KatoTullis { vc } => KatoTullis { vc }.theta_rate(&s),
            AbiLaw::Prz => Prz.theta_rate(&s),
            AbiLaw::NoHealing => AgingNoHealing.theta_rate(&s),
        }
    }
}

/// Calls `f` with the law of `s` (its d ln θ/dt at (ln V, ln θ) and its θ scale), after
/// checking it.
pub(crate) fn with_law<T>(
    s: &RsfStateParams,
    f: impl FnOnce(&dyn Fn(f64, f64) -> f64, f64) -> T,
) -> Result<T, RsfStatus> {
    let law = AbiLaw::of(s)?;
    let (b, dc) = (s.b, s.dc);
    Ok(f(&|x, z| law.ln_rate(&LnArgs::new(x, z, dc, b)), law.theta_scale()))
}

/// The logarithm of the last value asked for, kept: elements of a fault usually share V0 and
/// Dc, so a batch call takes their logs once instead of once per element (same numbers).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LnMemo {
    x: f64,
    ln: f64,
}

impl Default for LnMemo {
    fn default() -> Self {
        LnMemo { x: f64::NAN, ln: f64::NAN }
    }
}

impl LnMemo {
    #[inline]
    pub(crate) fn ln(&mut self, x: f64) -> f64 {
        if x.to_bits() != self.x.to_bits() {
            self.refresh(x);
        }
        self.ln
    }

    /// The miss path, out of line: inlined, the optimiser computes the (side-effect-free) log
    /// before the comparison and keeps the memo from saving anything.
    #[cold]
    #[inline(never)]
    fn refresh(&mut self, x: f64) {
        (self.x, self.ln) = (x, x.ln());
    }
}
