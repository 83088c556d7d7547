//! The geoslip command line.

use clap::{Parser, Subcommand};
use geoslip::analysis::{self, RunOptions, StepRecord, StepSink};
use geoslip::linsol::Backend;
use geoslip::model::{Case, Model};
use geoslip::output::ResultWriter;
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

fn exit_code(e: &geoslip::Error) -> ExitCode {
    use geoslip::Error::*;
    ExitCode::from(match e {
        Read { .. } | Parse { .. } | Model(_) => exit::BAD_INPUT,
        NotConverged { .. } => exit::NOT_CONVERGED,
        Solve { .. } | Backend(_) => exit::SOLVER,
        Write { .. } => exit::WRITE,
        _ => exit::WRITE,
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
    },
    /// One benchmark measurement, in a process of its own (used by `bench`).
    #[command(hide = true)]
    BenchOne {
        #[arg(long)]
        dofs: usize,
        /// A backend, or "none" for the model alone.
        #[arg(long)]
        backend: String,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let cli_flags = (cli.quiet, cli.verbose);
    match cli.command {
        Command::Schema => {
            println!("{}", geoslip::model::schema());
            ExitCode::SUCCESS
        }
        Command::Backends => {
            for b in Backend::available() {
                println!("{}", b.name());
            }
            ExitCode::SUCCESS
        }
        Command::Bench { sizes, backends, repeats } => match bench(&sizes, &backends, repeats) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(exit::SOLVER)
            }
        },
        Command::BenchOne { dofs, backend } => {
            let backend = Backend::available().into_iter().find(|b| b.name() == backend);
            let m = geoslip::bench::measure(dofs, backend);
            println!("{}", serde_json::to_string(&m).unwrap_or_default());
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
        Command::Run { model, solver, out } => match run(&model, solver, out, Verbosity::of(&cli_flags)) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                exit_code(&e)
            }
        },
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

impl StepSink for Progress<'_> {
    fn step_done(
        &mut self,
        results: &geoslip::analysis::results::StepResults,
        record: &StepRecord,
        stats: &geoslip::analysis::system::SolverStats,
    ) -> Result<(), geoslip::Error> {
        self.writer.step_done(results, record, stats)?;
        // a cutback adds steps: the bar grows with them
        let done = self.bar.position() + 1;
        if self.bar.length().is_some_and(|l| done > l) {
            self.bar.set_length(done);
        }
        self.bar.set_position(done);
        self.bar.set_message(format!("{} (load factor {:.3})", record.stage, record.load_factor));
        if self.verbosity == Verbosity::Verbose {
            let line = format!(
                "stage \"{}\" step {}: load factor {:.4}, {} iterations, {} cutbacks, force residual {:.1e}, {} sliding of {} in contact, {} state changes, {} re-associations",
                record.stage,
                record.step,
                record.load_factor,
                record.iterations,
                record.cutbacks,
                record.force_residual,
                record.sliding_points,
                record.contact_points,
                record.state_changes.len(),
                record.reassociations.len()
            );
            // a hidden bar (output not a terminal) prints nothing of its own
            if self.bar.is_hidden() {
                eprintln!("{line}");
            } else {
                self.bar.println(line);
            }
        }
        Ok(())
    }
}

/// Run a model, or each run of its series and then the series summary.
fn run(
    path: &std::path::Path,
    solver: Backend,
    out: Option<PathBuf>,
    verbosity: Verbosity,
) -> Result<(), geoslip::Error> {
    geoslip::linsol::check_available(solver)?;
    let cases = Model::load_cases(path)?;
    let out = out.unwrap_or_else(|| {
        PathBuf::from("results").join(path.file_stem().map(|s| s.to_os_string()).unwrap_or_else(|| "model".into()))
    });
    let [Case { label: None, model, .. }] = cases.as_slice() else {
        return run_series(path, &cases, solver, &out, verbosity);
    };
    run_case(path, model, solver, &out, verbosity, &mut Vec::new())
}

/// Each run of a series in a folder of its own, then `series.csv`, the envelope plot and the report.
fn run_series(
    path: &std::path::Path,
    cases: &[Case],
    solver: Backend,
    out: &std::path::Path,
    verbosity: Verbosity,
) -> Result<(), geoslip::Error> {
    use geoslip::output::series::{self, CaseOutcome, PulloutReference};
    let mut outcomes = Vec::new();
    let mut first_error = None;
    let mut pullout = None;
    for case in cases {
        let label = case.label.clone().unwrap_or_default();
        if verbosity != Verbosity::Quiet {
            println!("— run {label} —");
        }
        let mut peaks = Vec::new();
        let error = match run_case(path, &case.model, solver, &out.join(&label), verbosity, &mut peaks) {
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
    out: &std::path::Path,
    verbosity: Verbosity,
    peaks: &mut Vec<geoslip::output::TargetPeak>,
) -> Result<(), geoslip::Error> {
    let started = std::time::Instant::now();
    let model = model.clone();
    let out = out.to_path_buf();
    let options = RunOptions::for_model(&model, solver);
    let mut writer = ResultWriter::new(&model, &out, solver.resolve().name())?;
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
        analysis::run(&model, &options, &mut progress)
    };
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    match result {
        Ok(stats) => {
            for w in &stats.warnings {
                eprintln!("warning: {w}");
            }
            writer.finish(&model, None, Some(stats), seconds)?;
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
            writer.finish(&model, Some(&e), None, seconds)?;
            eprintln!("the {} completed steps are in {}", writer.summary.steps.len(), out.display());
            *peaks = writer.peak_reactions();
            Err(e)
        }
    }
}

/// Run every (size, backend) measurement in a child process and print a Markdown table.
fn bench(sizes: &[usize], backends: &[Backend], repeats: usize) -> Result<(), String> {
    use geoslip::bench::Measurement;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let backends: Vec<Backend> =
        if backends.is_empty() { Backend::available() } else { backends.iter().map(|b| b.resolve()).collect() };
    for b in &backends {
        geoslip::linsol::check_available(*b).map_err(|e| e.to_string())?;
    }
    println!("geoslip {} — backends: {}", env!("CARGO_PKG_VERSION"), env!("GEOSLIP_BACKENDS"));
    println!();
    println!("| unknowns | nonzeros | backend | analysis [s] | factorisation [s] | solve [s] | factor entries | peak memory [MB] | ‖Ax−b‖/‖b‖ |");
    println!("|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    for &size in sizes {
        let mut names: Vec<String> = vec!["none".into()];
        names.extend(backends.iter().map(|b| b.name().to_string()));
        for name in names {
            if name == "dense" && size > geoslip::linsol::dense_ref::SIZE_LIMIT {
                continue;
            }
            let out = std::process::Command::new(&exe)
                .args(["bench-one", "--dofs", &size.to_string(), "--backend", &name])
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
            let (path, bare, n) = geoslip::bench::mumps_overhead(size, repeats.max(1))?;
            println!("| {n} | {path:.4} | {bare:.4} | {:.3} |", path / bare);
        }
    }
    Ok(())
}
