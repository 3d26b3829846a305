//! A state law written in Python: a callable `theta_rate(v, theta, dc, b, stress_rate,
//! *params)` returning dθ/dt (s/s) — given `sigma` (MPa) and `sigma_rate` (MPa/s) by keyword
//! when its signature names `sigma` — used by every solver like a built-in law; registered
//! (`rsf.register_law`), by every fit and diagnosis too, its own parameters fitted.
//!
//! The slow path, on purpose: each right-hand side takes the GIL and calls Python once per
//! state variable (about 1 µs per call against ~20 ns for a Rust law), and implicit methods'
//! derivatives come from central differences of the callable (relative step 1e-6), not from dual
//! numbers. The first exception the callable raises is kept and re-raised after the solve.

use pyo3::prelude::*;
use rsf_core::{Jet, Real, StateArgs, StateLaw};
use std::sync::{Arc, Mutex};

/// A Python callable as a state law.
#[derive(Clone)]
pub struct PyLaw {
    f: Arc<Py<PyAny>>,
    name: String,
    /// The law's own parameters (passed after `stress_rate`, in this order).
    params: Vec<(&'static str, f64)>,
    /// The function takes `sigma` (MPa) and `sigma_rate` (MPa/s) by keyword.
    sigma: bool,
    /// The first error raised by the callable (re-raised after the solve).
    pub error: Arc<Mutex<Option<PyErr>>>,
}

impl std::fmt::Debug for PyLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PyLaw({})", self.name)
    }
}

impl PyLaw {
    /// Wraps `f`; `name` labels it in messages and output.
    pub fn new(f: Py<PyAny>, name: String) -> Self {
        // a function whose signature names `sigma` gets the normal stress and its rate by
        // keyword; one that does not is called as before
        let sigma = Python::attach(|py| {
            py.import("inspect")
                .and_then(|m| m.call_method1("signature", (f.bind(py),)))
                .and_then(|sig| sig.getattr("parameters"))
                .and_then(|p| p.contains("sigma"))
                .unwrap_or(false)
        });
        Self { f: Arc::new(f), name, params: vec![], sigma, error: Arc::new(Mutex::new(None)) }
    }

    /// The same law with its own parameters (name, value), passed after `stress_rate`.
    pub fn with_params(mut self, params: Vec<(&'static str, f64)>) -> Self {
        self.params = params;
        self
    }

    /// Calls the function at plain values; NaN (with the error kept) when it raises or
    /// returns something that is not a number.
    fn call(&self, s: &StateArgs<f64>) -> f64 {
        Python::attach(|py| {
            let mut args = vec![s.v, s.theta, s.dc, s.b, s.stress_rate];
            args.extend(self.params.iter().map(|p| p.1));
            let args = pyo3::types::PyTuple::new(py, args);
            let kwargs = if self.sigma {
                let d = pyo3::types::PyDict::new(py);
                d.set_item("sigma", s.normal_stress)
                    .and_then(|()| d.set_item("sigma_rate", s.normal_stress_rate))
                    .map(|()| Some(d))
            } else {
                Ok(None)
            };
            let r = args
                .and_then(|a| kwargs.and_then(|k| self.f.call(py, a, k.as_ref())))
                .and_then(|x| x.extract::<f64>(py));
            r.unwrap_or_else(|e| {
                let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
                if slot.is_none() {
                    *slot = Some(e);
                }
                f64::NAN
            })
        })
    }
}

impl StateLaw for PyLaw {
    /// Plain values only: the derivatives of a Python law come from [`jet`](Self::jet), by
    /// central differences, so this is never asked for dual numbers (their derivative parts
    /// would be zero).
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        R::from(self.call(&s.plain()))
    }

    fn name(&self) -> String {
        self.name.clone()
    }

    fn parameters(&self) -> Vec<(&'static str, f64)> {
        self.params.clone()
    }

    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        match self.params.iter_mut().find(|p| p.0 == name) {
            Some(p) => {
                p.1 = value;
                Ok(())
            }
            None => Err(format!("law `{}` has no parameter `{name}`", self.name)),
        }
    }

    fn jet(&self, s: &StateArgs<f64>) -> Jet {
        let g = |v: f64, theta: f64, dc: f64, b: f64, stress_rate: f64| {
            self.call(&StateArgs { v, theta, dc, b, stress_rate, ..*s })
        };
        let rate = g(s.v, s.theta, s.dc, s.b, s.stress_rate);
        let cd = |x: f64, f: &dyn Fn(f64) -> f64| {
            let h = 1e-6 * x.abs().max(1e-12);
            (f(x + h) - f(x - h)) / (2.0 * h)
        };
        let sr_scale = s.stress_rate.abs().max(1e-9);
        let d_sr = {
            let h = 1e-6 * sr_scale;
            (g(s.v, s.theta, s.dc, s.b, s.stress_rate + h) - g(s.v, s.theta, s.dc, s.b, s.stress_rate - h)) / (2.0 * h)
        };
        Jet {
            rate,
            d_v: cd(s.v, &|x| g(x, s.theta, s.dc, s.b, s.stress_rate)),
            d_theta: cd(s.theta, &|x| g(s.v, x, s.dc, s.b, s.stress_rate)),
            d_stress_rate: d_sr,
            d_dc: cd(s.dc, &|x| g(s.v, s.theta, x, s.b, s.stress_rate)),
            d_b: cd(s.b, &|x| g(s.v, s.theta, s.dc, x, s.stress_rate)),
        }
    }
}
