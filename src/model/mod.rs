//! The model: read a file, check every part of it, and build the mesh, interfaces and loading
//! history that the analysis runs on.

mod dynamic_plan;
pub mod file;
pub mod ground_motion;
pub mod import;
mod parse;
pub mod problems;
mod rows;
mod side;
mod soil_laws;
mod validate;

pub use crate::element::soil_state::WaterTable;
use crate::error::{Error, ModelError};
use crate::interface::Interface;
use crate::mesh::{Mesh, NodeIndex};
use crate::timing::Phase;
pub use dynamic_plan::{AbsorbingSide, DynamicPlan, HalfSpace};
pub use parse::{parse, read_text, read_text_within};
pub use side::LoadedSide;
// The `[analysis]` settings are checked as the file gives them: the run reads them from here.
pub use file::{AnalysisSettings, Extrapolation, ReassociationRule, Scheme};
use file::{Direction, ModelFile, ReinforcementMaterial, SoilMaterial, Units};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A checked model, ready to analyse.
#[derive(Debug, Clone)]
pub struct Model {
    pub source: PathBuf,
    pub title: String,
    pub units: Units,
    pub mesh: Mesh,
    pub soils: Vec<(String, SoilMaterial)>,
    pub reinforcements: Vec<(String, ReinforcementMaterial)>,
    pub node_sets: BTreeMap<String, Vec<NodeIndex>>,
    /// Named element sets: indices into `mesh.solids`.
    pub element_sets: BTreeMap<String, Vec<usize>>,
    /// Permanent zero-displacement supports.
    pub supports: Vec<(NodeIndex, Direction)>,
    pub interfaces: Vec<Interface>,
    pub stages: Vec<StagePlan>,
    /// Things worth knowing that do not stop a run.
    pub notes: Vec<String>,
    pub analysis: file::AnalysisSettings,
    /// The Gmsh mesh the nodes and elements came from, when the model names one.
    pub mesh_source: Option<import::MeshRecord>,
    /// How long reading, parsing, importing the mesh and checking this model took, phase by phase
    /// (only the checks for a model made in memory).
    pub load_times: Vec<Phase>,
    /// The wall its `[design]` table describes, for the design checks.
    pub design: Option<crate::design::Wall>,
}

/// One run of a model file.
#[derive(Debug, Clone)]
pub struct Case {
    /// `<load>-<value>` for a run of a series; `None` for a model without one.
    pub label: Option<String>,
    /// The series' load name.
    pub load: Option<String>,
    /// The series value of this run.
    pub value: Option<f64>,
    /// The checked model, kept for a model without a series and for a series' first run.
    model: Option<Model>,
    /// The file a series' runs are made from.
    series: Option<std::sync::Arc<SeriesBase>>,
}

impl Case {
    /// The checked model of this run: the one kept, or, for a series' later runs, made again from
    /// the file (it was checked when the cases were made).
    ///
    /// # Errors
    /// As [`Model::load`] (a `.geo` mesh is meshed again, and Gmsh may fail the second time).
    pub fn model(&self) -> Result<std::borrow::Cow<'_, Model>, Error> {
        match (&self.model, &self.series, &self.load, self.value) {
            (Some(m), ..) => Ok(std::borrow::Cow::Borrowed(m)),
            (None, Some(base), Some(load), Some(value)) => Ok(std::borrow::Cow::Owned(base.model_at(load, value)?)),
            _ => unreachable!("a case keeps its model or can make it"),
        }
    }
}

/// What a series' runs are made from.
#[derive(Debug)]
struct SeriesBase {
    path: PathBuf,
    file: ModelFile,
    options: LoadOptions,
}

impl SeriesBase {
    /// The run of the series at `value` of the load named `load`.
    fn model_at(&self, load: &str, value: f64) -> Result<Model, Error> {
        let mut f = self.file.clone();
        f.series = None;
        for stage in &mut f.stages {
            for spec in &mut stage.loads {
                if let file::LoadSpec::EdgeTraction { name: Some(n), pressure, .. } = spec {
                    if n == load {
                        *pressure = value;
                    }
                }
            }
        }
        Model::from_file_with(&self.path, &f, self.options).map_err(Error::Model)
    }
}

