//! `geoslip bench`: the solver backends on generated pull-out meshes, side by side.
//!
//! Each (size, backend) pair runs in a child process of its own (`geoslip bench-one`), so that its
//! peak resident memory is its own; a child with no backend measures the model alone. Times are
//! wall-clock seconds on this machine and are reported next to ratios measured in the same command,
//! because machines here are noisy. The MUMPS path (assembly to CSC, lower triangle, analysis,
//! factorisation, solve, residual check) is also timed against a bare MUMPS call on the same matrix,
//! interleaved, in one process: the path starts from the assembled matrix (assembly is the same work
//! whichever backend follows) and includes the wrapper's own work (lower triangle, index
//! conversion, copies) and the residual check.

use crate::analysis;
use crate::linsol::csc::{CscMatrix, PatternCache};
use crate::linsol::{self, Backend};
use crate::meshgen::PullOutBox;
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// A generated pull-out box with about `dofs` unknowns (quad4, square-ish elements).
pub fn pullout_model(dofs: usize) -> Model {
    // unknowns ≈ 2·(nx+1)·(2·ny_half+1), with nx = r·2·ny_half for square elements in the
    // 1.0 m × 0.6 m box (r = 1/0.6): 2·r·(2·ny_half)² ≈ unknowns
    let r = 1.0 / 0.6;
    let rows = (dofs as f64 / (2.0 * r)).sqrt();
    let ny_half = ((rows / 2.0).round() as usize).max(1);
    let nx = ((r * 2.0 * ny_half as f64).round() as usize).max(4);
    let file = PullOutBox { nx, ny_half, steps: 1, ..PullOutBox::default() }.model();
    Model::from_file(Path::new("generated-pullout-box"), &file).expect("the generated pull-out box is a valid model")
}

/// One backend on one matrix.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Measurement {
    pub backend: String,
    pub unknowns: usize,
    pub nonzeros: usize,
    pub analyse_seconds: f64,
    pub factorize_seconds: f64,
    pub solve_seconds: f64,
    pub factor_entries: Option<u64>,
    pub peak_memory_mb: f64,
    pub relative_residual: f64,
    pub error: Option<String>,
}

/// Peak resident memory of this process so far (VmHWM), MB.
pub fn peak_memory_mb() -> f64 {
    crate::memory::process_status_mb("VmHWM:")
}

/// Build the model's first system and time one backend on it (`None`: the model alone).
pub fn measure(dofs: usize, backend: Option<Backend>, ordering: linsol::Ordering) -> Measurement {
    let model = pullout_model(dofs);
    let (n, system) = analysis::first_system(&model);
    let matrix = PatternCache::default().assemble(n, &system.triplets).0;
    let mut m = Measurement {
        backend: match backend.map(Backend::resolve) {
            Some(Backend::Mumps) => format!("mumps ({})", ordering.name()),
            Some(b) => b.name().to_string(),
            None => "model only".into(),
        },
        unknowns: n,
        nonzeros: matrix.pattern.nnz(),
        analyse_seconds: 0.0,
        factorize_seconds: 0.0,
        solve_seconds: 0.0,
        factor_entries: None,
        peak_memory_mb: 0.0,
        relative_residual: 0.0,
        error: None,
    };
    if let Some(backend) = backend {
        if let Err(e) = time_backend(backend, ordering, &matrix, &system.rhs, &mut m) {
            m.error = Some(e);
        }
    }
    m.peak_memory_mb = peak_memory_mb();
    m
}

fn time_backend(
    backend: Backend,
    ordering: linsol::Ordering,
    matrix: &CscMatrix,
    rhs: &[f64],
    m: &mut Measurement,
) -> Result<(), String> {
    let options = linsol::SolverOptions { ordering, ..linsol::SolverOptions::default() };
    let mut solver = linsol::make(backend, true, &options).map_err(|e| e.to_string())?;
    let t = Instant::now();
    solver.analyse(matrix).map_err(|e| format!("{e:?}"))?;
    m.analyse_seconds = t.elapsed().as_secs_f64();
    let t = Instant::now();
    solver.factorize(matrix).map_err(|e| format!("{e:?}"))?;
    m.factorize_seconds = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let x = solver.solve(rhs).map_err(|e| format!("{e:?}"))?;
    m.solve_seconds = t.elapsed().as_secs_f64();
    m.factor_entries = solver.factor_entries();
    m.relative_residual = linsol::relative_residual(matrix, &x, rhs);
    Ok(())
}

