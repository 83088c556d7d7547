//! `geoslip bench --pullout`: a whole pull-out run, results written, against the floor of one
//! factorisation and one solve per pull step measured in the same process.
//!
//! The model: a 2 m × 1 m elastic soil block of square quad4 elements (E = 20 MPa, ν = 0.3), a
//! reinforcement at mid-height from x = 0 to 1.6 m on the soil's nodes (EA = 500 kN/m), Coulomb
//! faces (Ks = 2000 kPa/m, c = 0, φ = 30°) with σn frozen at the 20 kPa surcharge, the head pulled
//! 20 mm in 40 steps of 0.5 mm. Each size runs in a child process of its own (`bench-one
//! --pullout`), so that its peak memory is its own.

use super::measure::peak_memory_mb;
use crate::analysis::results::StepResults;
use crate::analysis::{self, StepRecord, StepSink};
use crate::linsol::linear_system::{LinearSystem, SolverStats};
use crate::linsol::{self, Backend};
use crate::meshgen::PullOutBox;
use crate::model::file::{ModelFile, ShearLawSpec};
use crate::model::{Extrapolation, Model, Scheme};
use crate::timing::{Phase, ProcessStart, Timings};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// Pull steps of the benchmark run.
pub const PULL_STEPS: usize = 40;

/// The benchmark model with about `dofs` unknowns.
pub fn pullout_box(dofs: usize, scheme: Scheme, extrapolation: Extrapolation) -> Model {
    Model::from_file(Path::new("generated-pullout-benchmark"), &pullout_box_file(dofs, scheme, extrapolation))
        .expect("the generated pull-out benchmark is a valid model")
}

/// The benchmark model with about `dofs` unknowns, as its model file (the mesh inline).
pub fn pullout_box_file(dofs: usize, scheme: Scheme, extrapolation: Extrapolation) -> ModelFile {
    // unknowns ≈ 2·(nx+1)·(2·ny_half+1) with nx = 2·(2·ny_half) for square elements in 2 m × 1 m
    let ny_half = ((dofs as f64 / 16.0).sqrt().round() as usize).max(2);
    let nx = 4 * ny_half;
    let mut file = PullOutBox {
        length: 2.0,
        height: 1.0,
        embedded: 1.6,
        nx,
        ny_half,
        axial_stiffness: 500.0,
        law: ShearLawSpec::Coulomb { shear_stiffness: 2000.0, cohesion: 0.0, friction_angle: 30.0 },
        surcharge: 20.0,
        pull: 0.02,
        steps: PULL_STEPS,
        ..PullOutBox::default()
    }
    .model();
    file.analysis.freeze_normal_stress = true;
    file.analysis.scheme = scheme;
    file.analysis.extrapolation = extrapolation;
    file
}

