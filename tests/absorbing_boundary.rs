//! Plane waves at normal incidence leaving through Lysmer–Kuhlemeyer dashpots, put in through a
//! compliant base.
//!
//! Reference: docs/verification.md §15.4 (Lysmer & Kuhlemeyer 1969; Joyner & Chen 1975; Kramer,
//! Geotechnical Earthquake Engineering, 1996, §7.2.1). A dashpot ρ·V per unit area takes exactly
//! the traction a plane wave at normal incidence carries (σ = −ρ·V·v), so the wave leaves without
//! reflection; a compliant base loaded by ρ·V·v_o(t), v_o the outcrop velocity (twice the incident
//! wave's), sends the incident wave up. So:
//!
//! - the energy in the soil once the whole pulse is in it is the incident wave's,
//!   E_in = ρ·V·A·∫(v_o/2)² dt;
//! - over a half-space of the soil's own impedance the surface moves as the outcrop, a_o(t − H/V);
//! - once the pulse has gone out again, the energy left is what the boundary reflected.
//!
//! The models: a shear column (S waves, H = 20 m in 40 quad4 elements, every y held apart from
//! the base's, which its dashpots take) on a compliant base; a strip along x (P waves, 20 m in 40
//! elements, every y held apart from its ends') with the motion put in at its left end and an
//! absorbing right end. Vs = 100 m/s, ν = 0.3 (Vp = 187.08 m/s), ρ = 2 t/m³; HHT α = 0 (no
//! numerical damping), Δt = 1 ms; the pulse a_o = A·sin(2πt/T)·sin²(πt/T), T = 0.2 s (its
//! velocity returns to zero): 40 elements to the wavelength at 1/T.
//!
//! Goals, with what was measured (every backend alike):
//! - E once the pulse is in within 1e-3 of E_in (measured: 2.4e-4 short, S and P; constant to
//!   1e-11 while the pulse is inside, as the trapezoidal rule keeps it);
//! - the energy left after the pulse has gone out below 1e-5 of E_in (measured: 2.2e-6 of the S
//!   wave, 1.8e-8 of the P wave);
//! - the surface's acceleration within 5 % of the pulse's peak of a_o(t − H/V) (measured: 1.8 %,
//!   the mesh's dispersion at the pulse's 10 Hz, 20 elements to the wavelength), also as
//!   `motion.csv` records it, in columns that say the motion is absolute.

mod common;

use geoslip::analysis::Collect;
use geoslip::linsol::Backend;
use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use geoslip::model::Model;
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// The column's height [m].
const HEIGHT: f64 = 20.0;
/// The strip's length [m]: longer than the P wave's pulse (Vp·T = 37.4 m).
const STRIP: f64 = 60.0;
/// The elements' side [m].
const SIDE: f64 = 0.5;
const VS: f64 = 100.0;
const NU: f64 = 0.3;
const RHO: f64 = 2.0;
const DT: f64 = 0.001;
const PULSE: f64 = 0.2;
const PEAK: f64 = 1.0;

/// The outcrop acceleration a_o(t) and velocity v_o(t).
fn outcrop(t: f64) -> (f64, f64) {
    if !(0.0..=PULSE).contains(&t) {
        return (0.0, 0.0);
    }
    let x = PI * t / PULSE;
    // ∫ sin 2x·sin²x dx = sin⁴x / 2
    (PEAK * (2.0 * x).sin() * x.sin().powi(2), PEAK * PULSE / PI * x.sin().powi(4) / 2.0)
}

fn shear_modulus() -> f64 {
    RHO * VS * VS
}

fn constrained_modulus() -> f64 {
    2.0 * shear_modulus() * (1.0 - NU) / (1.0 - 2.0 * NU)
}

/// The incident wave's energy per unit area of the boundary: ρ·V·∫(v_o/2)² dt.
fn incident_energy(velocity: f64) -> f64 {
    let n = 20_000;
    let h = PULSE / n as f64;
    let integral: f64 = (0..n).map(|k| (0.5 * outcrop((k as f64 + 0.5) * h).1).powi(2) * h).sum();
    RHO * velocity * integral
}

/// A dynamic stage of `duration` under the outcrop pulse in `direction`, over a compliant base
/// `base` (its half-space the soil's own) with the `absorbing` edge sets.
fn shaking(direction: Direction, duration: f64, absorbing: &[&str]) -> DynamicSpec {
    let steps = (PULSE / DT).round() as usize;
    let samples = (0..=steps).map(|k| [k as f64 * DT, outcrop(k as f64 * DT).0]).collect();
    let mut spec = common::dynamics::shaking_in_x(DT, duration, 0.0, None, Lumping::Lumped, samples);
    spec.base_motion[0].direction = direction;
    // (the dashpots act along the motion: across it, every node is held)
    let directions = vec![direction];
    spec.absorbing =
        absorbing.iter().map(|&e| AbsorbingEdges { edges: e.into(), directions: directions.clone() }).collect();
    spec.compliant_base = Some(CompliantBase {
        edges: "base".into(),
        directions,
        unit_weight: None,
        shear_wave_velocity: None,
        poissons_ratio: None,
    });
    spec
}

