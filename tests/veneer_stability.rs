//! Veneer stability: cover soil on a geomembrane-lined slope, factor of safety by strength reduction.
//!
//! Reference: shared/reference/closed-forms.md §7 (Koerner & Soong, Geotextiles and Geomembranes 16
//! (1998) 1–36, the two-wedge method; Giroud & Beech 1989): a long slope with no toe has
//! FS = tan φ_i / tan β; a toe (passive wedge on the horizontal ground, resisting through the cover
//! soil's own friction) adds to it, by the quadratic A·FS² + B·FS + C₀ = 0.
//!
//! Goal: the strength reduction of geoslip (c and tan φ divided by F in the interfaces) finds FS
//! within 1 % of tan φ_i / tan β on a slope with no toe. (The two-wedge case with a toe is not yet
//! verified: see docs/soil.md.)
//!
//! ```text
//!   crest                       cover soil, thickness h (normal to the slope)
//!     \\
//!      \\  geomembrane interface (φ_i) on a rigid slope
//!       \\
//!        \\__________  toe: the cover continues on the horizontal ground (interface φ: the
//!         O            passive wedge slides on soil-like friction)
//! ```

mod common;

use geoslip::linsol::Backend;
use geoslip::model::file::*;
use std::collections::BTreeMap;

const GAMMA: f64 = 18.0;
const H: f64 = 0.5;
/// A little cohesion keeps the cover's surface and the toe corner off the stress-free apex (it
/// enters the two-wedge formula as C = c·h/sin β).
const COVER_COHESION: f64 = 1.0;

