//! A stack of geosynthetics sheared under a normal stress: the weakest interface governs.
//!
//! Reference: the direct shear of a multi-layer liner (Stark & Poeppel, J. Geotech. Eng. 120 (1994)
//! 597–615; Koerner, Designing with Geosynthetics, 6th ed., §5.1.3): the stack slides on the
//! interface of least strength, and the shear force it carries is N·tan φ of that interface, its
//! peak first and its residual once the peak is passed. The other interfaces stay below their
//! strength and do not slide.
//!
//! ```text
//!   q ↓↓↓↓↓↓↓↓↓↓↓↓↓↓↓↓↓↓↓↓
//!   ┌──────────────────────┐  cover soil: its upper rows pushed to the right, held from rising or tilting
//!   ├──────────────────────┤  cover / geotextile: φ = 33°
//!   ├──────────────────────┤  geotextile / geomembrane: peak 16°, residual 10°   ← the weakest
//!   ├──────────────────────┤  geomembrane / clay: c = 5 kPa, φ = 28°
//!   └──────────────────────┘  clay liner, fixed
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::meshgen::{support, Block};
use geoslip::model::file::*;
use std::collections::BTreeMap;

const LENGTH: f64 = 2.0;
const Q: f64 = 50.0;
const PUSH: f64 = 0.02;

fn stack_in_shear() -> ModelFile {
    let clay = Block::new(SolidKind::Quad4, (0.0, -0.2), (LENGTH, 0.2), (20, 2), "clay", 1, 1);
    let cover = Block::new(SolidKind::Quad4, (0.0, 0.0), (LENGTH, 0.2), (20, 2), "cover", 1000, 1000);
    let (nodes, elements, _) = common::stack(&clay, &cover);
    // above its bottom row: a node set holding a node of the split path holds its twin too
    let cover_nodes: Vec<u64> = (1..=cover.ny).flat_map(|j| cover.row_nodes(j)).collect();
    let liner_path = clay.row_nodes(clay.ny);
    let mut node_sets = BTreeMap::new();
    // the clay below its top row (which the split leaves to the cover; the clay's top gets twins)
    node_sets.insert("clay".into(), (0..clay.ny).flat_map(|j| clay.row_nodes(j)).collect::<Vec<_>>());
    node_sets.insert("cover".into(), cover_nodes);
    let mut edge_sets = BTreeMap::new();
    edge_sets.insert("top".into(), cover.row_edges(cover.ny));
    let mut soil = BTreeMap::new();
    // ν = 0: the normal stress spreads nothing sideways, so the interfaces start unsheared, as in
    // a shear box that confines the specimen
    soil.insert("clay".into(), SoilMaterial::linear_elastic(1.0e5, 0.0, 0.0));
    soil.insert("cover".into(), SoilMaterial::linear_elastic(1.0e5, 0.0, 0.0));
    let mut reinforcement = BTreeMap::new();
    let sheet = |ea: f64| ReinforcementMaterial {
        axial_stiffness: ea,
        tension_only: false,
        rupture_strength: None,
        weight: None,
    };
    reinforcement.insert("hdpe".into(), sheet(5.0e3));
    reinforcement.insert("nonwoven".into(), sheet(2.0e2));
    let coulomb = |phi: f64| ShearLawSpec::Coulomb { shear_stiffness: 2.0e4, cohesion: 0.0, friction_angle: phi };
    ModelFile {
        title: "liner stack in direct shear".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement },
        nodes,
        elements,
        bars: Vec::new(),
        node_sets,
        edge_sets,
        element_sets: BTreeMap::new(),
        supports: vec![support("clay", &[Direction::X, Direction::Y])],
        interfaces: vec![InterfaceSpec {
            name: "geomembrane".into(),
            reinforcement: Some(ReinforcementPath {
                path: liner_path,
                line: None,
                head: None,
                material: "hdpe".into(),
                stack: vec![StackedLayer {
                    name: "geotextile".into(),
                    material: "nonwoven".into(),
                    law: ShearLawSpec::PeakResidual {
                        shear_stiffness: 2.0e4,
                        cohesion: 0.0,
                        friction_angle: 16.0,
                        residual_cohesion: 0.0,
                        residual_friction_angle: 10.0,
                    },
                }],
                free_length: None,
                mode: Default::default(),
            }),
            law: coulomb(33.0),
            lower_law: Some(ShearLawSpec::Coulomb { shear_stiffness: 2.0e4, cohesion: 5.0, friction_angle: 28.0 }),
            ..Default::default()
        }],
        stages: vec![
            Stage {
                name: "normal stress".into(),
                loads: vec![LoadSpec::EdgeTraction { name: None, edge_set: "top".into(), pressure: Q, shear: 0.0 }],
                ..Default::default()
            },
            Stage {
                name: "shear".into(),
                // 0.01 mm steps to 3 mm (past the peak, about 2 mm), then 0.5 mm steps
                load_factors: (1..=300)
                    .map(|k| k as f64 * 1e-5 / PUSH)
                    .chain((7..=40).map(|k| k as f64 / 40.0))
                    .collect(),
                // a platen that neither rises nor tilts (the interfaces do not dilate)
                prescribed: vec![common::prescribed("cover", Some(PUSH), Some(0.0))],
                ..Default::default()
            },
        ],
        analysis: common::newton(1e-8),
        mesh: None,
        series: None,
        design: None,
    }
}