/// Write the benchmark model of each size into `folder` as `pullout-<size>.toml` (constant
/// stiffness, the mesh inline): the same runs from a model file, with `geoslip run`.
///
/// # Errors
/// What could not be written, by its path.
pub fn write_pullout_models(sizes: &[usize], folder: &Path) -> Result<(), String> {
    std::fs::create_dir_all(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    for &size in sizes {
        let file = pullout_box_file(size, Scheme::ConstantStiffness, Extrapolation::None);
        let text = toml::to_string(&file).map_err(|e| format!("the benchmark model of {size} unknowns: {e}"))?;
        let path = folder.join(format!("pullout-{size}.toml"));
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        println!("{}", path.display());
    }
    Ok(())
}

/// One run of the benchmark model.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct PulloutMeasurement {
    pub backend: String,
    pub scheme: String,
    pub condensed: bool,
    pub unknowns: usize,
    /// Unknowns the condensed system kept.
    pub kept: Option<usize>,
    pub wall_seconds: f64,
    /// One factorisation and one solve of the run's first system, in this process (medians of 3).
    pub factorize_seconds: f64,
    pub solve_seconds: f64,
    pub pull_steps: usize,
    pub iterations: usize,
    pub factorizations: usize,
    pub dense_factorizations: usize,
    /// BiCGSTAB iterations on the dense interface system while it drifts.
    #[serde(default)]
    pub dense_iterations: usize,
    pub solves: usize,
    pub output_seconds: f64,
    /// The first run's time in the result writer on the run's own thread (the summary's
    /// `write_seconds`).
    #[serde(default)]
    pub write_seconds: f64,
    /// The CPU time of the thread writing `results.h5` in the first run, where known.
    #[serde(default)]
    pub writer_thread_seconds: Option<f64>,
    /// The same run in the same process with no result files (the head force kept in memory):
    /// the mean of two, one before and one after `rewritten_wall_seconds`.
    #[serde(default)]
    pub unwritten_wall_seconds: f64,
    /// The run writing its results once more, between the two writing nothing.
    #[serde(default)]
    pub rewritten_wall_seconds: f64,
    /// How many written runs `rewritten_wall_seconds` and `unwritten_wall_seconds` are the means
    /// of (`--pairs`): the written runs alternate with runs writing nothing, one more of those.
    #[serde(default)]
    pub share_pairs: usize,
    /// The mean over the written runs of 1 − (the mean of the two unwritten runs around it) / (its
    /// wall time), and that mean's standard error (zero for one written run).
    #[serde(default)]
    pub output_share_mean: f64,
    #[serde(default)]
    pub output_share_error: f64,
    pub output_bytes: u64,
    /// The peak resident memory of the process when the run (the first, writing its results) has
    /// ended: the model built and the run, before the run writing nothing and the floor's
    /// factorisations of the whole first system (which peak apart, measured in `process_peak_mb`).
    pub peak_memory_mb: f64,
    /// The peak resident memory of the whole process, the floor's measurement included.
    #[serde(default)]
    pub process_peak_mb: f64,
    /// The head force at the end of the pull [kN/m].
    pub head_force: f64,
    /// The run's own phase times [s]: assembly, interface, residual, solution check, sparse
    /// factorisation, sparse solves, dense (condensed) factorisations and solves.
    pub phases: [f64; 8],
    /// The first run's timings, from this process's start to the end of that run (its
    /// `summary.json`'s `timings`).
    #[serde(default)]
    pub timings: Timings,
    pub error: Option<String>,
}

impl PulloutMeasurement {
    /// Wall time over the floor: one factorisation and one solve per pull step.
    pub fn floor_ratio(&self) -> f64 {
        self.wall_seconds / (self.factorize_seconds + self.pull_steps as f64 * self.solve_seconds)
    }

    /// The share of the run that writing its results costs: 1 − (the run writing nothing) / (the
    /// run writing its results), both after the first run of the process (whose wall time is the
    /// one reported), each written run between two unwritten ones, averaged over the written
    /// runs. A process's first run pays once for what the later ones find ready (the heap grown,
    /// the libraries' first calls), and its later runs drift faster still: a pair with the first
    /// run in it would count either as output.
    pub fn output_share(&self) -> f64 {
        if self.share_pairs > 0 {
            return self.output_share_mean;
        }
        if self.unwritten_wall_seconds == 0.0 {
            // (`--pairs 0`: no run writing nothing)
            return f64::NAN;
        }
        let written = if self.rewritten_wall_seconds > 0.0 { self.rewritten_wall_seconds } else { self.wall_seconds };
        1.0 - self.unwritten_wall_seconds / written
    }
}

/// Keeps the pull steps' count and the last head force.
struct Head {
    nodes: Vec<u64>,
    pull_steps: usize,
    force: f64,
}

impl StepSink for Head {
    fn step_done(
        &mut self,
        _: &crate::model::Model,
        step: &StepResults,
        record: &StepRecord,
        _: &analysis::RunStats,
    ) -> Result<(), crate::Error> {
        if record.stage_index == 1 {
            self.pull_steps += 1;
            let head = step.reactions.iter().filter(|r| self.nodes.contains(&r.node));
            self.force = head.filter_map(|r| r.rx).sum::<f64>().abs();
        }
        Ok(())
    }
}

