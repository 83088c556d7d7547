//! Turn a parsed [`ModelFile`] into a checked [`Model`], listing every problem found.
//!
//! The checks run in the order the model is built, one concept per file: materials and shear laws,
//! the mesh, the named sets, the interfaces (which split the soil), the supports and other node
//! targets, the stages, the `[analysis]` settings, and last the free bodies. Each adds what it
//! built to the [`Draft`] and its problems to the list; the model exists only when there are none.

mod design;
pub mod dynamic;
mod free_bodies;
mod interfaces;
mod materials;
mod mesh;
mod sets;
mod stages;
mod targets;

use super::file::*;
use super::problems::Problems;
use super::{LoadedSide, Model, StagePlan};
use crate::error::ModelError;
use crate::interface::Interface;
use crate::mesh::{Mesh, NodeIndex};
use crate::timing::Phase;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::Path;
use std::time::Instant;

/// What the checks have built so far.
#[derive(Default)]
struct Draft {
    soils: Vec<(String, SoilMaterial)>,
    reinforcements: Vec<(String, ReinforcementMaterial)>,
    /// Material name → index into `soils` / `reinforcements`.
    soil_index: HashMap<String, usize>,
    reinf_index: HashMap<String, usize>,
    mesh: Mesh,
    /// Every node and element could be built (else the interfaces are not checked).
    mesh_ok: bool,
    /// Ids of the soil elements and bars (one id space).
    element_ids: HashSet<u64>,
    node_sets: BTreeMap<String, Vec<NodeIndex>>,
    edge_sets: BTreeMap<String, Vec<LoadedSide>>,
    element_sets: BTreeMap<String, Vec<usize>>,
    interfaces: Vec<Interface>,
    /// A split soil node → its twin on the other side of the slit.
    twins: HashMap<NodeIndex, NodeIndex>,
    supports: Vec<(NodeIndex, Direction)>,
    supported: HashSet<(NodeIndex, Direction)>,
    stages: Vec<StagePlan>,
}

pub(super) fn validate(source: &Path, file: &ModelFile) -> Result<Model, ModelError> {
    let mut p = Problems::default();
    let mut d = Draft { mesh_ok: true, ..Draft::default() };
    let mut times = Vec::new();
    let mut timed = |phase: &str, step: &mut dyn FnMut(&mut Draft, &mut Problems)| {
        let started = Instant::now();
        step(&mut d, &mut p);
        times.push(Phase::since(phase, started));
    };
    timed("model: materials", &mut |d, p| materials::materials(d, file, p));
    timed("model: mesh checked", &mut |d, p| mesh::mesh(d, file, p));
    timed("model: node and edge sets", &mut |d, p| sets::node_and_edge_sets(d, file, p));
    timed("model: interfaces split and paired", &mut |d, p| interfaces::interfaces(d, file, p));
    timed("model: supports, element sets, stages", &mut |d, p| {
        targets::supports(d, file, p);
        sets::element_sets(d, file, p);
        stages::stages(d, file, source, p);
        analysis_settings(file, p);
    });
    timed("model: every body held", &mut |d, p| {
        if p.is_empty() {
            free_bodies::check_free_bodies(&d.mesh, &d.interfaces, &d.supports, d.stages.first(), p);
        }
    });
    if !p.is_empty() {
        return Err(ModelError { file: source.to_path_buf(), problems: p.into_vec() });
    }
    let mut model = Model {
        source: source.to_path_buf(),
        title: file.title.clone(),
        units: file.units.clone(),
        mesh: d.mesh,
        soils: d.soils,
        reinforcements: d.reinforcements,
        node_sets: d.node_sets,
        element_sets: d.element_sets,
        supports: d.supports,
        interfaces: d.interfaces,
        stages: d.stages,
        notes: Vec::new(),
        analysis: file.analysis.clone(),
        mesh_source: None,
        load_times: times,
        design: None,
    };
    if let Some(parameters) = &file.design {
        let started = Instant::now();
        let wall = design::wall(&model, parameters)
            .map_err(|problem| ModelError { file: source.to_path_buf(), problems: vec![problem] })?;
        model.design = Some(wall);
        model.load_times.push(Phase::since("model: the wall of the design checks", started));
    }
    Ok(model)
}

/// The `[analysis]` settings.
fn analysis_settings(file: &ModelFile, p: &mut Problems) {
    let a = &file.analysis;
    // below 1e-12 a relative tolerance asks for more than double precision can give
    let tolerances = [("force_tolerance", a.force_tolerance), ("displacement_tolerance", a.displacement_tolerance)];
    for (name, t) in tolerances {
        if !(t.is_finite() && (1e-12..1.0).contains(&t)) {
            p.push(format!("analysis.{name}"), None, format!("must be in [1e-12, 1), found {t:?}"));
        }
    }
    // counts bounded so that no model makes a run loop or allocate without a limit it names
    let counts = [
        ("max_iterations", a.max_iterations, 1, MAX_ITERATIONS),
        ("stall_iterations", a.stall_iterations, 0, MAX_ITERATIONS),
        ("max_cutbacks", a.max_cutbacks, 0, MAX_CUTBACKS),
        ("reserved_segments", a.reserved_segments, 0, MAX_RESERVED_SEGMENTS),
    ];
    for (name, value, low, high) in counts {
        if !(low..=high).contains(&value) {
            p.push(format!("analysis.{name}"), None, format!("must be in [{low}, {high}], found {value}"));
        }
    }
    if a.geometry == Geometry::Axisymmetric && a.reassociation == ReassociationRule::Mortar {
        p.push(
            "analysis.reassociation",
            None,
            "mortar ties are not yet weighted by the radius in an axisymmetric model: use `segment` (the default) or `nearest-node`",
        );
    }
}

/// The most equilibrium iterations an increment may be given.
pub const MAX_ITERATIONS: usize = 10_000;
/// The most halvings of one increment (2⁻³⁰ of it is below any meaningful load step).
pub const MAX_CUTBACKS: usize = 30;
/// The most master segments reserved either side of an interface point.
pub const MAX_RESERVED_SEGMENTS: usize = 1_000;
/// The most load factors of one stage.
pub const MAX_LOAD_FACTORS: usize = 10_000;
/// The largest factor a loading history may reach (of the stage's loads and displacements).
pub const MAX_HISTORY_FACTOR: f64 = 1e6;
/// The most runs of a series.
pub const MAX_SERIES_VALUES: usize = 1_000;
