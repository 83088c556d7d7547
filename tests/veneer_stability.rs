//! Veneer stability: cover soil on a geomembrane-lined slope, factor of safety by strength reduction.
//!
//! Reference: docs/verification.md §7 (Koerner & Soong, Geotextiles and Geomembranes 16
//! (1998) 1–36, the two-wedge method; Giroud & Beech 1989): a long slope with no toe has
//! FS = tan φ_i / tan β; a toe (passive wedge on the horizontal ground, resisting through the cover
//! soil's own friction) adds to it, by the quadratic A·FS² + B·FS + C₀ = 0.
//!
//! Goal: the strength reduction of geoslip finds FS within 1 % of tan φ_i / tan β on a slope with no
//! toe (the interfaces reduced), and within 5 % of the two-wedge value with a toe at L/h = 15 and
//! three slope angles (soil and interfaces reduced together, as limit equilibrium does).
//!
//! ```text
//!   crest                       cover soil, thickness h (normal to the slope), Mohr–Coulomb
//!     \\
//!      \\  geomembrane interface (φ_i) on a rigid slope
//!       \\
//!        O\    passive wedge O–P–T (P above O on the cover's surface), resting on the ground
//!         O--T  O–T through an interface with the soil's own c and φ
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

/// Cover soil of thickness `h` on a slope of angle `beta` whose liner runs `length` along the slope
/// from the crest to the toe corner O at the origin, on rigid bases with interfaces (the liner's φ_i;
/// at the toe, the soil's own φ).
///
/// With `toe`, the cover's surface runs on down to the ground at T = (h / sin β, 0) as in the
/// two-wedge method: the passive wedge is the triangle O, P = (0, h / cos β), T, resting on the
/// horizontal ground O–T. Without it the cover ends at O with a face normal to the slope.
fn lined_slope(
    beta_deg: f64,
    length: f64,
    toe: bool,
    phi_i: f64,
    phi_soil: f64,
    reduce: ReducedStrengths,
) -> ModelFile {
    let beta = beta_deg.to_radians();
    let (c, s) = (beta.cos(), beta.sin());
    let up_normal = [s, c];
    let crest = [-length * c, length * s];
    let top_crest = [crest[0] + H * up_normal[0], crest[1] + H * up_normal[1]];
    // the top of the last slope column: above O (the two-wedge method's interwedge line) with a
    // toe, else normal to the slope
    let p = if toe { [0.0, H / c] } else { [H * up_normal[0], H * up_normal[1]] };
    let t = [H / s, 0.0];
    let n_slope = (length / H * 4.0).round() as usize; // elements along the slope
    let n_toe = if toe { (H / s / H * 4.0).round().max(2.0) as usize } else { 0 };
    let m = 4; // elements through the thickness
    let mut nodes = Vec::new();
    let slope_id = |i: usize, j: usize| (1 + j * (n_slope + 1) + i) as u64;
    for j in 0..=m {
        for i in 0..=n_slope {
            let a = i as f64 / n_slope as f64;
            let base = [crest[0] * (1.0 - a), crest[1] * (1.0 - a)];
            let top = [top_crest[0] + a * (p[0] - top_crest[0]), top_crest[1] + a * (p[1] - top_crest[1])];
            let f = j as f64 / m as f64;
            nodes.push(NodeRow(slope_id(i, j), base[0] + f * (top[0] - base[0]), base[1] + f * (top[1] - base[1])));
        }
    }
    let mut elements = Vec::new();
    let mut element = |kind: SolidKind, nodes: Vec<u64>| {
        let id = elements.len() as u64 + 1;
        elements.push(SolidElementRow { id, kind, nodes, material: "cover".into() });
    };
    for j in 0..m {
        for i in 0..n_slope {
            element(
                SolidKind::Quad4,
                vec![slope_id(i, j), slope_id(i + 1, j), slope_id(i + 1, j + 1), slope_id(i, j + 1)],
            );
        }
    }
    // the passive wedge: rays from the nodes on O–P to T, quads but for a last column of triangles
    let toe_id = |i: usize, j: usize| match i {
        0 => slope_id(n_slope, j),
        i if i == n_toe => 50_000,
        i => (50_001 + j * n_toe + i) as u64,
    };
    if toe {
        nodes.push(NodeRow(50_000, t[0], t[1]));
        for j in 0..=m {
            let q = [0.0, j as f64 / m as f64 * p[1]];
            for i in 1..n_toe {
                let a = i as f64 / n_toe as f64;
                nodes.push(NodeRow(toe_id(i, j), q[0] + a * (t[0] - q[0]), q[1] + a * (t[1] - q[1])));
            }
        }
        for j in 0..m {
            for i in 0..n_toe - 1 {
                element(SolidKind::Quad4, vec![toe_id(i, j), toe_id(i + 1, j), toe_id(i + 1, j + 1), toe_id(i, j + 1)]);
            }
            element(SolidKind::Tri3, vec![toe_id(n_toe - 1, j), 50_000, toe_id(n_toe - 1, j + 1)]);
        }
    }
    // rigid bases: their own nodes, fixed, under the cover's base nodes
    let mut base_nodes: Vec<(u64, u64)> = (0..=n_slope).map(|i| (slope_id(i, 0), 100_000 + i as u64)).collect();
    let toe_base: Vec<(u64, u64)> = (0..=n_toe).map(|i| (toe_id(i, 0), 200_000 + i as u64)).collect();
    if toe {
        base_nodes.extend(toe_base.iter().copied());
    }
    let position: BTreeMap<u64, (f64, f64)> = nodes.iter().map(|n| (n.0, (n.1, n.2))).collect();
    for &(cover, base) in &base_nodes {
        let (x, y) = position[&cover];
        nodes.push(NodeRow(base, x, y));
    }
    let mut node_sets = BTreeMap::new();
    node_sets.insert("bases".into(), base_nodes.iter().map(|b| b.1).collect::<Vec<_>>());
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
        slave: Some((0..=n_slope).rev().map(|i| base_nodes[i].0).collect()),
        master: Some((0..=n_slope).rev().map(|i| base_nodes[i].1).collect()),
        master_normal: Some([-up_normal[0], -up_normal[1]]),
        law: coulomb(phi_i),
        ..Default::default()
    }];
    if toe {
        interfaces.push(InterfaceSpec {
            name: "toe".into(),
            slave: Some(toe_base.iter().rev().map(|b| b.0).collect()),
            master: Some(toe_base.iter().rev().map(|b| b.1).collect()),
            master_normal: Some([0.0, -1.0]),
            // the cohesion of the two-wedge method's passive wedge base, C = c·h / sin β
            law: ShearLawSpec::Coulomb { shear_stiffness: 5.0e4, cohesion: COVER_COHESION, friction_angle: phi_soil },
            ..Default::default()
        });
    }
    let mut file = geoslip::model::file::ModelFile {
        title: "lined slope".into(),
        materials: geoslip::model::file::Materials { soil, ..Default::default() },
        nodes,
        elements,
        node_sets,
        supports: vec![geoslip::meshgen::support("bases", &[Direction::X, Direction::Y])],
        stages: vec![
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
        analysis: AnalysisSettings {
            scheme: Scheme::Newton,
            max_iterations: 400,
            force_tolerance: 1e-6,
            displacement_tolerance: 1e-6,
            ..AnalysisSettings::default()
        },
        ..Default::default()
    };
    file.interfaces = interfaces;
    file
}

