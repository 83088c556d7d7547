//! geoslip from Python: the engine in-process (no subprocess), its results as NumPy arrays.
//!
//! `Model` holds a parsed model file and its check; `Model.run` runs it with the GIL released,
//! writing the CLI's results folder (to `out`, or to a temporary one), and returns the history, the
//! fields of every converged step, the events and the summary. Ctrl-C stops the run at the next
//! converged step: the `KeyboardInterrupt` raised carries the completed steps as `.results`.

use geoslip::analysis::results::StepResults;
use geoslip::analysis::RunStats;
use geoslip::analysis::{Collect, RunOptions, StepRecord, StepSink};
use geoslip::linsol::Backend;
use geoslip::model::file::ModelFile;
use geoslip::output::ResultWriter;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::{Path, PathBuf};

create_exception!(
    geoslip,
    ModelError,
    PyException,
    "A model file that cannot be read, parsed or checked: the message names the file, the field and the entity."
);
create_exception!(
    geoslip,
    CalibrationError,
    PyException,
    "A calibration that gave no parameters: unreadable curves or file (named with the line and column), \
     parameters the data cannot identify (named), or a fit that did not converge."
);
create_exception!(
    geoslip,
    RunError,
    PyException,
    "A run that failed: no equilibrium, a singular system, a solver or output error."
);

/// A model file, parsed, and what its check found.
#[pyclass(module = "geoslip", frozen)]
struct Model {
    source: PathBuf,
    checked: Result<geoslip::model::Model, Vec<String>>,
}

fn model_error(e: geoslip::Error) -> PyErr {
    ModelError::new_err(e.to_string())
}

fn checked(source: &Path, file: &ModelFile) -> Result<geoslip::model::Model, Vec<String>> {
    geoslip::model::Model::from_file(source, file)
        .map_err(|e| e.problems.iter().map(|p| format!("{}: {p}", e.file.display())).collect())
}

#[pymethods]
impl Model {
    /// Read a model file (TOML, or JSON when it ends in .json). A file that cannot be read or
    /// parsed raises ModelError; the problems of one that parses are listed by `check()`.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        let text = geoslip::model::read_text(&path).map_err(model_error)?;
        let file = geoslip::model::parse(&path, &text).map_err(model_error)?;
        let checked = checked(&path, &file);
        Ok(Model { source: path, checked })
    }

    /// A model from the JSON text of a dict in the model file's schema (`geoslip.Model.from_dict`
    /// makes it); `name` names it in messages, and relative paths in it (a mesh file) are taken
    /// from the current folder.
    #[staticmethod]
    #[pyo3(signature = (text, name = "model.json".to_string()))]
    fn from_json(text: &str, name: String) -> PyResult<Self> {
        let path = PathBuf::from(if name.ends_with(".json") { name } else { format!("{name}.json") });
        let file = geoslip::model::parse(&path, text).map_err(model_error)?;
        let checked = checked(&path, &file);
        Ok(Model { source: path, checked })
    }

    /// Every problem the check found, as `geoslip check` prints them; empty when the model is fine.
    fn check(&self) -> Vec<String> {
        match &self.checked {
            Ok(_) => Vec::new(),
            Err(problems) => problems.clone(),
        }
    }

    /// The file the model came from (or the name it was given).
    #[getter]
    fn source(&self) -> PathBuf {
        self.source.clone()
    }

    /// Run every stage. `solver`: auto, mumps, umfpack, faer or dense. `out`: the results folder
    /// to write (as `geoslip run --out`; a temporary one when None). `progress`: called after each
    /// converged step with (stage, step, load_factor). Returns the results (see `Results`).
    #[pyo3(signature = (solver = "auto", out = None, progress = None))]
    fn run(
        &self,
        py: Python<'_>,
        solver: &str,
        out: Option<PathBuf>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<PyObject> {
        let model = match &self.checked {
            Ok(m) => m,
            Err(problems) => {
                return Err(ModelError::new_err(format!(
                    "{}: {} problem{} in the model\n  {}",
                    self.source.display(),
                    problems.len(),
                    if problems.len() == 1 { "" } else { "s" },
                    problems.join("\n  ")
                )))
            }
        };
        let backend = parse_backend(solver)?;
        if !Backend::available().contains(&backend.resolve()) {
            return Err(PyValueError::new_err(format!("solver \"{solver}\" is not built into this geoslip")));
        }
        let temporary = match out {
            Some(_) => None,
            None => {
                Some(tempfile::tempdir().map_err(|e| RunError::new_err(format!("a temporary results folder: {e}")))?)
            }
        };
        let folder = out.unwrap_or_else(|| temporary.as_ref().expect("made above").path().to_path_buf());
        let options = RunOptions::for_model(model, backend);
        let mut writer = ResultWriter::new(model, &folder, backend.resolve().name())
            .map_err(|e| RunError::new_err(e.to_string()))?;
        let targets = writer.targets();
        let mut observer = Observer { steps: Collect::default(), progress, stop: None, source: self.source.clone() };
        let result = py.allow_threads(|| geoslip::output::write_run(model, &options, None, &mut writer, &mut observer));
        let summary = std::fs::read_to_string(folder.join("summary.json")).unwrap_or_else(|_| "{}".into());
        let results = results(py, model, &observer.steps, &targets, &summary, result.is_ok())?;
        // a wall's design checks (docs/design-checks.md), when the model asks for them
        if let Ok(checks) = std::fs::read_to_string(folder.join("design-checks.csv")) {
            results.bind(py).set_item("design_checks_csv", checks)?;
        }
        // the dynamic stages' histories (docs/dynamics.md), when the model has any
        if let Ok(motion) = std::fs::read_to_string(folder.join("motion.csv")) {
            results.bind(py).set_item("motion_csv", motion)?;
        }
        match (result, observer.stop) {
            (Ok(_), _) => Ok(results),
            (Err(_), Some(stop)) => {
                // Ctrl-C (or the progress callback's own exception): raised with the steps kept
                let _ = stop.value(py).setattr("results", results);
                Err(stop)
            }
            (Err(e), None) => {
                let err = match e {
                    geoslip::Error::Read { .. } | geoslip::Error::Parse { .. } | geoslip::Error::Model(_) => {
                        ModelError::new_err(e.to_string())
                    }
                    _ => RunError::new_err(e.to_string()),
                };
                let _ = err.value(py).setattr("results", results);
                Err(err)
            }
        }
    }
}

