//! The reinforced-wall example runs to the end and gives the working-stress picture that
//! instrumented geosynthetic walls show.
//!
//! Reference: the simplified method's layer loads K_a·(γz + q)·S_v (AASHTO LRFD §11.10.6.2) are a
//! design bound: measured working-stress tensions in geosynthetic-reinforced walls fall well below
//! them in total (Allen, Bathurst, Holtz, Walters & Lee, Can. Geotech. J. 40 (2003) 976–994, the
//! data behind the K-stiffness method). Goal: the model of examples/reinforced-wall builds in its
//! twelve stages, every grid is placed and in tension, the sum of the layers' T_max lies below the
//! simplified method's, and each grid's force balance closes (what its interfaces carry equals what
//! is applied to its nodes); continued from a saved step of its last stage, the run makes its last
//! step again to 1e-6 of each field (MUMPS's Scotch ordering differs from one analysis to the next).

mod common;

use geoslip::linsol::Backend;
use geoslip::model::Model;
use std::path::Path;

#[test]
fn the_wall_is_built_and_its_grids_carry_less_than_the_simplified_method() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/reinforced-wall/reinforced-wall.toml");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let saved = common::restart::run_saving(&model, Backend::Auto);
    let c = &saved.steps;
    let (record, last) = c.steps.last().unwrap();
    assert_eq!(record.stage, "surcharge");
    let ka = (std::f64::consts::FRAC_PI_4 - 34f64.to_radians() / 2.0).tan().powi(2);
    let (mut fe, mut simplified) = (0.0, 0.0);
    for k in 1..=10 {
        let y = 0.6 * k as f64 - 0.3;
        let bars: Vec<_> = last.bar_forces.iter().filter(|b| (b.midpoint[1] - y).abs() < 1e-6).collect();
        assert_eq!(bars.len(), 15, "grid-{k} has its 15 bars");
        assert!(bars.iter().all(|b| b.state != "not placed"), "grid-{k} was placed");
        let t_max = bars.iter().map(|b| b.axial_force).fold(f64::MIN, f64::max);
        assert!(t_max > 0.0, "grid-{k} is in tension");
        fe += t_max;
        simplified += ka * (18.0 * (6.0 - y) + 10.0) * 0.6;
    }
    assert!(fe < simplified, "sum of T_max {fe:.2} kN/m against the simplified method's {simplified:.2} kN/m");
    // no load is applied to the grids: what their two faces carry must cancel
    for b in &record.balance {
        let carried = (b.interface_force[0].powi(2) + b.interface_force[1].powi(2)).sqrt();
        assert!(carried < 1e-6 * fe, "{}: the interfaces carry a net {carried:e} kN/m", b.interface);
    }
    // continued from the surcharge stage's first step, the last step is made again as it was
    // (tests/restart_examples.rs does the other examples)
    let n = saved.checkpoints.len();
    let first = &saved.checkpoints[n - 2];
    assert_eq!(first.stage, "surcharge");
    let checkpoint =
        common::restart::through_file(&saved, "surcharge", first.step, &model).unwrap_or_else(|e| panic!("{e}"));
    let continued = common::restart::resume(&model, Backend::Auto, checkpoint);
    // (on MUMPS with Scotch, whose ordering is not the same from one analysis to the next: the
    // continued run's factors are not the straight run's, so the two agree to the iterations'
    // tolerance, 1e-7, not to the last digit; tests/restart_examples.rs checks the last digits on
    // faer)
    let worst = common::restart::assert_steps_within(c, n - 1, &continued, "the wall from surcharge:1", 1e-6, false);
    eprintln!("the wall from surcharge:1: largest difference {worst:.2e}");
}
