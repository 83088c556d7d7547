//! `geoslip bench --dynamic`: a dynamic stage of many time steps, results written, against the
//! floor of one factorisation and one solve per time step measured in the same process.
//!
//! The model: an elastic soil layer 40 m wide and 20 m deep of square quad4 elements (E = 100 MPa,
//! ν = 0.3, γ = 20 kN/m³: Vs = 155 m/s) on a rigid base, its sides held in x, its weight first;
//! then `--steps` time steps of Δt = 5 ms under a 2 Hz harmonic base acceleration of 0.1 g, lumped
//! mass, Rayleigh damping 5 % at 1 and 10 Hz, HHT α = −0.05. Each size runs in a child process of
//! its own (`bench-one --dynamic`), so that its peak memory is its own.

use super::measure::peak_memory_mb;
use crate::analysis::results::StepResults;
use crate::analysis::{self, StepRecord, StepSink};
use crate::linsol::{self, Backend};
use crate::meshgen::{support, Block};
use crate::model::file::*;
use crate::model::Model;
use crate::output::{KeptSteps, OutputOptions};
use crate::timing::{Phase, ProcessStart, Timings};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// The time step [s].
const TIME_STEP: f64 = 0.005;
/// The fields of every this many steps are written (`--keep`).
const KEEP_EVERY: usize = 50;

/// The benchmark model with about `dofs` unknowns and `steps` time steps.
pub fn shaken_layer(dofs: usize, steps: usize) -> Model {
    Model::from_file(Path::new("generated-dynamic-benchmark"), &shaken_layer_file(dofs, steps))
        .expect("the generated dynamic benchmark is a valid model")
}

/// The benchmark model as its model file.
pub fn shaken_layer_file(dofs: usize, steps: usize) -> ModelFile {
    // unknowns ≈ 2·(2n + 1)·(n + 1) for n elements deep and 2n wide
    let n = ((dofs as f64 / 4.0).sqrt().round() as usize).max(2);
    let block = Block::new(SolidKind::Quad4, (0.0, 0.0), (40.0, 20.0), (2 * n, n), "soil", 1, 1);
    let mut node_sets = BTreeMap::new();
    node_sets.insert("base".into(), block.row_nodes(0));
    let mut sides = block.column_nodes(0);
    sides.extend(block.column_nodes(2 * n));
    node_sets.insert("sides".into(), sides);
    node_sets.insert("surface".into(), block.row_nodes(n));
    let mut soil = BTreeMap::new();
    soil.insert("soil".into(), SoilMaterial::linear_elastic(100_000.0, 0.3, 20.0));
    let duration = steps as f64 * TIME_STEP;
    let omega = 2.0 * std::f64::consts::PI * 2.0;
    let samples = (0..=steps).map(|k| [k as f64 * TIME_STEP, 0.1 * (omega * k as f64 * TIME_STEP).sin()]).collect();
    let shaking = DynamicSpec {
        time_step: TIME_STEP,
        duration,
        alpha: -0.05,
        damping: Some(RayleighDamping {
            ratio: Some(0.05),
            frequencies: Some([1.0, 10.0]),
            mass_coefficient: None,
            stiffness_coefficient: None,
        }),
        mass: Lumping::Lumped,
        base_motion: vec![BaseMotion {
            direction: Direction::X,
            file: None,
            samples: Some(samples),
            unit: Some(AccelerationUnit::G),
            scale: 1.0,
        }],
        record: vec!["surface".into()],
        absorbing: Vec::new(),
        compliant_base: None,
    };
    ModelFile {
        title: "dynamic benchmark: a shaken elastic layer".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement: BTreeMap::new() },
        nodes: block.nodes,
        elements: block.elements,
        bars: Vec::new(),
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![support("base", &[Direction::X, Direction::Y]), support("sides", &[Direction::X])],
        interfaces: Vec::new(),
        stages: vec![
            Stage { name: "weight".into(), loads: vec![LoadSpec::Gravity { factor: 1.0 }], ..Default::default() },
            Stage { name: "shaking".into(), dynamic: Some(shaking), ..Default::default() },
        ],
        analysis: AnalysisSettings::default(),
        mesh: None,
        series: None,
        design: None,
    }
}

