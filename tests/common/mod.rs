//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod dynamics;
pub mod law_curve;
pub mod restart;
pub mod slip;
pub mod two_wedge;

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::linsol::Backend;
use geoslip::model::file::ModelFile;
use geoslip::model::Model;
use std::path::Path;

/// Check a model built in code; panics with the full problem list if it is rejected.
pub fn model(file: &ModelFile, name: &str) -> Model {
    Model::from_file(Path::new(name), file).unwrap_or_else(|e| panic!("{e}"))
}

/// Run a model on a backend and keep every step.
pub fn run(model: &Model, backend: Backend) -> Collect {
    let mut sink = Collect::default();
    analysis::run(model, &RunOptions::for_model(model, backend), &mut sink).unwrap_or_else(|e| panic!("{e}"));
    sink
}

/// The pull-out force at the nodes of `head` (a node set) in each step after the first: the sum of
/// their x reactions, as a magnitude.
pub fn head_forces(model: &Model, c: &Collect, head: &str) -> Vec<f64> {
    let head: Vec<u64> = model.node_sets[head].iter().map(|&n| model.mesh.node_id(n)).collect();
    c.steps
        .iter()
        .skip(1)
        .map(|(_, s)| s.reactions.iter().filter(|r| head.contains(&r.node)).filter_map(|r| r.rx).sum::<f64>().abs())
        .collect()
}

/// Assert that two runs of a pull-out give the same head force at every step, to `tolerance` of
/// the first run's peak (which must show a pull), and that the second run's points slid past soil
/// nodes (large slip). Returns the first run's head forces.
pub fn assert_same_head_forces(
    (model_a, a): (&Model, &Collect),
    (model_b, b): (&Model, &Collect),
    tolerance: f64,
) -> Vec<f64> {
    let (x, y) = (head_forces(model_a, a, "grid.head"), head_forces(model_b, b, "grid.head"));
    assert_eq!(x.len(), y.len());
    let peak = x.iter().cloned().fold(0.0, f64::max);
    assert!(peak > 1.0, "the grid is pulled: peak {peak} kN/m");
    for (step, (p, q)) in x.iter().zip(&y).enumerate() {
        assert!((p - q).abs() <= tolerance * peak, "step {}: head force {q} against {p}", step + 1);
    }
    let reassociated: usize = b.steps.iter().map(|(r, _)| r.reassociations.len()).sum();
    assert!(reassociated > 0, "the points slide past soil nodes (large slip)");
    x
}

/// The pull-out box of issue #16: a 2 m × 1 m weightless elastic block (E = 10 MPa, ν = 0.3) of
/// 20 × 10 quad4 (h = 0.1 m), a grid at mid-height from x = 0 to 1.6 m on the soil's nodes (EA = 500
/// kN/m), Coulomb faces (Ks = 2000 kPa/m, c = 0, φ = 30°), q = 20 kPa; the head pulled 20 mm in 40
/// steps.
pub fn issue_pullout_box() -> geoslip::meshgen::PullOutBox {
    geoslip::meshgen::PullOutBox {
        length: 2.0,
        height: 1.0,
        embedded: 1.6,
        nx: 20,
        ny_half: 5,
        youngs_modulus: 10_000.0,
        poissons_ratio: 0.3,
        unit_weight: 0.0,
        axial_stiffness: 500.0,
        law: geoslip::model::file::ShearLawSpec::Coulomb {
            shear_stiffness: 2000.0,
            cohesion: 0.0,
            friction_angle: 30.0,
        },
        surcharge: 20.0,
        pull: 0.02,
        steps: 40,
        ..geoslip::meshgen::PullOutBox::default()
    }
}

/// Assert that the pull-out force of each step from `first` on (1-based, the head moved `step`
/// further each step) is n_f·τmax·(L − u) of a fully sliding, nearly rigid two-face reinforcement of
/// embedded length `length` (docs/verification.md §2, large slip), to `tolerance` relative.
pub fn assert_sliding_plateau(forces: &[f64], first: usize, step: f64, length: f64, tau_max: f64, tolerance: f64) {
    for (k, &force) in forces.iter().enumerate().skip(first - 1) {
        let u = step * (k + 1) as f64;
        let plateau = 2.0 * tau_max * (length - u);
        assert!(
            relative_error(force, plateau) < tolerance,
            "step {}: force {force} kN/m against n_f·τmax·(L − u) = {plateau}",
            k + 1
        );
    }
}

/// Displacement of node `id` in the last step.
pub fn displacement(c: &Collect, id: u64) -> [f64; 2] {
    let r = c.last().expect("at least one step");
    r.displacements.iter().find(|(n, _, _)| *n == id).map(|(_, _, d)| *d).unwrap_or_else(|| panic!("no node {id}"))
}