/// The MUMPS path (wrapper: JOB −1, lower triangle and 1-based indices, JOB 1, 2, 3, residual check,
/// JOB −2) against a bare MUMPS call on the same matrix, interleaved `repeats` times in this process. Returns (median path seconds, median bare seconds, unknowns).
pub fn mumps_overhead(dofs: usize, repeats: usize) -> Result<(f64, f64, usize), String> {
    if !Backend::available().contains(&Backend::Mumps) {
        return Err("this build has no MUMPS".into());
    }
    let model = pullout_model(dofs);
    let (n, system) = analysis::first_system(&model);
    // The bare call gets MUMPS's input ready-made: 1-based lower-triangle coordinates.
    let matrix = PatternCache::default().assemble(n, &system.triplets).0;
    let (mut irn, mut jcn, mut a) = (Vec::new(), Vec::new(), Vec::new());
    let p = &matrix.pattern;
    for j in 0..n {
        for k in p.col_ptr()[j]..p.col_ptr()[j + 1] {
            if p.row_idx()[k] >= j {
                irn.push(p.row_idx()[k] as i32 + 1);
                jcn.push(j as i32 + 1);
                a.push(matrix.values[k]);
            }
        }
    }
    let mut path = Vec::new();
    let mut bare = Vec::new();
    for _ in 0..repeats {
        // The path: geoslip's MUMPS wrapper from the assembled matrix to a checked solution.
        let t = Instant::now();
        let mut solver =
            linsol::make(Backend::Mumps, true, &linsol::SolverOptions::default()).map_err(|e| e.to_string())?;
        solver.analyse(&matrix).map_err(|e| format!("{e:?}"))?;
        solver.factorize(&matrix).map_err(|e| format!("{e:?}"))?;
        let x = solver.solve(&system.rhs).map_err(|e| format!("{e:?}"))?;
        let residual = linsol::relative_residual(&matrix, &x, &system.rhs);
        drop(solver);
        path.push(t.elapsed().as_secs_f64());
        if !(residual < 1e-8) {
            return Err(format!("the MUMPS path's residual is {residual:e}"));
        }
        let t = Instant::now();
        bare_mumps(n, &mut irn, &mut jcn, &mut a, &system.rhs)?;
        bare.push(t.elapsed().as_secs_f64());
    }
    Ok((median(&mut path), median(&mut bare), n))
}

#[cfg(geoslip_mumps)]
fn bare_mumps(n: usize, irn: &mut [i32], jcn: &mut [i32], a: &mut [f64], rhs: &[f64]) -> Result<(), String> {
    let mut x = rhs.to_vec();
    match linsol::native::mumps::bare_run(true, n, irn, jcn, a, &mut x) {
        0 => Ok(()),
        code => Err(crate::error::SolveError::mumps(crate::error::Phase::Factorisation, code, 0).to_string()),
    }
}

#[cfg(not(geoslip_mumps))]
fn bare_mumps(_: usize, _: &mut [i32], _: &mut [i32], _: &mut [f64], _: &[f64]) -> Result<(), String> {
    Err("this build has no MUMPS".into())
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// The nonlinear benchmark model: a pull-out box of quad4 elements with about `dofs` unknowns and
/// as many reinforcement layers (`grid-1`, … from the bottom up) as make the reinforcement
/// stations about 1 % of the unknowns. The interfaces are Coulomb (c = 0, φ = 30°, Ks = 20 MN/m³)
/// under 50 kPa, so the grids slip and slide over several soil segments in the 20 pull increments
/// (30 mm in all), and re-association happens.
pub fn multilayer_model(dofs: usize) -> Model {
    let r = 1.0 / 0.6;
    let rows = (dofs as f64 / (2.0 * r)).sqrt();
    let ny_half = ((rows / 2.0).round() as usize).max(2);
    let nx = ((r * 2.0 * ny_half as f64).round() as usize).max(4);
    let stations_per_layer = (0.8 * nx as f64).max(1.0);
    let layers = ((0.01 * dofs as f64 / stations_per_layer).round() as usize).clamp(1, ny_half);
    let file = PullOutBox {
        nx,
        ny_half,
        layers,
        steps: 20,
        pull: 0.03,
        law: crate::model::file::ShearLawSpec::Coulomb {
            shear_stiffness: 20_000.0,
            cohesion: 0.0,
            friction_angle: 30.0,
        },
        ..PullOutBox::default()
    }
    .model();
    Model::from_file(Path::new("generated-multilayer-pullout"), &file)
        .expect("the generated multi-layer pull-out box is a valid model")
}

/// One nonlinear run of the benchmark model: counts, phase times and memory.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct NonlinearMeasurement {
    pub backend: String,
    pub ordering: String,
    /// Soil and reinforcement displacement unknowns (free and held) and multipliers.
    pub dofs: usize,
    pub layers: usize,
    /// Reinforcement nodes (slave points of one face).
    pub stations: usize,
    pub increments: usize,
    pub iterations: usize,
    pub analyses: usize,
    pub factorizations: usize,
    pub solves: usize,
    pub reassociations: usize,
    /// Largest slip of any point at the end [m] and the element length [m].
    pub max_slip: f64,
    pub element_length: f64,
    pub total_seconds: f64,
    /// Element matrices and the first assembly's bookkeeping.
    pub setup_seconds: f64,
    pub assembly_seconds: f64,
    pub interface_seconds: f64,
    pub residual_seconds: f64,
    pub check_seconds: f64,
    pub analyse_seconds: f64,
    pub factorize_seconds: f64,
    pub solve_seconds: f64,
    pub output_seconds: f64,
    /// The model's own storage: the model, its element matrices and its assembled system
    /// (`analysis::model_memory_estimate_mb`, calibrated on the "model and assembly only" rows), MB.
    pub model_memory_mb: f64,
    pub peak_memory_mb: f64,
    /// MUMPS's INFOG(22) of the last factorisation, MB.
    pub factor_memory_mb: Option<f64>,
    pub error: Option<String>,
}

