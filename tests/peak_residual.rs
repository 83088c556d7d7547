//! Peak then residual: the strength drops from τp to τr once the peak is passed (the paper's
//! Fig. 2).
//!
//! Reference: docs/verification.md §3. With a residual zone of length s_f from the head,
//! P(s_f) = n_f·τr·s_f + (n_f·τp/α)·tanh(α(L − s_f)); its maximum, when cosh(αL) > sqrt(τp/τr), is at
//! s* = L − arccosh(sqrt(τp/τr))/α: P_max = n_f·τr·s* + (n_f·τp/α)·sqrt(1 − τr/τp). After the peak
//! the response snaps back; under displacement control it drops to the residual n_f·τr·L.
//!
//! Parameters (the reference's test): EA = 1000 kN/m, Ks = 2000 kN/m³, L = 1 m, n_f = 2 (αL = 2),
//! cohesive strengths τp = 5 kPa, τr = 2.5 kPa (τp/τr = 2), 50 bar elements, rigid soil, small slip.
//! Goal: P_max within 1 % (the discretisation error is first order in h, about +0.8 % here), the
//! residual to solver precision.

mod common;

use common::slip::{bar_in_rigid_soil, pullout_curve};
use geoslip::linsol::Backend;
use geoslip::model::file::{ReassociationRule, ShearLawSpec};

#[test]
fn peak_and_residual_pullout_forces_match_the_closed_form() {
    let (tp, tr, alpha, nf, l) = (5.0f64, 2.5f64, 2.0f64, 2.0f64, 1.0f64);
    let s_star = l - (tp / tr).sqrt().acosh() / alpha;
    let p_max = nf * tr * s_star + nf * tp / alpha * (1.0 - tr / tp).sqrt();
    let law = ShearLawSpec::PeakResidual {
        shear_stiffness: 2000.0,
        cohesion: tp,
        friction_angle: 0.0,
        residual_cohesion: tr,
        residual_friction_angle: 0.0,
    };
    for backend in Backend::available() {
        let file = bar_in_rigid_soil(l, 50, 1000.0, law.clone(), 0.02, 100, ReassociationRule::None);
        let model = common::model(&file, "peak-residual.toml");
        let c = common::run(&model, backend);
        let curve = pullout_curve(&model, &c);
        let peak = curve.iter().map(|&(_, p)| p).fold(f64::MIN, f64::max);
        let err = (peak - p_max) / p_max;
        assert!(err.abs() < 0.01, "{backend:?}: P_max = {peak} vs {p_max} ({err:+.4})");
        let (_, last) = *curve.last().unwrap();
        let residual = nf * tr * l;
        assert!((last - residual).abs() < 1e-8 * residual, "{backend:?}: residual {last} vs {residual}");
        assert!(c.last().unwrap().interface_points.iter().filter(|p| p.face != "slit").all(|p| p.post_peak));
    }
}
