//! The result writer: every step's files as it converges (the fields, the history, the summary),
//! and at the end the report and the plots. The module comment of `output` says how each file is
//! kept whole.

use super::figures::{self, profile, StepProfile};
use super::folder::path_component;
#[cfg(feature = "hdf5")]
use super::results_h5;
use super::run_timings;
use super::writer_thread::{self, WriterThread};
use super::{checkpoints, events, grids, pace, report, step_tables, vtk};

use super::options::OutputOptions;
use super::owned_folder::OwnedFolder;
use super::summary::{RunSummary, TargetPeak};
use super::targets::{TargetStep, Targets};

use super::history::{self, HistoryRow};
use super::kept_steps::{HeldStep, HeldSteps};
use super::motion::MotionHistory;
use crate::analysis::results::StepResults;
use crate::analysis::RunStats;
use crate::analysis::{StepRecord, StepSink};
use crate::error::Error;
use crate::model::{Model, UnitLabels};
use crate::timing::Phase;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Writes each step under `<out>/stage-<k>-<name>/step-<nnn>/` and keeps `summary.json` and
/// `history.csv` current.
pub struct ResultWriter {
    out: PathBuf,
    /// The output folder's handle: every file of the run is written through it.
    folder: OwnedFolder,
    units: UnitLabels,
    /// The prescribed targets, and the peaks of their reactions.
    targets: Targets,
    history: Vec<HistoryRow>,
    /// What has happened so far, and each stage's end.
    events: events::Events,
    /// Profiles along each reinforcement, per step, for the plots.
    profiles: Vec<StepProfile>,
    /// Steps worth plotting: where slip starts, where everything slides.
    marked_steps: Vec<usize>,
    /// Each reinforcement interface and its nodes.
    reinforcements: Vec<figures::ReinforcementNodes>,
    /// The dynamic stages' histories, when the model has any.
    motion: Option<MotionHistory>,
    /// The field files asked for.
    options: OutputOptions,
    /// The grids' fixed parts, for the `.vtu` and HDF5 files.
    layout: Arc<grids::GridLayout>,
    /// ParaView `.vtu` grids and their `.pvd` collection, when written.
    vtk: Option<vtk::VtkWriter>,
    /// The thread that writes the run's files, in the order they are handed to it
    /// (`writer_thread.rs`), `results.h5` and its `results.xdmf` included.
    thread: Option<WriterThread>,
    /// Steps held back until they prove to be kept (`--keep events` or `N`).
    held: HeldSteps,
    /// When the files written whole (the index, history.csv, summary.json) are next rewritten.
    pace: pace::Pace,
    /// When this writer started opening its folder, and how long that took [s].
    created: Instant,
    opening_seconds: f64,
    /// When the process started and the phases its program timed before this writer existed
    /// ([`ResultWriter::timed_before`]).
    before: Option<(Instant, Vec<Phase>)>,
    pub summary: RunSummary,
}

impl ResultWriter {
    /// The prescribed targets the history follows: (label, `x` or `y`, nodes). Its displacement is
    /// the mean over the nodes, its reaction the sum.
    pub fn targets(&self) -> Vec<(String, &'static str, Vec<usize>)> {
        self.targets.list()
    }

    /// A writer of every step's fields in the build's default files (no per-step CSV files).
    ///
    /// # Errors
    /// [`Error::Write`] naming what could not be written or cleared in `out`.
    pub fn new(model: &Model, out: &Path, solver: &str) -> Result<Self, Error> {
        Self::with_options(model, out, solver, &OutputOptions::default())
    }

    /// A writer of the field files `options` asks for.
    ///
    /// # Errors
    /// [`Error::Write`] naming what could not be written or cleared in `out`.
    pub fn with_options(model: &Model, out: &Path, solver: &str, options: &OutputOptions) -> Result<Self, Error> {
        let started = Instant::now();
        let folder = OwnedFolder::open(out, &Self::inputs(model))?;
        let mut writer = Self::with_folder(model, folder, solver, options)?;
        (writer.created, writer.opening_seconds) = (started, started.elapsed().as_secs_f64());
        Ok(writer)
    }

