//! When to rewrite the files that are written whole and grow with the run: `results.xdmf` (an
//! entry a kept step), `results.pvd`, `history.csv` and `summary.json` (a record a step). Rewritten
//! at every step, a run of n steps writes them n²/2 entries over: a small model pulled in 2000
//! steps spent 64 of its 73 s on them. They are rewritten at every step while that is cheap
//! against the steps, and once it is not, only when the run has gone on for `SPACING` times what
//! the last rewrite took: together they then cost at most about 1/`SPACING` of the run, however
//! many steps it has. At the end of a run they are always written.
//!
//! All four are rewritten at the same steps (the index after `results.h5` is flushed, the others
//! after it), so a run killed at any moment leaves them listing the same whole steps; the steps
//! after their last rewrite are in `results.h5` (flushed every step) but not yet listed.

use std::time::{Duration, Instant};

/// A rewrite is due once the run has gone on for this many times what the last one took.
pub const SPACING: u32 = 20;

/// The last rewrite of the files a [`Pace`] keeps: when it ended and what it took.
#[derive(Debug, Default)]
pub struct Pace {
    last: Option<(Instant, Duration)>,
}

impl Pace {
    /// Whether the files are due for a rewrite: never written, or last written at least
    /// [`SPACING`] times as long ago as that rewrite took.
    pub fn due(&self) -> bool {
        self.due_at(Instant::now())
    }

    fn due_at(&self, now: Instant) -> bool {
        match self.last {
            None => true,
            Some((ended, took)) => now.saturating_duration_since(ended) >= took * SPACING,
        }
    }

    /// A rewrite that took `took` has just ended.
    pub fn rewritten(&mut self, took: Duration) {
        self.last = Some((Instant::now(), took));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rewrite_is_due_first_and_then_after_spacing_times_what_the_last_took() {
        let mut pace = Pace::default();
        assert!(pace.due(), "never written");
        pace.rewritten(Duration::from_millis(10));
        let (ended, _) = pace.last.unwrap();
        assert!(!pace.due_at(ended + Duration::from_millis(199)));
        assert!(pace.due_at(ended + Duration::from_millis(200)));
        // a free rewrite is due at once
        pace.rewritten(Duration::ZERO);
        assert!(pace.due());
    }
}
