//! The geoslip command line (the `geoslip` and `geoslip-mpi` programs).

mod bench;
mod calibrate;
mod dynamic_bench;
pub mod measure;
mod progress;
mod pullout_bench;
mod run;

use crate::linsol::{Backend, Ordering, SolverOptions};
use crate::model::{Extrapolation, LoadOptions, Model, Scheme};
use crate::output::{KeptSteps, OutputOptions};
use bench::{bench, bench_nonlinear};
use clap::{Parser, Subcommand};
use progress::Verbosity;
use run::{run, RunSettings};
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
        Read { .. } | Parse { .. } | Model(_) | Restart { .. } => exit::BAD_INPUT,
        NotConverged { .. } | NonFinite { .. } | SingularIterate { .. } => exit::NOT_CONVERGED,
        Solve { .. } | Backend(_) => exit::SOLVER,
        Write { .. } => exit::WRITE,
        Stopped { .. } => exit::NOT_CONVERGED,
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
        #[arg(long, value_name = "MB", value_parser = positive_number)]
        memory_limit: Option<f64>,
        /// Mesh a .geo script even if it runs programs or writes files (SystemCall, Printf > file,
        /// …), and without the confinement Gmsh otherwise runs in. A .geo file is a program: read
        /// it first.
        #[arg(long)]
        trust_geo: bool,
        /// The longest Gmsh may take to mesh a .geo script, seconds of wall time (it is stopped
        /// then, and the run with it).
        #[arg(long, value_name = "SECONDS", default_value = "300", value_parser = positive_number)]
        gmsh_time_limit: f64,
        /// Solve the whole system in every iteration instead of condensing an elastic soil onto the
        /// interface's unknowns (the same answers; for comparison and benchmarks).
        #[arg(long)]
        full_system: bool,
        /// Write each kept step's whole fields as CSV files too, in stage-<k>-<name>/step-<nnn>/
        /// (history.csv, summary.json, report.md and the plots are always written).
        #[arg(long)]
        csv: bool,
        /// Which steps' fields to write: every; events (the first and last step of each stage, and
        /// where slip starts, the soil yields, everything slides, a reaction peaks or falls); or N
        /// (every N-th step, the events and the last). The history, summary and plots cover every
        /// step.
        #[arg(long, value_name = "every|events|N", default_value = "every")]
        keep: KeptSteps,
        /// Write the ParaView .vtu files and results.pvd beside results.h5/results.xdmf (a build
        /// without the hdf5 feature writes them in any case).
        #[arg(long)]
        vtu: bool,
        /// Continue the run whose results are in this folder, from the saved step --from, instead of
        /// starting over: the same model, or one with stages added after that step or the later ones
        /// changed (a changed mesh, material, interface, support or earlier stage is refused).
        #[arg(long, value_name = "RESULTS", requires = "from")]
        restart: Option<PathBuf>,
        /// The saved step to continue from: STAGE:STEP, the stage by its name or number from 1 and
        /// a converged step of it (as numbered in the history and the report).
        #[arg(long, value_name = "STAGE:STEP", requires = "restart")]
        from: Option<crate::output::checkpoints::From>,
        /// Do not save the steps a run can continue from (restart/ in the output folder): their disk
        /// space for the ability to continue.
        #[arg(long)]
        no_restart: bool,
        /// The precision of the step fields in results.h5: single (4-byte floats, about 7
        /// significant digits, half the size) or double (every value exactly as computed). The
        /// mesh, the history, history.csv, the CSV files and the saved steps hold every digit
        /// either way.
        #[arg(long, value_name = "single|double", default_value = "single")]
        field_precision: crate::output::options::FieldPrecision,
    },
    /// Check a model and list every problem found. It runs no other program: a mesh given as a .geo
    /// script is read (and refused if it runs programs or writes files) but meshed only with --mesh.
    Check {
        model: PathBuf,
        /// Mesh a .geo script with Gmsh to check the whole model on its mesh (a .geo file is a
        /// program: one that runs programs or writes files is still refused without --trust-geo).
        #[arg(long)]
        mesh: bool,
        /// Mesh a .geo script even if it runs programs or writes files (see `run --trust-geo`).
        #[arg(long)]
        trust_geo: bool,
        /// Memory the check may use, MB (default: what the machine has available).
        #[arg(long, value_name = "MB", value_parser = positive_number)]
        memory_limit: Option<f64>,
        /// The longest Gmsh may take to mesh a .geo script, seconds (see `run --gmsh-time-limit`).
        #[arg(long, value_name = "SECONDS", default_value = "300", value_parser = positive_number)]
        gmsh_time_limit: f64,
    },
    /// Fit an interface law to measured curves (direct-shear τ–δ or pull-out P–δ at several normal
    /// stresses) and write each parameter with its standard error and 95 % interval, the fitted
    /// curves and the law ready to paste into a model (docs/calibration.md).
    Calibrate {
        /// Calibration file (TOML): the test, the curves' CSV file, the law.
        spec: PathBuf,
        /// Output folder (default: results/<title>).
        #[arg(long)]
        out: Option<PathBuf>,
    },
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
        /// The pull-out benchmark instead: a whole run with its results written, against one
        /// factorisation and one solve per pull step (docs/performance.md); each size with the
        /// constant-stiffness and newton schemes, on the full system, condensed, and condensed with
        /// the extrapolated first iterate.
        #[arg(long)]
        pullout: bool,
        /// With --pullout: write the benchmark's model of each size into this folder as a model
        /// file (`pullout-<size>.toml`, its mesh inline) and run nothing.
        #[arg(long, requires = "pullout")]
        write_models: Option<PathBuf>,
        /// The dynamic benchmark instead: a shaken elastic layer, `--steps` time steps with its
        /// results written, against one factorisation and one solve per time step
        /// (docs/performance.md).
        #[arg(long)]
        dynamic: bool,
        /// With --dynamic: the time steps.
        #[arg(long, default_value_t = 2000)]
        steps: usize,
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
        #[arg(long)]
        pullout: bool,
        /// constant-stiffness, newton or newton-symmetric
        #[arg(long, default_value = "constant-stiffness")]
        scheme: String,
        #[arg(long)]
        full_system: bool,
        /// The pull-out run with `extrapolation = "linear"`.
        #[arg(long)]
        extrapolate: bool,
        /// The pull-out run's output share from this many written runs, each between two runs
        /// writing nothing (its mean and standard error in the measurement); 0: the first run and
        /// the floor only.
        #[arg(long, default_value_t = 1)]
        pairs: usize,
        #[arg(long)]
        dynamic: bool,
        #[arg(long, default_value_t = 2000)]
        steps: usize,
    },
}