fn parse_backend(name: &str) -> PyResult<Backend> {
    Ok(match name {
        "auto" => Backend::Auto,
        "mumps" => Backend::Mumps,
        "umfpack" => Backend::Umfpack,
        "faer" => Backend::Faer,
        "dense" => Backend::Dense,
        other => {
            return Err(PyValueError::new_err(format!("solver \"{other}\": one of auto, mumps, umfpack, faer, dense")))
        }
    })
}

/// Keeps each converged step, reports it to the progress callback and looks for Ctrl-C.
struct Observer {
    steps: Collect,
    progress: Option<Py<PyAny>>,
    stop: Option<PyErr>,
    source: PathBuf,
}

impl StepSink for Observer {
    fn step_done(
        &mut self,
        model: &geoslip::model::Model,
        step: &StepResults,
        record: &StepRecord,
        stats: &RunStats,
    ) -> Result<(), geoslip::Error> {
        self.steps.step_done(model, step, record, stats)?;
        let stopped = Python::with_gil(|py| -> PyResult<()> {
            if let Some(callback) = &self.progress {
                callback.call1(py, (record.stage.clone(), record.step, record.load_factor))?;
            }
            py.check_signals()
        });
        match stopped {
            Ok(()) => Ok(()),
            Err(e) => {
                let reason = Python::with_gil(|py| {
                    if e.is_instance_of::<PyKeyboardInterrupt>(py) {
                        "interrupted (Ctrl-C)".to_string()
                    } else {
                        format!("the progress callback raised {e}")
                    }
                });
                self.stop = Some(e);
                Err(geoslip::Error::Stopped { file: self.source.clone(), steps: self.steps.steps.len(), reason })
            }
        }
    }

    fn factor_of_safety(&mut self, fs: &geoslip::analysis::FactorOfSafety) -> Result<(), geoslip::Error> {
        self.steps.factor_of_safety(fs)
    }
}

