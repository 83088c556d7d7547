//! A Coulomb interface driven through cycles of slip: the dissipated energy per cycle.
//!
//! Reference: docs/verification.md §4 (the Coulomb block: a soil block on a rigid base
//! with the tangential displacement applied to every node, F = τ(d)·A) with the elastic–perfectly
//! plastic law unloaded and reloaded: between ±a the τ–d loop is a parallelogram of height 2τp and
//! width 2(a − τp/Ks), so each cycle dissipates W = 4·τp·A·(a − τp/Ks) (e.g. Kramer 1996, §5.4's
//! bilinear hysteresis loop).
//!
//! Parameters: the 1 m × 0.5 m block of `common::block_on_rigid_base` (A = 1 m), Coulomb base with
//! Ks = 1000 kPa/m, c = 2 kPa, φ = 0 (τp = 2 kPa, τp/Ks = 2 mm) under q = 10 kPa; a `history`
//! stage drives d = factor × 10 mm from 0 to +a, then three times round −a and back to +a, in 1 mm steps (every
//! corner of the loop on a step, so the trapezoidal ∮F·dd is exact). Goal: W of each cycle to 1e-9,
//! the force ±τp·A at every reversal, six reversals reported, on every backend.

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::ShearLawSpec;

const KS: f64 = 1000.0;
const TAU_P: f64 = 2.0;
const A: f64 = 0.01;

#[test]
fn each_cycle_dissipates_four_tau_p_times_a_less_the_elastic_slip() {
    let mut file = common::block_on_rigid_base(
        ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: TAU_P, friction_angle: 0.0 },
        10.0,
        A,
        vec![1.0],
    );
    let cycle = [[1.0, 1.0], [2.0, -1.0], [3.0, 1.0]];
    file.stages[1].history = Some(
        [[0.0, 0.0]].into_iter().chain((0..3).flat_map(|k| cycle.map(|[t, f]| [t + 3.0 * k as f64, f]))).collect(),
    );
    file.stages[1].history_increment = Some(0.1);
    let model = common::model(&file, "cyclic-block.toml");
    let exact = 4.0 * TAU_P * 1.0 * (A - TAU_P / KS);
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        // (d, F) at every step of the history, from the stage's start
        let mut path = vec![(0.0, 0.0)];
        let mut reversals = 0;
        for (record, step) in c.steps.iter().filter(|(r, _)| r.stage_index == 1) {
            let f: f64 = model.node_sets["block"].iter().map(|&n| step.reaction_vector[2 * n]).sum();
            path.push((A * record.load_factor, f));
            if record.reversal {
                reversals += 1;
                assert!((f.abs() - TAU_P).abs() < 1e-9 * TAU_P, "{backend:?}: F = {f} at a reversal");
            }
        }
        assert_eq!(reversals, 6, "{backend:?}: +a, −a, +a, −a, +a, −a reverse; the last +a ends the stage");
        // the cycles: from +a (step 10) round to +a again, every 40 steps
        for k in 0..3 {
            let from = 10 + 40 * k;
            let w: f64 = path[from..=from + 40].windows(2).map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0)).sum();
            assert!((w - exact).abs() < 1e-9 * exact, "{backend:?}, cycle {}: W = {w}, expected {exact}", k + 1);
        }
    }
}
