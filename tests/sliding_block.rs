//! Newmark's rigid sliding block: a stiff soil block on a Coulomb interface over a rigid base,
//! horizontal or inclined, that shakes horizontally.
//!
//! Reference: docs/verification.md §15.3 (Newmark 1965, "Effects of earthquakes on dams and
//! embankments", Géotechnique 15(2); the inclined plane as in Kramer 1996, §10.6.1.2). A block on
//! a plane inclined at β with friction tan φ slides down it while the horizontal ground
//! acceleration towards the slope exceeds the yield acceleration a_y = g·tan(φ − β), and until
//! its velocity relative to the plane is zero again; while it slides, s̈ = κ·(a − a_y) along the
//! plane, κ = cos(φ − β)/cos φ. Under a rectangular pulse of A > a_y lasting t0 the permanent slip
//! is d = ½·κ·(A − a_y)·t0²·A/a_y; under a half-sine pulse it is the same equation integrated
//! here, in the test's own code, on a step a hundred times finer than the run's. Below a_y the
//! block does not slide. The pseudo-static method gives the same a_y: under the weight times kh
//! towards the foot, FS = tan φ·(cos β − kh·sin β)/(sin β + kh·cos β), which is 1 at
//! kh = tan(φ − β).
//!
//! The model: a 1 m × 0.25 m block of 4 × 2 quad4 elements (low enough that its base stays in
//! contact), E = 1 GPa, γ = 20 kN/m³, on a rigid base; the interface Coulomb with c = 0, φ = 30°,
//! Ks = 10⁷ kPa/m (stiff: under a sudden pulse, a softer spring lets the block overshoot and start
//! sliding with a velocity of order A/ω, ω² = Ks·B/m, which the rigid block does not have);
//! gravity first (a static stage), then the base shaken in x with Δt = 1 ms, HHT α = −0.3.
//! Goal: the slip within 0.5 % of Newmark's (measured: 0.05 % and 0.04 % under the rectangle,
//! horizontal and at β = 10°; 0.15 % and 0.20 % under the half sine), and below 5·10⁻⁶ m under
//! 0.8·a_y (measured: 6·10⁻⁷ m).

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;

use common::dynamics::G;
const PHI: f64 = 30.0;
const DT: f64 = 0.001;
const DURATION: f64 = 0.5;

/// The yield acceleration on a plane inclined at `beta` (degrees).
fn yield_acceleration(beta: f64) -> f64 {
    (PHI - beta).to_radians().tan() * G
}

/// κ = cos(φ − β)/cos φ: the relative acceleration along the plane per unit of ground
/// acceleration beyond a_y.
fn kappa(beta: f64) -> f64 {
    (PHI - beta).to_radians().cos() / PHI.to_radians().cos()
}

/// The block and its base, turned by `beta` degrees clockwise (the plane falls towards +x).
fn block_on_shaking_base(beta: f64, samples: Vec<[f64; 2]>) -> ModelFile {
    let block = Block::new(SolidKind::Quad4, (0.0, 0.0), (1.0, 0.25), (4, 2), "soil", 1, 1);
    let mut nodes = block.nodes.clone();
    let base: Vec<u64> = (0..=12).map(|i| 100 + i as u64).collect();
    for (i, id) in base.iter().enumerate() {
        nodes.push(NodeRow(*id, -0.5 + 0.25 * i as f64, 0.0));
    }
    let (s, c) = (-beta).to_radians().sin_cos();
    let turned = |x: f64, y: f64| (c * x - s * y, s * x + c * y);
    for n in &mut nodes {
        (n.1, n.2) = turned(n.1, n.2);
    }
    let normal = turned(0.0, -1.0);
    let mut node_sets = BTreeMap::new();
    node_sets.insert("block".into(), block.nodes.iter().map(|n| n.0).collect());
    node_sets.insert("base".into(), base.clone());
    let mut soil = BTreeMap::new();
    soil.insert("soil".into(), SoilMaterial::linear_elastic(1.0e6, 0.3, 20.0));
    ModelFile {
        title: "sliding block".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement: BTreeMap::new() },
        nodes,
        elements: block.elements.clone(),
        bars: Vec::new(),
        node_sets,
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        supports: vec![support("base", &[Direction::X, Direction::Y])],
        interfaces: vec![InterfaceSpec {
            name: "base".into(),
            slave: Some(block.row_nodes(0)),
            master: Some(base),
            master_normal: Some([normal.0, normal.1]),
            law: ShearLawSpec::Coulomb { shear_stiffness: 1.0e7, cohesion: 0.0, friction_angle: PHI },
            ..Default::default()
        }],
        stages: vec![
            Stage { name: "weight".into(), loads: vec![LoadSpec::Gravity { factor: 1.0 }], ..Default::default() },
            Stage {
                name: "shaking".into(),
                dynamic: Some(common::dynamics::shaking_in_x(DT, DURATION, -0.3, None, Lumping::Lumped, samples)),
                ..Default::default()
            },
        ],
        analysis: AnalysisSettings { freeze_normal_stress: false, scheme: Scheme::Newton, ..Default::default() },
        mesh: None,
        series: None,
        design: None,
    }
}

