//! The landfill-slope example runs to the end: the lined slope is built, and its factor of safety
//! lies between the two-wedge values at the critical interface's residual and peak friction.
//!
//! Reference: Koerner & Soong, Geotextiles and Geomembranes 16 (1998) 1–36, the two-wedge method
//! (docs/verification.md §7). The cover of examples/landfill-slope slides on its
//! geotextile / geomembrane interface (peak 24°, residual 16°): with no geosynthetic tension the
//! two-wedge FS is 1.457 at peak and 0.991 at residual. Construction takes that interface past its
//! peak where it slides, and the anchored geotextile and geogrid add a little: goal, FS between the
//! two, the slip on that interface and on no other, every layer placed, none ruptured, and each
//! layer's force balance closed.

mod common;

use geoslip::linsol::Backend;
use geoslip::model::Model;
use std::path::Path;

#[test]
fn the_lined_slope_is_built_and_its_factor_of_safety_lies_between_residual_and_peak() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/landfill-slope/landfill-slope.toml");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let c = common::run(&model, Backend::Auto);
    let fs = c.factors_of_safety.last().expect("the strength-reduction stage reports FS");
    assert!(fs.failed_at.is_some(), "the search bracketed FS: {:?}", fs.trials);
    assert!(0.991 < fs.value && fs.value < 1.457, "FS {:.3} between the residual and peak two-wedge values", fs.value);

    let built = &c.steps.iter().rev().find(|(r, _)| r.strength_factor.is_none()).expect("construction steps").1;
    assert_eq!(c.steps.iter().rev().find(|(r, _)| r.strength_factor.is_none()).unwrap().0.stage, "cover on the crest");
    assert!(
        built.bar_forces.iter().all(|b| b.state != "not placed" && b.state != "ruptured"),
        "every layer placed and whole"
    );
    let largest_slip =
        |face: &str| built.interface_points.iter().filter(|p| p.face == face).fold(0.0f64, |m, p| m.max(p.slip.abs()));
    let weak = largest_slip("geotextile on geomembrane");
    assert!(weak > 5e-3, "the geotextile slides on the geomembrane: {weak:.4} m");
    for face in ["upper", "geogrid on geotextile", "lower"] {
        let slip = largest_slip(face);
        assert!(slip < 0.25 * weak, "face {face} slips {slip:.4} m, less than the weak interface's {weak:.4} m");
    }
    // no load is applied to the sheets: what their faces carry must cancel
    let record = &c.steps.iter().rev().find(|(r, _)| r.strength_factor.is_none()).unwrap().0;
    assert!(!record.balance.is_empty(), "the stack's balance is checked");
    for b in &record.balance {
        let carried = (b.interface_force[0].powi(2) + b.interface_force[1].powi(2)).sqrt();
        assert!(carried < 1e-3, "{}: the stack's faces carry a net {carried:e} kN/m", b.interface);
    }
}