pub fn relative_error(value: f64, exact: f64) -> f64 {
    ((value - exact) / exact).abs()
}

/// Two blocks stacked: `upper` sits on `lower`'s top row, whose nodes it takes over. Returns the
/// nodes, the elements, and the renaming of `upper`'s bottom-row nodes.
pub fn stack(
    lower: &geoslip::meshgen::Block,
    upper: &geoslip::meshgen::Block,
) -> (
    Vec<geoslip::model::file::NodeRow>,
    Vec<geoslip::model::file::SolidElementRow>,
    std::collections::BTreeMap<u64, u64>,
) {
    let rename: std::collections::BTreeMap<u64, u64> =
        upper.row_nodes(0).into_iter().zip(lower.row_nodes(lower.ny)).collect();
    let mut nodes = lower.nodes.clone();
    nodes.extend(upper.nodes.iter().filter(|n| !rename.contains_key(&n.0)).cloned());
    let mut elements = lower.elements.clone();
    for e in &upper.elements {
        let mut e = e.clone();
        e.nodes = e.nodes.iter().map(|n| *rename.get(n).unwrap_or(n)).collect();
        elements.push(e);
    }
    (nodes, elements, rename)
}

/// A prescribed displacement of a node set.
pub fn prescribed(set: &str, ux: Option<f64>, uy: Option<f64>) -> geoslip::model::file::PrescribedDisplacement {
    geoslip::model::file::PrescribedDisplacement { node: None, nodes: None, set: Some(set.into()), ux, uy }
}

/// A triaxial sample's shearing stages "shear 1", "shear 2", …: each moves the `top` set down by
/// its axial strain times `height` in its number of equal steps.
pub fn shearing_stages(stages: &[(f64, usize)], height: f64) -> Vec<geoslip::model::file::Stage> {
    stages
        .iter()
        .enumerate()
        .map(|(k, &(strain, steps))| geoslip::model::file::Stage {
            name: format!("shear {}", k + 1),
            load_factors: (1..=steps).map(|i| i as f64 / steps as f64).collect(),
            prescribed: vec![prescribed("top", None, Some(-strain * height))],
            ..Default::default()
        })
        .collect()
}

/// A triaxial sample, axisymmetric: a `radius` × `height` block of 2 × 2 `kind` elements of the
/// soil `sand`, its base held vertically, node sets `base` and `top`, edge sets `side` and `top`
/// (for the cell pressure), run by Newton's method to `tolerance` through `stages`.
pub fn triaxial_sample(
    kind: geoslip::model::file::SolidKind,
    (radius, height): (f64, f64),
    sand: geoslip::model::file::SoilMaterial,
    stages: Vec<geoslip::model::file::Stage>,
    tolerance: f64,
) -> ModelFile {
    use geoslip::meshgen::{support, Block};
    use geoslip::model::file::{Direction, Geometry, Materials};
    let block = Block::new(kind, (0.0, 0.0), (radius, height), (2, 2), "sand", 1, 1);
    let mut file = ModelFile {
        title: "triaxial sample".into(),
        materials: Materials { soil: [("sand".to_string(), sand)].into(), ..Default::default() },
        node_sets: [("base".to_string(), block.row_nodes(0)), ("top".to_string(), block.row_nodes(2))].into(),
        edge_sets: [("side".to_string(), block.column_edges(2)), ("top".to_string(), block.row_edges(2))].into(),
        nodes: block.nodes,
        elements: block.elements,
        supports: vec![support("base", &[Direction::Y])],
        stages,
        analysis: newton(tolerance),
        ..Default::default()
    };
    file.analysis.geometry = Geometry::Axisymmetric;
    file
}

/// Newton's method with the consistent tangent, to a relative tolerance on force and displacement.
pub fn newton(tolerance: f64) -> geoslip::model::file::AnalysisSettings {
    geoslip::model::file::AnalysisSettings {
        scheme: geoslip::model::file::Scheme::Newton,
        force_tolerance: tolerance,
        displacement_tolerance: tolerance,
        ..Default::default()
    }
}

