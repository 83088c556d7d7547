//! Progressive slip of an elastic reinforcement on an elastic–perfectly plastic interface.
//!
//! Reference: docs/verification.md §2 (the shear-lag bar with a slip zone growing from the
//! head; e.g. Sobhi & Wu 1996). With the slip front at s_f from the head,
//! P(s_f) = n_f·τmax·[s_f + tanh(α(L−s_f))/α] and
//! u_head(s_f) = u_y + T_e·s_f/EA + n_f·τmax·s_f²/(2·EA), T_e = (n_f·τmax/α)·tanh(α(L−s_f)).
//! Whole length slipping: P_ult = n_f·τmax·L.
//!
//! Parameters (the reference's test): EA = 1000 kN/m, Ks = 2000 kN/m³, L = 1 m, n_f = 2 → α = 2,
//! αL = 2; 20 bar elements; a cohesive interface, τmax = c = 5 kPa (φ = 0, so σn does not matter);
//! small slip (no re-association), as the closed form assumes a fixed embedded length. Goal: P and
//! u_head within 0.5 %, P_ult to solver precision.
//!
//! ```text
//!   rigid soil //////////////////////////
//!   P <-- o----o----o-- … --o----o        20 bars, slip zone growing from the head
//!   rigid soil //////////////////////////
//! ```

mod common;

use common::slip::progressive::{at_slip_front as closed_form, ALPHA, EA, KS, NF, TAU};
use common::slip::{bar_in_rigid_soil, pullout_curve};
use geoslip::linsol::Backend;
use geoslip::model::file::{ReassociationRule, ShearLawSpec};

#[test]
fn slip_front_positions_and_the_ultimate_pull_match_the_closed_form() {
    let law = ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: TAU, friction_angle: 0.0 };
    for backend in Backend::available() {
        for sf in [0.25, 0.5] {
            let (u, p) = closed_form(sf);
            let file = bar_in_rigid_soil(1.0, 20, EA, law.clone(), u, 8, ReassociationRule::None);
            let model = common::model(&file, "progressive-slip.toml");
            let c = common::run(&model, backend);
            let (u_num, p_num) = *pullout_curve(&model, &c).last().unwrap();
            assert!((u_num - u).abs() < 1e-12);
            let err = (p_num - p) / p;
            assert!(err.abs() < 0.005, "{backend:?}, s_f = {sf}: P = {p_num} vs {p} ({err:+.4})");
        }
        // beyond full slip (u_y + n_f·τ·L²/(2EA) = 7.5 mm) the pull is n_f·τ·L exactly
        let file = bar_in_rigid_soil(1.0, 20, EA, law.clone(), 0.012, 6, ReassociationRule::None);
        let model = common::model(&file, "progressive-slip.toml");
        let c = common::run(&model, backend);
        let (_, p_num) = *pullout_curve(&model, &c).last().unwrap();
        assert!((p_num - NF * TAU * 1.0).abs() < 1e-8 * NF * TAU, "{backend:?}: P_ult = {p_num}");
        // every point slides at the strength, and the forces balance the pull at every step
        let (rec, last) = c.steps.last().unwrap();
        assert!(last.interface_points.iter().filter(|p| p.face != "slit").all(|p| (p.tau - TAU).abs() < 1e-9));
        for (rec, _) in &c.steps {
            for b in &rec.balance {
                assert!(b.mismatch < 1e-8, "{backend:?}: balance {b:?}");
            }
        }
        assert_eq!(rec.sliding_points, 2 * 21);
    }
}

#[test]
fn first_slip_happens_at_the_closed_form_load() {
    // P_y = n_f·τ·tanh(αL)/α at u_head = u_y = τ/Ks
    let law = ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: TAU, friction_angle: 0.0 };
    let u_y = TAU / KS;
    let file = bar_in_rigid_soil(1.0, 20, EA, law, u_y, 1, ReassociationRule::None);
    let model = common::model(&file, "first-slip.toml");
    let c = common::run(&model, Backend::Faer);
    let (_, p) = *pullout_curve(&model, &c).last().unwrap();
    let p_y = NF * TAU * (2.0f64).tanh() / ALPHA;
    assert!(((p - p_y) / p_y).abs() < 0.005, "P_y = {p} vs {p_y}");
}
