//! What the command line shows while a model runs: a progress bar on a terminal, a line per step
//! when verbose, and the factors of safety.

use crate::analysis::{StepRecord, StepSink};

#[derive(Clone, Copy, PartialEq)]
pub enum Verbosity {
    Quiet,
    Normal,
    Verbose,
}

impl Verbosity {
    pub fn of(&(quiet, verbose): &(bool, bool)) -> Verbosity {
        if quiet {
            Verbosity::Quiet
        } else if verbose {
            Verbosity::Verbose
        } else {
            Verbosity::Normal
        }
    }
}

/// Moves the progress bar with each converged step, and prints a line per step when verbose.
pub struct Progress {
    pub bar: indicatif::ProgressBar,
    pub verbosity: Verbosity,
}

impl Progress {
    /// A line above the progress bar; a hidden bar (output not a terminal) prints nothing of its
    /// own, so the line goes to standard error.
    pub fn say(&self, line: String) {
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }
}

impl StepSink for Progress {
    fn step_done(
        &mut self,
        _: &crate::model::Model,
        _: &crate::analysis::results::StepResults,
        record: &StepRecord,
        _: &crate::analysis::RunStats,
    ) -> Result<(), crate::Error> {
        // a cutback adds steps: the bar grows with them
        let done = self.bar.position() + 1;
        if self.bar.length().is_some_and(|l| done > l) {
            self.bar.set_length(done);
        }
        self.bar.set_position(done);
        self.bar.set_message(format!("{} ({})", record.stage, record.position()));
        if self.verbosity == Verbosity::Verbose {
            let line = format!(
                "stage \"{}\" step {}: {}, {} iterations, {} cutbacks, force residual {:.1e}, {} sliding of {} in contact, {} soil points yielding, {} state changes, {} re-associations",
                record.stage,
                record.step,
                record.position(),
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
