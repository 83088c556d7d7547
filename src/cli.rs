//! The geoslip command line (the `geoslip` and `geoslip-mpi` programs).

use crate::analysis::{self, RunOptions, StepRecord, StepSink};
use crate::linsol::{Backend, Ordering, SolverOptions};
use crate::model::{Case, Model};
use crate::output::ResultWriter;
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "geoslip",
    version = version(),
    about = "Finite-element analysis of soil–geosynthetic interfaces that slip a lot",
    after_help = "Exit codes: 0 success; 1 cannot write the results; 2 bad input (model file or flags); \
                  3 no equilibrium (an increment did not converge); 4 the solver failed (a singular model, \
                  a backend not in this build)."
)]
struct Cli {
    /// Print only errors: no progress bar, no summary line.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Print a line per step: iterations, cutbacks, state changes, re-associations.
    #[arg(short, long, global = true)]
    verbose: bool,
    #[command(subcommand)]
    command: Command,
}

/// Exit codes, distinct per kind of failure so that scripts can tell them apart.
mod exit {
    pub const WRITE: u8 = 1;
    pub const BAD_INPUT: u8 = 2;
    pub const NOT_CONVERGED: u8 = 3;
    pub const SOLVER: u8 = 4;
}

fn exit_code(e: &crate::Error) -> ExitCode {
    use crate::Error::*;
    ExitCode::from(match e {
        Read { .. } | Parse { .. } | Model(_) => exit::BAD_INPUT,
        NotConverged { .. } => exit::NOT_CONVERGED,
        Solve { .. } | Backend(_) => exit::SOLVER,
        Write { .. } => exit::WRITE,
    })
}

fn version() -> &'static str {
    concat!(env!("CARGO_PKG_VERSION"), " (solver backends: ", env!("GEOSLIP_BACKENDS"), ")")
}

#[derive(Subcommand)]
enum Command {
    /// Run every stage of a model and write the results.
    Run {
        /// Model file (TOML, or JSON when it ends in .json).
        model: PathBuf,
        /// Linear solver backend.
        #[arg(long, value_enum, default_value = "auto")]
        solver: Backend,
        /// Output folder (default: results/<model name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// MUMPS's fill-reducing ordering (auto: Scotch, or PORD in the MPI build).
        #[arg(long, value_enum, default_value = "auto")]
        ordering: Ordering,
        /// MUMPS keeps its factors on disk (ICNTL(22) = 1), in $MUMPS_OOC_TMPDIR or /tmp.
        #[arg(long)]
        out_of_core: bool,
        /// Memory the run may use, MB (default: what the machine has available). A factorisation
        /// that MUMPS estimates above it stops the run before it starts.
        #[arg(long, value_name = "MB")]
        memory_limit: Option<f64>,
    },
    /// Check a model and list every problem found.
    Check { model: PathBuf },
    /// Print the JSON Schema of the model file.
    Schema,
    /// List the solver backends compiled into this build.
    Backends,
    /// Compare the solver backends on generated pull-out meshes (times, factor entries, peak memory).
    Bench {
        /// Approximate numbers of unknowns, comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "1000,10000,100000")]
        sizes: Vec<usize>,
        /// Backends to compare (default: every backend of this build).
        #[arg(long, value_enum, value_delimiter = ',')]
        backends: Vec<Backend>,
        /// Repeats of the MUMPS-path-against-bare-MUMPS comparison (interleaved; medians reported).
        #[arg(long, default_value_t = 5)]
        repeats: usize,
        /// MUMPS orderings to compare on the same matrices (default: the build's own).
        #[arg(long, value_enum, value_delimiter = ',')]
        orderings: Vec<Ordering>,
        /// The nonlinear benchmark instead: a multi-layer pull-out box, 20 pull increments with slip
        /// and re-association, timed phase by phase (on the first of `--backends`, default the best).
        #[arg(long)]
        nonlinear: bool,
    },
    /// One benchmark measurement, in a process of its own (used by `bench`).
    #[command(hide = true)]
    BenchOne {
        #[arg(long)]
        dofs: usize,
        /// A backend, or "none" for the model alone.
        #[arg(long)]
        backend: String,
        #[arg(long, value_enum, default_value = "auto")]
        ordering: Ordering,
        #[arg(long)]
        nonlinear: bool,
    },
}

