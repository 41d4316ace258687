//! A loaded mechanism: its declaration text, its parameter values, and the interpreted
//! system derived from them (with the robotics routines: inverse dynamics, frames and
//! Jacobians). A model is immutable; a call's `set={...}` runs on a copy. It pickles to its
//! text and values, so a Ray task or a Dask delayed function can take one: unpickling
//! derives it again.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};

use mechanism::{Interpreted, Kinematic, System};
use mechanism_codegen::{Tangents, UrdfOptions, urdf_to_mech};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::errors::{declaration, did_you_mean, input};
use crate::sources;

/// A mechanism loaded by [`load`]: see the module docs.
#[pyclass(module = "mechanism", frozen)]
pub struct Model {
    /// The declaration text (for a URDF, the declaration `mechanism import` writes).
    pub(crate) source: String,
    /// How messages name it: the path or the built-in name.
    pub(crate) shown: String,
    /// Parameter values, in declaration order.
    pub(crate) values: Vec<f64>,
    /// The interpreted system at `values`, with the robotics routines, without tangents.
    pub(crate) system: Arc<Interpreted>,
    /// The same with the residual's tangent, for HHT, derived on first use.
    pub(crate) implicit: OnceLock<Arc<Interpreted>>,
    /// The same with every derivative of the dynamics (`Tangents::Derivatives`), derived
    /// on first use.
    pub(crate) derivatives: OnceLock<Arc<Interpreted>>,
    /// Unique among the models of this process (the per-thread buffers' key).
    pub(crate) id: u64,
}

/// The next [`Model::id`].
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// Derives `source` (shown as `shown` in messages) through the interpreter route.
pub(crate) fn derive(
    source: &str,
    shown: &str,
    tangents: Tangents,
    robotics: bool,
) -> PyResult<Interpreted> {
    let model = mechanism_codegen::parse_model_str(source).map_err(|e| declaration(shown, &e))?;
    Interpreted::from_model_with(model, tangents, robotics).map_err(|e| declaration(shown, &e))
}

/// The declaration text `spec` names and how messages show it: a URDF file (`.urdf`,
/// imported with `lock`, `damping` and `floating`), a `.mech` file, or a built-in name.
fn read(spec: &str, lock: &[String], damping: bool, floating: bool) -> PyResult<(String, String)> {
    let path = std::path::Path::new(spec);
    let urdf = spec.ends_with(".urdf");
    if !urdf && (!lock.is_empty() || damping || floating) {
        return Err(input(format!(
            "load {spec}: `lock`, `damping` and `floating` apply to a URDF file (a path ending \
             in .urdf)"
        )));
    }
    let is_file = urdf || spec.ends_with(".mech") || spec.contains('/') || path.is_file();
    if !is_file {
        return match sources::source(spec) {
            Some(text) => Ok((text.to_string(), spec.to_string())),
            None => {
                let names: Vec<String> = sources::BUILTIN
                    .iter()
                    .map(|(n, _)| n.to_string())
                    .collect();
                Err(input(format!(
                    "unknown mechanism `{spec}`{}; available: {} (or a path to a .mech or \
                     .urdf file)",
                    did_you_mean(spec, &names),
                    names.join(", ")
                )))
            }
        };
    }
    let text =
        std::fs::read_to_string(path).map_err(|e| input(format!("cannot read {spec}: {e}")))?;
    if !urdf {
        return Ok((text, spec.to_string()));
    }
    let options = UrdfOptions {
        file_name: spec.to_string(),
        lock: lock.to_vec(),
        damping,
        floating,
        ..UrdfOptions::default()
    };
    let mech = urdf_to_mech(&text, &options)
        .map_err(|e| crate::errors::DeclarationError::new_err(e.to_string()))?;
    Ok((mech, spec.to_string()))
}

impl Model {
    /// The model of `source` with the parameters `set` (name -> value) changed from their
    /// declared values, checked like declared ones.
    pub(crate) fn build(source: String, shown: String, set: &[(String, f64)]) -> PyResult<Self> {
        let mut system = derive(&source, &shown, Tangents::None, true)?;
        apply(&mut system, &source, &shown, set)?;
        let mut values = vec![0.0; system.info().parameters.len()];
        system.parameter_values(&mut values);
        Ok(Self {
            source,
            shown,
            values,
            system: Arc::new(system),
            implicit: OnceLock::new(),
            derivatives: OnceLock::new(),
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        })
    }

