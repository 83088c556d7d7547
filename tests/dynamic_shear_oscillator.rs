//! One soil element in simple shear as a single-degree-of-freedom oscillator: its free vibration
//! after a base pulse, integrated by the trapezoidal rule (HHT with α = 0).
//!
//! Reference: docs/verification.md §15.1. A 1 m × 1 m quad4 element, every y held, the base
//! fixed: its top moves as one DOF with k = G·w/h, m = ρ·w·h/4 per top node lumped (ω² = 2G/(ρh²))
//! or 6·ρwh/36 consistent (ω² = 3G/(ρh²)); damping c/m = a0 + a1·ω². The trapezoidal rule's
//! free response obeys x_{n+1} = b1·x_n + b2·x_{n−1} exactly, with (Hughes 1987, §9.3; from the
//! eigenvalues (1 + hμ/2)/(1 − hμ/2) of the rule, μ the roots of μ² + 2ξωμ + ω² = 0):
//!
//! b1 = (2 − Ω²/2)/(1 + ξΩ + Ω²/4),   b2 = −(1 − ξΩ + Ω²/4)/(1 + ξΩ + Ω²/4),   Ω = ω·h.
//!
//! So the period (b1 = 2 cos ω̄h when ξ = 0) and the decay (−b2 = e^(−2ξ̄ω̄h)) measured from the run
//! check the mass, the damping and the integration together, to round-off. A bar along the top,
//! whose nodes move as one, adds its mass to m. Goal: b1 and b2 within 1e-11 on every backend
//! (measured: 6e-14).

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;

const G: f64 = 10_000.0;
const RHO: f64 = 2.0;
const DT: f64 = 0.002;

fn oscillator(mass: Lumping, damping: Option<RayleighDamping>) -> ModelFile {
    // a triangular pulse, then free vibration
    let pulse = vec![[0.0, 0.0], [0.01, 1.0], [0.02, 0.0]];
    let shaking = common::dynamics::shaking_in_x(DT, 0.3, 0.0, damping, mass, pulse);
    common::dynamics::shear_column(1.0, 1.0, 1, G, RHO, shaking, 1e-12)
}

