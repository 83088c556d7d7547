//! The events of a run, found step by step: the loading history reversing, slip starting, the
//! soil yielding, every interface point in contact sliding. An event step's fields are kept
//! (`--keep events`), and the steps where slip starts and where everything slides are marked in
//! the plots.

use crate::analysis::StepRecord;

/// What has happened in the run so far.
pub(super) struct Events {
    slip_started: bool,
    soil_yielded: bool,
    all_sliding: bool,
    /// Each stage's last load factor, where its last step shows by it (not a strength-reduction
    /// stage's).
    stage_ends: Vec<Option<f64>>,
}

impl Events {
    pub fn new(stage_ends: Vec<Option<f64>>) -> Events {
        Events { slip_started: false, soil_yielded: false, all_sliding: false, stage_ends }
    }

    /// Whether the step `record` (the `index`th of the run, from 0) is an event step: the first or
    /// (where it shows) the last of its stage, or one where something happens, which is said in
    /// `events`. The steps where slip starts and where everything slides go to `marked`.
    pub fn of_step(
        &mut self,
        record: &StepRecord,
        index: usize,
        events: &mut Vec<String>,
        marked: &mut Vec<usize>,
    ) -> bool {
        let when = when(record);
        let ends_stage = record.strength_factor.is_none()
            && self.stage_ends.get(record.stage_index).copied().flatten() == Some(record.load_factor);
        let mut event = record.step == 1 || ends_stage;
        if record.reversal {
            event = true;
            events.push(format!("{when}: the loading history reverses"));
        }
        if !self.slip_started && record.sliding_points > 0 {
            self.slip_started = true;
            event = true;
            marked.push(index);
            events.push(format!("{when}: slip starts ({} interface points at their strength)", record.sliding_points));
        }
        if !self.soil_yielded && record.yielding_points > 0 {
            self.soil_yielded = true;
            event = true;
            events.push(format!(
                "{when}: the soil yields ({} Gauss points on the yield surface)",
                record.yielding_points
            ));
        }
        if !self.all_sliding && record.contact_points > 0 && record.sliding_points == record.contact_points {
            self.all_sliding = true;
            event = true;
            marked.push(index);
            events.push(format!("{when}: every interface point in contact slides"));
        }
        event
    }
}

/// How the events name a step.
pub(super) fn when(record: &StepRecord) -> String {
    format!("stage \"{}\" step {} ({})", record.stage, record.step, record.position())
}
