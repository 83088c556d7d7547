//! Result files: the fields of the kept steps (`results.h5` + `results.xdmf` in a build with the
//! `hdf5` feature, ParaView `.vtu` files without it or on request, per-step CSV files on request), a
//! history of the prescribed targets, a JSON run summary, a report and plots.
//!
//! Every file but `results.h5` is written to a temporary file in the same folder and renamed into
//! place, so a crash never leaves a truncated file under a final name; `results.h5` is written in
//! place, flushed after every step, and only `results.xdmf`, rewritten atomically after the flush,
//! says which of its steps are complete (see `results_h5.rs`). Each step's files are written as
//! soon as the step converges (a step held back by `--keep` as soon as it proves to be kept):
//! completed steps are never lost. The files written whole that grow with the run (the index, the
//! history and the summary) are rewritten at every step while that is cheap, less often once it
//! is not (`pace.rs`), and always at the end.

pub mod checkpoints;
#[cfg(feature = "hdf5")]
mod chunk_deflate;
mod figures;
mod folder;
pub mod grids;
#[cfg(feature = "hdf5")]
mod h5_arrays;
#[cfg(feature = "hdf5")]
pub mod hdf5_thread;
pub mod kept_steps;
pub mod options;
pub mod owned_folder;
mod pace;
pub mod plots;
mod record;
mod record_removal;
pub mod report;
#[cfg(feature = "hdf5")]
pub mod results_h5;
pub mod series;
mod summary;
pub mod vtk;
pub mod xdmf;

use figures::{profile, StepProfile};
pub use folder::path_component;
use folder::{csv_bytes, num};
pub use kept_steps::KeptSteps;
pub use options::OutputOptions;
pub use owned_folder::OwnedFolder;
pub use summary::{FieldFiles, RunSummary, TargetPeak, Unknowns};

use crate::analysis::results::StepResults;
use crate::analysis::SolverStats;
use crate::analysis::{StepRecord, StepSink};
use crate::error::Error;
use crate::model::file::Direction;
use crate::model::{Model, UnitLabels};
use kept_steps::{HeldStep, HeldSteps};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Run `model` on the best backend with its standard results written to `out`, passing every step
/// and factor of safety to `observe` as well (an example's own post-processing). Returns the run's
/// wall time in seconds; a failed run still finishes its summary and report before the error.
pub fn run_and_write(model: &Model, out: &Path, observe: &mut dyn StepSink) -> Result<f64, Error> {
    run_and_write_with(model, out, &OutputOptions::default(), observe)
}

/// [`run_and_write`] with the field files chosen by `output` (per-step CSV files, kept steps, `.vtu`
/// files).
///
/// # Errors
/// The run's error, after the summary and the report have recorded it (or the error writing them).
pub fn run_and_write_with(
    model: &Model,
    out: &Path,
    output: &OutputOptions,
    observe: &mut dyn StepSink,
) -> Result<f64, Error> {
    let mut writer = ResultWriter::with_options(model, out, "auto", output)?;
    let options = crate::analysis::RunOptions { analysis: model.analysis.clone(), ..Default::default() };
    write_run(model, &options, &mut writer, observe)
}

/// Run `model` with `options`, every step and factor of safety written by `writer` as soon as it
/// exists and passed to `observe` as well (a progress display, an example's post-processing); then
/// the summary and the report. This is the one path from a model to its results, for the command
/// line and the examples alike. Returns the run's wall time in seconds.
///
/// # Errors
/// The run's error, after the summary and the report have recorded it (or the error writing them).
pub fn write_run(
    model: &Model,
    options: &crate::analysis::RunOptions,
    writer: &mut ResultWriter,
    observe: &mut dyn StepSink,
) -> Result<f64, Error> {
    write_run_from(model, options, None, writer, observe)
}