#[derive(Debug, Clone)]
pub enum Load {
    EdgeTraction {
        sides: Vec<LoadedSide>,
        pressure: f64,
        shear: f64,
    },
    Point {
        node: NodeIndex,
        force: [f64; 2],
    },
    Gravity {
        factor: f64,
    },
    /// The soil's weight times (kh, kv) as a body force.
    PseudoStatic {
        coefficients: [f64; 2],
    },
}

#[derive(Debug, Clone, Default)]
pub struct StagePlan {
    pub name: String,
    /// The factors of this stage's additions at its steps: cumulative fractions, increasing, ending
    /// at 1; or, from a `history`, any sequence (cyclic loading).
    pub load_factors: Vec<f64>,
    /// The steps (1-based, among `load_factors`) where a history's factor reverses.
    pub reversals: Vec<usize>,
    /// The factors come from a `history`: the stage's out-of-balance force is applied in its first
    /// step (it is not ramped by a factor that may go back or change sign).
    pub cyclic: bool,
    pub loads: Vec<Load>,
    /// (node, direction, displacement added over this stage).
    pub prescribed: Vec<(NodeIndex, Direction, f64)>,
    /// Soil elements (indices into `mesh.solids`) placed in this stage.
    pub activate: Vec<usize>,
    /// Soil elements removed in this stage.
    pub deactivate: Vec<usize>,
    /// Reinforcement bars (indices into `mesh.bars`) placed in this stage.
    pub activate_bars: Vec<usize>,
    /// Set the K0 initial stresses at the start of this stage.
    pub k0: bool,
    /// A new water table from this stage on (`Some(None)`: no water).
    pub water: Option<Option<WaterTable>>,
    /// A search for the factor of safety instead of a loading.
    pub strength_reduction: Option<StrengthReduction>,
    /// The stage's own `freeze_normal_stress`, if it sets one.
    pub freeze_normal_stress: Option<bool>,
    /// Time steps under a base motion instead of a loading.
    pub dynamic: Option<DynamicPlan>,
}

/// A checked strength-reduction stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrengthReduction {
    /// Reduce the soil's strength too, not only the interfaces'.
    pub soil: bool,
    pub tolerance: f64,
    pub max_factor: f64,
}

/// How a model file may be read.
#[derive(Debug, Clone, Copy)]
pub struct LoadOptions {
    /// Mesh a `.geo` script even when it starts programs or writes files (`--trust-geo`): a
    /// `.geo` file is a program, and by default one that does either is refused.
    pub trust_geo: bool,
    /// Memory the run may use, MB (`--memory-limit`); `None`: what the machine has available. A
    /// mesh whose declared size would not fit is refused before it is read.
    pub memory_limit_mb: Option<f64>,
    /// The longest Gmsh may take to mesh a `.geo` script, seconds (`--gmsh-time-limit`).
    pub gmsh_time_limit_s: f64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions { trust_geo: false, memory_limit_mb: None, gmsh_time_limit_s: 300.0 }
    }
}

impl LoadOptions {
    /// The memory limit a mesh is held to: the one given, or what the machine has available.
    pub fn memory_limit(&self) -> Option<f64> {
        self.memory_limit_mb.or_else(crate::memory::available_memory_mb)
    }
}

impl Model {
    /// Read and check a model file (TOML, or JSON when the name ends in `.json`).
    ///
    /// # Errors
    /// [`Error::Read`] or [`Error::Parse`] when the file cannot be read or parsed, and
    /// [`Error::Model`] listing every problem found in it.
    pub fn load(path: &Path) -> Result<Model, Error> {
        Model::load_with(path, LoadOptions::default())
    }

