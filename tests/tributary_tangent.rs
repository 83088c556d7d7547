//! The tributary lengths' derivative that Newton's tangent takes under large slip.
//!
//! Reference: the tributary lengths themselves. `reassociate::tributary_rates` must be the
//! derivative of what `reassociate::clip_tributaries` sets, so central differences of the latter
//! (steps of 1e-7 m, truncation error O(h²)) must agree with it, on the issue #15 pull-out box with
//! the grid stretched and pulled until its head has crossed the front face (the head's segment
//! clipped) and in axisymmetry (the circumference changing along the segment).
//!
//! Model: the generated pull-out box, its grid's nodes moved by u_x = −a − b·x (a = 3 cm, so the
//! head segment straddles the front face; b = 1 %, a stretch), the soil's by a small smooth
//! stretch u_x = 1e-4·sin(1.3·x), and once bent by u_y = 3e-4·sin(2x); the grid's nodes lie on
//! the master path, as the rows hold them (the derivative leaves out the turning of a segment under
//! a point off it, a gap's share).

mod common;

use geoslip::interface::reassociate::{clip_tributaries, tributary_rates};
use geoslip::meshgen::PullOutBox;

fn check(axisymmetric: bool, curved: bool) {
    let file = PullOutBox { nx: 20, ny_half: 3, ..common::issue_pullout_box() }.model();
    let mut model = common::model(&file, "tributaries.toml");
    if axisymmetric {
        // (the lengths alone: the box's supports, which an axisymmetric model would need on its
        // axis, play no part)
        model.mesh.geometry = geoslip::element::geometry::Geometry::Axisymmetric;
    }
    let grid: Vec<usize> = model.node_sets["grid.reinforcement"].clone();
    let mut u = vec![0.0; 2 * model.mesh.nodes.len()];
    for n in 0..model.mesh.nodes.len() {
        let x = model.mesh.position(n);
        // the soil: a small smooth stretch along the grid, and a bend of its master paths
        u[2 * n] = 1e-4 * (x[0] * 1.3).sin();
        if curved {
            u[2 * n + 1] = 3e-4 * (x[0] * 2.0).sin();
            // the master paths' second node moved 5 cm towards the front face, so that the point
            // beside the clipped head segment lies on the paths' second segment: its arc then
            // moves with the nodes before it
            if (x[0] - 0.1).abs() < 1e-9 && (x[1] - 0.5).abs() < 1e-9 && !grid.contains(&n) {
                u[2 * n] -= 0.05;
            }
        }
    }
    // the slit's soil-to-soil points shifted by 2e-5 m, so that none sits exactly on a node of its
    // master path (a kink of the clipped lengths, whose two one-sided derivatives a central
    // difference averages)
    for face in model.interfaces.iter().flat_map(|i| &i.faces) {
        for p in face.points.iter().filter(|p| !grid.contains(&p.slave)) {
            u[2 * p.slave] += 2e-5;
        }
    }
    // the grid's points on the (deformed) master path, extended beyond its ends, as the rows hold
    // them
    let path = &model.interfaces[0].faces[0].master;
    let at = |n: usize, u: &[f64]| {
        let x = model.mesh.position(n);
        [x[0] + u[2 * n], x[1] + u[2 * n + 1]]
    };
    let soil = u.clone();
    for &n in &grid {
        let x = model.mesh.position(n);
        u[2 * n] = -0.03 - 0.01 * x[0];
        let xc = x[0] + u[2 * n];
        let k = (0..path.len() - 1).find(|&k| at(path[k + 1], &soil)[0] > xc).unwrap_or(path.len() - 2);
        let (a, b) = (at(path[k], &soil), at(path[k + 1], &soil));
        u[2 * n + 1] = a[1] + (b[1] - a[1]) * (xc - a[0]) / (b[0] - a[0]) - x[1];
    }
    let rates = tributary_rates(&model.mesh, &model.interfaces, &u);
    let lengths = |u: &[f64]| {
        let mut interfaces = model.interfaces.clone();
        clip_tributaries(&model.mesh, &mut interfaces, u);
        interfaces
    };
    let h = 1e-7;
    let mut checked = 0;
    let mut clipped = false;
    let base = lengths(&u);
    for (i, interface) in base.iter().enumerate() {
        for (f, face) in interface.faces.iter().enumerate() {
            for (p, point) in face.points.iter().enumerate() {
                let full = model.interfaces[i].faces[f].points[p].tributary;
                clipped |= point.tributary < 0.9 * full && point.tributary > 0.0;
                // (a DOF may appear twice, as a slave node and a master path's end: summed)
                let mut by_dof = std::collections::BTreeMap::new();
                for &(dof, rate) in &rates[i][f][p] {
                    *by_dof.entry(dof).or_insert(0.0) += rate;
                }
                for (dof, rate) in by_dof {
                    let (mut up, mut down) = (u.clone(), u.clone());
                    up[dof] += h;
                    down[dof] -= h;
                    let difference = (lengths(&up)[i].faces[f].points[p].tributary
                        - lengths(&down)[i].faces[f].points[p].tributary)
                        / (2.0 * h);
                    let scale = 1.0f64.max(difference.abs());
                    assert!(
                        (rate - difference).abs() <= 1e-6 * scale,
                        "interface {i} face {f} point {p}, DOF {dof}: rate {rate}, central difference {difference}"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 100, "{checked} derivatives checked");
    assert!(clipped, "a point's tributary is clipped at the front face");
}

#[test]
fn tributary_rates_are_the_derivative_of_the_clipped_lengths_in_plane_strain() {
    check(false, false);
}

#[test]
fn tributary_rates_are_the_derivative_of_the_clipped_lengths_on_a_bent_master_path() {
    check(false, true);
}

#[test]
fn tributary_rates_are_the_derivative_of_the_clipped_lengths_in_axisymmetry() {
    check(true, false);
}