#[test]
fn the_stack_slides_on_its_weakest_interface_at_peak_then_residual_strength() {
    let file = stack_in_shear();
    let model = common::model(&file, "liner-stack.toml");
    let c = common::run(&model, Backend::Auto);
    let cover: Vec<usize> = file.node_sets["cover"].iter().map(|&id| model.mesh.node_index(id).unwrap()).collect();
    // the shear force: the cover's reactions to its displacement
    let shear: Vec<f64> = c
        .steps
        .iter()
        .filter(|(r, _)| r.stage == "shear")
        .map(|(_, s)| cover.iter().map(|&n| s.reaction_vector[2 * n]).sum::<f64>())
        .collect();
    let normal = Q * LENGTH;
    let peak = normal * 16f64.to_radians().tan();
    let residual = normal * 10f64.to_radians().tan();
    let largest = shear.iter().fold(0.0f64, |m, &f| m.max(f));
    let last = *shear.last().unwrap();
    common::doc_number("liner-stack.shear", format!("{largest:.2} and {last:.2} kN/m"));
    assert!(common::relative_error(largest, peak) < 0.01, "peak shear {largest:.3} kN/m against N·tan 16° = {peak:.3}");
    assert!(
        common::relative_error(last, residual) < 0.01,
        "final shear {last:.3} kN/m against N·tan 10° = {residual:.3}"
    );

    // where it slid: on the geotextile / geomembrane face only
    let end = &c.steps.last().unwrap().1;
    let mean_slip = |face: &str| {
        let points: Vec<f64> = end.interface_points.iter().filter(|p| p.face == face).map(|p| p.slip.abs()).collect();
        assert!(!points.is_empty(), "no points on face {face}");
        points.iter().sum::<f64>() / points.len() as f64
    };
    let between = mean_slip("geotextile on geomembrane");
    assert!(between > 0.9 * PUSH, "the weakest interface slides: mean slip {between:.4} m of {PUSH} m");
    for face in ["upper", "lower"] {
        let slip = mean_slip(face);
        assert!(slip < 0.05 * PUSH, "face {face} stays below its strength: mean slip {slip:.5} m");
    }
    assert!(
        end.interface_points.iter().filter(|p| p.face == "geotextile on geomembrane").all(|p| p.post_peak),
        "every point of the weakest interface is past its peak"
    );
}

/// The stack of `stack_in_shear` with a dilatant interface, sheared 20 mm in 40 steps of 0.5 mm by a
/// platen that is pushed but free to rise (the surcharge stays q).
fn dilatant_stack(upper_law: ShearLawSpec) -> geoslip::model::Model {
    let mut file = stack_in_shear();
    file.interfaces[0].law = upper_law;
    file.interfaces[0].dilation = Some(DilationSpec { angle: PSI, max_dilation: 0.01 });
    file.stages[1].load_factors = (1..=40).map(|k| k as f64 / 40.0).collect();
    file.stages[1].prescribed = vec![common::prescribed("cover", Some(PUSH), None)];
    common::model(&file, "dilatant-liner-stack.toml")
}

const PSI: f64 = 10.0;