/// The block's permanent slip down the plane: its base's mean displacement along the plane
/// (falling towards +x), averaged over the last 0.1 s (the rattle on the springs averages out);
/// less what the weight alone moved it.
fn permanent_slip(beta: f64, samples: Vec<[f64; 2]>, backend: Backend) -> f64 {
    let model = common::model(&block_on_shaking_base(beta, samples), "sliding-block.toml");
    let c = common::run(&model, backend);
    let ids = Block::new(SolidKind::Quad4, (0.0, 0.0), (1.0, 0.25), (4, 2), "soil", 1, 1).row_nodes(0);
    let bottom: Vec<usize> =
        model.node_sets["block"].iter().copied().filter(|&n| ids.contains(&model.mesh.node_id(n))).collect();
    let (s, c_) = (-beta).to_radians().sin_cos();
    let along = |u: &[f64]| bottom.iter().map(|&n| c_ * u[2 * n] + s * u[2 * n + 1]).sum::<f64>() / bottom.len() as f64;
    let static_ = along(&c.steps[0].1.displacement_vector);
    let late: Vec<f64> = c
        .steps
        .iter()
        .filter(|(rec, _)| rec.time.is_some_and(|t| t > DURATION - 0.1))
        .map(|(_, r)| along(&r.displacement_vector))
        .collect();
    late.iter().sum::<f64>() / late.len() as f64 - static_
}

/// Newmark's equation along a plane inclined at `beta` (degrees, falling towards +x) under the
/// horizontal ground acceleration `a_g` (towards +x): with a = −a_g the acceleration that drives
/// the block towards +x (down the plane), s̈ = κ_d·(a − g·tan(φ − β)) while it slides down and
/// s̈ = κ_u·(a + g·tan(φ + β)) while it slides up, κ_d,u = cos(φ ∓ β)/cos φ; it sticks when its
/// velocity returns to zero and −g·tan(φ + β) ≤ a ≤ g·tan(φ − β). Integrated on `step`.
fn newmark_slip(a_g: impl Fn(f64) -> f64, beta: f64, duration: f64, step: f64) -> f64 {
    let (down, up) = (yield_acceleration(beta), yield_acceleration(-beta));
    let (k_down, k_up) = (kappa(beta), kappa(-beta));
    let rate = |a: f64, v: f64| -> f64 {
        if v > 0.0 || (v == 0.0 && a > down) {
            k_down * (a - down)
        } else if v < 0.0 || (v == 0.0 && a < -up) {
            k_up * (a + up)
        } else {
            0.0
        }
    };
    let (mut v, mut d, mut t) = (0.0f64, 0.0, 0.0);
    while t < duration {
        let dv = rate(-a_g(t + step / 2.0), v) * step;
        let next = if v != 0.0 && (v + dv) * v < 0.0 { 0.0 } else { v + dv };
        d += 0.5 * (v + next) * step;
        v = next;
        t += step;
    }
    d
}

/// A rectangular pulse of `a` for `t0` with one-step ramps (the run samples it at its steps).
fn rectangle(a: f64, t0: f64) -> Vec<[f64; 2]> {
    vec![[0.0, 0.0], [DT, a], [t0, a], [t0 + DT, 0.0]]
}

/// A half-sine pulse of amplitude `a` lasting 0.1 s, sampled at the run's steps.
fn half_sine(a: f64) -> Vec<[f64; 2]> {
    let steps = (DURATION / DT).round() as usize;
    let pulse = |t: f64| if t < 0.1 { a * (std::f64::consts::PI * t / 0.1).sin() } else { 0.0 };
    (0..=steps).map(|k| [k as f64 * DT, pulse(k as f64 * DT)]).collect()
}

