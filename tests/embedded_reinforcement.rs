//! A reinforcement embedded in continuous soil against the same box built by hand.
//!
//! Reference: an independent construction of the same continuous-soil problem with the contact
//! pairs geoslip has had from the start: the soil's node row along the grid doubled and tied back
//! to itself (a `tie` pair, so the soil is one body again), and the grid as a pair of its own nodes
//! against that row, one face standing for both: Ks = 2·2000 kPa/m and a strength 2·σn·tan φ with
//! σn = 20 kPa, written as a cohesion (φ = 0), since a pair's σn is its multiplier, which a grid
//! inside continuous soil does not load. The embedded mode must give the same answers: the issue
//! asks for the head force to 0.5 % at every pull step and the soil field to 1e-6 m.
//!
//! Model: the issue's pull-out box (2 m × 1 m, E = 10 MPa, ν = 0.3, weightless, 20 × 10 quad4, a
//! grid at mid-height from x = 0 to 1.6 m, EA = 500 kN/m, Coulomb faces Ks = 2000 kPa/m, c = 0,
//! φ = 30°, q = 20 kPa, σn frozen in the pull stage), the head pulled 20 mm in 40 steps.

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::PullOutBox;
use geoslip::model::file::*;
use std::collections::BTreeMap;

const SIGMA_N: f64 = 20.0;

fn embedded_box(pull: f64, steps: usize) -> ModelFile {
    let mut file = PullOutBox { pull, steps, ..common::issue_pullout_box() }.model();
    file.interfaces[0].reinforcement.as_mut().unwrap().mode = ReinforcementMode::Embedded;
    file.stages[1].freeze_normal_stress = Some(true);
    file
}

/// The box with the soil's node row along the grid doubled and tied back, and the grid as a pair
/// on the upper row.
fn doubled_and_retied(pull: f64, steps: usize) -> ModelFile {
    let mut file = PullOutBox { pull, steps, ..common::issue_pullout_box() }.model();
    let spec = file.interfaces.remove(0);
    let path = spec.reinforcement.unwrap().path;
    let position: BTreeMap<u64, [f64; 2]> = file.nodes.iter().map(|n| (n.0, [n.1, n.2])).collect();
    let y_line = position[&path[0]][1];
    let mut next = file.nodes.iter().map(|n| n.0).max().unwrap() + 1;
    let mut twin = BTreeMap::new();
    for &p in &path {
        twin.insert(p, next);
        file.nodes.push(NodeRow(next, position[&p][0], position[&p][1]));
        next += 1;
    }
    for e in file.elements.iter_mut() {
        let below = e.nodes.iter().map(|n| position[n][1]).sum::<f64>() / (e.nodes.len() as f64) < y_line;
        if below {
            for n in e.nodes.iter_mut() {
                if let Some(&t) = twin.get(n) {
                    *n = t;
                }
            }
        }
    }
    // the twin on the front face is held there as its original is
    file.node_sets.get_mut("front").unwrap().push(twin[&path[0]]);
    let grid: Vec<u64> = path
        .iter()
        .map(|p| {
            file.nodes.push(NodeRow(next, position[p][0], position[p][1]));
            next += 1;
            next - 1
        })
        .collect();
    let mut bar_id = file.elements.iter().map(|e| e.id).max().unwrap() + 1;
    for w in grid.windows(2) {
        file.bars.push(BarRow { id: bar_id, nodes: [w[0], w[1]], material: "grid".into() });
        bar_id += 1;
    }
    file.node_sets.insert("grid.head".into(), vec![grid[0]]);
    let pair = |name: &str, slave: Vec<u64>, law: ShearLawSpec| InterfaceSpec {
        name: name.into(),
        slave: Some(slave),
        master: Some(path.clone()),
        law,
        ..Default::default()
    };
    let (ks, phi) = match spec.law {
        ShearLawSpec::Coulomb { shear_stiffness, friction_angle, .. } => (shear_stiffness, friction_angle),
        _ => unreachable!("the issue's box has Coulomb faces"),
    };
    file.interfaces = vec![
        pair("soil", path.iter().map(|p| twin[p]).collect(), ShearLawSpec::Tie),
        pair(
            "grid",
            grid,
            ShearLawSpec::Coulomb {
                shear_stiffness: 2.0 * ks,
                cohesion: 2.0 * SIGMA_N * phi.to_radians().tan(),
                friction_angle: 0.0,
            },
        ),
    ];
    file
}

