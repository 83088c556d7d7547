//! Which steps' fields a run writes (`--keep`): every step, the event steps only, or every N-th
//! step with the events. `history.csv`, `summary.json`, the report and the plots always cover every
//! step; only the field files (`results.h5`/`.xdmf`, the `.vtu` files, the per-step CSV files) are
//! thinned.
//!
//! The event steps are the first and the last step of each stage, the step where slip starts, where
//! the soil first yields, where every interface point in contact slides, where a prescribed
//! target's reaction falls from its peak, and the step of that peak. Whether a step is the last of
//! its stage, or a peak, shows only later (a strength-reduction stage has no set number of steps; a
//! peak is a peak once the reaction falls), so the writer holds such steps back ([`HeldSteps`]) and
//! writes them once they prove to be kept; the last step of the run is written when the run ends,
//! also when it fails.

use crate::analysis::results::StepResults;
use crate::analysis::StepRecord;
use std::sync::Arc;

/// Which steps' fields are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum KeptSteps {
    /// Every step.
    #[default]
    Every,
    /// The event steps only (see the module's documentation).
    Events,
    /// Every N-th step of the run (its step number, counted over all stages from 1, a multiple of
    /// N), the event steps and the last step.
    EveryNth(usize),
}

impl KeptSteps {
    /// Whether step number `time` (1, 2, … over the run) is kept, given whether it is an event step.
    pub fn keeps(self, time: usize, event: bool) -> bool {
        match self {
            KeptSteps::Every => true,
            KeptSteps::Events => event,
            KeptSteps::EveryNth(n) => event || time % n == 0,
        }
    }

    /// Whether steps may be left out (and so held back until they prove to be kept).
    pub fn thins(self) -> bool {
        !matches!(self, KeptSteps::Every | KeptSteps::EveryNth(1))
    }
}

impl std::str::FromStr for KeptSteps {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "every" => Ok(KeptSteps::Every),
            "events" => Ok(KeptSteps::Events),
            _ => match s.parse::<usize>() {
                Ok(n) if n >= 1 => Ok(KeptSteps::EveryNth(n)),
                _ => Err(format!("expected every, events or a whole number N ≥ 1 (every N-th step), found {s:?}")),
            },
        }
    }
}

impl std::fmt::Display for KeptSteps {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            KeptSteps::Every => write!(f, "every"),
            KeptSteps::Events => write!(f, "events"),
            KeptSteps::EveryNth(n) => write!(f, "{n}"),
        }
    }
}

/// A step held back in memory until it proves to be kept.
#[derive(Clone)]
pub struct HeldStep {
    /// The step's number over the run (1, 2, …).
    pub time: usize,
    pub record: StepRecord,
    pub results: Arc<StepResults>,
}

/// The steps a thinned run holds back: the latest step not written (kept if it turns out to be the
/// last of its stage or of the run), and for each prescribed target the step of its peak reaction
/// so far (kept once the reaction falls from it).
#[derive(Default)]
pub struct HeldSteps {
    pub latest: Option<HeldStep>,
    pub peaks: Vec<Option<HeldStep>>,
}

impl HeldSteps {
    pub fn new(targets: usize) -> Self {
        HeldSteps { latest: None, peaks: vec![None; targets] }
    }
}

#[cfg(test)]
mod tests {
    use super::KeptSteps;

    #[test]
    fn the_keep_option_reads_every_events_and_a_step_count() {
        assert_eq!("every".parse(), Ok(KeptSteps::Every));
        assert_eq!("events".parse(), Ok(KeptSteps::Events));
        assert_eq!("5".parse(), Ok(KeptSteps::EveryNth(5)));
        assert!("0".parse::<KeptSteps>().is_err());
        assert!("some".parse::<KeptSteps>().is_err());
        assert_eq!(KeptSteps::EveryNth(5).to_string(), "5");
    }

    #[test]
    fn every_fifth_step_keeps_the_multiples_of_five_and_the_events() {
        let kept: Vec<usize> = (1..=12).filter(|&t| KeptSteps::EveryNth(5).keeps(t, t == 7)).collect();
        assert_eq!(kept, [5, 7, 10]);
        assert!(!KeptSteps::Events.keeps(5, false));
        assert!(KeptSteps::Every.keeps(3, false));
    }
}