    /// Count the timings from `process_started`, the process's start, with `phases` its program
    /// timed before this writer existed (the process's start itself, …): `summary.json`'s
    /// `timings` then cover the whole process, the model's loading included.
    pub fn timed_before(&mut self, process_started: Instant, phases: Vec<Phase>) {
        self.before = Some((process_started, phases));
    }

    /// The files a run of `model` reads, which its output never replaces or removes: the model
    /// file and its mesh.
    pub fn inputs(model: &Model) -> Vec<&Path> {
        let mut inputs = vec![model.source.as_path()];
        if let Some(mesh) = &model.mesh_source {
            inputs.push(mesh.file.as_path());
        }
        inputs
    }

    /// A writer into `folder`, opened already (a run of a series, in its series' folder).
    ///
    /// # Errors
    /// [`Error::Write`] naming what could not be written in the folder.
    pub fn with_folder(
        model: &Model,
        folder: OwnedFolder,
        solver: &str,
        options: &OutputOptions,
    ) -> Result<Self, Error> {
        let created = Instant::now();
        let out = folder.path().to_path_buf();
        let out = out.as_path();
        let targets = Targets::of_model(model);
        let units = model.unit_labels();
        if let Some(generated) = model.mesh_source.as_ref().and_then(|m| m.generated.as_ref()) {
            folder.write("mesh.msh", &generated.msh)?;
        }
        let mut files = Vec::new();
        if options.writes_hdf5() {
            files.extend(["results.h5".to_string(), "results.xdmf".to_string()]);
        }
        if options.writes_vtu() {
            files.push("results.pvd".to_string());
        }
        let layout = Arc::new(grids::GridLayout::new(model));
        let mut writer = ResultWriter {
            vtk: options.writes_vtu().then(|| vtk::VtkWriter::new(folder.path())),
            thread: None,
            held: HeldSteps::new(targets.count()),
            pace: pace::Pace::default(),
            created,
            opening_seconds: 0.0,
            before: None,
            events: events::Events::new(
                model
                    .stages
                    .iter()
                    .map(|s| if s.strength_reduction.is_some() { None } else { s.load_factors.last().copied() })
                    .collect(),
            ),
            options: *options,
            layout,
            out: out.to_path_buf(),
            folder: folder.clone(),
            motion: None,
            targets,
            history: Vec::new(),
            profiles: Vec::new(),
            marked_steps: Vec::new(),
            reinforcements: model
                .interfaces
                .iter()
                .filter_map(|i| {
                    model.node_sets.get(&format!("{}.reinforcement", i.name)).map(|nodes| {
                        let mut indices = nodes.clone();
                        indices.sort_unstable();
                        indices.dedup();
                        figures::ReinforcementNodes {
                            name: i.name.clone(),
                            ids: indices.iter().map(|&n| model.mesh.node_id(n)).collect(),
                            indices,
                        }
                    })
                })
                .collect(),
            summary: RunSummary::starting(model, solver, options, &units, files),
            units,
        };
        writer.motion = MotionHistory::new(model, writer.reinforcements.iter().map(|r| r.name.clone()).collect());
        // at once, so that a run killed before its first step leaves a folder the next run
        // recognises as geoslip's (and clears)
        writer.write_summary()?;
        #[cfg(feature = "hdf5")]
        let hdf5 = {
            let labels = writer.targets.labels();
            let history: Vec<results_h5::HistoryTarget<'_>> =
                labels.iter().map(|&(label, direction)| results_h5::HistoryTarget { label, direction }).collect();
            let results = results_h5::Hdf5Results::create(
                &writer.folder,
                &model.title,
                &writer.units,
                &writer.layout,
                &history,
                options.precision,
            )?;
            Some(writer_thread::Hdf5Files { results, layout: writer.layout.clone() })
        };
        // (after the first summary, and after `results.h5` is created: a folder with a summary is
        // geoslip's)
        #[cfg(feature = "hdf5")]
        let thread = WriterThread::start(writer.folder.clone(), hdf5)?;
        #[cfg(not(feature = "hdf5"))]
        let thread = WriterThread::start(writer.folder.clone())?;
        writer.thread = Some(thread);
        writer.opening_seconds = created.elapsed().as_secs_f64();
        Ok(writer)
    }