/// [`write_run`], or, given a saved step that fits the model ([`checkpoints::read`]), the run's
/// continuation from it: the summary and the report then say where it continued from.
///
/// # Errors
/// As [`write_run`].
pub fn write_run_from(
    model: &Model,
    options: &crate::analysis::RunOptions,
    from: Option<(crate::analysis::Checkpoint, PathBuf)>,
    writer: &mut ResultWriter,
    observe: &mut dyn StepSink,
) -> Result<f64, Error> {
    struct Tee<'a> {
        writer: &'a mut ResultWriter,
        observe: &'a mut dyn StepSink,
    }
    impl StepSink for Tee<'_> {
        fn step_done(&mut self, step: &StepResults, record: &StepRecord, stats: &SolverStats) -> Result<(), Error> {
            self.writer.step_done(step, record, stats)?;
            self.observe.step_done(step, record, stats)
        }
        fn factor_of_safety(&mut self, fs: &crate::analysis::FactorOfSafety) -> Result<(), Error> {
            self.writer.factor_of_safety(fs)?;
            self.observe.factor_of_safety(fs)
        }
        fn keeps_checkpoints(&self) -> bool {
            self.writer.keeps_checkpoints()
        }
        fn checkpoint(&mut self, checkpoint: &crate::analysis::Checkpoint) -> Result<(), Error> {
            self.writer.checkpoint(checkpoint)
        }
    }
    let started = std::time::Instant::now();
    let mut tee = Tee { writer: &mut *writer, observe };
    let result = match from {
        None => crate::analysis::run(model, options, &mut tee),
        Some((checkpoint, path)) => {
            tee.writer.summary.notes.push(format!(
                "continued from step {} of stage \"{}\" as saved in {}: the steps up to it are in that run's results",
                checkpoint.step,
                checkpoint.stage,
                path.display()
            ));
            crate::analysis::resume(model, options, checkpoint, &mut tee)
        }
    };
    let seconds = started.elapsed().as_secs_f64();
    match result {
        Ok(stats) => writer.finish(model, None, Some(stats), seconds)?,
        Err(e) => {
            writer.finish(model, Some(&e), None, seconds)?;
            return Err(e);
        }
    }
    Ok(seconds)
}

/// A prescribed target followed through the run: its mean displacement and total reaction.
struct Target {
    label: String,
    nodes: Vec<usize>,
    direction: Direction,
}

/// Writes each step under `<out>/stage-<k>-<name>/step-<nnn>/` and keeps `summary.json` and
/// `history.csv` current.
pub struct ResultWriter {
    out: PathBuf,
    /// The output folder's handle: every file of the run is written through it.
    folder: OwnedFolder,
    units: UnitLabels,
    targets: Vec<Target>,
    history: Vec<Vec<String>>,
    /// Largest |reaction| so far per target, and whether a drop from it was reported.
    peak_reaction: Vec<(f64, bool)>,
    /// The target's displacement where its reaction peaked.
    peak_displacement: Vec<f64>,
    slip_started: bool,
    all_sliding: bool,
    soil_yielded: bool,
    /// Profiles along each reinforcement, per step, for the plots.
    profiles: Vec<StepProfile>,
    /// Steps worth plotting: where slip starts, where everything slides.
    marked_steps: Vec<usize>,
    /// Each reinforcement interface and its nodes.
    reinforcements: Vec<figures::ReinforcementNodes>,
    /// The field files asked for.
    options: OutputOptions,
    /// The grids' fixed parts, for the `.vtu` and HDF5 files.
    layout: Arc<grids::GridLayout>,
    /// ParaView `.vtu` grids and their `.pvd` collection, when written.
    vtk: Option<vtk::VtkWriter>,
    /// `results.h5` and its `results.xdmf`.
    #[cfg(feature = "hdf5")]
    h5: Option<hdf5_thread::Hdf5Thread>,
    /// Steps held back until they prove to be kept (`--keep events` or `N`).
    held: HeldSteps,
    /// When the files written whole (the index, history.csv, summary.json) are next rewritten.
    pace: pace::Pace,
    /// Each stage's last load factor, where its last step shows by it (not a strength-reduction
    /// stage's).
    stage_ends: Vec<Option<f64>>,
    pub summary: RunSummary,
}

