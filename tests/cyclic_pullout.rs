//! A cyclic pull-out: examples/cyclic-pullout.toml, the box of examples/pullout-box.toml with its
//! grid pulled and pushed ±5 mm three times.
//!
//! Reference: the dense reference solver (every backend must give its answers). At ±5 mm the grid
//! does not slide over its whole length (first slip at u_y = σn·tan φ/Ks = 1.2 mm, the whole length
//! would slide at about 16 mm: docs/verification.md §2), so no closed form gives the loop; it must close
//! on itself (the same force at each return after the first cycle) and resist the motion both ways.
//!
//! Model: the example (1.0 m × 0.6 m box, 20 × 6 quad4, the grid over 0.8 m, EA = 1000 kN/m,
//! q = 50 kPa) with a Coulomb interface (Ks = 20 000 kPa/m, c = 0, φ = 25°) instead of its linear one,
//! and its pull-out stage given as a history: the head to −5 mm (out), +5 mm (in), three times, in
//! 0.5 mm steps. Goal: the same answers on every backend to 1e-10 of each quantity's scale; a
//! closed force–displacement loop (the force at each return to −5 mm within 1 % of the last); the
//! reversals reported; the report's pull-out plot drawn.

mod common;

use geoslip::analysis::Collect;
use geoslip::linsol::Backend;
use std::path::Path;

fn cyclic_model() -> geoslip::model::Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cyclic-pullout.toml");
    geoslip::model::Model::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn head_force(model: &geoslip::model::Model, c: &Collect) -> Vec<(f64, f64)> {
    let head = &model.node_sets["grid.head"];
    c.steps
        .iter()
        .filter(|(r, _)| r.stage_index == 1)
        .map(|(r, s)| {
            let f: f64 = head.iter().map(|&n| s.reaction_vector[2 * n]).sum();
            (-0.005 * r.load_factor, f)
        })
        .collect()
}

#[test]
fn every_backend_draws_the_same_closed_loops() {
    let model = cyclic_model();
    let reference = common::run(&model, Backend::Dense);
    let loop_ref = head_force(&model, &reference);
    assert_eq!(loop_ref.len(), 10 + 6 * 20, "10 steps out, then six half-cycles of 20");
    let reversals: Vec<f64> = reference.steps.iter().filter(|(r, _)| r.reversal).map(|(r, _)| r.load_factor).collect();
    assert_eq!(reversals, vec![1.0, -1.0, 1.0, -1.0, 1.0, -1.0]);
    // the force at −5 mm (pulled out) at each return: the loop closes
    let out: Vec<f64> = [10, 50, 90, 130].iter().map(|&k| loop_ref[k - 1].1).collect();
    // (the first return follows the first loading from rest, not a loop; between the later returns
    // the force differs by 4e-5 of itself, measured; 2e-4 is five times that)
    for w in out.windows(2).skip(1) {
        assert!((w[1] - w[0]).abs() < 2e-4 * w[0].abs(), "the force at −5 mm: {out:?}");
    }
    // the force resists the motion: one sign pulled out, the other pushed in (at +5 mm, step 30)
    assert!(out.iter().all(|&f| f.signum() == out[0].signum()), "{out:?}");
    assert!(loop_ref[29].1.signum() == -out[0].signum(), "{loop_ref:?}");
    let scale = out[0].abs();
    for backend in Backend::available().into_iter().filter(|b| *b != Backend::Dense) {
        let other = head_force(&model, &common::run(&model, backend));
        for ((d, a), (_, b)) in loop_ref.iter().zip(&other) {
            assert!((a - b).abs() < 1e-10 * scale, "{backend:?} at {d}: {b} against {a}");
        }
    }
    // the run's report draws the loops
    let out_dir = tempfile::tempdir().unwrap();
    geoslip::output::run_and_write(&model, out_dir.path(), &Default::default(), &mut Collect::default()).unwrap();
    assert!(out_dir.path().join("pullout.png").is_file());
    let summary = std::fs::read_to_string(out_dir.path().join("summary.json")).unwrap();
    assert_eq!(summary.matches("the loading history reverses").count(), 6, "{summary}");
}