/// Each shear step: (the platen's push, the rise of the cover's top, every point's (face, dilation, sliding)).
fn rise_by_step(c: &geoslip::analysis::Collect) -> Vec<(f64, f64, Vec<(String, f64, bool)>)> {
    c.steps
        .iter()
        .filter(|(r, _)| r.stage == "shear")
        .map(|(r, s)| {
            let top: Vec<f64> =
                s.displacements.iter().filter(|d| (d.1[1] - 0.2).abs() < 1e-12).map(|d| d.2[1]).collect();
            assert_eq!(top.len(), 21, "the cover's top row");
            let rise = top.iter().sum::<f64>() / top.len() as f64;
            let points = s.interface_points.iter().map(|p| (p.face.clone(), p.dilation, p.sliding)).collect();
            (PUSH * r.load_factor, rise, points)
        })
        .collect()
}

#[test]
fn a_stack_whose_face_against_the_soil_slides_dilates_it_by_tan_psi_of_the_slip() {
    // docs/verification.md §9: once the cover slides on the geotextile with σn = q held, every further
    // push is plastic slip of that face, so the free platen rises by tan ψ per unit push; the faces
    // between the sheets and against the clay do not slide and do not open
    // 8°, below the geotextile on geomembrane's residual 10°: that face never takes the slip over
    let upper = ShearLawSpec::Coulomb { shear_stiffness: 2.0e4, cohesion: 0.0, friction_angle: 8.0 };
    let model = dilatant_stack(upper);
    let c = common::run(&model, Backend::Auto);
    let steps = rise_by_step(&c);
    let tan_psi = PSI.to_radians().tan();
    let mut checked = 0;
    for pair in steps.windows(2) {
        let ((u0, rise0, points0), (u1, rise1, points1)) = (&pair[0], &pair[1]);
        for (face, dilation, _) in points1.iter().filter(|p| p.0 != "upper") {
            assert_eq!(*dilation, 0.0, "u = {u1}: face {face} opens by {dilation}");
        }
        let sliding = |points: &[(String, f64, bool)]| points.iter().filter(|p| p.0 == "upper").all(|p| p.2);
        if sliding(points0) && sliding(points1) {
            let expected = tan_psi * (u1 - u0);
            // measured 4e-4 to 7e-4 below, growing with u: the cover's contact with the sheet shortens
            // by u, so σn, τ and the elastic part of the slip grow by about u/L a step; the points
            // measured up to 5e-3 below (those near the ends, where the shortening is)
            assert!(
                (rise1 - rise0 - expected).abs() < 2e-3 * expected,
                "u = {u1}: the cover rose {:.4e} m in the step, tan ψ·Δu = {expected:.4e}",
                rise1 - rise0
            );
            let upper = |points: &[(String, f64, bool)]| -> Vec<f64> {
                points.iter().filter(|p| p.0 == "upper").map(|p| p.1).collect()
            };
            for (d0, d1) in upper(points0).iter().zip(upper(points1)) {
                assert!((d1 - d0 - expected).abs() < 1.5e-2 * expected, "u = {u1}: a point opens {d0} → {d1}");
            }
            checked += 1;
        }
    }
    assert!(checked >= 30, "the face slides in {checked} of 40 steps");
}

#[test]
fn a_stack_that_slides_between_its_sheets_does_not_open() {
    // docs/model-format.md: in a stack only the faces against the soil dilate; here the weakest
    // interface is the geotextile on the geomembrane, the faces against the soil stay below their
    // strength, so no face opens and the free platen stays where the surcharge put it
    let model = dilatant_stack(ShearLawSpec::Coulomb { shear_stiffness: 2.0e4, cohesion: 0.0, friction_angle: 33.0 });
    let c = common::run(&model, Backend::Auto);
    let steps = rise_by_step(&c);
    let before = c.steps.iter().rev().find(|(r, _)| r.stage == "normal stress").unwrap();
    let top: Vec<f64> =
        before.1.displacements.iter().filter(|d| (d.1[1] - 0.2).abs() < 1e-12).map(|d| d.2[1]).collect();
    let settled = top.iter().sum::<f64>() / top.len() as f64;
    let (_, _, last_points) = steps.last().unwrap();
    assert!(
        last_points.iter().any(|p| p.0 == "geotextile on geomembrane" && p.2),
        "the geotextile slides on the geomembrane"
    );
    // had the sliding face opened, the cover would rise tan ψ·u (3.5 mm at the end); the shear's
    // couple only tilts it about its middle
    let open = PSI.to_radians().tan() * PUSH;
    for (u, rise, points) in &steps {
        assert!((rise - settled).abs() < 0.01 * open, "u = {u}: the cover rose {:.3e} m", rise - settled);
        for (face, dilation, _) in points {
            assert_eq!(*dilation, 0.0, "u = {u}: face {face} opens by {dilation}");
        }
    }
}
