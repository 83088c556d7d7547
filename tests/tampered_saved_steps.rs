//! A saved step from anyone: a damaged or changed file, or one whose fields point outside the model,
//! is refused with the file and the reason, before a run continues from it; a continuation with a
//! changed `[analysis]` setting is refused, naming the setting.
//!
//! Reference: docs/reliability.md ("saved steps"): every field of a saved step is checked against
//! the model before use, the file carries a CRC-32 of its contents, it inflates to no more than it
//! says and no more than the memory limit allows.
//!
//! The model: the pull-out box of `geoslip::meshgen::PullOutBox` (surcharge, then an 8 mm pull in 4
//! steps) with a Coulomb interface.

mod common;

use geoslip::analysis::{self, Checkpoint, RunOptions};
use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::*;
use geoslip::model::Model;
use geoslip::output::checkpoints::{self, From};
use geoslip::output::OwnedFolder;

use common::Saved;

fn pullout() -> ModelFile {
    PullOutBox {
        nx: 8,
        ny_half: 2,
        law: ShearLawSpec::Coulomb { shear_stiffness: 20_000.0, cohesion: 2.0, friction_angle: 25.0 },
        pull: 0.008,
        steps: 4,
        ..PullOutBox::default()
    }
    .model()
}

fn saved_run(model: &Model) -> Vec<Checkpoint> {
    let mut saved = Saved::default();
    analysis::run(model, &RunOptions::for_model(model, Backend::Faer), &mut saved).unwrap_or_else(|e| panic!("{e}"));
    saved.checkpoints
}

