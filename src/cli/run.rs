//! `geoslip run`: one model, or each run of a series and then the series summary, with the
//! progress bar, the warnings and the closing line.

use super::progress::{Progress, Verbosity};
use crate::analysis::RunOptions;
use crate::linsol::{Backend, SolverOptions};
use crate::model::{Case, LoadOptions, Model};
use crate::output::{OutputOptions, ResultWriter};
use std::path::PathBuf;

/// How `geoslip run` was asked to run: the backend and its settings, what to write, how much to
/// say.
#[derive(Clone, Copy)]
pub(super) struct RunSettings<'a> {
    pub solver: Backend,
    pub solver_options: &'a SolverOptions,
    pub output: &'a OutputOptions,
    pub verbosity: Verbosity,
    /// When the process started: a single run's timings count from there.
    pub process: crate::timing::ProcessStart,
}

/// Run a model, or each run of its series and then the series summary.
pub(super) fn run(
    path: &std::path::Path,
    load: LoadOptions,
    settings: &RunSettings,
    out: Option<PathBuf>,
    restart: Option<(PathBuf, crate::output::checkpoints::From)>,
) -> Result<(), crate::Error> {
    crate::linsol::check_available(settings.solver)?;
    let cases = Model::load_cases_with(path, load)?;
    let out = out.unwrap_or_else(|| {
        PathBuf::from("results").join(path.file_stem().map(|s| s.to_os_string()).unwrap_or_else(|| "model".into()))
    });
    let [case @ Case { label: None, .. }] = cases.as_slice() else {
        if let Some((results, _)) = restart {
            let message = "a test series is several runs, each with its own folder: continue one of them with a model file of that run alone".to_string();
            return Err(crate::Error::Restart { path: results, message });
        }
        return run_series(path, &cases, settings, &out);
    };
    let model = case.model()?;
    let from = match restart {
        None => None,
        Some((results, from)) => {
            let same = |a: &std::path::Path, b: &std::path::Path| {
                a.canonicalize().ok().is_some_and(|a| b.canonicalize().ok().is_some_and(|b| a == b))
            };
            if same(&results, &out) {
                let message = format!(
                    "the continued run would replace these results, saved steps and all: write it to another folder (--out {}-from-{}-{})",
                    out.display(),
                    crate::output::path_component(&from.stage),
                    from.step
                );
                return Err(crate::Error::Restart { path: results, message });
            }
            let checkpoint = crate::output::checkpoints::read(&results, &from, &model, load.memory_limit_mb)?;
            Some((checkpoint, results))
        }
    };
    run_case(path, &model, settings, Place::Path(&out), from, &mut Vec::new())
}

/// Each run of a series in a folder of its own, then `series.csv`, the envelope plot and the report.
fn run_series(
    path: &std::path::Path,
    cases: &[Case],
    settings: &RunSettings,
    out: &std::path::Path,
) -> Result<(), crate::Error> {
    let verbosity = settings.verbosity;
    use crate::output::series::{self, CaseOutcome, PulloutReference};
    let mut outcomes = Vec::new();
    let mut first_error = None;
    let mut pullout = None;
    let first = cases[0].model()?;
    let inputs = crate::output::ResultWriter::inputs(&first);
    let series_folder = crate::output::OwnedFolder::open(out, &inputs)?;
    for case in cases {
        let label = case.label.clone().unwrap_or_default();
        // the label holds the model's load name: one safe component inside `out`, the name cut
        // short enough that the value always shows
        let folder = match (&case.load, case.value) {
            (Some(load), Some(value)) => {
                let load: String = load.chars().take(64).collect();
                crate::output::path_component(&format!("{load}-{value}"))
            }
            _ => crate::output::path_component(&label),
        };
        if verbosity != Verbosity::Quiet {
            println!("— run {label} —");
        }
        let mut peaks = Vec::new();
        let model = case.model()?;
        let case_folder = series_folder.subfolder(&folder, &crate::output::ResultWriter::inputs(&model))?;
        let error = match run_case(path, &*model, settings, Place::Opened(case_folder), None, &mut peaks) {
            Ok(()) => None,
            Err(e) => {
                let message = e.to_string();
                first_error.get_or_insert(e);
                Some(message)
            }
        };
        if pullout.is_none() {
            pullout = PulloutReference::of(&*model, &peaks);
        }
        outcomes.push(CaseOutcome { folder, label, value: case.value.unwrap_or(0.0), peaks, error });
    }
    let load = cases[0].load.clone().unwrap_or_else(|| "load".to_string());
    let summary = series::write(&series_folder, path, &load, &cases[0].model()?.unit_labels(), outcomes, pullout)?;
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

/// Where a run writes: the folder the user named, or a folder opened already (a run of a series).
enum Place<'a> {
    Path(&'a std::path::Path),
    Opened(crate::output::OwnedFolder),
}

/// Run one model into `out`; `peaks` receives the peak reaction of each prescribed target, also when
/// the run stops early.
fn run_case(
    path: &std::path::Path,
    model: &Model,
    settings: &RunSettings,
    out: Place<'_>,
    from: Option<(crate::analysis::Checkpoint, PathBuf)>,
    peaks: &mut Vec<crate::output::TargetPeak>,
) -> Result<(), crate::Error> {
    let RunSettings { solver, solver_options, output, verbosity, process } = *settings;
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
    let mut writer = match out {
        Place::Path(out) => {
            let mut writer = ResultWriter::with_options(model, out, &solver_name, output)?;
            // the process is this run (a series' runs count from their own start)
            writer.timed_before(process.at, vec![process.phase()]);
            writer
        }
        Place::Opened(folder) => ResultWriter::with_folder(model, folder, &solver_name, output)?,
    };
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
    let mut progress = Progress { bar: bar.clone(), verbosity };
    let result = crate::output::write_run(model, &options, from, &mut writer, &mut progress);
    bar.finish_and_clear();
    *peaks = writer.peak_reactions();
    match result {
        Ok(seconds) => {
            for w in &writer.summary.solver_stats.warnings {
                eprintln!("warning: {w}");
            }
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
                    s.solver_stats.solver.max_relative_residual,
                    writer.out().display()
                );
            }
            Ok(())
        }
        Err(e) => {
            eprintln!("the {} completed steps are in {}", writer.summary.steps.len(), writer.out().display());
            Err(e)
        }
    }
}
