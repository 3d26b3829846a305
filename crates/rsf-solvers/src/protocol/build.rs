//! The one validator: the raw fields of a protocol (`raw.rs`) to a [`Protocol`], each error
//! naming the field and, where the field has a span, its line.

use super::raw::*;
use super::*;
use crate::WatchOptions;
use crate::solve::OutputTimes;
use rsf_core::{FrictionForm, Loading, Model, ModelError, Segment, StateVariable};
use std::collections::HashMap;

/// The one validator: raw fields (from text or memory) to a [`Protocol`], each error naming the
/// field and, where the field has a span, its line (`line_of`).
pub(super) fn build<W: Wrap>(
    raw: RawFile<W>,
    base: Option<&Path>,
    file: &str,
    line_of: &dyn Fn(&Range<usize>) -> usize,
) -> Result<Protocol, ProtocolError> {
    let err = |span: Option<&Range<usize>>, field: &str, message: String| ProtocolError {
        file: file.to_string(),
        line: span.map(line_of),
        field: if field.is_empty() { None } else { Some(field.to_string()) },
        message,
    };

    // ---- law files
    if let Some(files) = &raw.law_files {
        for f in files.get() {
            let path = match base {
                Some(b) => b.join(f),
                None => PathBuf::from(f),
            };
            rsf_laws::text_law::register_file(&path).map_err(|m| err(files.span().as_ref(), "law_files", m))?;
        }
    }

    // ---- model
    let rm = raw.model.get();
    let mut spans: HashMap<String, Option<Range<usize>>> = HashMap::new();
    let mut put = |k: &str, s: &W::Of<f64>| {
        spans.insert(k.to_string(), s.span());
        *s.get()
    };
    let mut model =
        Model::new(put("mu0", &rm.mu0), put("v0", &rm.v0), put("a", &rm.a), put("stiffness", &rm.stiffness));
    if let Some(eta) = &rm.eta {
        model.eta = put("eta", eta);
    }
    if let Some(a_slope) = &rm.a_slope {
        model.a_slope = put("a_slope", a_slope);
    }
    if let Some(sn) = &rm.normal_stress {
        model.normal_stress = Some(put("normal_stress", sn));
    }
    if let Some(form) = &rm.form {
        model.form = match form.get().as_str() {
            "classic" => FrictionForm::Classic,
            "regularized" => FrictionForm::Regularized,
            other => {
                return Err(err(
                    form.span().as_ref(),
                    "model.form",
                    format!("unknown form `{other}`; use \"classic\" or \"regularized\""),
                ));
            }
        };
    }
    let states = rm.state.as_deref().unwrap_or(&[]);
    if states.is_empty() {
        return Err(err(
            raw.model.span().as_ref(),
            "model.state",
            "at least one [[model.state]] table is required".into(),
        ));
    }
    let mut state_spans = Vec::new();
    for (i, st) in states.iter().enumerate() {
        let table = st.get();
        let field = format!("model.state[{}]", i + 1);
        let whole = st.span();
        let number = |key: &str| -> Result<Option<Located64>, ProtocolError> {
            let Some(v) = table.get(key) else { return Ok(None) };
            match v.get() {
                toml::Value::Float(x) => Ok(Some((*x, v.span()))),
                toml::Value::Integer(x) => Ok(Some((*x as f64, v.span()))),
                other => Err(err(
                    v.span().as_ref(),
                    &format!("{field}.{key}"),
                    format!("expected a number, found {}", other.type_str()),
                )),
            }
        };
        let required = |key: &str| -> Result<Located64, ProtocolError> {
            number(key)?.ok_or_else(|| err(whole.as_ref(), &field, format!("missing field `{key}`")))
        };
        let (law_name, law_span) = match table.get("law") {
            Some(v) => match v.get() {
                toml::Value::String(s) => (s.clone(), v.span()),
                other => {
                    return Err(err(
                        v.span().as_ref(),
                        &format!("{field}.law"),
                        format!("expected a law name, found {}", other.type_str()),
                    ));
                }
            },
            None => return Err(err(whole.as_ref(), &field, "missing field `law`".into())),
        };
        let entry =
            rsf_laws::registry::find(&law_name).map_err(|m| err(law_span.as_ref(), &format!("{field}.law"), m))?;
        for (key, v) in table {
            if !STATE_FIELDS.contains(&key.as_str()) && entry.parameter(key).is_none() {
                let own: Vec<&str> = entry.parameters().iter().map(|p| p.name).collect();
                return Err(err(
                    v.span().as_ref(),
                    &format!("{field}.{key}"),
                    format!(
                        "`{key}` does not apply to law `{law_name}` (a state has law, b, dc, alpha{}{})",
                        if own.is_empty() { "" } else { " and the law's own " },
                        own.join(", ")
                    ),
                ));
            }
        }
        let mut own = Vec::new();
        for p in entry.parameters() {
            let value = number(p.name)?;
            if let Some((x, span)) = &value {
                p.check(*x).map_err(|m| err(span.as_ref(), &format!("{field}.{}", p.name), m))?;
            }
            own.push((p.name, value.map(|x| x.0)));
        }
        let law = entry
            .build(|p| own.iter().find(|o| o.0 == p).and_then(|o| o.1))
            .map_err(|m| err(law_span.as_ref(), &format!("{field}.law"), m))?;
        let (b, b_span) = required("b")?;
        let (dc, dc_span) = required("dc")?;
        if entry.builtin() == Some(rsf_laws::Law::Nagata) && b == 0.0 {
            return Err(err(
                b_span.as_ref(),
                &format!("{field}.b"),
                "Nagata's law divides by b; b must not be 0".into(),
            ));
        }
        spans.insert(format!("state[{}].b", i + 1), b_span);
        spans.insert(format!("state[{}].dc", i + 1), dc_span);
        state_spans.push(whole);
        let mut sv = StateVariable::from_shared(law, b, dc);
        if let Some((alpha, alpha_span)) = number("alpha")? {
            spans.insert(format!("state[{}].alpha", i + 1), alpha_span);
            sv.alpha = alpha;
        }
        model.states.push(sv);
    }
    if let Err(e) = model.validate() {
        return Err(match &e {
            ModelError::Parameter { name, .. } => {
                err(spans.get(name).and_then(Option::as_ref), &format!("model.{name}"), e.to_string())
            }
            ModelError::Law { index, .. } => err(
                state_spans.get(index - 1).and_then(Option::as_ref),
                &format!("model.state[{index}]"),
                e.to_string(),
            ),
            ModelError::NoState => err(None, "model.state", e.to_string()),
        });
    }

    // ---- loading
    let rl = raw.loading.get();
    let v_init = *rl.v_init.get();
    if !(v_init > 0.0 && v_init.is_finite()) {
        return Err(err(
            rl.v_init.span().as_ref(),
            "loading.v_init",
            format!("{v_init} must be positive and finite (µm/s)"),
        ));
    }
    let mut measured_friction = None;
    let mut record_path: Option<PathBuf> = None;
    let mut normal_stress = None;
    let (loading, is_record) = match (&rl.segment, &rl.record) {
        (Some(_), Some(r)) => {
            return Err(err(
                r.span().as_ref(),
                "loading.record",
                "give either [[loading.segment]] tables or a record, not both".into(),
            ));
        }
        (None, None) => {
            return Err(err(
                raw.loading.span().as_ref(),
                "loading",
                "needs [[loading.segment]] tables or a `record`".into(),
            ));
        }
        (Some(segs), None) => {
            let mut out = Vec::new();
            for (i, sg) in segs.iter().enumerate() {
                let s = sg.get();
                let field = format!("loading.segment[{}]", i + 1);
                let end = match (&s.duration, &s.displacement) {
                    (Some(d), None) => Segment::for_duration(*s.v.get(), *d.get()),
                    (None, Some(x)) => Segment::for_displacement(*s.v.get(), *x.get()),
                    (Some(_), Some(x)) => {
                        return Err(err(
                            x.span().as_ref(),
                            &field,
                            "give exactly one of `duration` and `displacement`, not both".into(),
                        ));
                    }
                    (None, None) => {
                        return Err(err(
                            sg.span().as_ref(),
                            &field,
                            "needs `duration` (s) or `displacement` (µm)".into(),
                        ));
                    }
                };
                end.duration().map_err(|m| err(sg.span().as_ref(), &field, m))?;
                let mut end = end;
                if let Some(sn) = &s.normal_stress {
                    end.normal_stress = Some(*sn.get());
                }
                if let Some(r) = &s.normal_stress_rate {
                    end.normal_stress_rate = *r.get();
                }
                if end.changes_normal_stress() && model.normal_stress.is_none() {
                    let span = s.normal_stress.as_ref().or(s.normal_stress_rate.as_ref()).and_then(|x| x.span());
                    return Err(err(
                        span.as_ref(),
                        &field,
                        "changes the normal stress: give `normal_stress` (σ_ref, MPa) in [model]".into(),
                    ));
                }
                out.push(end);
            }
            if out.is_empty() {
                return Err(err(raw.loading.span().as_ref(), "loading.segment", "the protocol has no segments".into()));
            }
            (Loading::Segments(out), false)
        }
        (None, Some(r)) => {
            let rel = PathBuf::from(r.get());
            let path = match base {
                Some(b) if rel.is_relative() => b.join(&rel),
                _ => rel,
            };
            let tcol = rl.time_column.as_deref().unwrap_or("time_s");
            let lcol = rl.load_point_column.as_deref().unwrap_or("load_point_um");
            let cols = RecordColumns {
                time: tcol,
                load_point: lcol,
                friction: rl.friction_column.as_deref(),
                normal_stress: rl.normal_stress_column.as_deref(),
            };
            let read = read_load_record(&path, &cols).map_err(|m| err(r.span().as_ref(), "loading.record", m))?;
            record_path = Some(path.clone());
            measured_friction = read.friction;
            if let Some(sn) = read.normal_stress {
                if model.normal_stress.is_none() {
                    // σ_ref defaults to the record's first normal stress
                    model.normal_stress = Some(sn[0]);
                }
                normal_stress = Some(rsf_core::NormalStressRecord { time: read.load.time.clone(), sigma: sn });
            }
            (Loading::Record(read.load), true)
        }
    };

    // ---- output
    let dt = raw.output.as_ref().and_then(|o| o.get().dt.as_ref());
    let output = match dt {
        Some(dt) => {
            let v = *dt.get();
            if !(v > 0.0 && v.is_finite()) {
                return Err(err(dt.span().as_ref(), "output.dt", format!("{v} must be positive and finite (s)")));
            }
            OutputTimes::Every(v)
        }
        None if is_record => match &loading {
            Loading::Record(r) => OutputTimes::Times(r.time.clone()),
            Loading::Segments(_) => unreachable!("is_record"),
        },
        None => {
            let span = raw.output.as_ref().and_then(|o| o.span());
            return Err(err(span.as_ref(), "output.dt", "required: the output sampling interval in s".into()));
        }
    };

    // ---- initial state
    let (v_init, initial_theta) = match &raw.initial {
        None => (v_init, None),
        Some(ini) => {
            let ini = ini.get();
            let v = *ini.v.get();
            if !(v > 0.0 && v.is_finite()) {
                return Err(err(ini.v.span().as_ref(), "initial.v", format!("{v} must be positive and finite (µm/s)")));
            }
            let theta = ini.theta.get().clone();
            let n = model.states.len();
            if theta.len() != n || theta.iter().any(|t| !(*t > 0.0 && t.is_finite())) {
                return Err(err(
                    ini.theta.span().as_ref(),
                    "initial.theta",
                    format!("needs {n} positive, finite values (s), one per state variable (got {theta:?})"),
                ));
            }
            (v, Some(theta))
        }
    };

    // ---- solver
    let (mut method_name, mut rtol, mut atol, mut vmax) =
        (DEFAULT_METHOD.to_string(), DEFAULT_RTOL, DEFAULT_ATOL, crate::solve::MAX_SLIP_RATE);
    let mut method_span = None;
    if let Some(s) = &raw.solver {
        if let Some(m) = &s.method {
            method_name = m.get().clone();
            method_span = m.span();
        }
        if let Some(r) = &s.rtol {
            rtol = *r.get();
            crate::Tolerances { rtol, atol: DEFAULT_ATOL }
                .check()
                .map_err(|m| err(r.span().as_ref(), "solver.rtol", m))?;
        }
        if let Some(a) = &s.atol {
            atol = *a.get();
            crate::Tolerances { rtol: DEFAULT_RTOL, atol }
                .check()
                .map_err(|m| err(a.span().as_ref(), "solver.atol", m))?;
        }
        if let Some(v) = &s.max_slip_rate {
            vmax = *v.get();
            if !(vmax > v_init) {
                return Err(err(
                    v.span().as_ref(),
                    "solver.max_slip_rate",
                    format!("{vmax} must exceed v_init = {v_init}"),
                ));
            }
        }
    }
    let method = Method::from_name(&method_name, rtol, atol).ok_or_else(|| {
        err(
            method_span.as_ref(),
            "solver.method",
            format!("unknown method `{method_name}`; use one of {}", Method::NAMES.join(", ")),
        )
    })?;
    let watch = match raw.output.as_ref().map(|o| o.get()) {
        None => WatchOptions::default(),
        Some(o) => {
            let event_slip_rate = match &o.event_slip_rate {
                None => None,
                Some(v) if *v.get() > 0.0 && v.get().is_finite() => Some(*v.get()),
                Some(v) => {
                    return Err(err(
                        v.span().as_ref(),
                        "output.event_slip_rate",
                        format!("{} must be positive and finite (µm/s)", v.get()),
                    ));
                }
            };
            WatchOptions { peak_slip_rate: o.peak_slip_rate.unwrap_or(false), event_slip_rate }
        }
    };
    let problem = Problem { model, loading, v_init, initial_theta, output, max_slip_rate: vmax, watch, normal_stress };
    problem.pieces().map_err(|e| err(raw.loading.span().as_ref(), "loading", e.to_string()))?;
    Ok(Protocol { problem, method, measured_friction, record: record_path })
}