    /// The system at the model's values with `tangents` compiled (and the robotics routines),
    /// kept in `slot` once derived.
    fn with_tangents(
        &self,
        slot: &OnceLock<Arc<Interpreted>>,
        tangents: Tangents,
    ) -> PyResult<Arc<Interpreted>> {
        if let Some(s) = slot.get() {
            return Ok(s.clone());
        }
        let mut s = derive(&self.source, &self.shown, tangents, true)?;
        for (i, v) in self.values.iter().enumerate() {
            // The model's own values, accepted when it was built.
            s.set_parameter(i, *v).map_err(|e| input(e.to_string()))?;
        }
        Ok(slot.get_or_init(|| Arc::new(s)).clone())
    }

    /// The system with every derivative of the dynamics (`derivatives.rs`).
    pub(crate) fn system_with_derivatives(&self) -> PyResult<Arc<Interpreted>> {
        self.with_tangents(&self.derivatives, Tangents::Derivatives)
    }

    /// The system for a run: with the residual's tangent when `implicit` (HHT), with
    /// `set` applied on a copy.
    pub(crate) fn system_for(
        &self,
        implicit: bool,
        set: &[(String, f64)],
    ) -> PyResult<Interpreted> {
        let base = if implicit {
            self.with_tangents(&self.implicit, Tangents::Residual)?
        } else {
            self.system.clone()
        };
        let mut system = (*base).clone();
        apply(&mut system, &self.source, &self.shown, set)?;
        Ok(system)
    }

    /// The named parameter values of this model with `set` in place, for a declaration
    /// built again at them (linearisation).
    pub(crate) fn named_values(&self, set: &[(String, f64)]) -> PyResult<Vec<(String, f64)>> {
        let info = self.system.info();
        let mut named: Vec<(String, f64)> = info
            .parameters
            .iter()
            .cloned()
            .zip(self.values.iter().copied())
            .collect();
        for (name, value) in set {
            let k = parameter_index(&self.system, name)?;
            check_finite("set", name, *value)?;
            named[k].1 = *value;
        }
        Ok(named)
    }

    /// The index of frame `frame` (a name or an index).
    pub(crate) fn frame(&self, frame: &Bound<'_, PyAny>) -> PyResult<usize> {
        let frames = &self.system.info().frames;
        if let Ok(k) = frame.extract::<usize>() {
            return if k < frames.len() {
                Ok(k)
            } else {
                Err(input(format!(
                    "frame {k}: the model has {} link frame(s)",
                    frames.len()
                )))
            };
        }
        let name: String = frame.extract()?;
        self.system.info().frame_index(&name).ok_or_else(|| {
            input(if frames.is_empty() {
                format!("frame `{name}`: the model declares no link frames")
            } else {
                format!(
                    "unknown frame `{name}`{}; frames: {}",
                    did_you_mean(&name, frames),
                    frames.join(", ")
                )
            })
        })
    }
}

fn parameter_index(system: &Interpreted, name: &str) -> PyResult<usize> {
    let info = system.info();
    info.parameter_index(name).ok_or_else(|| {
        input(format!(
            "set: unknown parameter `{name}`{}; parameters: {}",
            did_you_mean(name, &info.parameters),
            info.parameters.join(", ")
        ))
    })
}

fn check_finite(what: &str, name: &str, value: f64) -> PyResult<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(input(format!(
            "{what} {name}: the value must be finite, got {value}"
        )))
    }
}

/// Sets the parameters `set` on `system` and checks the values like declared ones (a body's
/// mass not negative, its inertia possible, its orientation a rotation), as the
/// command-line tool's `--set` does.
fn apply(
    system: &mut Interpreted,
    source: &str,
    shown: &str,
    set: &[(String, f64)],
) -> PyResult<()> {
    if set.is_empty() {
        return Ok(());
    }
    for (name, value) in set {
        let k = parameter_index(system, name)?;
        check_finite("set", name, *value)?;
        let range = system.info().parameter_range(k);
        system.set_parameter(k, *value).map_err(|_| {
            input(format!(
                "set {name}={value}: `{name}` must be {} (its declaration says `{}`), got {value}",
                range.describe(),
                range.keyword()
            ))
        })?;
    }
    let info = system.info();
    let mut values = vec![0.0; info.parameters.len()];
    system.parameter_values(&mut values);
    let named: Vec<(&str, f64)> = info
        .parameters
        .iter()
        .map(String::as_str)
        .zip(values)
        .collect();
    mechanism_codegen::check_parameter_values(source, &named).map_err(|e| {
        let given: Vec<String> = set.iter().map(|(n, v)| format!("{n}={v}")).collect();
        input(format!(
            "set {}: {}",
            given.join(", "),
            crate::errors::located(shown, &e)
        ))
    })
}

