//! `summary.json`: what a run was, how it went and where its results are.

use super::options::{FieldPrecision, OutputOptions};
use crate::analysis::RunStats;
use crate::analysis::StepRecord;
use crate::model::file::Direction;
use crate::model::{Model, UnitLabels};
use crate::timing::Timings;

/// The peak reaction of one prescribed target (a pull-out force, a footing load).
#[derive(Debug, Clone, serde::Serialize)]
pub struct TargetPeak {
    pub label: String,
    pub direction: Direction,
    /// |reaction| at its largest [force per metre width].
    pub reaction: f64,
    /// Mean displacement of the target there [length].
    pub displacement: f64,
}

/// The JSON run summary.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RunSummary {
    pub geoslip_version: &'static str,
    pub model: String,
    pub title: String,
    /// `running`, `completed` or `failed`.
    pub status: String,
    pub error: Option<String>,
    pub solver: String,
    pub units: serde_json::Value,
    pub unknowns: Unknowns,
    pub notes: Vec<String>,
    /// What happened along the way: slip starting, the whole interface sliding, a drop of a
    /// prescribed target's reaction (softening, snap-back under displacement control, pull-out).
    pub events: Vec<String>,
    /// Factors of safety found by strength-reduction stages.
    pub factors_of_safety: Vec<crate::analysis::FactorOfSafety>,
    /// Where the fields of the kept steps are.
    pub fields: FieldFiles,
    pub steps: Vec<StepRecord>,
    pub solver_stats: RunStats,
    pub total_seconds: f64,
    /// Time in the result writer: the field files, history, summary, report and plots.
    pub write_seconds: f64,
    /// The CPU time of the thread that writes the run's files beside the run (`results.h5`'s
    /// compression included), where the system tells it: on a machine
    /// whose cores the run keeps busy, about what writing adds to the run's wall time beyond
    /// `write_seconds`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub writer_thread_seconds: Option<f64>,
    /// Where the time went, phase by phase: over the whole process when the program said when it
    /// started (`geoslip run`, `geoslip bench`), from the result writer's start otherwise.
    pub timings: Timings,
}

impl RunSummary {
    /// The summary of a run of `model` that is starting, on `solver`, its field files `files`.
    pub fn starting(
        model: &Model,
        solver: &str,
        options: &OutputOptions,
        units: &UnitLabels,
        files: Vec<String>,
    ) -> RunSummary {
        RunSummary {
            geoslip_version: env!("CARGO_PKG_VERSION"),
            model: model.source.display().to_string(),
            title: model.title.clone(),
            status: "running".into(),
            error: None,
            solver: solver.into(),
            units: serde_json::json!({
            "length": units.length, "force": units.force,
            "force_per_width": units.force_per_width, "stress": units.stress,
            "geometry": model.mesh.geometry,
            "forces": if model.mesh.geometry.is_axisymmetric() { "total over the circumference" } else { "per metre width" } }),
            unknowns: Unknowns {
                nodes: model.mesh.nodes.len(),
                soil_elements: model.mesh.solids.len(),
                bars: model.mesh.bars.len(),
                interface_points: model.interfaces.iter().flat_map(|i| &i.faces).map(|f| f.points.len()).sum(),
            },
            notes: model.notes.clone(),
            events: Vec::new(),
            factors_of_safety: Vec::new(),
            fields: FieldFiles {
                files,
                csv: options.csv,
                keep: options.keep.to_string(),
                precision: options.writes_hdf5().then_some(match options.precision {
                    FieldPrecision::Single => "single",
                    FieldPrecision::Double => "double",
                }),
                kept_steps: Vec::new(),
            },
            steps: Vec::new(),
            solver_stats: RunStats::default(),
            total_seconds: 0.0,
            write_seconds: 0.0,
            writer_thread_seconds: None,
            timings: Timings::default(),
        }
    }
}

/// The files that hold the fields of the kept steps.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FieldFiles {
    /// `results.h5` and `results.xdmf`, `results.pvd` (with `vtk/*.vtu`), or both.
    pub files: Vec<String>,
    /// Whether each kept step's fields are in CSV files too (`stage-<k>-<name>/step-<nnn>/`).
    pub csv: bool,
    /// Which steps are kept: `every`, `events` or N (every N-th step and the events).
    pub keep: String,
    /// The precision of the step fields in `results.h5`: `single` or `double` (absent from a
    /// build without it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub precision: Option<&'static str>,
    /// The kept steps, by their number over the run (1, 2, …; the `Time` in `results.xdmf`).
    pub kept_steps: Vec<usize>,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct Unknowns {
    pub nodes: usize,
    pub soil_elements: usize,
    pub bars: usize,
    pub interface_points: usize,
}
