//! The geoslip command line.

use clap::{Parser, Subcommand};
use geoslip::analysis::{self, RunOptions};
use geoslip::linsol::Backend;
use geoslip::model::Model;
use geoslip::output::ResultWriter;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "geoslip", version = version(), about = "Finite-element analysis of soil–geosynthetic interfaces that slip a lot")]
struct Cli {
    #[command(subcommand)]
    command: Command,
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
                ExitCode::FAILURE
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
                ExitCode::FAILURE
            }
        },
        Command::Run { model, solver, out } => match run(&model, solver, out) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
    }
}

fn run(path: &std::path::Path, solver: Backend, out: Option<PathBuf>) -> Result<(), geoslip::Error> {
    let started = std::time::Instant::now();
    geoslip::linsol::check_available(solver)?;
    let model = Model::load(path)?;
    let out = out.unwrap_or_else(|| {
        PathBuf::from("results").join(path.file_stem().map(|s| s.to_os_string()).unwrap_or_else(|| "model".into()))
    });
    let options = RunOptions::for_model(&model, solver);
    let mut writer = ResultWriter::new(&model, &out, solver.resolve().name())?;
    for note in &model.notes {
        eprintln!("note: {note}");
    }
    let result = analysis::run(&model, &options, &mut writer);
    let seconds = started.elapsed().as_secs_f64();
    match result {
        Ok(stats) => {
            for w in &stats.warnings {
                eprintln!("warning: {w}");
            }
            for e in &writer.summary.events {
                println!("{e}");
            }
            writer.finish(None, Some(stats), seconds)?;
            let s = &writer.summary;
            println!(
                "{}: {} steps in {:.2} s with {} (max ‖Ax−b‖/‖b‖ {:.1e}); results in {}",
                path.display(),
                s.steps.len(),
                seconds,
                s.solver,
                s.solver_stats.max_relative_residual,
                out.display()
            );
            Ok(())
        }
        Err(e) => {
            writer.finish(Some(&e), None, seconds)?;
            eprintln!("the {} completed steps are in {}", writer.summary.steps.len(), out.display());
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