/// `lined_slope` with a geosynthetic parallel to the slope at mid-thickness of the cover, bonded
/// to it (`tie`), from the crest's end face to the vertical through O, pulled up the slope at its
/// head by `pull` [kN/m]: the two-wedge method's force T on the active wedge.
fn lined_slope_with_pull(beta_deg: f64, length: f64, phi_i: f64, phi_soil: f64, pull: f64) -> ModelFile {
    let mut file = lined_slope(beta_deg, length, true, phi_i, phi_soil, ReducedStrengths::SoilAndInterfaces);
    let n_slope = (length / H * 4.0).round() as usize;
    let mid_row = |i: usize| (1 + 2 * (n_slope + 1) + i) as u64; // slope_id(i, 2) of `lined_slope`
    file.materials.reinforcement.insert(
        "geogrid".into(),
        ReinforcementMaterial { axial_stiffness: 1000.0, tension_only: false, rupture_strength: None, weight: None },
    );
    file.interfaces.push(InterfaceSpec {
        name: "geogrid".into(),
        reinforcement: Some(ReinforcementPath {
            path: (0..=n_slope).map(mid_row).collect(),
            line: None,
            head: None,
            material: "geogrid".into(),
            stack: Vec::new(),
            free_length: None,
            mode: Default::default(),
        }),
        law: ShearLawSpec::Tie,
        ..Default::default()
    });
    let beta = beta_deg.to_radians();
    file.stages[0].loads.push(LoadSpec::Point {
        node: None,
        nodes: None,
        set: Some("geogrid.head".into()),
        fx: -pull * beta.cos(),
        fy: pull * beta.sin(),
    });
    file
}