#[test]
fn embedded_grid_matches_the_soil_doubled_and_tied_back_by_hand() {
    let (pull, steps) = (0.02, 40);
    let embedded = common::model(&embedded_box(pull, steps), "embedded.toml");
    let by_hand = common::model(&doubled_and_retied(pull, steps), "by-hand.toml");
    let backend = Backend::available()[0];
    let (a, b) = (common::run(&embedded, backend), common::run(&by_hand, backend));
    let (fa, fb) = (common::head_forces(&embedded, &a, "grid.head"), common::head_forces(&by_hand, &b, "grid.head"));
    assert_eq!(fa.len(), steps);
    assert_eq!(fb.len(), steps);
    for (k, (x, y)) in fa.iter().zip(&fb).enumerate() {
        assert!(common::relative_error(*x, *y) < 0.005, "step {}: embedded {x} kN/m, by hand {y}", k + 1);
    }
    // the extensible grid mobilises its length progressively: the force rises at every step and
    // stays below the fully sliding n_f·τmax·L
    let ultimate = 2.0 * SIGMA_N * 30f64.to_radians().tan() * 1.6;
    assert!(fa.windows(2).all(|w| w[1] > w[0]), "the force rises: {fa:?}");
    assert!(fa[steps - 1] < ultimate, "force at 20 mm {} above n_f·τmax·L = {ultimate}", fa[steps - 1]);

    // the soil field: every soil node of the box, at every step
    for ((_, ra), (_, rb)) in a.steps.iter().zip(&b.steps) {
        let theirs: BTreeMap<u64, [f64; 2]> = rb.displacements.iter().map(|(n, _, d)| (*n, *d)).collect();
        let mut compared = 0;
        for (node, _, d) in &ra.displacements {
            let in_soil = embedded
                .mesh
                .node_index(*node)
                .is_some_and(|i| embedded.mesh.solids.iter().any(|s| s.nodes.contains(&i)));
            if !in_soil {
                continue;
            }
            let e = theirs[node];
            assert!(
                (d[0] - e[0]).abs() < 1e-6 && (d[1] - e[1]).abs() < 1e-6,
                "node {node}: embedded {d:?}, by hand {e:?}"
            );
            compared += 1;
        }
        assert_eq!(compared, 21 * 11);
    }
}

#[test]
fn embedded_grid_uses_the_soils_normal_stress_and_both_faces() {
    let file = embedded_box(0.01, 4);
    let model = common::model(&file, "embedded.toml");
    // one continuous soil: no node doubled, one face for the grid, no slit
    assert_eq!(model.mesh.nodes.len(), 21 * 11 + 17);
    assert_eq!(model.interfaces.len(), 1);
    assert_eq!(model.interfaces[0].faces.len(), 1);
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let (_, last) = c.steps.last().unwrap();
        let tau_max = SIGMA_N * 30f64.to_radians().tan();
        for p in &last.interface_points {
            assert_eq!(p.face, "embedded");
            // the soil's σn across the grid under the 20 kPa surcharge, frozen at the pull's start
            assert!((p.sigma_n - SIGMA_N).abs() < 1e-6, "{backend:?}: node {}: σn {}", p.slave_node, p.sigma_n);
            assert!(p.tau.abs() <= tau_max * (1.0 + 1e-9), "{backend:?}: τ {} above τmax", p.tau);
            assert_eq!(p.state, "active");
        }
        // the pull is carried by both faces: Σ 2·τ·ℓ over the points
        let carried: f64 = last.interface_points.iter().map(|p| 2.0 * p.tau * p.tributary).sum();
        let force = common::head_forces(&model, &c, "grid.head")[3];
        assert!(common::relative_error(carried, force) < 1e-6, "{backend:?}: Σ2τℓ {carried} against the pull {force}");
    }
}

#[test]
fn the_report_says_the_embedded_face_stands_for_both() {
    let model = common::model(&embedded_box(0.005, 2), "embedded.toml");
    let out = tempfile::tempdir().unwrap();
    let backend = Backend::available()[0];
    let options = geoslip::analysis::RunOptions::for_model(&model, backend);
    let mut writer = geoslip::output::ResultWriter::new(&model, out.path(), backend.name()).unwrap();
    let mut keep = geoslip::analysis::Collect::default();
    geoslip::output::write_run(&model, &options, None, &mut writer, &mut keep).unwrap();
    let report = std::fs::read_to_string(out.path().join("report.md")).unwrap();
    assert!(report.contains("| grid | coulomb | 2 (embedded: one set of points for both) | 17 |"), "{report}");
    let interface = std::fs::read_to_string(out.path().join("summary.json")).unwrap();
    assert!(interface.contains("\"status\": \"completed\""), "{interface}");
}