/// One run of the benchmark model.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct DynamicMeasurement {
    pub backend: String,
    pub unknowns: usize,
    pub time_steps: usize,
    /// The run with its results written (every 50th step's fields), from the model built.
    pub wall_seconds: f64,
    /// The same run in the same process writing nothing.
    pub unwritten_wall_seconds: f64,
    /// One factorisation and one solve of the run's first system, in this process (medians of 3).
    pub factorize_seconds: f64,
    pub solve_seconds: f64,
    pub iterations: usize,
    pub factorizations: usize,
    pub solves: usize,
    /// The written run's phases [s]: assembly, residual, factorisation, solves, output.
    pub phases: [f64; 5],
    /// The written run's timings, from this process's start to its end.
    pub timings: Timings,
    pub output_bytes: u64,
    pub peak_memory_mb: f64,
    /// The surface's largest x displacement relative to the base [m].
    pub surface_peak: f64,
    pub error: Option<String>,
}

impl DynamicMeasurement {
    /// Wall time over the floor: one factorisation and one solve per time step.
    pub fn floor_ratio(&self, wall: f64) -> f64 {
        wall / (self.factorize_seconds + self.time_steps as f64 * self.solve_seconds)
    }
}

/// Counts the time steps and keeps the surface's largest displacement.
struct Surface {
    node: usize,
    steps: usize,
    peak: f64,
}

impl StepSink for Surface {
    fn step_done(
        &mut self,
        _: &crate::model::Model,
        step: &StepResults,
        record: &StepRecord,
        _: &analysis::RunStats,
    ) -> Result<(), crate::Error> {
        if record.stage_index == 1 {
            self.steps += 1;
            self.peak = self.peak.max(step.displacement_vector[2 * self.node].abs());
        }
        Ok(())
    }
}

/// Run the benchmark model with about `dofs` unknowns and `steps` time steps, its results written
/// into a temporary folder; then once writing nothing; then the floor.
pub fn measure_dynamic(dofs: usize, steps: usize, backend: Backend, process: ProcessStart) -> DynamicMeasurement {
    let started = Instant::now();
    let model = shaken_layer(dofs, steps);
    let generated = Phase::new(
        "benchmark model generated",
        started.elapsed().as_secs_f64() - model.load_times.iter().map(|p| p.seconds).sum::<f64>(),
    );
    let mut m = DynamicMeasurement { backend: backend.resolve().name().into(), ..DynamicMeasurement::default() };
    let out = match tempfile::tempdir() {
        Ok(d) => d,
        Err(e) => {
            m.error = Some(e.to_string());
            return m;
        }
    };
    let options = analysis::RunOptions::for_model(&model, backend);
    let surface_nodes = &model.node_sets["surface"];
    let node = surface_nodes[surface_nodes.len() / 2];
    let output = OutputOptions { no_restart: true, keep: KeptSteps::EveryNth(KEEP_EVERY), ..Default::default() };
    let mut surface = Surface { node, steps: 0, peak: 0.0 };
    let t = Instant::now();
    let result = crate::output::ResultWriter::with_options(&model, out.path(), backend.name(), &output).and_then(
        |mut writer| {
            writer.timed_before(process.at, vec![process.phase(), generated]);
            crate::output::write_run(&model, &options, None, &mut writer, &mut surface).map(|_| writer)
        },
    );
    m.wall_seconds = t.elapsed().as_secs_f64();
    m.time_steps = surface.steps;
    m.surface_peak = surface.peak;
    match result {
        Ok(writer) => {
            let s = &writer.summary.solver_stats;
            m.iterations = s.iterations;
            m.factorizations = s.solver.factorizations;
            m.solves = s.solver.solves;
            m.phases = [
                s.solver.assembly_seconds,
                s.residual_seconds,
                s.solver.factorize_seconds,
                s.solver.solve_seconds,
                s.output_seconds,
            ];
            m.timings = writer.summary.timings.clone();
        }
        Err(e) => m.error = Some(e.to_string()),
    }
    m.output_bytes = super::pullout_bench::folder_bytes(out.path());
    drop(out);
    m.peak_memory_mb = peak_memory_mb();
    let mut unwritten = Surface { node, steps: 0, peak: 0.0 };
    let t = Instant::now();
    if let Err(e) = analysis::run(&model, &options, &mut unwritten) {
        m.error = Some(e.to_string());
    }
    m.unwritten_wall_seconds = t.elapsed().as_secs_f64();
    // the floor, in this process
    let (n, floor) = super::pullout_bench::floor(&model, backend);
    m.unknowns = n;
    match floor {
        Ok((factorize, solve)) => (m.factorize_seconds, m.solve_seconds) = (factorize, solve),
        Err(e) => m.error = Some(e),
    }
    m
}