/// The two-wedge factor of safety (docs/verification.md §7) of the tests' cover with a geosynthetic
/// force `t` parallel to the slope; `c_a` = 0 (the liner interface has no adhesion).
fn two_wedge(beta_deg: f64, length: f64, phi_i: f64, phi: f64, t: f64) -> f64 {
    common::two_wedge::Cover { gamma: GAMMA, h: H, c: COVER_COHESION, phi }.factor_of_safety(beta_deg, length, phi_i, t)
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
    let fs = factor_of_safety(&lined_slope(beta, 15.0 * H, false, phi_i, 35.0, ReducedStrengths::Interfaces));
    eprintln!("FS {fs:.4} against tan φ_i / tan β = {exact:.4}");
    common::doc_number("veneer.no-toe", format!("FS {fs:.4} (**{}**)", common::signed_percent(fs, exact, 2)));
    common::doc_number("veneer.no-toe-error", format!("{:.2} %", 100.0 * common::relative_error(fs, exact)));
    // measured −0.01 %; the search's bracket is 0.2 % wide, so 0.3 %
    assert!(common::relative_error(fs, exact) < 0.003, "FS {fs:.4} against tan φ_i / tan β = {exact:.4}");
}

/// The two-wedge method's L runs h / sin β past the toe corner O (its active wedge rests on
/// L − h/sin β of liner, its weight γh²(L/h − 1/sin β − tan β/2) is that of the cover above the liner
/// up to the vertical through O): the liner of the finite-element model is that shorter length.
fn liner_length(beta_deg: f64, two_wedge_length: f64) -> f64 {
    two_wedge_length - H / beta_deg.to_radians().sin()
}