    /// [`Model::load`] with `options`.
    ///
    /// # Errors
    /// As [`Model::load`].
    pub fn load_with(path: &Path, options: LoadOptions) -> Result<Model, Error> {
        let started = Instant::now();
        let text = read_text_within(path, options.memory_limit_mb)?;
        let read = Phase::since("model: file read", started);
        let started = Instant::now();
        let file = parse(path, &text)?;
        let parsed = Phase::since("model: file parsed", started);
        let mut model = Model::from_file_with(path, &file, options).map_err(Error::Model)?;
        model.load_times.splice(0..0, [read, parsed]);
        Ok(model)
    }

    /// The `.geo` script a model file's mesh is made from, when it is one: `check` reads it (for the
    /// commands it refuses) but runs Gmsh on it only when asked.
    ///
    /// # Errors
    /// As [`Model::load`], for a file that cannot be read or parsed.
    pub fn geo_script(path: &Path) -> Result<Option<PathBuf>, Error> {
        let text = read_text(path)?;
        let file = parse(path, &text)?;
        Ok(file
            .mesh
            .as_ref()
            .map(|m| path.parent().unwrap_or(Path::new(".")).join(&m.file))
            .filter(|script| script.extension().is_some_and(|e| e.eq_ignore_ascii_case("geo"))))
    }

    /// Check what can be checked of a model whose mesh is a `.geo` script without running Gmsh: the
    /// file parses, its series is sound, the script exists and does nothing refused (unless
    /// `options.trust_geo`). Returns the script.
    ///
    /// # Errors
    /// As [`Model::load`]; the refused commands of the script, or a missing script, are an
    /// [`Error::Model`] under `mesh.file`.
    pub fn check_without_meshing(path: &Path, options: LoadOptions) -> Result<PathBuf, Error> {
        let text = read_text_within(path, options.memory_limit_mb)?;
        let file = parse(path, &text)?;
        let mut problems = match &file.series {
            Some(series) => series_problems(&file, series),
            None => problems::Problems::default(),
        };
        let script = Model::geo_script(path)?.unwrap_or_default();
        if !script.is_file() {
            problems.push("mesh.file", None, format!("{}: no such file", script.display()));
        } else if !options.trust_geo {
            if let Err(e) = crate::gmsh::refuse_script_actions(&script) {
                problems.push("mesh.file", None, e.to_string());
            }
        }
        if !problems.is_empty() {
            return Err(Error::Model(ModelError { file: path.to_path_buf(), problems: problems.into_vec() }));
        }
        Ok(script)
    }

    /// Read a model file and make one checked model per run: the model itself, or one per value of
    /// its `series`.
    ///
    /// # Errors
    /// As [`Model::load`]; a series naming no edge-traction load, or with no values, is a
    /// [`Error::Model`].
    pub fn load_cases(path: &Path) -> Result<Vec<Case>, Error> {
        Model::load_cases_with(path, LoadOptions::default())
    }

    /// [`Model::load_cases`] with `options`.
    ///
    /// # Errors
    /// As [`Model::load_cases`].
    pub fn load_cases_with(path: &Path, options: LoadOptions) -> Result<Vec<Case>, Error> {
        let started = Instant::now();
        let text = read_text_within(path, options.memory_limit_mb)?;
        let read = Phase::since("model: file read", started);
        let started = Instant::now();
        let file = parse(path, &text)?;
        let parsed = Phase::since("model: file parsed", started);
        let Some(series) = file.series.clone() else {
            let mut model = Model::from_file_with(path, &file, options)?;
            model.load_times.splice(0..0, [read, parsed]);
            return Ok(vec![Case { label: None, load: None, value: None, model: Some(model), series: None }]);
        };
        let problems = series_problems(&file, &series);
        if !problems.is_empty() {
            return Err(Error::Model(ModelError { file: path.to_path_buf(), problems: problems.into_vec() }));
        }
        // every run is made and checked here, as a run would, but only the first is kept: a series
        // holds one model in memory at a time (`Case::model` makes the others again)
        let base = std::sync::Arc::new(SeriesBase { path: path.to_path_buf(), file, options });
        let mut cases = Vec::new();
        for (k, &value) in series.values.iter().enumerate() {
            let model = base.model_at(&series.load, value)?;
            cases.push(Case {
                label: Some(format!("{}-{}", series.load, value)),
                load: Some(series.load.clone()),
                value: Some(value),
                model: (k == 0).then_some(model),
                series: Some(base.clone()),
            });
        }
        Ok(cases)
    }