/// Each size in a child process; one Markdown table, then where each run's time went.
pub fn bench_dynamic(sizes: &[usize], steps: usize, backend: Backend) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let backend = backend.resolve();
    linsol::check_available(backend).map_err(|e| e.to_string())?;
    println!(
        "geoslip {} — dynamic benchmark on {}: a 40 m × 20 m elastic layer on a rigid base, {steps} time steps of {TIME_STEP} s, every {KEEP_EVERY}th step's fields written",
        env!("CARGO_PKG_VERSION"),
        backend.name()
    );
    println!();
    println!("| unknowns | time steps | wall [s] | wall, no files [s] | factorisation [s] | solve [s] | wall / (factorisation + {steps} solves) | no files / floor | iterations / step | factorisations | solves | assembly | residual | factorisations | solves | output | output [MB] | peak RSS [MiB] | surface's peak ux [mm] |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut timed = Vec::new();
    for &size in sizes {
        let out = std::process::Command::new(&exe)
            .args(["bench-one", "--dynamic", "--dofs", &size.to_string(), "--backend", backend.name()])
            .args(["--steps", &steps.to_string()])
            .output()
            .map_err(|e| e.to_string())?;
        let m: DynamicMeasurement = match serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()) {
            Ok(m) => m,
            Err(_) => {
                let why = String::from_utf8_lossy(&out.stderr);
                println!("| {size} | failed: {} |", why.lines().last().unwrap_or("no output"));
                continue;
            }
        };
        if let Some(e) = &m.error {
            println!("| {} | failed: {e} |", m.unknowns);
            continue;
        }
        let share = |s: f64| format!("{:.0} %", 100.0 * s / m.wall_seconds);
        println!(
            "| {} | {} | {:.2} | {:.2} | {:.3} | {:.4} | {:.2} | {:.2} | {:.2} | {} | {} | {} | {} | {} | {} | {} | {:.1} | {:.0} | {:.2} |",
            m.unknowns,
            m.time_steps,
            m.wall_seconds,
            m.unwritten_wall_seconds,
            m.factorize_seconds,
            m.solve_seconds,
            m.floor_ratio(m.wall_seconds),
            m.floor_ratio(m.unwritten_wall_seconds),
            m.iterations as f64 / (m.time_steps.max(1) + 1) as f64,
            m.factorizations,
            m.solves,
            share(m.phases[0]),
            share(m.phases[1]),
            share(m.phases[2]),
            share(m.phases[3]),
            share(m.phases[4]),
            m.output_bytes as f64 / 1e6,
            m.peak_memory_mb,
            1e3 * m.surface_peak,
        );
        timed.push((format!("{} unknowns, {} time steps", m.unknowns, m.time_steps), m.timings));
    }
    for (label, timings) in timed {
        println!("\nWhere the time went: {label} (other {:.1} %)\n", 100.0 * timings.other_share());
        print!("{}", timings.table());
    }
    Ok(())
}