/// The force T that the two-wedge method needs for a target FS (FS rises with T).
fn two_wedge_force(beta_deg: f64, length: f64, phi_i: f64, phi: f64, target: f64) -> f64 {
    let (mut low, mut high) = (0.0, 1.0);
    while two_wedge(beta_deg, length, phi_i, phi, high) < target {
        high *= 2.0;
    }
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if two_wedge(beta_deg, length, phi_i, phi, mid) < target {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

/// A geosynthetic pulling the active wedge up the slope with the force the two-wedge method needs
/// for a target FS gives that FS by strength reduction: 1.8 on a 2.5H:1V slope, 1.5 on 2H:1V, at
/// L/h = 15.
#[test]
fn the_two_wedge_geosynthetic_force_for_a_target_factor_of_safety_gives_that_factor() {
    let (phi_i, phi): (f64, f64) = (24.0, 35.0);
    let length = 15.0 * H;
    // measured +2.4 % and −0.1 % (docs/soil.md): the deforming cover is not the method's two rigid
    // wedges; about twice each, with the search's 0.2 % as a floor
    let mut measured = Vec::new();
    for (beta, target, tolerance) in [(21.8f64, 1.8, 0.05), (26.57, 1.5, 0.005)] {
        let unreinforced = two_wedge(beta, length, phi_i, phi, 0.0);
        assert!(unreinforced < 0.9 * target, "the slope needs the geosynthetic: FS {unreinforced:.3} without");
        let force = two_wedge_force(beta, length, phi_i, phi, target);
        let fs = factor_of_safety(&lined_slope_with_pull(beta, liner_length(beta, length), phi_i, phi, force));
        eprintln!("β = {beta}°: T = {force:.3} kN/m, FS {fs:.4} (target {target})");
        measured.push((fs, target));
        assert!(
            common::relative_error(fs, target) < tolerance,
            "β = {beta}°, T = {force:.3} kN/m: FS {fs:.4} against the two-wedge target {target}"
        );
    }
    let errors: Vec<String> = measured.iter().map(|&(fs, target)| common::signed_percent(fs, target, 1)).collect();
    let values: Vec<String> = measured.iter().map(|&(fs, _)| format!("{fs:.3}")).collect();
    common::doc_number("veneer.with-force", format!("FS {} (**{}**)", values.join(" and "), errors.join(", ")));
    let largest = measured.iter().map(|&(fs, target)| common::relative_error(fs, target)).fold(0.0, f64::max);
    common::doc_number("veneer.with-force-largest", format!("{:.1} %", 100.0 * largest));
}

/// The geosynthetic anchored at the crest instead (tension-only, EA = 1000 kN/m), with the two-wedge
/// force for FS = 1.35 on a 2H:1V slope as its rupture strength: the search finds FS within 3 % of
/// 1.35 (the grid at its strength there), and reports the rupture that ends it.
#[test]
fn an_anchored_geosynthetic_ruptures_at_the_two_wedge_factor_of_safety_for_its_strength() {
    let (phi_i, phi, beta, target): (f64, f64, f64, f64) = (24.0, 35.0, 26.57, 1.35);
    let length = 15.0 * H;
    let strength = two_wedge_force(beta, length, phi_i, phi, target);
    let mut file = lined_slope_with_pull(beta, liner_length(beta, length), phi_i, phi, 0.0);
    file.stages[0].loads.retain(|l| !matches!(l, LoadSpec::Point { .. }));
    file.stages[0].prescribed.push(common::prescribed("geogrid.head", Some(0.0), Some(0.0)));
    let grid = file.materials.reinforcement.get_mut("geogrid").unwrap();
    grid.axial_stiffness = 1000.0;
    grid.tension_only = true;
    grid.rupture_strength = Some(strength);
    file.analysis.force_tolerance = 1e-5;
    file.analysis.displacement_tolerance = 1e-5;
    let model = common::model(&file, "lined-slope.toml");
    let c = common::run(&model, Backend::Auto);
    let fs = c.factors_of_safety.last().expect("a strength-reduction stage reports its FS");
    let why = fs.failure.clone().unwrap_or_default();
    let t_max = c.steps.last().unwrap().1.bar_forces.iter().map(|b| b.axial_force).fold(0.0, f64::max);
    eprintln!("T_ult = {strength:.3} kN/m: FS {:.4}, T_max there {t_max:.3}; {why}", fs.value);
    common::doc_number(
        "veneer.rupture",
        format!("FS {:.3} (**{}**)", fs.value, common::signed_percent(fs.value, target, 1)),
    );
    // measured +1.4 % (docs/soil.md): twice that
    assert!(common::relative_error(fs.value, target) < 0.03, "FS {:.4} against {target}", fs.value);
    assert!(t_max > 0.95 * strength, "at FS the grid is near its strength: {t_max:.3} of {strength:.3} kN/m");
    assert!(why.contains("bars of geogrid"), "the failure names the ruptured geosynthetic: {why}");
}

/// L/h = 15, where the toe adds 25–40 % to tan φ_i / tan β: three slope angles, 3H:1V to 2H:1V.
#[test]
fn a_toe_gives_the_two_wedge_factor_of_safety_at_three_slope_angles() {
    let (phi_i, phi): (f64, f64) = (24.0, 35.0);
    let length = 15.0 * H;
    // measured +0.1 %, +1.5 % and +0.4 % (docs/soil.md): the deforming cover is not the method's two
    // rigid wedges; about twice each, with the search's 0.2 % as a floor
    let mut measured = Vec::new();
    for (beta, tolerance) in [(18.43f64, 0.005), (21.8, 0.03), (26.57, 0.008)] {
        let no_toe = phi_i.to_radians().tan() / f64::to_radians(beta).tan();
        let exact = two_wedge(beta, length, phi_i, phi, 0.0);
        assert!(exact > 1.2 * no_toe, "at this L/h the toe must matter: {exact} against {no_toe}");
        let model =
            lined_slope(beta, liner_length(beta, length), true, phi_i, phi, ReducedStrengths::SoilAndInterfaces);
        let fs = factor_of_safety(&model);
        eprintln!("β = {beta}°: FS {fs:.4} against the two-wedge {exact:.4}");
        measured.push((fs, exact));
        assert!(
            common::relative_error(fs, exact) < tolerance,
            "β = {beta}°: FS {fs:.4} against the two-wedge {exact:.4} (no toe: {no_toe:.4})"
        );
    }
    let errors: Vec<String> = measured.iter().map(|&(fs, exact)| common::signed_percent(fs, exact, 1)).collect();
    let values: Vec<String> = measured.iter().map(|&(fs, _)| format!("{fs:.3}")).collect();
    common::doc_number("veneer.toe", format!("{} (**{}**)", values.join(", "), errors.join(", ")));
    let largest = measured.iter().map(|&(fs, exact)| common::relative_error(fs, exact)).fold(0.0, f64::max);
    common::doc_number("veneer.toe-largest", format!("{:.1} %", 100.0 * largest));
}