/// Newmark's closed form under the rectangle, the run's slip on each backend.
fn rectangle_slides_as_closed_form(beta: f64, towards: f64) {
    let a_y = yield_acceleration(beta);
    let (a, t0) = (1.5 * a_y, 0.1);
    let exact = -towards * 0.5 * kappa(beta) * (a - a_y) * t0 * t0 * a / a_y;
    for backend in Backend::available() {
        let slip = permanent_slip(beta, rectangle(towards * a, t0), backend);
        assert!(
            (slip - exact).abs() < 5e-3 * exact.abs(),
            "β = {beta}°, {backend:?}: slip {slip} m, Newmark {exact} m"
        );
    }
}

/// The half sine against Newmark's equation integrated here.
fn half_sine_slides_as_newmarks_equation(beta: f64, towards: f64) {
    let samples = half_sine(towards * 2.0 * yield_acceleration(beta));
    let ground = geoslip::model::ground_motion::GroundMotion::from_samples(&samples, 1.0).unwrap();
    let exact = newmark_slip(|t| ground.at(t), beta, DURATION, DT / 100.0);
    let slip = permanent_slip(beta, samples, Backend::Faer);
    assert!(exact.abs() > 0.005, "the pulse slides the block: {exact}");
    assert!((slip - exact).abs() < 5e-3 * exact.abs(), "β = {beta}°: slip {slip} m, Newmark's equation {exact} m");
}

#[test]
fn a_rectangular_pulse_slides_the_block_by_newmarks_closed_form() {
    rectangle_slides_as_closed_form(0.0, 1.0);
}

#[test]
fn on_a_slope_a_rectangular_pulse_slides_the_block_down_by_newmarks_closed_form() {
    rectangle_slides_as_closed_form(10.0, -1.0);
}

#[test]
fn a_half_sine_pulse_slides_the_block_as_newmarks_equation() {
    half_sine_slides_as_newmarks_equation(0.0, 1.0);
}

#[test]
fn on_a_slope_a_half_sine_pulse_slides_the_block_as_newmarks_equation() {
    half_sine_slides_as_newmarks_equation(10.0, -1.0);
}

#[test]
fn below_the_yield_acceleration_the_block_does_not_slide() {
    for beta in [0.0, 10.0] {
        let slip = permanent_slip(beta, rectangle(-0.8 * yield_acceleration(beta), 0.1), Backend::Faer);
        assert!(slip.abs() < 5e-6, "β = {beta}°: slip {slip} m under 0.8·a_y");
    }
}

/// The pseudo-static method on the block at β = 10°: its weight times kh towards the slope's foot,
/// then the factor of safety by strength reduction of the interface; for the rigid block
/// FS = tan φ·(cos β − kh·sin β)/(sin β + kh·cos β), which is 1 at kh = tan(φ − β), Newmark's
/// yield coefficient.
#[test]
fn a_pseudo_static_force_gives_the_factor_of_safety_of_the_block_on_the_slope() {
    let beta = 10.0f64;
    for kh in [0.0, 0.1, 0.2] {
        let mut file = block_on_shaking_base(beta, vec![[0.0, 0.0], [0.1, 0.0]]);
        file.stages.truncate(1);
        file.stages.push(Stage {
            name: "pseudo-static".into(),
            loads: vec![LoadSpec::PseudoStatic { kh, kv: 0.0 }],
            ..Default::default()
        });
        file.stages.push(Stage {
            name: "factor of safety".into(),
            strength_reduction: Some(StrengthReductionSpec {
                reduce: ReducedStrengths::Interfaces,
                tolerance: Some(1e-5),
                max_factor: Some(5.0),
            }),
            ..Default::default()
        });
        let model = common::model(&file, "sliding-block-pseudo-static.toml");
        let c = common::run(&model, Backend::Faer);
        let fs = c.factors_of_safety[0].value;
        let (b, phi) = (beta.to_radians(), PHI.to_radians());
        let exact = phi.tan() * (b.cos() - kh * b.sin()) / (b.sin() + kh * b.cos());
        assert!((fs - exact).abs() < 3e-5 * exact, "kh = {kh}: FS = {fs}, the closed form {exact}");
    }
    let ky = (PHI - beta).to_radians().tan();
    assert!((yield_acceleration(beta) / G - ky).abs() < 1e-15);
}