fn median3(mut v: [f64; 3]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[1]
}

/// Run the benchmark model with about `dofs` unknowns, its results written into a temporary folder;
/// then `pairs` times the same run writing nothing and writing again, for the output share.
pub fn measure_pullout(
    dofs: usize,
    backend: Backend,
    scheme: Scheme,
    condense: bool,
    extrapolation: Extrapolation,
    pairs: usize,
    process: ProcessStart,
) -> PulloutMeasurement {
    let started = Instant::now();
    let model = pullout_box(dofs, scheme, extrapolation);
    let generated = Phase::new(
        "benchmark model generated",
        started.elapsed().as_secs_f64() - model.load_times.iter().map(|p| p.seconds).sum::<f64>(),
    );
    let mut m = PulloutMeasurement {
        backend: backend.resolve().name().into(),
        scheme: format!("{scheme:?}"),
        condensed: condense,
        ..PulloutMeasurement::default()
    };
    let out = match tempfile::tempdir() {
        Ok(d) => d,
        Err(e) => {
            m.error = Some(e.to_string());
            return m;
        }
    };
    let options = analysis::RunOptions {
        solver: linsol::SolverOptions { condense, ..linsol::SolverOptions::default() },
        ..analysis::RunOptions::for_model(&model, backend)
    };
    let nodes = model.node_sets.get("grid.head").map(|set| set.iter().map(|&n| model.mesh.node_id(n)).collect());
    let mut head = Head { nodes: nodes.unwrap_or_default(), pull_steps: 0, force: 0.0 };
    // the fields and the history, as issue-sized runs write them; the saved steps a run can
    // continue from are left out (measured apart: docs/performance.md)
    let output = crate::output::OutputOptions { no_restart: true, ..Default::default() };
    let written_run = |folder: &Path, head: &mut Head| {
        crate::output::ResultWriter::with_options(&model, folder, backend.name(), &output)
            .and_then(|mut writer| crate::output::write_run(&model, &options, None, &mut writer, head).map(|_| writer))
    };
    let t = Instant::now();
    // the first run's timings count from the process's start
    let result = crate::output::ResultWriter::with_options(&model, out.path(), backend.name(), &output).and_then(
        |mut writer| {
            writer.timed_before(process.at, vec![process.phase(), generated]);
            crate::output::write_run(&model, &options, None, &mut writer, &mut head).map(|_| writer)
        },
    );
    m.wall_seconds = t.elapsed().as_secs_f64();
    m.pull_steps = head.pull_steps;
    m.head_force = head.force;
    match result {
        Ok(writer) => {
            let s = &writer.summary.solver_stats;
            m.iterations = s.iterations;
            m.factorizations = s.solver.factorizations;
            m.dense_factorizations = s.solver.dense_factorizations;
            m.dense_iterations = s.solver.dense_iterations;
            m.solves = s.solver.solves;
            m.output_seconds = s.output_seconds;
            m.writer_thread_seconds = writer.summary.writer_thread_seconds;
            m.write_seconds = writer.summary.write_seconds;
            m.kept = s.solver.condensed_unknowns;
            m.timings = writer.summary.timings.clone();
            m.phases = [
                s.solver.assembly_seconds,
                s.interface_seconds,
                s.residual_seconds,
                s.solver.check_seconds,
                s.solver.factorize_seconds,
                s.solver.solve_seconds,
                s.solver.dense_seconds,
                s.solver.analyse_seconds,
            ];
        }
        Err(e) => m.error = Some(e.to_string()),
    }
    m.peak_memory_mb = peak_memory_mb();
    m.output_bytes = folder_bytes(out.path());
    drop(out);
    // the same run writing nothing, then writing its results again (in a folder of its own),
    // then writing nothing again, `pairs` times over: what writing costs is each written run
    // against the mean of the two around it
    let unwritten_run = || {
        let mut unwritten = Head { nodes: head.nodes.clone(), pull_steps: 0, force: 0.0 };
        let t = Instant::now();
        let result = analysis::run(&model, &options, &mut unwritten);
        (t.elapsed().as_secs_f64(), result.err())
    };
    let (mut unwritten, mut rewritten, mut shares) = (Vec::new(), Vec::new(), Vec::new());
    let mut before = 0.0;
    if pairs > 0 {
        let error;
        (before, error) = unwritten_run();
        if let Some(e) = error {
            m.error = Some(e.to_string());
        }
        unwritten.push(before);
    }
    for _ in 0..pairs {
        let written = match tempfile::tempdir() {
            Ok(again) => {
                let mut rewritten = Head { nodes: head.nodes.clone(), pull_steps: 0, force: 0.0 };
                let t = Instant::now();
                if let Err(e) = written_run(again.path(), &mut rewritten) {
                    m.error = Some(e.to_string());
                }
                t.elapsed().as_secs_f64()
            }
            Err(e) => {
                m.error = Some(e.to_string());
                break;
            }
        };
        let (after, error) = unwritten_run();
        if let Some(e) = error {
            m.error = Some(e.to_string());
        }
        rewritten.push(written);
        unwritten.push(after);
        shares.push(1.0 - 0.5 * (before + after) / written);
        before = after;
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    m.unwritten_wall_seconds = mean(&unwritten);
    m.rewritten_wall_seconds = mean(&rewritten);
    m.share_pairs = shares.len();
    m.output_share_mean = mean(&shares);
    if shares.len() > 1 {
        let spread = shares.iter().map(|s| (s - m.output_share_mean).powi(2)).sum::<f64>() / (shares.len() - 1) as f64;
        m.output_share_error = (spread / shares.len() as f64).sqrt();
    }
    // the floor, in this process
    let (n, floor) = floor(&model, backend);
    m.unknowns = n;
    match floor {
        Ok((factorize, solve)) => (m.factorize_seconds, m.solve_seconds) = (factorize, solve),
        Err(e) => m.error = Some(e),
    }
    m.process_peak_mb = peak_memory_mb();
    m
}

/// The floor of a run of `model`, measured in this process: its first system factorised and
/// solved three times each, the medians of a factorisation and of a solve [s], with the system's
/// unknowns.
pub(super) fn floor(model: &Model, backend: Backend) -> (usize, Result<(f64, f64), String>) {
    let (n, system) = analysis::first_system(model);
    let mut ls = match LinearSystem::new(backend, true, &linsol::SolverOptions::default()) {
        Ok(ls) => ls,
        Err(e) => return (n, Err(e.to_string())),
    };
    let mut stats = SolverStats::default();
    let (mut factorize, mut solve) = ([0.0; 3], [0.0; 3]);
    for k in 0..3 {
        let mut values = system.triplets.clone();
        // new values each time (the same matrix scaled), so that each is a factorisation
        for v in &mut values.values {
            *v *= 1.0 + 1e-9 * (k + 1) as f64;
        }
        let t = Instant::now();
        let _ = ls.solve(&mut stats, n, values, &system.rhs, system.active);
        factorize[k] = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let _ = ls.solve_again(&mut stats, &system.rhs);
        solve[k] = t.elapsed().as_secs_f64();
    }
    // a factorisation's time is the solve's call less its one solve
    let solve = median3(solve);
    (n, Ok(((median3(factorize) - solve).max(0.0), solve)))
}

pub(super) fn folder_bytes(dir: &Path) -> u64 {
    let Ok(entries) = std::fs::read_dir(dir) else { return 0 };
    entries
        .flatten()
        .map(|e| match e.file_type() {
            Ok(t) if t.is_dir() => folder_bytes(&e.path()),
            _ => e.metadata().map(|m| m.len()).unwrap_or(0),
        })
        .sum()
}

/// Each size and variant in a child process; one Markdown table.
pub fn bench_pullout(
    sizes: &[usize],
    backend: Backend,
    variants: &[(Scheme, bool, Extrapolation)],
) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let backend = backend.resolve();
    linsol::check_available(backend).map_err(|e| e.to_string())?;
    println!(
        "geoslip {} — pull-out benchmark on {}: 2 m × 1 m elastic soil, 1.6 m reinforcement, {PULL_STEPS} pull steps of 0.5 mm, results written",
        env!("CARGO_PKG_VERSION"),
        backend.name()
    );
    println!();
    println!("| unknowns | scheme | condensed (kept) | first iterate | wall [s] | factorisation [s] | solve [s] | wall / (factorisation + {PULL_STEPS} solves) | iterations / step | factorisations | dense LUs | dense iterations | solves | wall, no files written [s] | wall, written again [s] | output share | output [MB] | peak RSS, the run [MiB] | peak RSS, process [MiB] | head force [kN/m] |");
    println!("|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut timed = Vec::new();
    for &size in sizes {
        for &(scheme, condense, extrapolation) in variants {
            let scheme_name = match scheme {
                Scheme::ConstantStiffness => "constant-stiffness",
                Scheme::Newton => "newton",
                Scheme::NewtonSymmetric => "newton-symmetric",
            };
            let mut cmd = std::process::Command::new(&exe);
            cmd.args(["bench-one", "--pullout", "--dofs", &size.to_string(), "--backend", backend.name()]);
            cmd.args(["--scheme", scheme_name]);
            if !condense {
                cmd.arg("--full-system");
            }
            let first_iterate = match extrapolation {
                Extrapolation::None => "last converged",
                Extrapolation::Linear => {
                    cmd.arg("--extrapolate");
                    "extrapolated"
                }
            };
            let out = cmd.output().map_err(|e| e.to_string())?;
            let m: PulloutMeasurement = match serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()) {
                Ok(m) => m,
                Err(_) => {
                    let why = String::from_utf8_lossy(&out.stderr);
                    println!("| {size} | {scheme_name} | failed: {} |", why.lines().last().unwrap_or("no output"));
                    continue;
                }
            };
            if let Some(e) = &m.error {
                println!("| {} | {scheme_name} | failed: {e} |", m.unknowns);
                continue;
            }
            println!(
                "| {} | {} | {} | {} | {:.2} | {:.3} | {:.4} | {:.2} | {:.2} | {} | {} | {} | {} | {:.2} | {:.2} | {:.1} % | {:.1} | {:.0} | {:.0} | {:.4} |",
                m.unknowns,
                scheme_name,
                match (m.condensed, m.kept) {
                    (true, Some(k)) => format!("yes ({k})"),
                    (true, None) => "asked, not used".into(),
                    _ => "no".into(),
                },
                first_iterate,
                m.wall_seconds,
                m.factorize_seconds,
                m.solve_seconds,
                m.floor_ratio(),
                m.iterations as f64 / (m.pull_steps.max(1) + 1) as f64,
                m.factorizations,
                m.dense_factorizations,
                m.dense_iterations,
                m.solves,
                m.unwritten_wall_seconds,
                m.rewritten_wall_seconds,
                100.0 * m.output_share(),
                m.output_bytes as f64 / 1e6,
                m.peak_memory_mb,
                m.process_peak_mb,
                m.head_force,
            );
            let label = format!(
                "{} unknowns, {scheme_name}, {first_iterate} first iterate, condensed: {}",
                m.unknowns, m.condensed
            );
            timed.push((label, m.timings));
        }
    }
    // where each process's time went, up to the end of its first run (summary.json's timings)
    for (label, timings) in timed {
        println!("\nWhere the time went: {label} (other {:.1} %)\n", 100.0 * timings.other_share());
        print!("{}", timings.table());
    }
    Ok(())
}