/// A strip of square quad4 elements of side SIDE, STRIP along x (`along_x`) or HEIGHT up y, moving in direction `shaken` only (every node held in the other), the "base" edge at its
/// start and the "far" edge at its end.
fn strip(along_x: bool, shaken: Direction, dynamic: DynamicSpec, stages_before: Vec<Stage>) -> ModelFile {
    let (h, length) = (SIDE, if along_x { STRIP } else { HEIGHT });
    let n = (length / h).round() as usize;
    let (size, division) = if along_x { ((length, h), (n, 1)) } else { ((h, length), (1, n)) };
    let block = Block::new(SolidKind::Quad4, (0.0, 0.0), size, division, "soil", 1, 1);
    let (start, end) =
        if along_x { (block.column_edges(0), block.column_edges(n)) } else { (block.row_edges(0), block.row_edges(n)) };
    let mut node_sets = BTreeMap::new();
    node_sets.insert("all".into(), block.nodes.iter().map(|n| n.0).collect());
    let start_nodes = if along_x { block.column_nodes(0) } else { block.row_nodes(0) };
    node_sets.insert("start".into(), start_nodes);
    node_sets.insert("end".into(), if along_x { block.column_nodes(n) } else { block.row_nodes(n) });
    let mut edge_sets = BTreeMap::new();
    edge_sets.insert("base".into(), start);
    edge_sets.insert("far".into(), end);
    let mut soil = BTreeMap::new();
    let e = 2.0 * shear_modulus() * (1.0 + NU);
    soil.insert("soil".into(), SoilMaterial::linear_elastic(e, NU, RHO * common::dynamics::G));
    let other = if shaken == Direction::X { Direction::Y } else { Direction::X };
    // every node is held in the other direction; the start is held in the shaken one until the
    // dynamic stage frees it (in both directions: its dashpots take the other)
    let supports = vec![support("all", &[other]), support("start", &[shaken])];
    let mut stages = stages_before;
    stages.push(Stage { name: "shaking".into(), dynamic: Some(dynamic), ..Default::default() });
    ModelFile {
        title: "absorbing boundary".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement: BTreeMap::new() },
        nodes: block.nodes,
        elements: block.elements,
        bars: Vec::new(),
        node_sets,
        edge_sets,
        element_sets: BTreeMap::new(),
        supports,
        interfaces: Vec::new(),
        stages,
        analysis: AnalysisSettings { force_tolerance: 1e-10, ..Default::default() },
        mesh: None,
        series: None,
        design: None,
    }
}

/// Kinetic and strain energy per unit area of the strip's cross-section at each step, with the
/// step's time, from the displacements' component `d`, varying along axis `axis`, with modulus
/// `modulus`.
fn energies(model: &Model, c: &Collect, axis: usize, d: usize, modulus: f64) -> Vec<(f64, f64)> {
    let h = SIDE;
    let nodes = &model.mesh.nodes;
    c.steps
        .iter()
        .map(|(_, r)| {
            let m = r.motion.as_ref().expect("a dynamic step has its motion");
            // lumped: a quarter of each element's mass at each of its nodes; per unit area of the
            // cross-section (h wide)
            let kinetic: f64 = model
                .mesh
                .solids
                .iter()
                .flat_map(|e| e.nodes.iter())
                .map(|&n| 0.5 * (RHO * h * h / 4.0) * m.velocity[2 * n + d].powi(2))
                .sum::<f64>()
                / h;
            let strain: f64 = model
                .mesh
                .solids
                .iter()
                .map(|e| {
                    // the strain along the strip, from the element's two faces across it
                    let at = |n: usize| nodes[n].x[axis];
                    let (mut low, mut high): (Vec<usize>, Vec<usize>) = (Vec::new(), Vec::new());
                    let lowest = e.nodes.iter().map(|&n| at(n)).fold(f64::INFINITY, f64::min);
                    for &n in &e.nodes {
                        if at(n) < lowest + 0.5 * h {
                            low.push(n)
                        } else {
                            high.push(n)
                        }
                    }
                    let mean = |ns: &[usize]| ns.iter().map(|&n| r.displacement_vector[2 * n + d]).sum::<f64>() / 2.0;
                    let strain = (mean(&high) - mean(&low)) / h;
                    0.5 * modulus * strain * strain * h * h
                })
                .sum::<f64>()
                / h;
            (m.time, kinetic + strain)
        })
        .collect()
}

/// The energy at `t` (the step nearest it).
fn at(energy: &[(f64, f64)], t: f64) -> f64 {
    energy.iter().min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs())).unwrap().1
}