fn array<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// An n × k array from rows.
fn table<'py, const K: usize>(py: Python<'py>, rows: impl Iterator<Item = [f64; K]>) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.flat_map(|r| r.into_iter()).collect();
    let n = flat.len() / K;
    Ok(PyArray1::from_vec(py, flat).reshape([n, K])?.into_any())
}

fn ids<'py>(py: Python<'py>, v: impl Iterator<Item = u64>) -> Bound<'py, PyArray1<u64>> {
    PyArray1::from_vec(py, v.collect())
}

/// The results as Python objects: a `geoslip.Results` made by the Python side from a dict.
fn results(
    py: Python<'_>,
    model: &geoslip::model::Model,
    collected: &Collect,
    targets: &[(String, &'static str, Vec<usize>)],
    summary: &str,
    completed: bool,
) -> PyResult<PyObject> {
    let out = PyDict::new(py);
    // the history: per target, each converged step's stage, step, load factor, displacement
    // (mean over its nodes) and reaction (sum), as history.csv has them
    let history = PyDict::new(py);
    for (label, direction, nodes) in targets {
        let d = |n: usize| 2 * n + if *direction == "x" { 0 } else { 1 };
        let entry = PyDict::new(py);
        let steps = &collected.steps;
        entry.set_item("stage", PyList::new(py, steps.iter().map(|(r, _)| r.stage.clone()))?)?;
        entry.set_item("step", ids(py, steps.iter().map(|(r, _)| r.step as u64)))?;
        entry.set_item("load_factor", array(py, steps.iter().map(|(r, _)| r.load_factor).collect()))?;
        entry.set_item(
            "displacement",
            array(
                py,
                steps
                    .iter()
                    .map(|(_, s)| nodes.iter().map(|&n| s.displacement_vector[d(n)]).sum::<f64>() / nodes.len() as f64)
                    .collect(),
            ),
        )?;
        entry.set_item(
            "reaction",
            array(py, steps.iter().map(|(_, s)| nodes.iter().map(|&n| s.reaction_vector[d(n)]).sum::<f64>()).collect()),
        )?;
        history.set_item(format!("{label} ({direction})"), entry)?;
    }
    out.set_item("history", history)?;
    let steps = PyList::empty(py);
    for (record, s) in &collected.steps {
        let step = PyDict::new(py);
        step.set_item("stage", record.stage.clone())?;
        step.set_item("step", record.step)?;
        step.set_item("load_factor", record.load_factor)?;
        step.set_item("iterations", record.iterations)?;
        let nodes = PyDict::new(py);
        nodes.set_item("id", ids(py, s.displacements.iter().map(|(n, _, _)| *n)))?;
        nodes.set_item("x", table(py, s.displacements.iter().map(|(_, x, _)| *x))?)?;
        nodes.set_item("u", table(py, s.displacements.iter().map(|(_, _, u)| *u))?)?;
        step.set_item("nodes", nodes)?;
        let bars = PyDict::new(py);
        bars.set_item("id", ids(py, s.bar_forces.iter().map(|b| b.bar)))?;
        bars.set_item("nodes", ids(py, s.bar_forces.iter().flat_map(|b| b.nodes)).reshape([s.bar_forces.len(), 2])?)?;
        bars.set_item("x", table(py, s.bar_forces.iter().map(|b| b.midpoint))?)?;
        bars.set_item("T", array(py, s.bar_forces.iter().map(|b| b.axial_force).collect()))?;
        bars.set_item("state", PyList::new(py, s.bar_forces.iter().map(|b| b.state))?)?;
        step.set_item("bars", bars)?;
        let p = &s.interface_points;
        let interface = PyDict::new(py);
        interface.set_item("interface", PyList::new(py, p.iter().map(|p| p.interface.clone()))?)?;
        interface.set_item("face", PyList::new(py, p.iter().map(|p| p.face.clone()))?)?;
        interface.set_item("node", ids(py, p.iter().map(|p| p.slave_node)))?;
        interface.set_item("x", table(py, p.iter().map(|p| p.x))?)?;
        interface.set_item("state", PyList::new(py, p.iter().map(|p| p.state))?)?;
        interface.set_item("tributary", array(py, p.iter().map(|p| p.tributary).collect()))?;
        interface.set_item("lambda", array(py, p.iter().map(|p| p.lambda).collect()))?;
        interface.set_item("sigma_n", array(py, p.iter().map(|p| p.sigma_n).collect()))?;
        interface.set_item("tau", array(py, p.iter().map(|p| p.tau).collect()))?;
        interface.set_item("bearing", array(py, p.iter().map(|p| p.bearing).collect()))?;
        interface.set_item("dilation", array(py, p.iter().map(|p| p.dilation).collect()))?;
        interface.set_item("slip", array(py, p.iter().map(|p| p.slip).collect()))?;
        interface.set_item("sliding", PyList::new(py, p.iter().map(|p| p.sliding))?)?;
        step.set_item("interface", interface)?;
        let g = s.stresses(model);
        let soil = PyDict::new(py);
        soil.set_item("element", ids(py, g.iter().map(|g| g.element)))?;
        soil.set_item("point", ids(py, g.iter().map(|g| g.point as u64)))?;
        soil.set_item("x", table(py, g.iter().map(|g| g.x))?)?;
        soil.set_item("stress", table(py, g.iter().map(|g| g.stress))?)?;
        soil.set_item("strain", table(py, g.iter().map(|g| g.strain))?)?;
        soil.set_item("pore_pressure", array(py, g.iter().map(|g| g.pore_pressure).collect()))?;
        soil.set_item("plastic_strain", array(py, g.iter().map(|g| g.plastic_strain).collect()))?;
        step.set_item("soil", soil)?;
        steps.append(step)?;
    }
    out.set_item("steps", steps)?;
    let fs = PyList::empty(py);
    for f in &collected.factors_of_safety {
        let d = PyDict::new(py);
        d.set_item("stage", f.stage.clone())?;
        d.set_item("value", f.value)?;
        d.set_item("failed_at", f.failed_at)?;
        fs.append(d)?;
    }
    out.set_item("factors_of_safety", fs)?;
    out.set_item("summary_json", summary)?;
    out.set_item("completed", completed)?;
    let u = model.unit_labels();
    let units = PyDict::new(py);
    units.set_item("length", u.length)?;
    units.set_item("force", u.force)?;
    units.set_item("force_per_width", u.force_per_width)?;
    units.set_item("stress", u.stress)?;
    out.set_item("units", units)?;
    Ok(out.into_any().unbind())
}

/// Fit an interface law to measured curves: `path` is a calibration file (TOML), or, with `text`,
/// the name the JSON text of a dict in its schema goes by (its `data` taken from the folder of
/// `path`). The fit runs with the GIL released; `out` (optional) receives what `geoslip calibrate`
/// writes. Returns the calibration as JSON text (`geoslip.calibrate` makes it an object).
#[pyfunction]
#[pyo3(signature = (path, text = None, out = None))]
fn calibrate(py: Python<'_>, path: PathBuf, text: Option<String>, out: Option<PathBuf>) -> PyResult<String> {
    use geoslip::calibration::{self, report, spec};
    let fail = |e: calibration::CalibrationError| CalibrationError::new_err(e.to_string());
    let spec = match text {
        None => spec::load(&path).map_err(fail)?,
        Some(text) => {
            let file: spec::CalibrationFile = serde_json::from_str(&text)
                .map_err(|e| CalibrationError::new_err(format!("{}: {e}", path.display())))?;
            spec::check(&path, file).map_err(fail)?
        }
    };
    let c = py.allow_threads(|| calibration::calibrate(&spec)).map_err(fail)?;
    if let Some(out) = out {
        report::write(&c, &out).map_err(fail)?;
    }
    let mut json = report::json(&c);
    json["law_spec"] = serde_json::to_value(c.law()).unwrap_or_default();
    Ok(json.to_string())
}

#[pymodule]
fn _geoslip(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Model>()?;
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    m.add("CalibrationError", m.py().get_type::<CalibrationError>())?;
    m.add("ModelError", m.py().get_type::<ModelError>())?;
    m.add("RunError", m.py().get_type::<RunError>())?;
    m.add("backends", Backend::available().iter().map(|b| b.name()).collect::<Vec<_>>())?;
    Ok(())
}