    /// Check a parsed model file. `source` names it in messages.
    ///
    /// # Errors
    /// A [`ModelError`] that lists every problem found.
    pub fn from_file(source: &Path, file: &ModelFile) -> Result<Model, ModelError> {
        Model::from_file_with(source, file, LoadOptions::default())
    }

    /// [`Model::from_file`] with `options`.
    ///
    /// # Errors
    /// As [`Model::from_file`].
    pub fn from_file_with(source: &Path, file: &ModelFile, options: LoadOptions) -> Result<Model, ModelError> {
        if file.mesh.is_none() {
            return validate::validate(source, file);
        }
        let started = Instant::now();
        let mut file = file.clone();
        let mut problems = problems::Problems::default();
        let record = import::import(source, &mut file, &mut problems, options);
        if !problems.is_empty() {
            return Err(ModelError { file: source.to_path_buf(), problems: problems.into_vec() });
        }
        let imported = Phase::since("model: mesh imported", started);
        let mut model = validate::validate(source, &file)?;
        model.load_times.insert(0, imported);
        if let Some(r) = &record {
            if r.flipped > 0 {
                model.notes.push(format!(
                    "{} element(s) of {} were numbered clockwise and were renumbered counter-clockwise",
                    r.flipped,
                    r.file.display()
                ));
            }
        }
        model.mesh_source = record;
        Ok(model)
    }

    pub fn node_set(&self, name: &str) -> Option<&[NodeIndex]> {
        self.node_sets.get(name).map(|v| v.as_slice())
    }

    pub fn soil(&self, solid: usize) -> &SoilMaterial {
        &self.soils[self.mesh.solids[solid].material].1
    }

    /// The Gauss rule of the soil elements.
    pub fn integration(&self) -> crate::element::solid::Integration {
        if self.analysis.reduced_integration {
            crate::element::solid::Integration::Reduced
        } else {
            crate::element::solid::Integration::Full
        }
    }

    /// Some Mohr–Coulomb or Duncan–Chang soil flows non-associatively (its consistent tangent is
    /// unsymmetric).
    pub fn has_non_associated_soil(&self) -> bool {
        self.soils.iter().any(|(_, m)| self.law_of(m).is_some_and(|l| l.non_associated()))
    }

    /// Soil elements absent at the start: those a stage activates.
    pub fn initially_absent(&self) -> Vec<bool> {
        let mut absent = vec![false; self.mesh.solids.len()];
        for s in &self.stages {
            for &e in &s.activate {
                absent[e] = true;
            }
        }
        absent
    }

    /// Bars absent at the start: those of the reinforcements a stage places.
    pub fn initially_absent_bars(&self) -> Vec<bool> {
        let mut absent = vec![false; self.mesh.bars.len()];
        for s in &self.stages {
            for &b in &s.activate_bars {
                absent[b] = true;
            }
        }
        absent
    }

    /// Atmospheric pressure, 101.325 kPa, in the given units.
    pub fn atmospheric_pressure(units: &Units) -> f64 {
        Model::default_water_weight(units) / 9.81 * 101.325 * Model::metre(units)
    }

    /// One metre in the given units' length.
    pub fn metre(units: &Units) -> f64 {
        match units.length {
            file::LengthUnit::Metre => 1.0,
            file::LengthUnit::Millimetre => 1e3,
        }
    }

    /// γw of 9.81 kN/m³ in the given units.
    pub fn default_water_weight(units: &Units) -> f64 {
        use file::{ForceUnit::*, LengthUnit::*};
        let force = match units.force {
            Newton => 1e3,
            Kilonewton => 1.0,
            Meganewton => 1e-3,
        };
        let length = match units.length {
            Metre => 1.0,
            Millimetre => 1e3,
        };
        9.81 * force / (length * length * length)
    }

