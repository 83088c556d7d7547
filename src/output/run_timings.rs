//! A run's timings put together for `summary.json`: the phases its program timed before the
//! result writer existed, the output folder's opening, and the run's own counts, in the order
//! they happen (`timing.rs` holds the types; docs/results.md says what each phase is).

use crate::analysis::RunStats;
use crate::model::Model;
use crate::timing::{Phase, Timings};
use std::time::Instant;

/// The timings of a run of `model`: from the process's start with the phases its program timed
/// before the result writer existed and the model's loading (`process`, when the program gave
/// them), from the writer's creation `created` otherwise; then the writer's folder opening, the
/// run's counts in `stats`, and its end since `finishing`.
pub(super) fn of_run(
    process: Option<&(Instant, Vec<Phase>)>,
    created: Instant,
    model: &Model,
    opening_seconds: f64,
    stats: &RunStats,
    finishing: Instant,
) -> Timings {
    let (started, mut phases) = match process {
        Some((started, before)) => (*started, before.iter().chain(&model.load_times).cloned().collect()),
        None => (created, Vec::new()),
    };
    let s = stats;
    phases.push(Phase::new("output folder opened", opening_seconds));
    phases.push(Phase::new("run set-up: soil, element matrices, solver", s.setup_seconds));
    phases.push(Phase::new("stage set-up: soil placed, water, K0, contacts, DOFs, loads", s.stage_setup_seconds));
    let increments = [
        ("increments: interface rows, laws, active set, re-association", s.interface_seconds),
        ("increments: assembly", s.solver.assembly_seconds),
        ("increments: symbolic analysis", s.solver.analyse_seconds),
        ("increments: sparse factorisation", s.solver.factorize_seconds),
        ("increments: sparse solves", s.solver.solve_seconds),
        ("increments: interface system: dense factorisations", s.solver.dense_factorization_seconds),
        ("increments: interface system: BiCGSTAB iterations", s.solver.dense_iteration_seconds),
        (
            "increments: interface system: solves, updates, products",
            s.solver.dense_seconds - s.solver.dense_factorization_seconds - s.solver.dense_iteration_seconds,
        ),
        ("increments: solution checks", s.solver.check_seconds),
        ("increments: out-of-balance force", s.residual_seconds),
        ("increments: step results, handed to the writer", s.output_seconds),
        ("increments: saved steps (restart), copied and handed over", s.checkpoint_seconds),
    ];
    let counted: f64 = increments.iter().map(|(_, seconds)| seconds).sum();
    phases.extend(increments.into_iter().map(|(phase, seconds)| Phase::new(phase, seconds)));
    phases.push(Phase::new("increments: the rest", s.increments_seconds - counted));
    phases.push(Phase::since("results finished: last files written, figures, report", finishing));
    Timings::new(started.elapsed().as_secs_f64(), phases)
}
