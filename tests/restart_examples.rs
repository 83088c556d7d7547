//! Every example, continued from a saved step half-way through, makes the later steps as the
//! example run straight through makes them.
//!
//! Reference: the run itself, uninterrupted (as tests/restart.rs). A saved step holds the whole
//! state (displacements, multipliers, the interfaces' points with their history, the soil's
//! stresses and the stage's progress), so on one backend (faer) every later step must agree with
//! the same iterations, to round-off: not always to the last digit, because where the soil is
//! condensed onto the interface the straight run solves the interface system through updates of a
//! factorisation made increments before (src/linsol/condensed/updated_lu.rs), where the
//! continued run factorises it afresh. Measured: up to 4.3e-12 of a field's largest value
//! (soil-nail, 1.8e-12 in the clay pull-out, 3e-13 or less in the others); the tolerance is 2e-11.
//!
//! The examples: every model file under examples/ that runs as one model. Not here:
//! - `lab-pullout/lab-pullout.toml` is a series of runs (`[series]`), which saves no steps;
//! - `reinforced-wall/reinforced-wall.toml` continues from its last stage in
//!   tests/reinforced_wall_example.rs, on the run that test makes anyway;
//! - `landfill-slope/landfill-slope.toml`: its last stage, a strength-reduction search, is most of
//!   its run and is not saved step by step; a straight run takes minutes in the test profile.
//! - `calibration/direct-shear.toml` is a calibration file, not a model.

mod common;

use common::restart::{assert_steps_within, resume, run_saving, through_file};
use geoslip::linsol::Backend;
use geoslip::model::Model;
use std::path::Path;

const EXAMPLES: [&str; 9] = [
    "annotated-pullout.toml",
    "cyclic-pullout.toml",
    "cyclic-shear-box.toml",
    "paper-block.toml",
    "paper-pullout-clay.toml",
    "pullout-box.toml",
    "soil-nail.toml",
    "embedded-pullout/embedded-pullout.toml",
    "embedded-pullout/embedded-pullout-bearing.toml",
];

#[test]
fn every_example_continued_from_half_way_makes_the_same_later_steps() {
    for name in EXAMPLES {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name);
        let model = Model::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let straight = run_saving(&model, Backend::Faer);
        let n = straight.checkpoints.len();
        assert!(n >= 2, "{name}: {n} saved steps");
        let half = &straight.checkpoints[n / 2];
        let (stage, step) = (half.stage.clone(), half.step);
        let checkpoint = through_file(&straight, &stage, step, &model).unwrap_or_else(|e| panic!("{name}: {e}"));
        let continued = resume(&model, Backend::Faer, checkpoint);
        let worst = assert_steps_within(
            &straight.steps,
            n / 2 + 1,
            &continued,
            &format!("{name} from {stage}:{step}"),
            2e-11,
            true,
        );
        eprintln!("{name} from {stage}:{step}: largest difference {worst:.2e}");
    }
}