    /// Each prescribed target's largest |reaction| so far, and the displacement where it occurred.
    pub fn peak_reactions(&self) -> Vec<TargetPeak> {
        self.targets.peaks()
    }

    /// The output folder, as the user named it.
    pub fn out(&self) -> &Path {
        &self.out
    }

    /// The folder of a step's CSV files, inside the output folder.
    pub fn step_dir(&self, record: &StepRecord) -> String {
        let name = path_component(&record.stage);
        format!("stage-{}-{}/step-{:03}", record.stage_index + 1, name, record.step)
    }

    pub fn write_summary(&mut self) -> Result<(), Error> {
        let json = serde_json::to_vec_pretty(&self.summary).unwrap_or_default();
        self.replace_file("summary.json", json)
    }

    /// Replace the file `name` of the output folder, written whole as the run grows, with
    /// `bytes`, atomically and synced: on the writer thread while it runs (after what was handed
    /// to it, so that the file never runs ahead of what it lists), here otherwise (before the
    /// thread starts, and after it has finished).
    fn replace_file(&mut self, name: &str, bytes: Vec<u8>) -> Result<(), Error> {
        match self.running_thread() {
            Some(thread) => thread.replace_file(name.to_string(), bytes),
            None => self.folder.write(name, &bytes),
        }
    }

    /// Write a file of one step, as [`ResultWriter::replace_file`] does.
    fn write_file(&mut self, name: String, bytes: Vec<u8>) -> Result<(), Error> {
        match self.running_thread() {
            Some(thread) => thread.write_file(name, bytes),
            None => self.folder.write(&name, &bytes),
        }
    }

    /// Write a step's folder `dir` of `files`, whole or not at all, as
    /// [`ResultWriter::replace_file`] does.
    fn write_step_folder(&mut self, dir: String, files: Vec<(String, Vec<u8>)>) -> Result<(), Error> {
        match self.running_thread() {
            Some(thread) => thread.write_step_folder(dir, files),
            None => writer_thread::write_folder_whole(&self.folder, &dir, files),
        }
    }

    /// The writer thread, while it takes work.
    fn running_thread(&mut self) -> Option<&mut WriterThread> {
        self.thread.as_mut().filter(|thread| thread.running())
    }

    /// The writer thread, while it takes work and writes `results.h5`.
    #[cfg(feature = "hdf5")]
    fn hdf5_thread(&mut self) -> Option<&mut WriterThread> {
        self.running_thread().filter(|thread| thread.has_hdf5())
    }

    /// Mark the run finished (or failed), write the summary a last time, and the report.
    pub fn finish(
        &mut self,
        model: &Model,
        error: Option<&Error>,
        stats: Option<RunStats>,
        seconds: f64,
    ) -> Result<(), Error> {
        let started = std::time::Instant::now();
        // the last step of the run, if it was held back
        if let Some(last) = self.held.latest.take() {
            self.write_held(model, &last)?;
        }
        self.summary.status = if error.is_some() { "failed".into() } else { "completed".into() };
        self.summary.error = error.map(|e| e.to_string());
        if let Some(s) = stats {
            self.summary.solver_stats = s;
        }
        self.summary.total_seconds = seconds;
        self.rewrite_growing_files()?;
        // everything handed over written (and `results.h5` committed and closed); the figures,
        // the report and the last summary after it
        if let Some(thread) = &mut self.thread {
            thread.finish()?;
            self.summary.writer_thread_seconds = thread.cpu_seconds();
        }
        let figures = self.figures().write()?;
        let design = match &model.design {
            Some(wall) => {
                let names: Vec<&str> = self.reinforcements.iter().map(|nodes| nodes.name.as_str()).collect();
                let checks = super::design_checks::checks(wall, self.profiles.last(), &names);
                let figure = super::design_checks::write_files(&self.folder, &checks, &self.units)?;
                Some(report::DesignSection { wall, checks, figure })
            }
            None => None,
        };
        let shaking = match &self.motion {
            Some(history) => {
                Some(report::ShakingSection { history, figure: history.figure(&self.folder, &self.units)? })
            }
            None => None,
        };
        let report = report::markdown(
            model,
            &self.summary,
            &self.history,
            &self.units,
            &figures,
            design.as_ref(),
            shaking.as_ref(),
        );
        self.folder.write("report.md", report.as_bytes())?;
        // once more, with the time the writer took to the end
        self.summary.write_seconds += started.elapsed().as_secs_f64();
        let (opening, stats) = (self.opening_seconds, &self.summary.solver_stats);
        self.summary.timings = run_timings::of_run(self.before.as_ref(), self.created, model, opening, stats, started);
        self.write_summary()
    }

