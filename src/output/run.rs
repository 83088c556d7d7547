//! The one path from a model to its results: the run, with every step written as it converges,
//! then the summary and the report.

use super::options::OutputOptions;
use super::writer::ResultWriter;
use crate::analysis::results::StepResults;
use crate::analysis::RunStats;
use crate::analysis::{StepRecord, StepSink};
use crate::error::Error;
use crate::model::Model;
use std::path::{Path, PathBuf};

/// Run `model` on the best backend with the results `output` asks for written to `out`, passing
/// every step and factor of safety to `observe` as well (an example's own post-processing).
/// Returns the run's wall time in seconds; a failed run still finishes its summary and report
/// before the error.
///
/// # Errors
/// The run's error, after the summary and the report have recorded it (or the error writing them).
pub fn run_and_write(
    model: &Model,
    out: &Path,
    output: &OutputOptions,
    observe: &mut dyn StepSink,
) -> Result<f64, Error> {
    let mut writer = ResultWriter::with_options(model, out, "auto", output)?;
    let options = crate::analysis::RunOptions { analysis: model.analysis.clone(), ..Default::default() };
    write_run(model, &options, None, &mut writer, observe)
}

/// Run `model` with `options`, every step and factor of safety written by `writer` as soon as it
/// exists and passed to `observe` as well (a progress display, an example's post-processing); then
/// the summary and the report. Given a saved step that fits the model ([`super::checkpoints::read`]),
/// the run continues from it, and the summary and the report say so. This is the one path from a
/// model to its results, for the command line, the examples and Python alike. Returns the run's
/// wall time in seconds.
///
/// # Errors
/// The run's error, after the summary and the report have recorded it (or the error writing them).
pub fn write_run(
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
        fn step_done(
            &mut self,
            model: &crate::model::Model,
            step: &StepResults,
            record: &StepRecord,
            stats: &RunStats,
        ) -> Result<(), Error> {
            self.writer.step_done(model, step, record, stats)?;
            self.observe.step_done(model, step, record, stats)
        }
        fn factor_of_safety(&mut self, fs: &crate::analysis::FactorOfSafety) -> Result<(), Error> {
            self.writer.factor_of_safety(fs)?;
            self.observe.factor_of_safety(fs)
        }
        fn keeps_checkpoints(&self) -> bool {
            self.writer.keeps_checkpoints()
        }
        fn checkpoint(&mut self, checkpoint: crate::analysis::Checkpoint) -> Result<(), Error> {
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