/// `{name: value}` as pairs, in the dict's order.
pub(crate) fn pairs(set: Option<HashMap<String, f64>>) -> Vec<(String, f64)> {
    let mut v: Vec<(String, f64)> = set.unwrap_or_default().into_iter().collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

/// Loads a mechanism: a built-in name (`mechanism.builtin_names()`), a `.mech` file, or a
/// URDF file (`.urdf`) imported at run time with the joints `lock` fixed at 0, when
/// `damping` its joints' damping as viscous forces, and when `floating` its root link free
/// (a free flyer). `set` changes parameters from their declared values. The declaration is
/// derived at once (a declaration error is raised here) and the derivation runs without
/// the GIL. A declaration with a floating root gives a `FloatingModel`, any other a
/// `Model`.
#[pyfunction]
#[pyo3(signature = (name_or_path, *, lock = None, set = None, damping = false, floating = false))]
pub fn load(
    py: Python<'_>,
    name_or_path: &str,
    lock: Option<Vec<String>>,
    set: Option<HashMap<String, f64>>,
    damping: bool,
    floating: bool,
) -> PyResult<Py<PyAny>> {
    let lock = lock.unwrap_or_default();
    let set = pairs(set);
    let built = py.detach(|| {
        let (source, shown) = read(name_or_path, &lock, damping, floating)?;
        either(source, shown, &set)
    })?;
    built.into_py(py)
}

/// A model of either kind, before it is handed to Python.
enum Built {
    Fixed(Model),
    Floating(Box<crate::floating::FloatingModel>),
}

impl Built {
    fn into_py(self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(match self {
            Built::Fixed(m) => Py::new(py, m)?.into_any(),
            Built::Floating(m) => Py::new(py, *m)?.into_any(),
        })
    }
}

/// `source` as a `FloatingModel` when its root floats, else as a `Model`.
fn either(source: String, shown: String, set: &[(String, f64)]) -> PyResult<Built> {
    if crate::floating::is_floating(&source) {
        crate::floating::build(&source, &shown, set).map(|m| Built::Floating(Box::new(m)))
    } else {
        Model::build(source, shown, set).map(Built::Fixed)
    }
}

/// The model of a declaration text given directly; `name` shows it in messages (a
/// `FloatingModel` when its root floats).
#[pyfunction]
#[pyo3(signature = (text, *, name = "<text>", set = None))]
pub fn from_source(
    py: Python<'_>,
    text: String,
    name: &str,
    set: Option<HashMap<String, f64>>,
) -> PyResult<Py<PyAny>> {
    let set = pairs(set);
    let name = name.to_string();
    let built = py.detach(|| either(text, name, &set))?;
    built.into_py(py)
}

/// What unpickling calls: the model of `source` with every parameter at `values`.
#[pyfunction]
pub fn _restore(
    py: Python<'_>,
    source: String,
    shown: String,
    values: Vec<f64>,
) -> PyResult<Model> {
    py.detach(|| {
        let mut model = Model::build(source, shown, &[])?;
        let mut system = (*model.system).clone();
        for (i, v) in values.iter().enumerate() {
            system
                .set_parameter(i, *v)
                .map_err(|e| input(format!("unpickling {}: {e}", model.shown)))?;
        }
        model.values = values;
        model.system = Arc::new(system);
        Ok(model)
    })
}

/// The names `load` takes without a path, in `mechanism list`'s order.
#[pyfunction]
pub fn builtin_names() -> Vec<&'static str> {
    sources::BUILTIN.iter().map(|(n, _)| *n).collect()
}

/// The pickling half of [`Model`]: `(mechanism._native._restore, (source, shown, values))`.
pub(crate) fn reduce<'py>(model: &Model, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
    let restore = py.import("mechanism._native")?.getattr("_restore")?;
    let args = (
        model.source.clone(),
        model.shown.clone(),
        model.values.clone(),
    );
    PyTuple::new(py, [restore, args.into_pyobject(py)?.into_any()])
}
