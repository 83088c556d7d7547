//! The seismic liner example (`examples/seismic-liner/seismic-liner.toml`): the cover's permanent
//! slip on a peak–residual liner under the synthetic record, between Newmark's rigid sliding
//! block's at the peak and at the residual strength.
//!
//! Reference: docs/verification.md §15.3 (Newmark's block on an inclined plane, s̈ = κ·(a − a_y)
//! while it slides, a_y = g·tan(φ − β)), integrated here on the example's own record. A rigid block
//! with the peak's yield acceleration slides least; one with the residual's, from the start, most;
//! the cover, whose interface keeps only the residual once it has slipped past its peak, slides in
//! between. Goal: the run's permanent slip within those bounds, and the report's Shaking section
//! stating it.

mod common;

use geoslip::analysis::Collect;
use geoslip::model::Model;
use std::path::Path;

/// Newmark's block down a plane inclined at `beta` degrees, friction angle `phi`, under the
/// acceleration `drive` towards its foot (midpoint rule, 0.1 ms).
fn newmark(drive: &dyn Fn(f64) -> f64, phi: f64, beta: f64, g: f64, duration: f64) -> f64 {
    let a_y = g * (phi - beta).to_radians().tan();
    let kappa = (phi - beta).to_radians().cos() / phi.to_radians().cos();
    let step = 1e-4;
    let (mut v, mut d, mut t) = (0.0f64, 0.0, 0.0);
    while t < duration {
        let a = drive(t + step / 2.0);
        let dv = if v > 0.0 || a > a_y { kappa * (a - a_y) * step } else { 0.0 };
        let next = (v + dv).max(0.0);
        d += 0.5 * (v + next) * step;
        v = next;
        t += step;
    }
    d
}

#[test]
fn the_cover_slides_between_newmarks_blocks_at_peak_and_residual_strength() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/seismic-liner/seismic-liner.toml");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let out = std::env::temp_dir().join(format!("geoslip-seismic-liner-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut c = Collect::default();
    geoslip::output::run_and_write(&model, &out, &Default::default(), &mut c).unwrap_or_else(|e| panic!("{e}"));
    let mean_slip = |r: &geoslip::analysis::results::StepResults| {
        let slips: Vec<f64> = r.interface_points.iter().filter(|p| p.interface == "liner").map(|p| p.slip).collect();
        slips.iter().sum::<f64>() / slips.len() as f64
    };
    let before =
        c.steps.iter().filter(|(rec, _)| rec.stage == "cover placed").last().map(|(_, r)| mean_slip(r)).unwrap();
    let end = c.steps.iter().filter(|(rec, _)| rec.time.is_some()).last().map(|(_, r)| mean_slip(r)).unwrap();
    // the slave line runs down the slope and its slip counts towards its first node: up
    let slip = -(end - before);

    let dynamic = model.stages.iter().find_map(|s| s.dynamic.as_ref()).unwrap();
    let ground = &dynamic.base_motion[0].1;
    let beta = (1.0f64 / 3.0).atan().to_degrees();
    let drive = |t: f64| -ground.at(t);
    let peak = newmark(&drive, 24.0, beta, dynamic.gravity, dynamic.duration);
    let residual = newmark(&drive, 20.0, beta, dynamic.gravity, dynamic.duration);
    assert!(peak > 0.0, "the record slides the block even at the peak strength");
    assert!(
        peak < slip && slip < residual,
        "the cover slid {slip} m; Newmark's block {peak} m at peak, {residual} m at residual"
    );

    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let shaking = report.split("## Shaking").nth(1).expect("the report's Shaking section");
    let line = shaking.lines().find(|l| l.starts_with("| liner |")).expect("the liner's row in the Shaking section");
    let stated: f64 = line.split('|').nth(3).unwrap().trim().parse().unwrap();
    assert!(
        (stated + slip).abs() < 1e-5,
        "the report's permanent slip {stated} m against the run's {slip} m down the slope"
    );
    let _ = std::fs::remove_dir_all(&out);
}
