//! `freeze_normal_stress` per stage: σn is frozen at the start of the stage that asks for it.
//!
//! Reference: the definition (DESIGN §1: with σn frozen, the shear law of each point uses the σn it
//! had when the stage started) and vertical equilibrium of a laterally confined, weightless box
//! under a surcharge q (docs/verification.md §5): after the surcharge the mean σn on the reinforcement is
//! q. A stage that froze σn before the surcharge would freeze 0 and leave the faces the cohesion
//! alone: that run must say so.
//!
//! Model: the issue's pull-out box (2 m × 1 m weightless block, E = 10 MPa, ν = 0.3, 20 × 10 quad4,
//! a grid over 1.6 m at mid-height, EA = 500 kN/m, Coulomb faces Ks = 2000 kPa/m, φ = 30°), q = 20
//! kPa in a first stage, the head pulled 10 mm in 5 steps in the second.

mod common;

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::ModelFile;

fn pullout_box() -> ModelFile {
    PullOutBox { pull: 0.01, steps: 5, ..common::issue_pullout_box() }.model()
}

fn run(file: &ModelFile) -> (Collect, Vec<String>) {
    let model = common::model(file, "frozen-sigma.toml");
    let mut sink = Collect::default();
    let stats = analysis::run(&model, &RunOptions::for_model(&model, Backend::available()[0]), &mut sink)
        .unwrap_or_else(|e| panic!("{e}"));
    (sink, stats.warnings.texts())
}

#[test]
fn a_stage_freezes_the_normal_stress_it_starts_with() {
    let mut file = pullout_box();
    file.stages[1].freeze_normal_stress = Some(true);
    let (c, warnings) = run(&file);
    assert!(warnings.iter().all(|w| !w.contains("freezes σn")), "{warnings:?}");
    let stage_steps = |name: &'static str| c.steps.iter().filter(move |(r, _)| r.stage == name);
    // the surcharge stage is not frozen: nothing slides under the surcharge alone
    assert!(stage_steps("surcharge").all(|(r, _)| r.sliding_points == 0));
    let (_, loaded) = stage_steps("surcharge").last().unwrap();
    let embedded: Vec<_> = loaded.interface_points.iter().filter(|p| p.face != "slit" && p.tributary > 0.0).collect();
    let mean = embedded.iter().map(|p| p.sigma_n * p.tributary).sum::<f64>()
        / embedded.iter().map(|p| p.tributary).sum::<f64>();
    assert!(common::relative_error(mean, 20.0) < 0.05, "mean σn after the surcharge {mean} kPa against q = 20");
    // every pull step's points use the σn they had when the pull-out stage started
    let frozen: Vec<(u64, String, f64)> =
        loaded.interface_points.iter().map(|p| (p.slave_node, p.face.clone(), p.sigma_n)).collect();
    for (r, s) in stage_steps("pull-out") {
        for (p, (node, face, sigma)) in s.interface_points.iter().zip(&frozen) {
            if p.face == "slit" || p.state != "active" {
                continue;
            }
            assert_eq!((p.slave_node, &p.face), (*node, face));
            assert!(
                (p.sigma_n - sigma).abs() < 1e-12 * 20.0,
                "step {}: node {node} σn {} against {sigma}",
                r.step,
                p.sigma_n
            );
        }
    }
}

#[test]
fn freezing_before_the_surcharge_is_reported() {
    let mut file = pullout_box();
    file.analysis.freeze_normal_stress = true;
    let (_, warnings) = run(&file);
    assert!(
        warnings.iter().any(|w| w.contains("stage \"surcharge\" freezes σn") && w.contains("cohesion alone")),
        "{warnings:?}"
    );
    assert!(warnings.iter().all(|w| !w.contains("stage \"pull-out\"")), "{warnings:?}");
}