/// The least-squares b1, b2 of the top's free response (after the pulse).
fn recurrence(model: &geoslip::model::Model, backend: Backend) -> (f64, f64) {
    let c = common::run(model, backend);
    let top = model.mesh.nodes.iter().position(|n| n.x == [1.0, 1.0]).unwrap();
    let x: Vec<f64> = c.steps.iter().map(|(_, r)| r.displacement_vector[2 * top]).collect();
    let times: Vec<f64> = c.steps.iter().map(|(rec, _)| rec.time.unwrap()).collect();
    assert!((times[0] - DT).abs() < 1e-15 && (times[times.len() - 1] - 0.3).abs() < 1e-12, "{times:?}");
    // the normal equations of x[n+1] = b1·x[n] + b2·x[n−1] over the free response
    let first = (0.02 / DT).round() as usize + 1;
    let (mut s11, mut s12, mut s22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for n in first..x.len() - 1 {
        let (a, b, y) = (x[n], x[n - 1], x[n + 1]);
        s11 += a * a;
        s12 += a * b;
        s22 += b * b;
        r1 += a * y;
        r2 += b * y;
    }
    let det = s11 * s22 - s12 * s12;
    ((r1 * s22 - r2 * s12) / det, (s11 * r2 - s12 * r1) / det)
}

fn check(mass: Lumping, omega: f64, damping: Option<RayleighDamping>, xi: f64) {
    check_model(&oscillator(mass, damping), mass, omega, xi);
}

/// The run of `file` against the trapezoidal rule's recurrence at ω and ξ.
fn check_model(file: &ModelFile, mass: Lumping, omega: f64, xi: f64) {
    let model = common::model(file, "shear-oscillator.toml");
    let w = omega * DT;
    let denominator = 1.0 + xi * w + w * w / 4.0;
    let b1 = (2.0 - w * w / 2.0) / denominator;
    let b2 = -(1.0 - xi * w + w * w / 4.0) / denominator;
    for backend in Backend::available() {
        let (m1, m2) = recurrence(&model, backend);
        assert!((m1 - b1).abs() < 1e-11, "{mass:?} ξ={xi} {backend:?}: b1 = {m1}, expected {b1}");
        assert!((m2 - b2).abs() < 1e-11, "{mass:?} ξ={xi} {backend:?}: b2 = {m2}, expected {b2}");
    }
}

#[test]
fn lumped_mass_vibrates_at_the_trapezoidal_rules_period() {
    check(Lumping::Lumped, (2.0 * G / RHO).sqrt(), None, 0.0);
}

#[test]
fn consistent_mass_vibrates_at_the_trapezoidal_rules_period() {
    check(Lumping::Consistent, (3.0 * G / RHO).sqrt(), None, 0.0);
}

/// A bar along the top, of total mass m_b (its weight per unit length over g, times its length):
/// its two nodes move as one (no stretch), so it adds m_b to the oscillator's mass,
/// ω² = k/(m + m_b) with m = ρwh/2 lumped or ρwh/3 consistent; the bar's own consistent matrix,
/// m_b/6·[2 1; 1 2] in x, sums to m_b over two nodes that move together.
#[test]
fn a_bars_mass_adds_to_the_oscillators() {
    let bar_mass = 1.5;
    for (mass, soil_mass) in [(Lumping::Lumped, RHO / 2.0), (Lumping::Consistent, RHO / 3.0)] {
        let mut file = oscillator(mass, None);
        let top: Vec<u64> = file.nodes.iter().filter(|n| n.2 == 1.0).map(|n| n.0).collect();
        file.bars.push(BarRow { id: 100, nodes: [top[0], top[1]], material: "grid".into() });
        let grid = ReinforcementMaterial {
            axial_stiffness: 1000.0,
            tension_only: false,
            rupture_strength: None,
            weight: Some(bar_mass * common::dynamics::G),
        };
        file.materials.reinforcement.insert("grid".into(), grid);
        check_model(&file, mass, (G / (soil_mass + bar_mass)).sqrt(), 0.0);
    }
}

/// Rayleigh damping with both coefficients: c/m = a0 + a1·ω² gives ξ = (a0 + a1ω²)/(2ω).
#[test]
fn rayleigh_damping_decays_at_its_ratio() {
    let omega = (2.0 * G / RHO).sqrt();
    let (a0, a1) = (4.0, 0.0006);
    let damping =
        RayleighDamping { ratio: None, frequencies: None, mass_coefficient: Some(a0), stiffness_coefficient: Some(a1) };
    check(Lumping::Lumped, omega, Some(damping), (a0 + a1 * omega * omega) / (2.0 * omega));
}

/// The energy ½·m·v² + ½·k·x² of the free vibration (m = 2·ρwh/4 over the two top nodes, k = G·w/h):
/// the trapezoidal rule conserves it exactly in a linear undamped system (Hughes 1987, §9.1.2),
/// and HHT with α < 0 dissipates it.
#[test]
fn the_trapezoidal_rule_keeps_the_energy_and_hht_dissipates_it() {
    for (alpha, conserved) in [(0.0, true), (-0.1, false)] {
        let pulse = vec![[0.0, 0.0], [0.01, 1.0], [0.02, 0.0]];
        let shaking = common::dynamics::shaking_in_x(DT, 0.3, alpha, None, Lumping::Lumped, pulse);
        let model = common::model(&common::dynamics::shear_column(1.0, 1.0, 1, G, RHO, shaking, 1e-12), "energy.toml");
        let c = common::run(&model, Backend::Faer);
        let top = model.mesh.nodes.iter().position(|n| n.x == [1.0, 1.0]).unwrap();
        let (m, k) = (2.0 * RHO / 4.0, G);
        let energy: Vec<f64> = c
            .steps
            .iter()
            .map(|(_, r)| r.motion.as_ref().unwrap())
            .zip(&c.steps)
            .filter(|(motion, _)| motion.time > 0.02 + 1e-9)
            .map(|(motion, (_, r))| {
                let (v, x) = (motion.velocity[2 * top], r.displacement_vector[2 * top]);
                0.5 * m * v * v + 0.5 * k * x * x
            })
            .collect();
        let first = energy[0];
        assert!(first > 0.0);
        if conserved {
            // (measured: 2.3e-14)
            let drift = energy.iter().map(|e| (e - first).abs()).fold(0.0, f64::max) / first;
            assert!(drift < 1e-12, "α = 0: the energy drifts by {drift:e} of itself");
        } else {
            // (measured: down 0.52 % after 4.5 periods; up at most 1.9e-4 within one, the rule's own
            // energy not being exactly this quadratic form)
            let highest = energy.iter().copied().fold(0.0, f64::max);
            assert!(highest < first * (1.0 + 5e-4), "α = {alpha}: the energy rose to {} of itself", highest / first);
            let last = energy[energy.len() - 1];
            assert!(last < 0.998 * first, "α = {alpha}: the energy kept {} of itself", last / first);
        }
    }
}
