//! The seismic wall example (`examples/seismic-wall/seismic-wall.toml`): the reinforced wall of
//! examples/reinforced-wall, built, then shaken by 8 s of the synthetic record at 0.2 g.
//!
//! Reference: docs/verification.md §15.5. Shaking-table tests of reduced-scale geosynthetic walls
//! (El-Emam & Bathurst, Geotextiles and Geomembranes 25 (2007) 33–49) and the seismic design
//! method of AASHTO LRFD §11.10.7.2 agree on the direction of what shaking does to such a wall:
//! the face moves out and stays out, and every layer's load grows during the shaking (the
//! design adds an inertial increment to each layer's static load) and keeps part of the growth
//! after it. Goals: the face's permanent displacement outward (−x) and every grid's largest
//! tension at the end of the shaking above its static value; each grid in balance (its two faces
//! carry what is applied to it: nothing) at the end of the shaking; the report's Shaking section
//! giving every grid and the face's final displacement as the run's last time step has it.

mod common;

use geoslip::analysis::Collect;
use geoslip::model::Model;
use std::path::Path;

#[test]
fn the_shaken_wall_moves_out_and_its_grids_keep_more_load() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/seismic-wall/seismic-wall.toml");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let out = std::env::temp_dir().join(format!("geoslip-seismic-wall-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut c = Collect::default();
    geoslip::output::run_and_write(&model, &out, &Default::default(), &mut c).unwrap_or_else(|e| panic!("{e}"));
    let last_of = |stage: &str| c.steps.iter().filter(|(rec, _)| rec.stage == stage).last().unwrap();
    let (_, before) = last_of("surcharge");
    let (end_record, end) = last_of("earthquake");
    assert_eq!(end_record.time.map(|t| (t - 8.0).abs() < 1e-9), Some(true), "the shaking runs its 8 s");
    assert_eq!(c.steps.last().unwrap().0.stage, "after the shaking");

    // the face's mean x displacement: outward is −x
    let face: Vec<usize> = model.node_sets["face"].clone();
    let mean_ux = |r: &geoslip::analysis::results::StepResults| {
        face.iter().map(|&n| r.displacement_vector[2 * n]).sum::<f64>() / face.len() as f64
    };
    let moved = mean_ux(end) - mean_ux(before);
    assert!(moved < -0.01, "the face moved {moved} m in x over the shaking");

    // each grid's largest tension, before and after the shaking
    let t_max = |r: &geoslip::analysis::results::StepResults, k: usize| {
        let y = 0.6 * k as f64 - 0.3;
        r.bar_forces.iter().filter(|b| (b.midpoint[1] - y).abs() < 1e-6).map(|b| b.axial_force).fold(f64::MIN, f64::max)
    };
    let mut total = 0.0;
    for k in 1..=10 {
        let (static_load, after) = (t_max(before, k), t_max(end, k));
        assert!(after > static_load, "grid-{k}: T_max {after:.3} kN/m after the shaking, {static_load:.3} before");
        total += after;
    }
    for b in &end_record.balance {
        let carried = b.interface_force[0].hypot(b.interface_force[1]);
        assert!(carried < 1e-6 * total, "{}: the interfaces carry a net {carried:e} kN/m", b.interface);
    }

    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let shaking = report.split("## Shaking").nth(1).expect("the report's Shaking section");
    for k in 1..=10 {
        assert!(shaking.contains(&format!("| grid-{k} |")), "grid-{k} in the Shaking section");
    }
    let line = shaking.lines().find(|l| l.starts_with("| face |")).expect("the face's row");
    let stated: f64 = line.split('|').nth(4).unwrap().trim().parse().unwrap();
    assert!((stated - mean_ux(end)).abs() < 1e-5, "the report's final ux {stated} m against {} m", mean_ux(end));
    let _ = std::fs::remove_dir_all(&out);
}
