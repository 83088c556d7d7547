//! Where a run's time goes, phase by phase, over the whole process: `summary.json`'s `timings` and
//! the table `geoslip bench` prints. Each phase is timed where it runs, exclusive of the others, and
//! the phases are listed in the order they happen; what no phase accounts for is `other`, the
//! process's wall time less their sum.

use std::time::{Duration, Instant};

/// One phase's time [s].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Phase {
    pub phase: String,
    pub seconds: f64,
}

impl Phase {
    pub fn new(phase: impl Into<String>, seconds: f64) -> Phase {
        Phase { phase: phase.into(), seconds }
    }

    /// The phase that began at `started` and ends now.
    pub fn since(phase: impl Into<String>, started: Instant) -> Phase {
        Phase::new(phase, started.elapsed().as_secs_f64())
    }
}

/// A process's wall time and its phases.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Timings {
    /// From the process's start (or, where that is not known, the start of the first phase) to
    /// the last summary.
    pub wall_seconds: f64,
    pub phases: Vec<Phase>,
    /// The wall time less the phases' sum.
    pub other_seconds: f64,
}

impl Timings {
    /// The timings of `phases` over `wall_seconds`.
    pub fn new(wall_seconds: f64, phases: Vec<Phase>) -> Timings {
        let timed: f64 = phases.iter().map(|p| p.seconds).sum();
        Timings { wall_seconds, other_seconds: wall_seconds - timed, phases }
    }

    /// `other` as a share of the wall time.
    pub fn other_share(&self) -> f64 {
        if self.wall_seconds > 0.0 {
            self.other_seconds / self.wall_seconds
        } else {
            0.0
        }
    }

    /// The timings as a table in Markdown: each phase, its seconds and its share of the wall time.
    pub fn table(&self) -> String {
        let share = |s: f64| if self.wall_seconds > 0.0 { 100.0 * s / self.wall_seconds } else { 0.0 };
        let mut t = String::from("| phase | s | % |\n|---|---:|---:|\n");
        for p in &self.phases {
            t.push_str(&format!("| {} | {:.3} | {:.1} |\n", p.phase, p.seconds, share(p.seconds)));
        }
        t.push_str(&format!("| other | {:.3} | {:.1} |\n", self.other_seconds, share(self.other_seconds)));
        t.push_str(&format!("| **wall** | **{:.3}** | 100 |\n", self.wall_seconds));
        t
    }
}

/// When the process started, as `main` finds it.
#[derive(Debug, Clone, Copy)]
pub struct ProcessStart {
    pub at: Instant,
    /// The time from the process's start to `main` [s] (zero where /proc does not tell it).
    pub before_main: f64,
}

impl ProcessStart {
    /// Called first thing in `main`.
    pub fn now() -> ProcessStart {
        let now = Instant::now();
        let age = process_age().unwrap_or_default();
        ProcessStart { at: now.checked_sub(age).unwrap_or(now), before_main: age.as_secs_f64() }
    }

    /// The process's start as a phase.
    pub fn phase(&self) -> Phase {
        Phase::new("process start: program loaded", self.before_main)
    }
}

/// The time this process ran before now and `main`: from its start (as the kernel gives it, in
/// clock ticks of 10 ms, `/proc/self/stat`'s 22nd field against `/proc/uptime`) to now. `None`
/// where /proc does not tell it.
pub fn process_age() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // the command name (field 2) is in parentheses and may hold spaces: fields count after it
    let after_name = &stat[stat.rfind(')')? + 1..];
    let start_ticks: f64 = after_name.split_whitespace().nth(19)?.parse().ok()?;
    let uptime: f64 = std::fs::read_to_string("/proc/uptime").ok()?.split_whitespace().next()?.parse().ok()?;
    // USER_HZ is 100 on every Linux architecture geoslip builds on
    let age = uptime - start_ticks / 100.0;
    (age.is_finite() && age >= 0.0).then(|| Duration::from_secs_f64(age))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn other_is_the_wall_time_less_the_phases() {
        let t = Timings::new(10.0, vec![Phase::new("a", 6.0), Phase::new("b", 3.5)]);
        assert_eq!(t.other_seconds, 0.5);
        assert_eq!(t.other_share(), 0.05);
        assert!(t.table().contains("| other | 0.500 | 5.0 |"), "{}", t.table());
    }

    #[test]
    fn a_process_is_younger_than_the_machine_and_older_than_zero() {
        // this test process has run for at least as long as it took to get here, and not for days
        let age = process_age().expect("/proc on Linux").as_secs_f64();
        assert!((0.0..86_400.0).contains(&age), "{age}");
    }
}