/// The saved step of the pull-out's step 2, changed by `tamper`, written as a run writes it (so
/// its checksum is right) under that step's name, and read back for `model`: the message of the
/// refusal.
fn refusal(model: &Model, saved: &[Checkpoint], tamper: impl FnOnce(&mut Checkpoint)) -> String {
    let mut checkpoint = saved.iter().find(|c| c.stage == "pull-out" && c.step == 2).unwrap().clone();
    tamper(&mut checkpoint);
    // the writer names the file after the fields it holds; the file is then put where step 2's is
    let scratch = tempfile::tempdir().unwrap();
    checkpoints::write(&OwnedFolder::open(scratch.path(), &[]).unwrap(), &checkpoint).unwrap();
    let written = std::fs::read_dir(scratch.path().join("restart")).unwrap().next().unwrap().unwrap().path();
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("restart")).unwrap();
    std::fs::rename(written, dir.path().join("restart/stage-2-step-00002.bin")).unwrap();
    match checkpoints::read(dir.path(), &From { stage: "pull-out".into(), step: 2 }, model, None) {
        Ok(_) => panic!("a tampered saved step was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn fields_that_point_outside_the_model_are_refused_before_use() {
    let model = common::model(&pullout(), "tampered.toml");
    let saved = saved_run(&model);
    // the untampered file is accepted
    let dir = tempfile::tempdir().unwrap();
    common::write_saved_steps(dir.path(), &saved);
    checkpoints::read(dir.path(), &From { stage: "pull-out".into(), step: 2 }, &model, None).unwrap();

    let cases: Vec<(&str, Box<dyn FnOnce(&mut Checkpoint)>, &str)> = vec![
        ("stage index 0 in stage 2's file", Box::new(|c| c.stage_index = 0), "its name says stage 2"),
        ("stage index 2^63", Box::new(|c| c.stage_index = 1 << 63), "past the model's 2 stages"),
        ("a step other than the file's", Box::new(|c| c.step = 3), "its name says stage 2 step 2"),
        (
            "a displacement short",
            Box::new(|c| {
                c.state.u.pop();
            }),
            "u holds",
        ),
        ("a multiplier not a number", Box::new(|c| c.state.lambda[0] = f64::NAN), "lambda[0] is NaN"),
        (
            "a slave node past the mesh",
            Box::new(|c| c.state.interfaces[0].faces[0].points[0].slave = usize::MAX),
            "slave node is not the model's",
        ),
        (
            "a segment past the face",
            Box::new(|c| c.state.interfaces[0].faces[0].points[1].segment = 1 << 40),
            "is past the face's",
        ),
        (
            "mortar weights on a master node past the face",
            Box::new(|c| c.state.interfaces[0].faces[0].points[1].weights = Some(vec![(1 << 30, 1.0)])),
            "mortar weight names master node",
        ),
        (
            "a soil element more",
            Box::new(|c| {
                let extra = c.state.soil.elements()[0].clone();
                let mut all = c.state.soil.elements().to_vec();
                all.push(extra);
                c.state.soil = geoslip::element::soil_state::SoilField::new(all);
            }),
            "soil elements",
        ),
        ("held DOFs short", Box::new(|c| c.held.truncate(3)), "held holds 3 DOFs"),
        ("targets past the stage's", Box::new(|c| c.progress.targets = vec![0.5; 100]), "load factors still to reach"),
        ("an infinite gravity", Box::new(|c| c.gravity = f64::INFINITY), "gravity"),
    ];
    for (what, tamper, expected) in cases {
        let e = refusal(&model, &saved, tamper);
        assert!(e.contains("cannot continue from it") && e.contains(expected), "{what}: {e}");
    }
}

#[test]
fn a_changed_analysis_setting_is_refused_naming_it() {
    let model = common::model(&pullout(), "tampered.toml");
    let saved = saved_run(&model);
    let dir = tempfile::tempdir().unwrap();
    common::write_saved_steps(dir.path(), &saved);
    let mut changed = pullout();
    changed.analysis.reduced_integration = true;
    let changed = common::model(&changed, "changed.toml");
    let e = checkpoints::read(dir.path(), &From { stage: "pull-out".into(), step: 2 }, &changed, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`analysis.reduced_integration` changed"), "{e}");

    let mut tolerance = pullout();
    tolerance.analysis.force_tolerance *= 0.1;
    let tolerance = common::model(&tolerance, "tolerance.toml");
    let e = checkpoints::read(dir.path(), &From { stage: "pull-out".into(), step: 2 }, &tolerance, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`analysis.force_tolerance` changed"), "{e}");
}

#[test]
fn a_damaged_file_a_bomb_and_a_foreign_file_are_refused() {
    let model = common::model(&pullout(), "tampered.toml");
    let saved = saved_run(&model);
    let dir = tempfile::tempdir().unwrap();
    common::write_saved_steps(dir.path(), &saved);
    let path = dir.path().join("restart/stage-2-step-00002.bin");
    let good = std::fs::read(&path).unwrap();
    let read = || {
        checkpoints::read(dir.path(), &From { stage: "pull-out".into(), step: 2 }, &model, Some(64.0))
            .unwrap_err()
            .to_string()
    };

    // one byte of the compressed stream changed
    let mut flipped = good.clone();
    let k = flipped.len() / 2;
    flipped[k] ^= 0x10;
    std::fs::write(&path, &flipped).unwrap();
    let e = read();
    assert!(e.contains("damaged") || e.contains("cannot be inflated") || e.contains("checksum"), "{e}");

    // cut short
    std::fs::write(&path, &good[..good.len() / 3]).unwrap();
    let e = read();
    assert!(e.contains("damaged") || e.contains("cannot be inflated"), "{e}");

    // a header that claims more than the memory limit: refused before anything is inflated
    let mut claims = good.clone();
    claims[16..24].copy_from_slice(&(1u64 << 40).to_le_bytes());
    std::fs::write(&path, &claims).unwrap();
    let e = read();
    assert!(e.contains("it says it holds 1048576.0 MB") && e.contains("64.0 MB"), "{e}");

    // a bomb: 200 MB of zeros deflated to ~200 kB, under a header that says 1 kB
    let mut bomb = geoslip::output::checkpoints::MAGIC.to_vec();
    bomb.extend_from_slice(&1024u64.to_le_bytes());
    bomb.extend_from_slice(&0u32.to_le_bytes());
    let mut deflate = flate2::write::DeflateEncoder::new(bomb, flate2::Compression::best());
    let zeros = vec![0u8; 1 << 20];
    for _ in 0..200 {
        std::io::Write::write_all(&mut deflate, &zeros).unwrap();
    }
    std::fs::write(&path, deflate.finish().unwrap()).unwrap();
    let e = read();
    assert!(e.contains("where it says 1024: it is damaged"), "{e}");

    // not a saved step at all
    std::fs::write(&path, b"stage_index = 0\n").unwrap();
    let e = read();
    assert!(e.contains("not a saved step"), "{e}");
}