impl ResultWriter {
    /// A writer of every step's fields in the build's default files (no per-step CSV files).
    ///
    /// # Errors
    /// [`Error::Write`] naming what could not be written or cleared in `out`.
    /// The prescribed targets the history follows: (label, `x` or `y`, nodes). Its displacement is
    /// the mean over the nodes, its reaction the sum.
    pub fn targets(&self) -> Vec<(String, &'static str, Vec<usize>)> {
        self.targets
            .iter()
            .map(|t| (t.label.clone(), if t.direction == Direction::X { "x" } else { "y" }, t.nodes.clone()))
            .collect()
    }

    pub fn new(model: &Model, out: &Path, solver: &str) -> Result<Self, Error> {
        Self::with_options(model, out, solver, &OutputOptions::default())
    }

    /// A writer of the field files `options` asks for.
    ///
    /// # Errors
    /// [`Error::Write`] naming what could not be written or cleared in `out`.
    pub fn with_options(model: &Model, out: &Path, solver: &str, options: &OutputOptions) -> Result<Self, Error> {
        let folder = OwnedFolder::open(out, &Self::inputs(model))?;
        Self::with_folder(model, folder, solver, options)
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
        let out = folder.path().to_path_buf();
        let out = out.as_path();
        let mut targets = Vec::new();
        for stage in &model.stages {
            for &(n, d, _) in &stage.prescribed {
                let set = model.node_sets.iter().find(|(_, nodes)| nodes.contains(&n)).map(|(name, _)| name.clone());
                let label = set.unwrap_or_else(|| format!("node {}", model.mesh.node_id(n)));
                match targets.iter_mut().find(|t: &&mut Target| t.label == label && t.direction == d) {
                    Some(t) => {
                        if !t.nodes.contains(&n) {
                            t.nodes.push(n)
                        }
                    }
                    None => targets.push(Target { label, nodes: vec![n], direction: d }),
                }
            }
        }
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
        #[allow(unused_mut)] // its HDF5 file is added after the first summary
        let mut writer = ResultWriter {
            vtk: options.writes_vtu().then(|| vtk::VtkWriter::new(folder.clone())),
            #[cfg(feature = "hdf5")]
            h5: None,
            held: HeldSteps::new(targets.len()),
            pace: pace::Pace::default(),
            stage_ends: model
                .stages
                .iter()
                .map(|s| if s.strength_reduction.is_some() { None } else { s.load_factors.last().copied() })
                .collect(),
            options: *options,
            layout,
            out: out.to_path_buf(),
            folder: folder.clone(),
            peak_reaction: vec![(0.0, false); targets.len()],
            peak_displacement: vec![0.0; targets.len()],
            targets,
            history: Vec::new(),
            slip_started: false,
            soil_yielded: false,
            all_sliding: false,
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
            summary: RunSummary {
                geoslip_version: env!("CARGO_PKG_VERSION"),
                model: model.source.display().to_string(),
                title: model.title.clone(),
                status: "running".into(),
                error: None,
                solver: solver.into(),
                units: serde_json::json!({
                    "length": units.length, "force": units.force,
                    "force_per_width": units.force_per_width, "stress": units.stress,
                    "geometry": model.mesh.geometry,
                    "forces": if model.mesh.geometry.is_axisymmetric() { "total over the circumference" } else { "per metre width" } }),
                unknowns: Unknowns {
                    nodes: model.mesh.nodes.len(),
                    soil_elements: model.mesh.solids.len(),
                    bars: model.mesh.bars.len(),
                    interface_points: model.interfaces.iter().flat_map(|i| &i.faces).map(|f| f.points.len()).sum(),
                },
                notes: model.notes.clone(),
                events: Vec::new(),
                factors_of_safety: Vec::new(),
                fields: FieldFiles {
                    files,
                    csv: options.csv,
                    keep: options.keep.to_string(),
                    precision: options.writes_hdf5().then_some(match options.precision {
                        options::FieldPrecision::Single => "single",
                        options::FieldPrecision::Double => "double",
                    }),
                    kept_steps: Vec::new(),
                },
                steps: Vec::new(),
                solver_stats: SolverStats::default(),
                total_seconds: 0.0,
                write_seconds: 0.0,
                writer_thread_seconds: None,
            },
            units,
        };
        // at once, so that a run killed before its first step leaves a folder the next run
        // recognises as geoslip's (and clears)
        writer.write_summary()?;
        #[cfg(feature = "hdf5")]
        {
            let labels: Vec<(String, &str)> = writer
                .targets
                .iter()
                .map(|t| (t.label.clone(), if t.direction == Direction::X { "x" } else { "y" }))
                .collect();
            let history: Vec<results_h5::HistoryTarget<'_>> =
                labels.iter().map(|(label, direction)| results_h5::HistoryTarget { label, direction }).collect();
            let results = results_h5::Hdf5Results::create(
                &writer.folder,
                &model.title,
                &writer.units,
                &writer.layout,
                &history,
                options.precision,
            )?;
            writer.h5 = Some(hdf5_thread::Hdf5Thread::start(results, writer.layout.clone(), writer.folder.clone())?);
        }
        Ok(writer)
    }