/// A pull-out box model file: 4 × 2 quad4 elements, 0.4 m × 0.2 m, a geogrid at mid-height over
/// 0.3 m, its head pulled in `pull_steps` steps; `law` is the interface's law as a TOML inline table.
pub fn small_pullout_box(title: &str, law: &str, pull_steps: usize) -> String {
    let (nx, ny) = (4, 2);
    let id = |i: usize, j: usize| 1 + j * (nx + 1) + i;
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push(format!("[{}, {:.1}, {:.1}]", id(i, j), 0.1 * i as f64, 0.1 * j as f64));
        }
    }
    let mut elements = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            elements.push(format!(
                "{{ id = {}, type = \"quad4\", nodes = [{}, {}, {}, {}], material = \"sand\" }}",
                elements.len() + 1,
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            ));
        }
    }
    let list = |ids: Vec<usize>| ids.iter().map(usize::to_string).collect::<Vec<_>>().join(", ");
    let factors: Vec<String> = (1..=pull_steps).map(|k| format!("{}", k as f64 / pull_steps as f64)).collect();
    format!(
        r#"title = "{title}"
nodes = [{nodes}]
elements = [{elements}]

[units]
length = "m"
force = "kN"

[materials.soil.sand]
youngs_modulus = 20000.0
poissons_ratio = 0.3
unit_weight = 18.0

[materials.reinforcement.grid]
axial_stiffness = 1000.0
tension_only = true

[node_sets]
base = [{base}]
front = [{front}]
back = [{back}]

[edge_sets]
top = [{top}]

[[supports]]
set = "base"
fix = ["x", "y"]

[[supports]]
set = "front"
fix = ["x"]

[[supports]]
set = "back"
fix = ["x"]

[[interfaces]]
name = "grid"
reinforcement = {{ path = [{path}], material = "grid" }}
law = {law}

[[stages]]
name = "surcharge"
loads = [{{ type = "edge-traction", edge_set = "top", pressure = 50.0 }}]

[[stages]]
name = "pull-out"
load_factors = [{factors}]
prescribed = [{{ set = "grid.head", ux = -0.05 }}]

[analysis]
scheme = "newton"
"#,
        nodes = nodes.join(", "),
        elements = elements.join(",\n  "),
        base = list((0..=nx).map(|i| id(i, 0)).collect()),
        front = list((0..=ny).map(|j| id(0, j)).collect()),
        back = list((0..=ny).map(|j| id(nx, j)).collect()),
        top = (0..nx).map(|i| format!("[{}, {}]", id(i, ny), id(i + 1, ny))).collect::<Vec<_>>().join(", "),
        path = list((0..nx).map(|i| id(i, 1)).collect()),
        factors = factors.join(", "),
    )
}

/// The Coulomb block of docs/verification.md §4 (see `geoslip::meshgen::block_on_rigid_base`).
#[allow(unused_imports)] // (used by some of the test files that share this module)
pub use geoslip::meshgen::block_on_rigid_base;

/// A sink that keeps every step and every saved state of a run (for the restart tests).
#[derive(Default)]
pub struct Saved {
    pub steps: Collect,
    pub checkpoints: Vec<analysis::Checkpoint>,
}

impl analysis::StepSink for Saved {
    fn step_done(
        &mut self,
        model: &geoslip::model::Model,
        step: &analysis::results::StepResults,
        record: &analysis::StepRecord,
        stats: &geoslip::analysis::RunStats,
    ) -> Result<(), geoslip::Error> {
        self.steps.step_done(model, step, record, stats)
    }
    fn keeps_checkpoints(&self) -> bool {
        true
    }
    fn checkpoint(&mut self, checkpoint: analysis::Checkpoint) -> Result<(), geoslip::Error> {
        self.checkpoints.push(checkpoint);
        Ok(())
    }
}

/// Write `checkpoints` into the results folder `dir` as a run writes them.
pub fn write_saved_steps(dir: &Path, checkpoints: &[analysis::Checkpoint]) {
    let folder = geoslip::output::OwnedFolder::open(dir, &[]).unwrap();
    for c in checkpoints {
        geoslip::output::checkpoints::write(&folder, c).unwrap();
    }
}

/// Record a number that a document quotes from this test's run, as the document writes it:
/// `scripts/doc-numbers.py --measured DIR` compares the document's
/// `<!-- number: ID -->…<!-- /number -->` with it. Written to `$GEOSLIP_DOC_NUMBERS/ID` when that
/// variable names a folder (the test command sets it); otherwise nothing is written.
pub fn doc_number(id: &str, text: impl Into<String>) {
    if let Some(dir) = std::env::var_os("GEOSLIP_DOC_NUMBERS") {
        let dir = Path::new(&dir);
        std::fs::create_dir_all(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        let path = dir.join(id);
        std::fs::write(&path, text.into()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
}

/// `value` against `exact` as a signed percentage with `digits` decimals, as the documents write
/// it: "+2.4 %", "−0.1 %" (a true minus sign), "0.0 %".
pub fn signed_percent(value: f64, exact: f64, digits: usize) -> String {
    let d = 100.0 * (value - exact) / exact;
    let text = format!("{d:+.digits$} %");
    if text.trim_start_matches(['+', '-']).chars().all(|c| c == '0' || c == '.' || c == ' ' || c == '%') {
        return text.trim_start_matches(['+', '-']).to_string();
    }
    text.replace('-', "−")
}