pub use crate::memory::resident_memory_mb;

/// Counts steps and re-associations, keeps nothing else.
#[derive(Default)]
struct Counter {
    increments: usize,
    reassociations: usize,
    max_slip: f64,
}

impl analysis::StepSink for Counter {
    fn step_done(
        &mut self,
        _: &crate::model::Model,
        step: &analysis::results::StepResults,
        record: &analysis::StepRecord,
        _: &crate::analysis::RunStats,
    ) -> Result<(), crate::Error> {
        self.increments += 1;
        self.reassociations += record.reassociations.len();
        self.max_slip = step.interface_points.iter().map(|p| p.slip.abs()).fold(self.max_slip, f64::max);
        Ok(())
    }
}

/// Run the nonlinear benchmark model with about `dofs` unknowns on one backend.
pub fn measure_nonlinear(dofs: usize, backend: Backend, ordering: linsol::Ordering) -> NonlinearMeasurement {
    let model = multilayer_model(dofs);
    let mut m = NonlinearMeasurement {
        backend: backend.resolve().name().into(),
        ordering: ordering.name().into(),
        dofs: 2 * model.mesh.nodes.len() + crate::dofs::multipliers(&model.interfaces).len(),
        layers: model.interfaces.iter().filter(|i| i.slit_of.is_none()).count(),
        stations: model.interfaces.iter().filter(|i| i.slit_of.is_none()).map(|i| i.faces[0].points.len()).sum(),
        element_length: model.mesh.characteristic_length(),
        model_memory_mb: analysis::model_memory_estimate_mb(&model),
        ..NonlinearMeasurement::default()
    };
    let options = analysis::RunOptions {
        solver: linsol::SolverOptions { ordering, ..linsol::SolverOptions::default() },
        ..analysis::RunOptions::for_model(&model, backend)
    };
    let mut counter = Counter::default();
    let t = Instant::now();
    let result = analysis::run(&model, &options, &mut counter);
    m.total_seconds = t.elapsed().as_secs_f64();
    m.peak_memory_mb = peak_memory_mb();
    m.increments = counter.increments;
    m.reassociations = counter.reassociations;
    m.max_slip = counter.max_slip;
    match result {
        Ok(s) => {
            m.iterations = s.iterations;
            m.analyses = s.solver.analyses;
            m.factorizations = s.solver.factorizations;
            m.solves = s.solver.solves;
            m.assembly_seconds = s.solver.assembly_seconds;
            m.interface_seconds = s.interface_seconds;
            m.residual_seconds = s.residual_seconds;
            m.check_seconds = s.solver.check_seconds;
            m.analyse_seconds = s.solver.analyse_seconds;
            m.factorize_seconds = s.solver.factorize_seconds;
            m.solve_seconds = s.solver.solve_seconds;
            m.output_seconds = s.output_seconds;
            m.factor_memory_mb = s.solver.factor_memory_mb;
            m.setup_seconds = m.total_seconds
                - (s.solver.assembly_seconds
                    + s.interface_seconds
                    + s.residual_seconds
                    + s.solver.check_seconds
                    + s.solver.analyse_seconds
                    + s.solver.factorize_seconds
                    + s.solver.solve_seconds
                    + s.output_seconds);
        }
        Err(e) => m.error = Some(e.to_string()),
    }
    m
}