    /// Each prescribed target's largest |reaction| so far, and the displacement where it occurred.
    pub fn peak_reactions(&self) -> Vec<TargetPeak> {
        self.targets
            .iter()
            .enumerate()
            .map(|(i, t)| TargetPeak {
                label: t.label.clone(),
                direction: t.direction,
                reaction: self.peak_reaction[i].0,
                displacement: self.peak_displacement[i],
            })
            .collect()
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

    /// Replace the file `name` of the output folder with `bytes`, atomically and synced: on the
    /// `results.h5` thread while a run has one (after what was handed to it, so that the file
    /// never runs ahead of `results.xdmf`), here otherwise.
    fn replace_file(&mut self, name: &str, bytes: Vec<u8>) -> Result<(), Error> {
        #[cfg(feature = "hdf5")]
        if let Some(h5) = self.h5.as_mut().filter(|h5| h5.running()) {
            return h5.replace_file(name.to_string(), bytes);
        }
        self.folder.write(name, &bytes)
    }

    /// Mark the run finished (or failed), write the summary a last time, and the report.
    pub fn finish(
        &mut self,
        model: &Model,
        error: Option<&Error>,
        stats: Option<SolverStats>,
        seconds: f64,
    ) -> Result<(), Error> {
        let started = std::time::Instant::now();
        // the last step of the run, if it was held back
        if let Some(last) = self.held.latest.take() {
            self.write_held(&last)?;
        }
        #[cfg(feature = "hdf5")]
        if let Some(h5) = &mut self.h5 {
            h5.finish()?;
            self.summary.writer_thread_seconds = h5.cpu_seconds();
        }
        self.summary.status = if error.is_some() { "failed".into() } else { "completed".into() };
        self.summary.error = error.map(|e| e.to_string());
        if let Some(s) = stats {
            self.summary.solver_stats = s;
        }
        self.summary.total_seconds = seconds;
        self.rewrite_growing_files()?;
        let figures = self.figures().write()?;
        let report = report::markdown(model, &self.summary, &self.history, &self.units, &figures);
        self.folder.write("report.md", report.as_bytes())?;
        // once more, with the time the writer took to the end
        self.summary.write_seconds += started.elapsed().as_secs_f64();
        self.write_summary()
    }

    /// Write the fields of step number `time` in every field file asked for, unless they are
    /// written already.
    fn write_fields(&mut self, time: usize, record: &StepRecord, results: &StepResults) -> Result<(), Error> {
        let kept = &mut self.summary.fields.kept_steps;
        let Err(at) = kept.binary_search(&time) else { return Ok(()) };
        kept.insert(at, time);
        if self.options.csv {
            // the step's folder appears whole or not at all: written beside it, then renamed into
            // place (over the same step of an earlier run into this folder)
            let dir = self.step_dir(record);
            let partial = self.folder.temporary_folder(&dir)?;
            self.write_step_files(&partial, results)?;
            self.folder.move_folder(&partial, &dir)?;
        }
        if self.vtk.is_none() && !self.options.writes_hdf5() {
            return Ok(());
        }
        let grids = self.layout.step(results);
        if let Some(vtk) = &mut self.vtk {
            vtk.write_step(time, &self.layout, &grids)?;
        }
        #[cfg(feature = "hdf5")]
        if let Some(h5) = &mut self.h5 {
            h5.write_step(time, record, grids)?;
        }
        Ok(())
    }

    fn write_held(&mut self, held: &HeldStep) -> Result<(), Error> {
        self.write_fields(held.time, &held.record, &held.results)
    }

    fn write_step_files(&self, dir: &str, r: &StepResults) -> Result<(), Error> {
        let u = &self.units;
        let (l, f, s) = (u.length, u.force_per_width.as_str(), u.stress.as_str());
        let h = |names: &[String]| names.to_vec();
        self.folder.write(
            &format!("{dir}/displacements.csv"),
            &csv_bytes(
                &h(&["node".into(), format!("x [{l}]"), format!("y [{l}]"), format!("ux [{l}]"), format!("uy [{l}]")]),
                r.displacements
                    .iter()
                    .map(|(id, x, d)| vec![id.to_string(), num(x[0]), num(x[1]), num(d[0]), num(d[1])]),
            ),
        )?;
        let opt = |v: Option<f64>| v.map(num).unwrap_or_default();
        self.folder.write(
            &format!("{dir}/reactions.csv"),
            &csv_bytes(
                &h(&["node".into(), format!("rx [{f}]"), format!("ry [{f}]")]),
                r.reactions.iter().map(|re| vec![re.node.to_string(), opt(re.rx), opt(re.ry)]),
            ),
        )?;
        self.folder.write(
            &format!("{dir}/bar_forces.csv"),
            &csv_bytes(
                &h(&[
                    "bar".into(),
                    "node_a".into(),
                    "node_b".into(),
                    format!("x_mid [{l}]"),
                    format!("y_mid [{l}]"),
                    format!("T [{f}]"),
                    "state".into(),
                ]),
                r.bar_forces.iter().map(|b| {
                    vec![
                        b.bar.to_string(),
                        b.nodes[0].to_string(),
                        b.nodes[1].to_string(),
                        num(b.midpoint[0]),
                        num(b.midpoint[1]),
                        num(b.axial_force),
                        b.state.to_string(),
                    ]
                }),
            ),
        )?;
        self.folder.write(
            &format!("{dir}/interface.csv"),
            &csv_bytes(
                &h(&[
                    "interface".into(),
                    "face".into(),
                    "slave_node".into(),
                    format!("x [{l}]"),
                    format!("y [{l}]"),
                    "master_a".into(),
                    "master_b".into(),
                    "xi [-]".into(),
                    "state".into(),
                    format!("tributary [{}]", u.tributary),
                    format!("lambda [{f}]"),
                    format!("sigma_n [{s}]"),
                    format!("tau [{s}]"),
                    format!("bearing [{s}]"),
                    format!("dilation [{l}]"),
                    format!("slip [{l}]"),
                    "contact".into(),
                ]),
                r.interface_points.iter().map(|p| {
                    vec![
                        p.interface.clone(),
                        p.face.clone(),
                        p.slave_node.to_string(),
                        num(p.x[0]),
                        num(p.x[1]),
                        p.master_nodes[0].to_string(),
                        p.master_nodes[1].to_string(),
                        num(p.xi),
                        p.state.to_string(),
                        num(p.tributary),
                        num(p.lambda),
                        num(p.sigma_n),
                        num(p.tau),
                        num(p.bearing),
                        num(p.dilation),
                        num(p.slip),
                        grids::contact_name(grids::interface_state_code(p.state, p.sliding, p.post_peak)).to_string(),
                    ]
                }),
            ),
        )?;
        self.folder.write(
            &format!("{dir}/stresses.csv"),
            &csv_bytes(
                &h(&[
                    "element".into(),
                    "gauss_point".into(),
                    format!("x [{l}]"),
                    format!("y [{l}]"),
                    format!("sxx [{s}]"),
                    format!("syy [{s}]"),
                    format!("sxy [{s}]"),
                    format!("szz [{s}]"),
                    format!("pore_pressure [{s}]"),
                    "yield".into(),
                    "plastic_strain".into(),
                ]),
                r.stresses.iter().map(|e| {
                    vec![
                        e.element.to_string(),
                        e.point.to_string(),
                        num(e.x[0]),
                        num(e.x[1]),
                        num(e.stress[0]),
                        num(e.stress[1]),
                        num(e.stress[2]),
                        num(e.stress[3]),
                        num(e.pore_pressure),
                        e.yield_state.name().to_string(),
                        num(e.plastic_strain),
                    ]
                }),
            ),
        )
    }
}

impl StepSink for ResultWriter {
    fn keeps_checkpoints(&self) -> bool {
        !self.options.no_restart
    }

