//! A uniform, damped, elastic soil column on a rigid base under harmonic base acceleration: the
//! steady-state amplification of the surface's acceleration.
//!
//! Reference: docs/verification.md §15.2 (Kramer, Geotechnical Earthquake Engineering, 1996,
//! §7.2.1): |u_surface/u_base| = |1/cos(ωH/V*)|, V* = Vs·√(1 + 2iξ), for a Kelvin–Voigt soil; with
//! stiffness-proportional damping C = a1·K, 2ξ = a1·ω. The first resonance is at f1 = Vs/4H.
//!
//! The model: H = 10 m in 20 quad4 elements 0.5 m square, every y held (one-dimensional shear),
//! Vs = 100 m/s (G = 20 MPa, ρ = 2 t/m³), f1 = 2.5 Hz, ξ = 5 % at f1, lumped mass, HHT α = 0,
//! Δt = 5 ms, 12 s of shaking; the amplitude is fitted over the last 2 s.
//!
//! The discrete answer is known exactly too: the lumped column is a chain whose waves obey
//! ω² = (4G*/(ρΔz²))·sin²(kΔz/2), so |1/cos(k_d·H)| with k_d = (2/Δz)·asin(ωΔz/(2V*)); and the
//! trapezoidal rule's steady response to a sampled harmonic input is the semi-discrete one at
//! ω' = (2/Δt)·tan(ωΔt/2). Goals: the run within 1e-3 of that discrete answer at every frequency
//! of the sweep (measured: 1.9e-4 at f1, the transient left after 12 s; 1e-5 elsewhere), and the
//! discrete answer within 1.5 % of Kramer's (measured: 0.08 % at f1, 1.0 % at 3·f1: the mesh's
//! dispersion and the time step's period error).

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;
use nalgebra::Complex;
use std::f64::consts::PI;

const H: f64 = 10.0;
const ELEMENTS: usize = 20;
const VS: f64 = 100.0;
const RHO: f64 = 2.0;
const XI: f64 = 0.05;
const DT: f64 = 0.005;
const DURATION: f64 = 12.0;
const FITTED: f64 = 2.0;

fn f1() -> f64 {
    VS / (4.0 * H)
}

/// Rayleigh's a1 giving ξ at f1.
fn a1() -> f64 {
    2.0 * XI / (2.0 * PI * f1())
}

fn column(frequency: f64) -> ModelFile {
    let omega = 2.0 * PI * frequency;
    let steps = (DURATION / DT).round() as usize;
    let samples = (0..=steps).map(|k| [k as f64 * DT, (omega * k as f64 * DT).sin()]).collect();
    let damping =
        RayleighDamping { ratio: None, frequencies: None, mass_coefficient: None, stiffness_coefficient: Some(a1()) };
    let shaking = common::dynamics::shaking_in_x(DT, DURATION, 0.0, Some(damping), Lumping::Lumped, samples);
    common::dynamics::shear_column(H / ELEMENTS as f64, H, ELEMENTS, RHO * VS * VS, RHO, shaking, 1e-10)
}

/// Kramer's |1/cos(ωH/V*)| at angular frequency `omega`.
fn continuum(omega: f64) -> f64 {
    let v_star = Complex::new(1.0, a1() * omega).sqrt() * VS;
    (Complex::new(1.0, 0.0) / (Complex::new(omega * H, 0.0) / v_star).cos()).norm()
}

/// The lumped chain's amplification under the trapezoidal rule at angular frequency `omega`.
fn discrete(omega: f64) -> f64 {
    let warped = 2.0 / DT * (omega * DT / 2.0).tan();
    let v_star = Complex::new(1.0, a1() * warped).sqrt() * VS;
    let dz = H / ELEMENTS as f64;
    let k = (Complex::new(warped * dz / 2.0, 0.0) / v_star).asin() * (2.0 / dz);
    (Complex::new(1.0, 0.0) / (k * H).cos()).norm()
}

/// The surface's absolute acceleration amplitude over the last `FITTED` seconds, by least
/// squares on cos ωt and sin ωt.
fn surface_amplification(frequency: f64, backend: Backend) -> f64 {
    let model = common::model(&column(frequency), "soil-column.toml");
    let c = common::run(&model, backend);
    let top = model.mesh.nodes.iter().position(|n| n.x == [0.0, H]).unwrap();
    let omega = 2.0 * PI * frequency;
    let (mut cc, mut cs, mut ss, mut rc, mut rs) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (_, r) in &c.steps {
        let m = r.motion.as_ref().expect("a dynamic step has its motion");
        if m.time < DURATION - FITTED - 1e-9 {
            continue;
        }
        let a = m.acceleration[2 * top] + m.ground[0];
        let (co, si) = ((omega * m.time).cos(), (omega * m.time).sin());
        (cc, cs, ss, rc, rs) = (cc + co * co, cs + co * si, ss + si * si, rc + co * a, rs + si * a);
    }
    let det = cc * ss - cs * cs;
    let (a, b) = ((rc * ss - rs * cs) / det, (cc * rs - cs * rc) / det);
    a.hypot(b)
}

#[test]
fn amplification_follows_the_closed_form_through_a_sweep() {
    for ratio in [0.5, 1.0, 1.5, 2.0, 3.0] {
        let f = ratio * f1();
        let omega = 2.0 * PI * f;
        let (exact, chain) = (continuum(omega), discrete(omega));
        assert!(
            (chain - exact).abs() < 0.015 * exact,
            "f = {f} Hz: the discrete column's {chain} and Kramer's {exact} differ by more than the stated error"
        );
        for backend in if ratio == 1.0 { Backend::available() } else { vec![Backend::Faer] } {
            let run = surface_amplification(f, backend);
            assert!(
                (run - chain).abs() < 1e-3 * chain,
                "f = {f} Hz, {backend:?}: amplification {run}, the discrete column's {chain} (Kramer: {exact})"
            );
        }
    }
}

/// Every step of the elastic column has the same matrix, K + c·M at a constant Δt: the run
/// factorises it once, and each step costs the solves of its iterations (docs/dynamics.md).
#[test]
fn a_constant_time_step_factorises_once() {
    let model = common::model(&column(f1()), "soil-column.toml");
    let mut sink = geoslip::analysis::Collect::default();
    let options = geoslip::analysis::RunOptions::for_model(&model, Backend::Faer);
    let stats = geoslip::analysis::run(&model, &options, &mut sink).unwrap_or_else(|e| panic!("{e}"));
    let steps = sink.steps.len();
    assert_eq!(steps, (DURATION / DT).round() as usize);
    assert_eq!(stats.solver.factorizations, 1, "{steps} steps");
    assert!(stats.solver.solves >= steps, "{} solves for {steps} steps", stats.solver.solves);
}