    /// Write the fields of step number `time` in every field file asked for, unless they are
    /// written already.
    fn write_fields(
        &mut self,
        model: &Model,
        time: usize,
        record: &StepRecord,
        results: &StepResults,
    ) -> Result<(), Error> {
        let kept = &mut self.summary.fields.kept_steps;
        let Err(at) = kept.binary_search(&time) else { return Ok(()) };
        kept.insert(at, time);
        if self.options.csv {
            // the step's folder appears whole or not at all: written beside it, then renamed into
            // place (over the same step of an earlier run into this folder)
            let files = step_tables::step_files(&self.units, results, results.stresses(model));
            self.write_step_folder(self.step_dir(record), files)?;
        }
        if self.vtk.is_none() && !self.options.writes_hdf5() {
            return Ok(());
        }
        let grids = self.layout.step(results, results.stresses(model));
        let vtu = match &mut self.vtk {
            Some(vtk) => vtk.step_files(time, &self.layout, &grids)?,
            None => Vec::new(),
        };
        for (name, bytes) in vtu {
            self.write_file(name, bytes)?;
        }
        #[cfg(feature = "hdf5")]
        if let Some(thread) = self.hdf5_thread() {
            thread.write_step(time, record, grids)?;
        }
        Ok(())
    }

    fn write_held(&mut self, model: &Model, held: &HeldStep) -> Result<(), Error> {
        self.write_fields(model, held.time, &held.record, &held.results)
    }
}

impl StepSink for ResultWriter {
    fn keeps_checkpoints(&self) -> bool {
        !self.options.no_restart
    }

    fn checkpoint(&mut self, checkpoint: crate::analysis::Checkpoint) -> Result<(), Error> {
        match self.running_thread() {
            // encoded on the writer thread, beside the run
            Some(thread) => thread.write_checkpoint(checkpoint),
            None => checkpoints::write(&self.folder, &checkpoint),
        }
    }

    fn factor_of_safety(&mut self, fs: &crate::analysis::FactorOfSafety) -> Result<(), Error> {
        let bracket = match (fs.failed_at, &fs.failure) {
            (Some(f), Some(why)) => format!("at F = {f:.4}: {why}"),
            (Some(f), None) => format!("no equilibrium at F = {f:.4}"),
            (None, _) => "equilibrium up to the largest factor tried: FS is at least this".to_string(),
        };
        self.summary.events.push(format!(
            "stage \"{}\": factor of safety FS = {:.3} by strength reduction of the {} ({bracket})",
            fs.stage, fs.value, fs.reduced
        ));
        self.summary.factors_of_safety.push(fs.clone());
        // at once, whatever the pace (the index first, so the summary is not ahead of it)
        #[cfg(feature = "hdf5")]
        if let Some(thread) = self.hdf5_thread() {
            thread.commit(true)?;
        }
        self.rewrite_growing_files()
    }