#[test]
fn an_s_wave_enters_through_a_compliant_base_and_leaves_through_it() {
    for backend in Backend::available() {
        let file = strip(false, Direction::X, shaking(Direction::X, 0.8, &[]), Vec::new());
        let model = common::model(&file, "s-wave.toml");
        let c = common::run(&model, backend);
        let energy = energies(&model, &c, 1, 0, shear_modulus());
        let incoming = incident_energy(VS);
        // the whole pulse is in the column from 0.2 s until its reflection reaches the base at 0.4 s
        let inside = at(&energy, 0.3);
        assert!((inside / incoming - 1.0).abs() < 1e-3, "{backend:?}: {inside} in the column against {incoming}");
        let left = at(&energy, 0.8);
        assert!(left < 1e-5 * incoming, "{backend:?}: {} of the pulse's energy stayed", left / incoming);
        // the surface moves as the outcrop, H/Vs later
        let top = model.mesh.nodes.iter().position(|n| n.x == [0.0, HEIGHT]).unwrap();
        let worst = c
            .steps
            .iter()
            .map(|(_, r)| {
                let m = r.motion.as_ref().unwrap();
                (m.acceleration[2 * top] - outcrop(m.time - HEIGHT / VS).0).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst < 0.05 * PEAK, "{backend:?}: the surface is {worst} off the outcrop's motion");
    }
}

/// The same as a user reads it: `motion.csv` records the surface's motion as absolute (the base is
/// compliant), and its acceleration is the outcrop's, H/Vs later.
#[test]
fn motion_csv_gives_the_surface_s_absolute_motion_over_a_compliant_base() {
    let mut shaken = shaking(Direction::X, 0.4, &[]);
    shaken.record = vec!["end".into()];
    let model = common::model(&strip(false, Direction::X, shaken, Vec::new()), "s-wave.toml");
    let out = std::env::temp_dir().join(format!("geoslip-compliant-base-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    geoslip::output::run_and_write(&model, &out, &Default::default(), &mut Collect::default()).unwrap();
    let csv = std::fs::read_to_string(out.join("motion.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert!(header.iter().any(|h| h.starts_with("end ux absolute")), "{header:?}");
    assert!(!header.iter().any(|h| h.contains("relative")), "{header:?}");
    let column = |name: &str| header.iter().position(|h| h.starts_with(name)).unwrap();
    let (time, ax) = (column("time"), column("end ax absolute"));
    let rows: Vec<Vec<f64>> =
        csv.lines().skip(1).map(|l| l.split(',').skip(1).map(|c| c.parse().unwrap()).collect()).collect();
    assert!(rows.len() >= 400, "{} rows", rows.len());
    let worst = rows.iter().map(|r| (r[ax - 1] - outcrop(r[time - 1] - HEIGHT / VS).0).abs()).fold(0.0, f64::max);
    assert!(worst < 0.05 * PEAK, "motion.csv: the surface is {worst} off the outcrop's motion");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_p_wave_passes_along_a_strip_and_out_of_its_absorbing_end() {
    let vp = (constrained_modulus() / RHO).sqrt();
    let file = strip(true, Direction::X, shaking(Direction::X, 0.8, &["far"]), Vec::new());
    let model = common::model(&file, "p-wave.toml");
    let c = common::run(&model, Backend::Faer);
    let energy = energies(&model, &c, 0, 0, constrained_modulus());
    let incoming = incident_energy(vp);
    // (in the strip from 0.2 s until its front reaches the far end at L/Vp = 0.32 s)
    let inside = at(&energy, 0.26);
    assert!((inside / incoming - 1.0).abs() < 1e-3, "{inside} in the strip against {incoming}");
    let left = at(&energy, 0.8);
    assert!(left < 1e-5 * incoming, "{} of the pulse's energy stayed", left / incoming);
}

/// Dashpots in place of the supports of a column at rest under its weight (in one-dimensional
/// compression: every x held): their reactions stay on as forces, and nothing moves.
#[test]
fn a_column_at_rest_stays_at_rest_when_its_supports_become_dashpots() {
    let weight = Stage { name: "weight".into(), loads: vec![LoadSpec::Gravity { factor: 1.0 }], ..Default::default() };
    let mut dynamic = shaking(Direction::Y, 0.05, &[]);
    dynamic.base_motion[0].samples = Some(vec![[0.0, 0.0], [0.05, 0.0]]);
    let mut file = strip(false, Direction::Y, dynamic, vec![weight]);
    file.stages.push(Stage { name: "after".into(), ..Default::default() });
    let model = common::model(&file, "at-rest.toml");
    let c = common::run(&model, Backend::Faer);
    let settled = &c.steps[0].1.displacement_vector;
    let sag = settled.iter().fold(0.0f64, |m, u| m.max(u.abs()));
    assert!(sag > 0.0);
    for (_, r) in &c.steps {
        let moved = r.displacement_vector.iter().zip(settled).map(|(u, s)| (u - s).abs()).fold(0.0, f64::max);
        assert!(moved < 1e-9 * sag, "moved {moved} after settling {sag}");
    }
    // held again after the shaking, the base carries the column's weight
    let last = &c.steps[c.steps.len() - 1].1;
    let carried: f64 = last.reactions.iter().filter_map(|r| r.ry).sum();
    let weight = RHO * common::dynamics::G * HEIGHT * SIDE;
    assert!((carried / weight - 1.0).abs() < 1e-9, "the base carries {carried} of {weight}");
}