/// The `geoslip` program: parse the command line and carry it out. In a build with the `mpi` feature
/// MPI starts first; rank 0 runs the command and every other rank serves MUMPS's distributed
/// factorisations and solves until rank 0 is done.
pub fn main() -> ExitCode {
    #[cfg(feature = "mpi")]
    {
        let Some(cluster) = crate::linsol::cluster::Cluster::start() else {
            eprintln!("error: MPI could not be started");
            return ExitCode::from(exit::SOLVER);
        };
        if !cluster.is_host() {
            cluster.serve();
            return ExitCode::SUCCESS;
        }
        let code = command_line();
        cluster.release();
        code
    }
    #[cfg(not(feature = "mpi"))]
    command_line()
}

fn command_line() -> ExitCode {
    let cli = Cli::parse();
    let cli_flags = (cli.quiet, cli.verbose);
    match cli.command {
        Command::Schema => {
            println!("{}", crate::model::schema());
            ExitCode::SUCCESS
        }
        Command::Backends => {
            for b in Backend::available() {
                println!("{}", b.name());
            }
            ExitCode::SUCCESS
        }
        Command::Bench { sizes, backends, repeats, orderings, nonlinear } => match if nonlinear {
            bench_nonlinear(&sizes, &backends, &orderings)
        } else {
            bench(&sizes, &backends, repeats, &orderings)
        } {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(exit::SOLVER)
            }
        },
        Command::BenchOne { dofs, backend, ordering, nonlinear } => {
            let backend = Backend::available().into_iter().find(|b| b.name() == backend);
            let line = match (nonlinear, backend) {
                (true, Some(b)) => serde_json::to_string(&crate::bench::measure_nonlinear(dofs, b, ordering)),
                _ => serde_json::to_string(&crate::bench::measure(dofs, backend, ordering)),
            };
            println!("{}", line.unwrap_or_default());
            ExitCode::SUCCESS
        }
        Command::Check { model } => match Model::load(&model) {
            Ok(m) => {
                println!(
                    "{}: ok — {} nodes, {} soil elements, {} bars, {} interfaces, {} stages",
                    model.display(),
                    m.mesh.nodes.len(),
                    m.mesh.solids.len(),
                    m.mesh.bars.len(),
                    m.interfaces.len(),
                    m.stages.len()
                );
                for note in &m.notes {
                    println!("note: {note}");
                }
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                exit_code(&e)
            }
        },
        Command::Run { model, solver, out, ordering, out_of_core, memory_limit } => {
            let options = SolverOptions { ordering, out_of_core, memory_limit_mb: memory_limit };
            match run(&model, solver, &options, out, Verbosity::of(&cli_flags)) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: {e}");
                    exit_code(&e)
                }
            }
        }
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Verbosity {
    Quiet,
    Normal,
    Verbose,
}

impl Verbosity {
    fn of(&(quiet, verbose): &(bool, bool)) -> Verbosity {
        if quiet {
            Verbosity::Quiet
        } else if verbose {
            Verbosity::Verbose
        } else {
            Verbosity::Normal
        }
    }
}

/// Passes each converged step to the result writer and moves the progress bar.
struct Progress<'a> {
    writer: &'a mut ResultWriter,
    bar: indicatif::ProgressBar,
    verbosity: Verbosity,
}

impl Progress<'_> {
    /// A line above the progress bar; a hidden bar (output not a terminal) prints nothing of its
    /// own, so the line goes to standard error.
    fn say(&self, line: String) {
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }
}

impl StepSink for Progress<'_> {
    fn step_done(
        &mut self,
        results: &crate::analysis::results::StepResults,
        record: &StepRecord,
        stats: &crate::analysis::system::SolverStats,
    ) -> Result<(), crate::Error> {
        self.writer.step_done(results, record, stats)?;
        // a cutback adds steps: the bar grows with them
        let done = self.bar.position() + 1;
        if self.bar.length().is_some_and(|l| done > l) {
            self.bar.set_length(done);
        }
        self.bar.set_position(done);
        self.bar.set_message(match record.strength_factor {
            Some(f) => format!("{} (strengths / {f:.3})", record.stage),
            None => format!("{} (load factor {:.3})", record.stage, record.load_factor),
        });
        if self.verbosity == Verbosity::Verbose {
            let line = format!(
                "stage \"{}\" step {}: {}, {} iterations, {} cutbacks, force residual {:.1e}, {} sliding of {} in contact, {} soil points yielding, {} state changes, {} re-associations",
                record.stage,
                record.step,
                match record.strength_factor {
                    Some(f) => format!("strengths divided by {f:.4}"),
                    None => format!("load factor {:.4}", record.load_factor),
                },
                record.iterations,
                record.cutbacks,
                record.force_residual,
                record.sliding_points,
                record.contact_points,
                record.yielding_points,
                record.state_changes.len(),
                record.reassociations.len()
            );
            self.say(line);
        }
        Ok(())
    }

    fn factor_of_safety(&mut self, fs: &crate::analysis::FactorOfSafety) -> Result<(), crate::Error> {
        self.writer.factor_of_safety(fs)?;
        let line = match fs.failed_at {
            Some(f) => format!(
                "stage \"{}\": factor of safety {:.3} ({} reduced; no equilibrium at {f:.3})",
                fs.stage, fs.value, fs.reduced
            ),
            None => format!(
                "stage \"{}\": factor of safety at least {:.3} ({} reduced; the search stopped at max_factor)",
                fs.stage, fs.value, fs.reduced
            ),
        };
        if self.verbosity != Verbosity::Quiet {
            self.say(line);
        }
        Ok(())
    }
}