    fn checkpoint(&mut self, checkpoint: &crate::analysis::Checkpoint) -> Result<(), Error> {
        checkpoints::write(&self.folder, checkpoint)
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
        if let Some(h5) = self.h5.as_mut().filter(|h5| h5.running()) {
            h5.commit(true)?;
        }
        self.rewrite_growing_files()
    }

    fn step_done(&mut self, results: &StepResults, record: &StepRecord, stats: &SolverStats) -> Result<(), Error> {
        let started = std::time::Instant::now();
        let time = self.summary.steps.len() + 1;
        let when = format!("stage \"{}\" step {} (load factor {:.4})", record.stage, record.step, record.load_factor);
        // an event step: the first or (where it shows) the last of its stage, or one where something
        // happens
        let ends_stage = record.strength_factor.is_none()
            && self.stage_ends.get(record.stage_index).copied().flatten() == Some(record.load_factor);
        let mut event = record.step == 1 || ends_stage;
        if record.reversal {
            event = true;
            self.summary.events.push(format!("{when}: the loading history reverses"));
        }
        if !self.slip_started && record.sliding_points > 0 {
            self.slip_started = true;
            event = true;
            self.marked_steps.push(self.summary.steps.len());
            self.summary
                .events
                .push(format!("{when}: slip starts ({} interface points at their strength)", record.sliding_points));
        }
        if !self.soil_yielded && record.yielding_points > 0 {
            self.soil_yielded = true;
            event = true;
            self.summary.events.push(format!(
                "{when}: the soil yields ({} Gauss points on the yield surface)",
                record.yielding_points
            ));
        }
        if !self.all_sliding && record.contact_points > 0 && record.sliding_points == record.contact_points {
            self.all_sliding = true;
            event = true;
            self.marked_steps.push(self.summary.steps.len());
            self.summary.events.push(format!("{when}: every interface point in contact slides"));
        }
        // the targets' displacement and reaction; a new peak, or a fall from one
        let mut values = Vec::with_capacity(self.targets.len());
        let (mut peaked, mut fell) = (Vec::new(), Vec::new());
        for (ti, t) in self.targets.iter().enumerate() {
            let d = |n: usize| 2 * n + if t.direction == Direction::X { 0 } else { 1 };
            let mean_u = t.nodes.iter().map(|&n| results.displacement_vector[d(n)]).sum::<f64>() / t.nodes.len() as f64;
            let reaction: f64 = t.nodes.iter().map(|&n| results.reaction_vector[d(n)]).sum();
            let (peak, reported) = self.peak_reaction[ti];
            if peak > 0.0 && !reported && reaction.abs() < 0.98 * peak {
                self.summary.events.push(format!(
                    "{when}: the reaction on {} ({}) fell to {:.4} at displacement {:.5}, from its peak {:.4} at displacement {:.5}",
                    t.label,
                    if t.direction == Direction::X { "x" } else { "y" },
                    reaction.abs(),
                    mean_u,
                    peak,
                    self.peak_displacement[ti]
                ));
                self.peak_reaction[ti].1 = true; // once per peak
                event = true;
                fell.push(ti);
            } else if reaction.abs() > peak {
                self.peak_reaction[ti] = (reaction.abs(), false);
                self.peak_displacement[ti] = mean_u;
                peaked.push(ti);
            }
            self.history.push(vec![
                record.stage.clone(),
                record.step.to_string(),
                num(record.load_factor),
                t.label.clone(),
                if t.direction == Direction::X { "x".into() } else { "y".into() },
                num(mean_u),
                num(reaction),
            ]);
            values.push((mean_u, reaction));
        }

        // the fields: this step's if it is kept; the step before, held back, if this one starts
        // another stage (it was the last of its own); a peak held back, once the reaction falls
        // from it
        if let Some(before) = self.held.latest.take() {
            if before.record.stage_index != record.stage_index {
                self.write_held(&before)?;
            }
        }
        let keep = self.options.keep.keeps(time, event);
        let held = (self.options.keep.thins() && !keep).then(|| HeldStep {
            time,
            record: record.clone(),
            results: Arc::new(results.clone()),
        });
        if keep {
            self.write_fields(time, record, results)?;
        }
        for ti in peaked {
            self.held.peaks[ti] = held.clone();
        }
        for ti in fell {
            if let Some(peak) = self.held.peaks[ti].take() {
                self.write_held(&peak)?;
            }
        }
        self.held.latest = held;
        // the files written whole, at this step if they are due
        let rewrite = self.pace.due();
        #[cfg(feature = "hdf5")]
        if let Some(h5) = &mut self.h5 {
            h5.append_history(time, record, &values)?;
            h5.commit(rewrite)?;
        }
        self.profiles.push(StepProfile {
            label: format!("{} step {}", record.stage, record.step),
            reinforcements: self.reinforcements.iter().map(|nodes| profile(nodes, results)).collect(),
        });
        self.summary.steps.push(record.clone());
        self.summary.solver_stats = stats.clone();
        self.summary.write_seconds += started.elapsed().as_secs_f64();
        if !rewrite {
            return Ok(());
        }
        let rewriting = std::time::Instant::now();
        self.rewrite_growing_files()?;
        let took = rewriting.elapsed();
        self.summary.write_seconds += took.as_secs_f64();
        // (with the writer thread's time on the same files, as far as it has got)
        #[cfg(feature = "hdf5")]
        let took = took + self.h5.as_ref().map_or(std::time::Duration::ZERO, |h5| h5.take_rewrite_time());
        self.pace.rewritten(took);
        Ok(())
    }
}

impl ResultWriter {
    /// Rewrite the files written whole that grow with the run: the `.pvd` collection,
    /// `history.csv` and `summary.json` (`results.xdmf` with the commit: `h5.commit(true)`).
    fn rewrite_growing_files(&mut self) -> Result<(), Error> {
        if let Some(vtk) = &self.vtk {
            vtk.write_collection()?;
        }
        let u = &self.units;
        let header = vec![
            "stage".to_string(),
            "step".into(),
            "load_factor [-]".into(),
            "target".into(),
            "direction".into(),
            format!("displacement [{}]", u.length),
            format!("reaction [{}]", u.force_per_width),
        ];
        let csv = csv_bytes(&header, self.history.iter().cloned());
        self.replace_file("history.csv", csv)?;
        self.write_summary()
    }

    /// What the figures are drawn from: the history of each prescribed target, the profiles.
    fn figures(&self) -> figures::Figures<'_> {
        let curves = self
            .targets
            .iter()
            .map(|t| {
                let dir = if t.direction == Direction::X { "x" } else { "y" };
                let points = self
                    .history
                    .iter()
                    .filter(|h| h[3] == t.label && h[4] == dir)
                    .filter_map(|h| Some((h[5].parse::<f64>().ok()?, h[6].parse::<f64>().ok()?)))
                    .collect();
                (t.label.as_str(), dir, points)
            })
            .collect();
        figures::Figures {
            folder: &self.folder,
            units: &self.units,
            curves,
            profiles: &self.profiles,
            marked_steps: &self.marked_steps,
            reinforcements: self.reinforcements.iter().map(|nodes| nodes.name.as_str()).collect(),
        }
    }
}
