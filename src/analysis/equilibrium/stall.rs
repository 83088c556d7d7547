//! An increment whose iterations have stopped making progress.
//!
//! Where the iterate cycles (a soil point switching between loading and unloading, or between
//! elastic and plastic, and back, with the same two residuals for ever) or wanders without getting
//! closer to equilibrium, the rest of `max_iterations` changes nothing: the increment is cut back
//! as soon as its out-of-balance force has not fallen below [`PROGRESS`] of its value at the last
//! progress in `stall_iterations` iterations. Slow but steady convergence (a constant-stiffness
//! iteration, a linearly converging Newton one) makes progress within a few iterations and goes
//! on; an iterate whose residual is already within the tolerance (waiting for the interface points
//! or the displacement correction to settle) is never stalled.

/// The share of the residual at the last progress that a residual must fall below to count as
/// progress.
pub const PROGRESS: f64 = 0.99;

/// How far the iterations have got: the residual at the last progress and the iterations since.
pub(super) struct Progress {
    /// The iterations without progress after which the increment is given up (0: never).
    limit: usize,
    /// The residual of the last iteration that made progress (the smallest so far).
    mark: f64,
    since: usize,
}

impl Progress {
    pub fn new(limit: usize) -> Progress {
        Progress { limit, mark: f64::INFINITY, since: 0 }
    }

    /// Record an iteration's out-of-balance force `residual` against the convergence threshold
    /// (both in force units). Returns the iterations without progress when the increment has
    /// stalled.
    pub fn stalled(&mut self, residual: f64, threshold: f64) -> Option<usize> {
        if residual <= threshold || residual < PROGRESS * self.mark {
            self.since = 0;
            self.mark = self.mark.min(residual);
        } else {
            self.since += 1;
        }
        (self.limit > 0 && self.since >= self.limit).then_some(self.since)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_two_cycle_stalls_after_the_limit() {
        let mut p = Progress::new(30);
        let mut stalled_at = None;
        for i in 0..300 {
            let r = if i % 2 == 0 { 1.650e-3 } else { 1.904e-3 };
            if p.stalled(r, 1e-5).is_some() {
                stalled_at = Some(i);
                break;
            }
        }
        // the first 1.650e-3 is progress; 30 iterations without it after
        assert_eq!(stalled_at, Some(30));
    }

    #[test]
    fn slow_linear_convergence_does_not_stall() {
        let mut p = Progress::new(30);
        let mut r = 4.1e-5;
        for _ in 0..2000 {
            assert!(p.stalled(r, 1e-9).is_none());
            r *= 0.995;
        }
    }

    #[test]
    fn a_residual_within_the_tolerance_never_stalls() {
        let mut p = Progress::new(3);
        for _ in 0..100 {
            assert!(p.stalled(1e-7, 1e-6).is_none());
        }
    }

    #[test]
    fn a_limit_of_zero_never_stalls() {
        let mut p = Progress::new(0);
        for _ in 0..100 {
            assert!(p.stalled(1.0, 1e-6).is_none());
        }
    }
}
