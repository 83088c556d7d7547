//! Turn a parsed [`ModelFile`] into a checked [`Model`], listing every problem found.
//!
//! The checks run in the order the model is built, one concept per file: materials and shear laws,
//! the mesh, the named sets, the interfaces (which split the soil), the supports and other node
//! targets, the stages, the `[analysis]` settings, and last the free bodies. Each adds what it
//! built to the [`Draft`] and its problems to the list; the model exists only when there are none.

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
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::Path;

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
    materials::materials(&mut d, file, &mut p);
    mesh::mesh(&mut d, file, &mut p);
    sets::node_and_edge_sets(&mut d, file, &mut p);
    interfaces::interfaces(&mut d, file, &mut p);
    targets::supports(&mut d, file, &mut p);
    sets::element_sets(&mut d, file, &mut p);
    stages::stages(&mut d, file, &mut p);
    analysis_settings(file, &mut p);
    if p.is_empty() {
        free_bodies::check_free_bodies(&d.mesh, &d.interfaces, &d.supports, d.stages.first(), &mut p);
    }
    if !p.is_empty() {
        return Err(ModelError { file: source.to_path_buf(), problems: p.into_vec() });
    }
    Ok(Model {
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
    })
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