/// Run a model, or each run of its series and then the series summary.
fn run(
    path: &std::path::Path,
    solver: Backend,
    options: &SolverOptions,
    out: Option<PathBuf>,
    verbosity: Verbosity,
) -> Result<(), crate::Error> {
    crate::linsol::check_available(solver)?;
    let cases = Model::load_cases(path)?;
    let out = out.unwrap_or_else(|| {
        PathBuf::from("results").join(path.file_stem().map(|s| s.to_os_string()).unwrap_or_else(|| "model".into()))
    });
    let [Case { label: None, model, .. }] = cases.as_slice() else {
        return run_series(path, &cases, solver, options, &out, verbosity);
    };
    run_case(path, model, solver, options, &out, verbosity, &mut Vec::new())
}

/// Each run of a series in a folder of its own, then `series.csv`, the envelope plot and the report.
fn run_series(
    path: &std::path::Path,
    cases: &[Case],
    solver: Backend,
    options: &SolverOptions,
    out: &std::path::Path,
    verbosity: Verbosity,
) -> Result<(), crate::Error> {
    use crate::output::series::{self, CaseOutcome, PulloutReference};
    let mut outcomes = Vec::new();
    let mut first_error = None;
    let mut pullout = None;
    for case in cases {
        let label = case.label.clone().unwrap_or_default();
        if verbosity != Verbosity::Quiet {
            println!("— run {label} —");
        }
        let mut peaks = Vec::new();
        let error = match run_case(path, &case.model, solver, options, &out.join(&label), verbosity, &mut peaks) {
            Ok(()) => None,
            Err(e) => {
                let message = e.to_string();
                first_error.get_or_insert(e);
                Some(message)
            }
        };
        if pullout.is_none() {
            pullout = PulloutReference::of(&case.model, &peaks);
        }
        outcomes.push(CaseOutcome { folder: label.clone(), label, value: case.value.unwrap_or(0.0), peaks, error });
    }
    let load = cases[0].load.clone().unwrap_or_else(|| "load".to_string());
    let summary = series::write(out, path, &load, &cases[0].model.unit_labels(), outcomes, pullout)?;
    if verbosity != Verbosity::Quiet {
        if let (Some(p), Some(e)) = (&summary.pullout, &summary.envelope) {
            println!(
                "{}: apparent interface friction angle {:.2}° (input {:.2}°), apparent adhesion {:.3}; series report in {}",
                path.display(),
                e.apparent_friction_angle_deg,
                p.friction_angle_deg,
                e.apparent_adhesion,
                out.join("report.md").display()
            );
        } else {
            println!("{}: series report in {}", path.display(), out.join("report.md").display());
        }
    }
    match first_error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Run one model into `out`; `peaks` receives the peak reaction of each prescribed target, also when
/// the run stops early.
fn run_case(
    path: &std::path::Path,
    model: &Model,
    solver: Backend,
    solver_options: &SolverOptions,
    out: &std::path::Path,
    verbosity: Verbosity,
    peaks: &mut Vec<crate::output::TargetPeak>,
) -> Result<(), crate::Error> {
    let started = std::time::Instant::now();
    let options = RunOptions { solver: solver_options.clone(), ..RunOptions::for_model(model, solver) };
    let solver_name = match solver.resolve() {
        Backend::Mumps => format!(
            "mumps ({} ordering{}{})",
            solver_options.ordering.name(),
            if solver_options.out_of_core { ", out of core" } else { "" },
            if cfg!(feature = "mpi") { ", MPI build" } else { "" }
        ),
        b => b.name().to_string(),
    };
    let mut writer = ResultWriter::new(model, out, &solver_name)?;
    if verbosity != Verbosity::Quiet {
        for note in &model.notes {
            eprintln!("note: {note}");
        }
    }
    let steps: usize = model.stages.iter().map(|s| s.load_factors.len()).sum();
    // drawn on stderr, and only when it is a terminal
    let bar = if verbosity == Verbosity::Quiet {
        indicatif::ProgressBar::hidden()
    } else {
        indicatif::ProgressBar::new(steps as u64)
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} steps  {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let result = {
        let mut progress = Progress { writer: &mut writer, bar: bar.clone(), verbosity };
        analysis::run(model, &options, &mut progress)
    };
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    match result {
        Ok(stats) => {
            for w in &stats.warnings {
                eprintln!("warning: {w}");
            }
            writer.finish(model, None, Some(stats), seconds)?;
            if verbosity != Verbosity::Quiet {
                for e in &writer.summary.events {
                    println!("{e}");
                }
                let s = &writer.summary;
                println!(
                    "{}: {} steps in {:.2} s with {} (max ‖Ax−b‖/‖b‖ {:.1e}); results and report.md in {}",
                    path.display(),
                    s.steps.len(),
                    seconds,
                    s.solver,
                    s.solver_stats.max_relative_residual,
                    out.display()
                );
            }
            *peaks = writer.peak_reactions();
            Ok(())
        }
        Err(e) => {
            writer.finish(model, Some(&e), None, seconds)?;
            eprintln!("the {} completed steps are in {}", writer.summary.steps.len(), out.display());
            *peaks = writer.peak_reactions();
            Err(e)
        }
    }
}

/// The nonlinear benchmark: each size in a child process of its own, one Markdown table.
fn bench_nonlinear(sizes: &[usize], backends: &[Backend], orderings: &[Ordering]) -> Result<(), String> {
    use crate::bench::NonlinearMeasurement;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let backend = backends.first().copied().unwrap_or(Backend::Auto).resolve();
    crate::linsol::check_available(backend).map_err(|e| e.to_string())?;
    let ordering = orderings.first().copied().unwrap_or(Ordering::Auto);
    println!(
        "geoslip {} — nonlinear benchmark on {} ({} ordering): multi-layer pull-out box, 20 pull increments",
        env!("CARGO_PKG_VERSION"),
        backend.name(),
        ordering.name()
    );
    println!();
    println!("| unknowns | layers | stations | increments | iterations | analyses | factorisations | re-associations | slip / element | wall [s] | per increment [s] | per iteration [s] | setup | assembly | interface | residual | solution check | analysis | factorisation | solve | output | run / MUMPS | iteration / (factorisation + solve) | peak [MB] | peak [KB/unknown] | peak / (INFOG(22) + model) |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &size in sizes {
        let out = std::process::Command::new(&exe)
            .args(["bench-one", "--nonlinear", "--dofs", &size.to_string(), "--backend", backend.name()])
            .args(["--ordering", ordering.name()])
            .output()
            .map_err(|e| e.to_string())?;
        let m: NonlinearMeasurement = match serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()) {
            Ok(m) => m,
            Err(_) => {
                let why = String::from_utf8_lossy(&out.stderr);
                println!("| {size} | failed: {} |", why.lines().last().unwrap_or("no output (killed?)"));
                continue;
            }
        };
        if let Some(e) = &m.error {
            println!("| {} | failed after {} increments: {e} |", m.dofs, m.increments);
            continue;
        }
        let share = |s: f64| format!("{:.0} %", 100.0 * s / m.total_seconds);
        let mumps = m.analyse_seconds + m.factorize_seconds + m.solve_seconds;
        let in_run = m.total_seconds - m.output_seconds - m.setup_seconds;
        let memory_ratio = m.factor_memory_mb.map(|f| format!("{:.2}", m.peak_memory_mb / (f + m.model_memory_mb)));
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.1} | {:.1} | {:.3} | {:.4} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.0} | {:.2} | {} |",
            m.dofs,
            m.layers,
            m.stations,
            m.increments,
            m.iterations,
            m.analyses,
            m.factorizations,
            m.reassociations,
            m.max_slip / m.element_length,
            m.total_seconds,
            m.total_seconds / m.increments.max(1) as f64,
            in_run / m.iterations.max(1) as f64,
            share(m.setup_seconds),
            share(m.assembly_seconds),
            share(m.interface_seconds),
            share(m.residual_seconds),
            share(m.check_seconds),
            share(m.analyse_seconds),
            share(m.factorize_seconds),
            share(m.solve_seconds),
            share(m.output_seconds),
            in_run / mumps,
            // the target's reading: a mean iteration against one factorisation and one solve
            (in_run / m.iterations.max(1) as f64)
                / (m.factorize_seconds / m.factorizations.max(1) as f64 + m.solve_seconds / m.solves.max(1) as f64),
            m.peak_memory_mb,
            1024.0 * m.peak_memory_mb / m.dofs as f64,
            memory_ratio.unwrap_or_else(|| "n/a".into())
        );
    }
    Ok(())
}