    /// Unit labels for output headers.
    pub fn unit_labels(&self) -> UnitLabels {
        UnitLabels::new(&self.units, self.mesh.geometry)
    }
}

/// What is wrong with a model file's `[series]`, before any of its runs is made.
fn series_problems(file: &ModelFile, series: &file::Series) -> problems::Problems {
    let mut problems = problems::Problems::default();
    let entity = format!("load \"{}\"", series.load);
    let mut found = 0;
    for stage in &file.stages {
        for load in &stage.loads {
            if let file::LoadSpec::EdgeTraction { name: Some(n), .. } = load {
                found += usize::from(*n == series.load);
            }
        }
    }
    if found != 1 {
        problems.push(
            "series.load",
            &entity,
            format!("a series varies the pressure of exactly one edge-traction load with this `name`; found {found}"),
        );
    }
    if series.values.is_empty() {
        problems.push("series.values", &entity, "give at least one value");
    }
    if series.values.len() > validate::MAX_SERIES_VALUES {
        problems.push(
            "series.values",
            &entity,
            format!("at most {} runs in a series, found {}", validate::MAX_SERIES_VALUES, series.values.len()),
        );
    }
    for (k, v) in series.values.iter().enumerate() {
        if !v.is_finite() {
            problems.push(format!("series.values[{k}]"), &entity, format!("must be a finite number, found {v}"));
        } else if let Some(first) = series.values[..k].iter().position(|w| w == v) {
            problems.push(
                format!("series.values[{k}]"),
                &entity,
                format!(
                    "{v} is already series.values[{first}]: each run of a series writes a folder named by its value"
                ),
            );
        }
    }
    problems
}

/// Unit strings for column headers.
#[derive(Debug, Clone)]
pub struct UnitLabels {
    pub length: &'static str,
    pub force: &'static str,
    /// force per metre width (line load, bar force, multiplier) in plane strain; in axisymmetry a
    /// total force over the circumference (a nail's pull, a ring's reaction)
    pub force_per_width: String,
    pub stress: String,
    /// An interface point's tributary length (plane strain) or area (axisymmetry, ∫2πr ds).
    pub tributary: String,
}

impl UnitLabels {
    pub fn new(units: &Units, geometry: crate::element::geometry::Geometry) -> Self {
        use file::{ForceUnit::*, LengthUnit::*};
        let length = match units.length {
            Metre => "m",
            Millimetre => "mm",
        };
        let force = match units.force {
            Newton => "N",
            Kilonewton => "kN",
            Meganewton => "MN",
        };
        let stress = match (units.force, units.length) {
            (Newton, Metre) => "Pa".to_string(),
            (Kilonewton, Metre) => "kPa".to_string(),
            (Meganewton, Metre) | (Newton, Millimetre) => "MPa".to_string(),
            (f, l) => format!("{}/{}^2", UnitLabels::force_name(f), UnitLabels::length_name(l)),
        };
        let tributary = if geometry.is_axisymmetric() { format!("{length}^2") } else { length.to_string() };
        UnitLabels { length, force, force_per_width: geometry.force_unit(force, length), stress, tributary }
    }

    fn force_name(f: file::ForceUnit) -> &'static str {
        match f {
            file::ForceUnit::Newton => "N",
            file::ForceUnit::Kilonewton => "kN",
            file::ForceUnit::Meganewton => "MN",
        }
    }

    fn length_name(l: file::LengthUnit) -> &'static str {
        match l {
            file::LengthUnit::Metre => "m",
            file::LengthUnit::Millimetre => "mm",
        }
    }
}

/// The JSON Schema of the model file, generated from the same types that read it.
pub fn schema() -> String {
    let schema = schemars::schema_for!(ModelFile);
    serde_json::to_string_pretty(&schema).unwrap_or_default()
}