/// A strip of cover soil of thickness `h` on a slope of angle `beta` and length `length` (along the
/// slope, from the crest to the toe corner O at the origin), then on horizontal ground for `toe`,
/// on rigid bases with interfaces: the slope's (φ_i) and the toe's (φ, the soil's own).
fn lined_slope(beta_deg: f64, length: f64, toe: f64, phi_i: f64, phi_soil: f64, reduce: ReducedStrengths) -> ModelFile {
    let beta = beta_deg.to_radians();
    let (c, s) = (beta.cos(), beta.sin());
    // down-slope unit vector (towards +x, downwards) and the outward normal of the slope surface
    let down = [c, -s];
    let up_normal = [s, c];
    let crest = [-length * c, length * s];
    // the corner of the cover's surface above O, where the offset slope line meets y = h:
    // crest + h·n + t·down has y = h
    let t = (crest[1] + H * up_normal[1] - H) / s;
    let p = [crest[0] + H * up_normal[0] + t * down[0], H];
    let n_slope = (length / H * 4.0).round() as usize; // elements along the slope
    let n_toe = (toe / H * 4.0).round() as usize;
    let m = 4; // elements through the thickness
    let top_crest = [crest[0] + H * up_normal[0], crest[1] + H * up_normal[1]];
    let columns = n_slope + n_toe;
    let column = |i: usize| -> ([f64; 2], [f64; 2]) {
        if i <= n_slope {
            let a = i as f64 / n_slope as f64;
            let base = [crest[0] * (1.0 - a), crest[1] * (1.0 - a)];
            let top = [top_crest[0] + a * (p[0] - top_crest[0]), top_crest[1] + a * (p[1] - top_crest[1])];
            (base, top)
        } else {
            let a = (i - n_slope) as f64 / n_toe as f64;
            ([a * toe, 0.0], [p[0] + a * (toe - p[0]), H])
        }
    };
    let mut nodes = Vec::new();
    let id = |i: usize, j: usize| (1 + j * (columns + 1) + i) as u64;
    for j in 0..=m {
        for i in 0..=columns {
            let (b, t) = column(i);
            let f = j as f64 / m as f64;
            nodes.push(NodeRow(id(i, j), b[0] + f * (t[0] - b[0]), b[1] + f * (t[1] - b[1])));
        }
    }
    let mut elements = Vec::new();
    for j in 0..m {
        for i in 0..columns {
            elements.push(SolidElementRow {
                id: (1 + j * columns + i) as u64,
                kind: SolidKind::Quad4,
                nodes: vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
                material: "cover".into(),
            });
        }
    }
    // rigid bases: their own nodes, fixed, below the cover's base nodes
    let base_id = |i: usize| 100_000 + i as u64;
    for i in 0..=columns {
        let (b, _) = column(i);
        nodes.push(NodeRow(base_id(i), b[0], b[1]));
    }
    let mut node_sets = BTreeMap::new();
    node_sets.insert("bases".into(), (0..=columns).map(base_id).collect::<Vec<_>>());
    // ν = 0.4: the one-dimensional state on the slope stays inside the Mohr–Coulomb surface
    let mut cover = SoilMaterial::linear_elastic(2.0e4, 0.4, GAMMA);
    if reduce == ReducedStrengths::SoilAndInterfaces {
        cover.model = SoilModel::MohrCoulomb;
        cover.friction_angle = phi_soil;
        cover.dilatancy_angle = phi_soil; // associated, as limit equilibrium assumes
        cover.cohesion = COVER_COHESION;
    }
    let mut soil = BTreeMap::new();
    soil.insert("cover".into(), cover);
    let coulomb = |phi: f64| ShearLawSpec::Coulomb { shear_stiffness: 5.0e4, cohesion: 0.0, friction_angle: phi };
    let mut interfaces = vec![InterfaceSpec {
        name: "geomembrane".into(),
        reinforcement: None,
        slave: Some((0..=n_slope).rev().map(|i| id(i, 0)).collect()),
        master: Some((0..=n_slope).rev().map(base_id).collect()),
        master_normal: Some([-up_normal[0], -up_normal[1]]),
        law: coulomb(phi_i),
    }];
    if n_toe > 0 {
        interfaces.push(InterfaceSpec {
            name: "toe".into(),
            reinforcement: None,
            slave: Some((n_slope..=columns).rev().map(|i| id(i, 0)).collect()),
            master: Some((n_slope..=columns).rev().map(base_id).collect()),
            master_normal: Some([0.0, -1.0]),
            law: coulomb(phi_soil),
        });
    }
    let mut file = common::soil_model(
        "lined slope",
        nodes,
        elements,
        soil,
        node_sets,
        vec![geoslip::meshgen::support("bases", &[Direction::X, Direction::Y])],
        vec![
            Stage {
                name: "cover placed".into(),
                load_factors: vec![0.25, 0.5, 0.75, 1.0],
                loads: vec![LoadSpec::Gravity { factor: 1.0 }],
                ..Default::default()
            },
            Stage {
                name: "factor of safety".into(),
                strength_reduction: Some(StrengthReductionSpec { reduce, tolerance: Some(0.002), max_factor: None }),
                ..Default::default()
            },
        ],
        AnalysisSettings {
            scheme: Scheme::Newton,
            max_iterations: 400,
            force_tolerance: 1e-6,
            displacement_tolerance: 1e-6,
            ..AnalysisSettings::default()
        },
    );
    file.interfaces = interfaces;
    file
}

fn factor_of_safety(file: &ModelFile) -> f64 {
    let model = common::model(file, "lined-slope.toml");
    let c = common::run(&model, Backend::Auto);
    let fs = c.factors_of_safety.last().expect("a strength-reduction stage reports its FS");
    assert!(fs.failed_at.is_some(), "the search bracketed FS: {:?}", fs.trials);
    fs.value
}

#[test]
fn a_long_slope_with_no_toe_has_the_infinite_slope_factor_of_safety() {
    let (beta, phi_i): (f64, f64) = (18.43, 24.0);
    let exact = phi_i.to_radians().tan() / beta.to_radians().tan();
    let fs = factor_of_safety(&lined_slope(beta, 15.0 * H, 0.0, phi_i, 35.0, ReducedStrengths::Interfaces));
    assert!(common::relative_error(fs, exact) < 0.01, "FS {fs:.4} against tan φ_i / tan β = {exact:.4}");
}