/// Run every (size, backend) measurement in a child process and print a Markdown table.
fn bench(sizes: &[usize], backends: &[Backend], repeats: usize, orderings: &[Ordering]) -> Result<(), String> {
    use crate::bench::Measurement;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let backends: Vec<Backend> =
        if backends.is_empty() { Backend::available() } else { backends.iter().map(|b| b.resolve()).collect() };
    for b in &backends {
        crate::linsol::check_available(*b).map_err(|e| e.to_string())?;
    }
    println!("geoslip {} — backends: {}", env!("CARGO_PKG_VERSION"), env!("GEOSLIP_BACKENDS"));
    println!();
    println!("| unknowns | nonzeros | backend | analysis [s] | factorisation [s] | solve [s] | factor entries | peak memory [MB] | ‖Ax−b‖/‖b‖ |");
    println!("|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    // MUMPS once per ordering asked for; the other backends once
    let orderings: Vec<Ordering> = if orderings.is_empty() { vec![Ordering::Auto] } else { orderings.to_vec() };
    for &size in sizes {
        let mut runs: Vec<(String, Ordering)> = vec![("none".into(), Ordering::Auto)];
        for &b in &backends {
            if b == Backend::Mumps {
                runs.extend(orderings.iter().map(|&o| (b.name().to_string(), o)));
            } else {
                runs.push((b.name().to_string(), Ordering::Auto));
            }
        }
        for (name, ordering) in runs {
            if name == "dense" && size > crate::linsol::dense_ref::SIZE_LIMIT {
                continue;
            }
            let out = std::process::Command::new(&exe)
                .args(["bench-one", "--dofs", &size.to_string(), "--backend", &name, "--ordering", ordering.name()])
                .output()
                .map_err(|e| e.to_string())?;
            let line = String::from_utf8_lossy(&out.stdout);
            let m: Measurement = match serde_json::from_str(line.trim()) {
                Ok(m) => m,
                Err(_) => {
                    println!(
                        "| {size} | | {name} | failed: {} | | | | | |",
                        String::from_utf8_lossy(&out.stderr).lines().last().unwrap_or("no output")
                    );
                    continue;
                }
            };
            if let Some(e) = &m.error {
                println!("| {} | {} | {} | failed: {e} | | | | | |", m.unknowns, m.nonzeros, m.backend);
                continue;
            }
            if name == "none" {
                println!(
                    "| {} | {} | (model and assembly only) | | | | | {:.0} | |",
                    m.unknowns, m.nonzeros, m.peak_memory_mb
                );
                continue;
            }
            println!(
                "| {} | {} | {} | {:.3} | {:.3} | {:.4} | {} | {:.0} | {:.1e} |",
                m.unknowns,
                m.nonzeros,
                m.backend,
                m.analyse_seconds,
                m.factorize_seconds,
                m.solve_seconds,
                m.factor_entries.map(|e| e.to_string()).unwrap_or_else(|| "n/a".into()),
                m.peak_memory_mb,
                m.relative_residual
            );
        }
    }
    if backends.contains(&Backend::Mumps) {
        println!();
        println!("MUMPS path (geoslip's wrapper from the assembled matrix: JOB −1, lower triangle and 1-based indices, JOB 1, 2, 3,");
        println!("residual check, JOB −2) against a bare MUMPS call");
        println!("(JOB −1, 1, 2, 3, −2 on ready-made coordinates), interleaved, median of {repeats}:");
        println!();
        println!("| unknowns | path [s] | bare [s] | path / bare |");
        println!("|---:|---:|---:|---:|");
        for &size in sizes {
            let (path, bare, n) = crate::bench::mumps_overhead(size, repeats.max(1))?;
            println!("| {n} | {path:.4} | {bare:.4} | {:.3} |", path / bare);
        }
    }
    Ok(())
}