    fn step_done(
        &mut self,
        model: &Model,
        results: &StepResults,
        record: &StepRecord,
        stats: &RunStats,
    ) -> Result<(), Error> {
        let started = std::time::Instant::now();
        let time = self.summary.steps.len() + 1;
        let when = events::when(record);
        let index = self.summary.steps.len();
        let mut event = self.events.of_step(record, index, &mut self.summary.events, &mut self.marked_steps);
        // the targets' displacement and reaction; a new peak, or a fall from one
        let TargetStep { rows, values, peaked, fell } = self.targets.observe(record, results, &when);
        self.history.extend(rows);
        #[cfg(not(feature = "hdf5"))]
        let _ = values; // (results.h5's history only)
        event |= !fell.is_empty();
        let mut fallen = Vec::with_capacity(fell.len());
        for (ti, text) in fell {
            self.summary.events.push(text);
            fallen.push(ti);
        }
        // what the summary, the report and the figures say of the step, before any of its files is
        // handed over (a write that fails leaves them all with the step)
        self.profiles.push(StepProfile {
            label: format!("{} step {}", record.stage, record.step),
            reinforcements: self.reinforcements.iter().map(|nodes| profile(nodes, results)).collect(),
        });
        if let (Some(motion), Some(profile)) = (&mut self.motion, self.profiles.last()) {
            let tensions = profile.reinforcements.iter().map(|p| p.largest_tension().map_or(0.0, |(t, _)| t)).collect();
            motion.push(record, results, tensions);
        }
        self.summary.steps.push(record.clone());
        self.summary.solver_stats = stats.clone();

        // the fields: this step's if it is kept; the step before, held back, if this one starts
        // another stage (it was the last of its own); a peak held back, once the reaction falls
        // from it
        if let Some(before) = self.held.latest.take() {
            if before.record.stage_index != record.stage_index {
                self.write_held(model, &before)?;
            }
        }
        let keep = self.options.keep.keeps(time, event);
        let held = (self.options.keep.thins() && !keep).then(|| HeldStep {
            time,
            record: record.clone(),
            results: Arc::new(results.clone()),
        });
        if keep {
            self.write_fields(model, time, record, results)?;
        }
        for ti in peaked {
            self.held.peaks[ti] = held.clone();
        }
        for ti in fallen {
            if let Some(peak) = self.held.peaks[ti].take() {
                self.write_held(model, &peak)?;
            }
        }
        self.held.latest = held;
        // the files written whole, at this step if they are due
        let rewrite = self.pace.due();
        #[cfg(feature = "hdf5")]
        if let Some(thread) = self.hdf5_thread() {
            thread.append_history(time, record, &values)?;
            thread.commit(rewrite)?;
        }
        self.summary.write_seconds += started.elapsed().as_secs_f64();
        if !rewrite {
            return Ok(());
        }
        let rewriting = std::time::Instant::now();
        self.rewrite_growing_files()?;
        let took = rewriting.elapsed();
        self.summary.write_seconds += took.as_secs_f64();
        // (with the writer thread's time on the same files, as far as it has got)
        let took = took + self.thread.as_ref().map_or(std::time::Duration::ZERO, WriterThread::take_rewrite_time);
        self.pace.rewritten(took);
        Ok(())
    }
}

impl ResultWriter {
    /// Rewrite the files written whole that grow with the run: the `.pvd` collection,
    /// `history.csv` and `summary.json` (`results.xdmf` with the commit: `h5.commit(true)`).
    fn rewrite_growing_files(&mut self) -> Result<(), Error> {
        if let Some(pvd) = self.vtk.as_ref().map(vtk::VtkWriter::collection) {
            self.replace_file("results.pvd", pvd.into_bytes())?;
        }
        let csv = history::csv(&self.history, &self.units);
        self.replace_file("history.csv", csv)?;
        if let Some(motion) = &self.motion {
            let csv = motion.csv(&self.units);
            self.replace_file("motion.csv", csv)?;
        }
        self.write_summary()
    }

    /// What the figures are drawn from: the history of each prescribed target, the profiles.
    fn figures(&self) -> figures::Figures<'_> {
        figures::Figures {
            folder: &self.folder,
            units: &self.units,
            curves: self.targets.curves(&self.history),
            profiles: &self.profiles,
            marked_steps: &self.marked_steps,
            reinforcements: self.reinforcements.iter().map(|nodes| nodes.name.as_str()).collect(),
        }
    }
}
