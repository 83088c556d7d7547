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
    let options = RunOptions { backend: solver, ..RunOptions::default() };
    let mut writer = ResultWriter::new(&model, &out, solver.resolve().name())?;
    for note in &model.notes {
        eprintln!("note: {note}");
    }
    let result = analysis::run(&model, &options, &mut writer);
    let seconds = started.elapsed().as_secs_f64();
    match result {
        Ok(stats) => {
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