/// The results as a user reads them: `motion.csv` records the block at every step, and the report
/// states the interface's permanent slip, which is Newmark's (the interface's slip counts towards
/// the slave line's first node, here −x: the block's slip under a pulse towards +x).
#[test]
fn the_report_and_motion_csv_state_the_permanent_slip() {
    let a_y = yield_acceleration(0.0);
    let (a, t0) = (1.5 * a_y, 0.1);
    let exact = 0.5 * (a - a_y) * t0 * t0 * a / a_y;
    let mut file = block_on_shaking_base(0.0, rectangle(a, t0));
    let top = Block::new(SolidKind::Quad4, (0.0, 0.0), (1.0, 0.25), (4, 2), "soil", 1, 1).row_nodes(2);
    file.node_sets.insert("top".into(), top);
    if let Some(dynamic) = file.stages[1].dynamic.as_mut() {
        dynamic.record = vec!["top".into()];
    }
    let model = common::model(&file, "sliding-block.toml");
    let out = std::env::temp_dir().join(format!("geoslip-sliding-block-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut quiet = geoslip::analysis::Collect::default();
    geoslip::output::run_and_write(&model, &out, &Default::default(), &mut quiet).unwrap();
    let csv = std::fs::read_to_string(out.join("motion.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column =
        |name: &str| header.iter().position(|h| h.starts_with(name)).unwrap_or_else(|| panic!("{name}: {header:?}"));
    let rows: Vec<Vec<f64>> =
        csv.lines().skip(1).map(|l| l.split(',').skip(1).map(|c| c.parse().unwrap()).collect()).collect();
    let (time, slip, top_a) = (column("time") - 1, column("base mean slip") - 1, column("top ax absolute") - 1);
    // a row per time step (a step cut back adds its midpoints), time rising to the duration
    assert!(rows.len() >= (DURATION / DT).round() as usize, "{} rows", rows.len());
    assert!(rows.windows(2).all(|w| w[1][time] > w[0][time]));
    assert!((rows[rows.len() - 1][time] - DURATION).abs() < 1e-12);
    // the block's top rides with it: once it has stopped sliding, its absolute acceleration is the base's
    let last = rows.last().unwrap();
    assert!(last[top_a].abs() < 0.05 * a_y, "the top's acceleration at the end: {}", last[top_a]);
    // (the weight alone does not slide it: the slip before the shaking is zero)
    let permanent = last[slip];
    assert!((permanent - exact).abs() < 5e-3 * exact, "motion.csv: slip {permanent} m, Newmark {exact} m");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let shaking = report.split("## Shaking").nth(1).expect("the report's Shaking section");
    let line = shaking.lines().find(|l| l.starts_with("| base |")).expect("the interface's row in the report");
    let stated: f64 = line.split('|').nth(3).unwrap().trim().parse().unwrap();
    assert!((stated - exact).abs() < 5e-3 * exact, "the report: slip {stated} m, Newmark {exact} m\n{line}");
    assert!(out.join("motion.png").is_file());
    let _ = std::fs::remove_dir_all(&out);
}

/// The work the interface dissipates, Σ over the steps and points of ½(τ₀ + τ₁)·ℓ·Δs (the points'
/// own shear stress, tributary length and slip), against the friction force times the slip:
/// tan φ·W·d with W the block's weight (1 m × 0.25 m × 20 kN/m³ = 5 kN/m) and d Newmark's closed
/// form under the rectangle, on the horizontal base. A rigid block's base slides as one, with
/// τ = tan φ·σn at every point and Σσn·ℓ = W; the springs' elastic work, ½τ²ℓ/Ks, is 10⁻⁷ of it.
/// Goal: within 2·10⁻³ (measured: 5.2·10⁻⁴, the slip's own difference from the closed form).
#[test]
fn the_work_the_interface_dissipates_is_the_friction_force_times_the_slip() {
    let a_y = yield_acceleration(0.0);
    let (a, t0) = (1.5 * a_y, 0.1);
    let slip = 0.5 * (a - a_y) * t0 * t0 * a / a_y;
    let weight = 1.0 * 0.25 * 20.0;
    let expected = PHI.to_radians().tan() * weight * slip;
    let model = common::model(&block_on_shaking_base(0.0, rectangle(a, t0)), "sliding-block.toml");
    let c = common::run(&model, Backend::Faer);
    let mut work = 0.0;
    for pair in c.steps.windows(2) {
        let (before, after) = (&pair[0].1.interface_points, &pair[1].1.interface_points);
        for (p, q) in before.iter().zip(after) {
            assert_eq!(p.slave_node, q.slave_node);
            work += 0.5 * (p.tau * p.tributary + q.tau * q.tributary) * (q.slip - p.slip);
        }
    }
    assert!((work - expected).abs() < 2e-3 * expected, "dissipated {work} kJ/m, tan φ·W·d = {expected} kJ/m");
}
