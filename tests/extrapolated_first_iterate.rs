//! The extrapolated first iterate (`extrapolation = "linear"`): the same answers in fewer iterations.
//!
//! Reference: docs/verification.md §2 (progressive slip of an elastic bar on an
//! elastic–perfectly plastic interface, e.g. Sobhi & Wu 1996): with the slip front at s_f from the
//! head, P(s_f) = n_f·τmax·[s_f + tanh(α(L−s_f))/α] and
//! u_head(s_f) = u_y + T_e·s_f/EA + n_f·τmax·s_f²/(2·EA), T_e = (n_f·τmax/α)·tanh(α(L−s_f)).
//!
//! Goal: with the extrapolated first iterate, every step of the pull (EA = 1000 kN/m, Ks = 2000
//! kN/m³, L = 1 m, n_f = 2, τmax = 5 kPa, 40 bar elements, 24 steps to 9 mm, past full slip) lies on
//! the closed-form curve within 0.5 % of the pull, on every backend, in fewer iterations than from
//! the last converged state; on the elastic pull-out box of issue #15 (large slip, re-association,
//! a point crossing the front face) the head force of every step agrees with the run without
//! extrapolation to 1e-6 relative (the convergence tolerances are 1e-9), in fewer iterations.
//!
//! ```text
//!   rigid soil //////////////////////////
//!   P <-- o----o----o-- … --o----o        slip zone growing from the head
//!   rigid soil //////////////////////////
//! ```

mod common;

use common::slip::progressive::{at_slip_front as closed_form, ALPHA, EA, KS, L, NF, TAU};
use common::slip::{bar_in_rigid_soil, pullout_curve};
use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::{Extrapolation, ReassociationRule, ShearLawSpec};

/// The closed form's pull at head displacement `u`: elastic below first slip (P = EA·α·tanh(αL)·u),
/// the slip front found by bisection up to full slip, n_f·τmax·L beyond.
fn pull_at(u: f64) -> f64 {
    let u_y = TAU / KS;
    if u <= u_y {
        return NF * TAU * (ALPHA * L).tanh() / ALPHA * u / u_y;
    }
    if u >= closed_form(L).0 {
        return NF * TAU * L;
    }
    let (mut low, mut high) = (0.0, L);
    for _ in 0..80 {
        let mid = 0.5 * (low + high);
        if closed_form(mid).0 < u {
            low = mid;
        } else {
            high = mid;
        }
    }
    closed_form(0.5 * (low + high)).1
}

fn iterations(c: &geoslip::analysis::Collect) -> usize {
    c.steps.iter().map(|(r, _)| r.iterations).sum()
}

#[test]
fn every_step_of_a_progressive_slip_lies_on_the_closed_form_in_fewer_iterations() {
    let law = ShearLawSpec::Coulomb { shear_stiffness: KS, cohesion: TAU, friction_angle: 0.0 };
    let file = bar_in_rigid_soil(L, 40, EA, law, 0.009, 24, ReassociationRule::None);
    let mut extrapolated = file.clone();
    extrapolated.analysis.extrapolation = Extrapolation::Linear;
    let plain = common::run(&common::model(&file, "progressive-slip.toml"), Backend::Auto);
    let model = common::model(&extrapolated, "progressive-slip-extrapolated.toml");
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        for (u, p) in pullout_curve(&model, &c).into_iter().skip(1) {
            let exact = pull_at(u);
            assert!(
                (p - exact).abs() < 0.005 * exact,
                "{backend:?}: at u = {u:.5} m, P = {p:.5} against the closed form {exact:.5}"
            );
        }
        assert!(
            iterations(&c) < iterations(&plain),
            "{backend:?}: {} iterations extrapolated, {} from the last converged state",
            iterations(&c),
            iterations(&plain)
        );
    }
}

#[test]
fn the_pullout_box_gives_the_same_head_forces_in_fewer_iterations() {
    let mut file = PullOutBox { pull: 0.02, steps: 20, ..common::issue_pullout_box() }.model();
    file.analysis.freeze_normal_stress = true;
    let plain_model = common::model(&file, "pullout-box.toml");
    let plain = common::run(&plain_model, Backend::Auto);
    file.analysis.extrapolation = Extrapolation::Linear;
    let model = common::model(&file, "pullout-box-extrapolated.toml");
    let c = common::run(&model, Backend::Auto);
    common::assert_same_head_forces((&plain_model, &plain), (&model, &c), 1e-6);
    assert!(iterations(&c) < iterations(&plain), "{} iterations against {}", iterations(&c), iterations(&plain));
    eprintln!("iterations: {} extrapolated, {} without", iterations(&c), iterations(&plain));
}