/// The `geoslip` program: parse the command line and carry it out. In a build with the `mpi` feature
/// MPI starts first; rank 0 runs the command and every other rank serves MUMPS's distributed
/// factorisations and solves until rank 0 is done.
pub fn main() -> ExitCode {
    let process = crate::timing::ProcessStart::now();
    crate::native::heap::one_arena_per_core();
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
        let code = command_line(process);
        cluster.release();
        code
    }
    #[cfg(not(feature = "mpi"))]
    command_line(process)
}

/// A limit given on the command line: a finite number above zero (`NaN`, `inf`, 0 and negative
/// numbers would each turn a limit off or make it refuse everything).
fn positive_number(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{text}` is not a number above zero")),
    }
}

fn command_line(process: crate::timing::ProcessStart) -> ExitCode {
    let cli = Cli::parse();
    let cli_flags = (cli.quiet, cli.verbose);
    match cli.command {
        Command::Calibrate { spec, out } => calibrate::calibrate(&spec, out),
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
        Command::Bench { sizes, backends, repeats, orderings, nonlinear, pullout, write_models, dynamic, steps } => {
            match if let Some(folder) = write_models {
                pullout_bench::write_pullout_models(&sizes, &folder)
            } else if pullout {
                let backend = backends.first().copied().unwrap_or(Backend::Auto);
                let variants = [
                    (Scheme::ConstantStiffness, false, Extrapolation::None),
                    (Scheme::ConstantStiffness, true, Extrapolation::None),
                    (Scheme::ConstantStiffness, true, Extrapolation::Linear),
                    (Scheme::Newton, false, Extrapolation::None),
                    (Scheme::Newton, true, Extrapolation::None),
                    (Scheme::Newton, true, Extrapolation::Linear),
                ];
                pullout_bench::bench_pullout(&sizes, backend, &variants)
            } else if dynamic {
                dynamic_bench::bench_dynamic(&sizes, steps, backends.first().copied().unwrap_or(Backend::Auto))
            } else if nonlinear {
                bench_nonlinear(&sizes, &backends, &orderings)
            } else {
                bench(&sizes, &backends, repeats, &orderings)
            } {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(exit::SOLVER)
                }
            }
        }
        Command::BenchOne {
            dofs,
            backend,
            ordering,
            nonlinear,
            pullout,
            scheme,
            full_system,
            extrapolate,
            pairs,
            dynamic,
            steps,
        } => {
            let backend = Backend::available().into_iter().find(|b| b.name() == backend);
            let line = match (nonlinear, backend) {
                (_, Some(b)) if dynamic => {
                    serde_json::to_string(&dynamic_bench::measure_dynamic(dofs, steps, b, process))
                }
                (_, Some(b)) if pullout => {
                    let scheme = match scheme.as_str() {
                        "newton" => Scheme::Newton,
                        "newton-symmetric" => Scheme::NewtonSymmetric,
                        _ => Scheme::ConstantStiffness,
                    };
                    let extrapolation = if extrapolate { Extrapolation::Linear } else { Extrapolation::None };
                    serde_json::to_string(&pullout_bench::measure_pullout(
                        dofs,
                        b,
                        scheme,
                        !full_system,
                        extrapolation,
                        pairs,
                        process,
                    ))
                }
                (true, Some(b)) => serde_json::to_string(&measure::measure_nonlinear(dofs, b, ordering)),
                _ => serde_json::to_string(&measure::measure(dofs, backend, ordering)),
            };
            println!("{}", line.unwrap_or_default());
            ExitCode::SUCCESS
        }
        // the same models a run would make: a series is checked run by run
        Command::Check { model, mesh, trust_geo, memory_limit, gmsh_time_limit } => check(
            &model,
            mesh,
            LoadOptions { trust_geo, memory_limit_mb: memory_limit, gmsh_time_limit_s: gmsh_time_limit },
        ),
        Command::Run {
            model,
            solver,
            out,
            ordering,
            out_of_core,
            memory_limit,
            trust_geo,
            gmsh_time_limit,
            full_system,
            csv,
            keep,
            vtu,
            restart,
            from,
            no_restart,
            field_precision,
        } => {
            let options =
                SolverOptions { ordering, out_of_core, memory_limit_mb: memory_limit, condense: !full_system };
            let load = LoadOptions { trust_geo, memory_limit_mb: memory_limit, gmsh_time_limit_s: gmsh_time_limit };
            let output = OutputOptions { csv, keep, vtu, no_restart, precision: field_precision };
            let restart = restart.zip(from);
            let settings = RunSettings {
                solver,
                solver_options: &options,
                output: &output,
                verbosity: Verbosity::of(&cli_flags),
                process,
            };
            match run(&model, load, &settings, out, restart) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: {e}");
                    exit_code(&e)
                }
            }
        }
    }
}

/// `geoslip check`: every problem of the model, as a run would find them before it starts; a .geo
/// mesh is meshed only when asked (`mesh`).
fn check(model: &std::path::Path, mesh: bool, load: LoadOptions) -> ExitCode {
    let unmeshed = match Model::geo_script(model) {
        Ok(Some(_)) if !mesh => Some(Model::check_without_meshing(model, load)),
        Ok(_) => None,
        Err(e) => Some(Err(e)),
    };
    match unmeshed {
        Some(Ok(script)) => {
            let script_note = if load.trust_geo {
                "was not read for the commands it may run (--trust-geo)"
            } else {
                "runs no program and writes no file"
            };
            println!(
                "{}: the file reads, and its mesh script {} {script_note}; the mesh and everything on it were not \
                 checked: a .geo script is a program, which check runs only when asked (geoslip check --mesh)",
                model.display(),
                script.display()
            );
            return ExitCode::SUCCESS;
        }
        Some(Err(e)) => {
            eprintln!("error: {e}");
            return exit_code(&e);
        }
        None => {}
    }
    match Model::load_cases_with(model, load) {
        Ok(cases) => {
            let m = match cases[0].model() {
                Ok(m) => m,
                Err(e) => {
                    eprintln!("error: {e}");
                    return exit_code(&e);
                }
            };
            println!(
                "{}: ok — {} nodes, {} soil elements, {} bars, {} interfaces, {} stages{}",
                model.display(),
                m.mesh.nodes.len(),
                m.mesh.solids.len(),
                m.mesh.bars.len(),
                m.interfaces.len(),
                m.stages.len(),
                match cases.len() {
                    1 => String::new(),
                    n => format!("; a series of {n} runs"),
                }
            );
            for note in &m.notes {
                println!("note: {note}");
            }
            if let Some(wall) = &m.design {
                // what the design checks read from the model, to be seen before the run
                let layers: Vec<String> = wall
                    .layers
                    .iter()
                    .rev()
                    .map(|l| format!("{} (Z = {:.4}, Svt = {:.4}, L = {:.4})", l.name, l.depth, l.spacing(), l.length))
                    .collect();
                println!(
                    "design checks: a {} wall of `{}`, H = {:.4} from y = {} to {}, face at x = {}, surcharge {} (from {}); layers from the top: {}",
                    wall.reinforcement().name(),
                    wall.parameters.reinforced_soil,
                    wall.height(),
                    wall.base,
                    wall.crest,
                    wall.face_x,
                    wall.surcharge,
                    wall.surcharge_source,
                    layers.join(", ")
                );
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            exit_code(&e)
        }
    }
}
