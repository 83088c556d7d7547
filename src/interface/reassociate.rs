//! Large slip: after each converged increment every slave point is associated again with the master
//! segment it now faces (DESIGN §1, "Large slip: re-association").
//!
//! - `segment` (default): closest-point projection of the slave's current position onto the deformed
//!   master face; the constraint row and the spring are rebuilt with that segment's N_i(ξ), so the
//!   tie moves smoothly between soil nodes.
//! - `nearest-node` (the paper's approximation): the same projection, then ξ snapped to the nearer
//!   end of the segment, so the tie jumps from one soil node to the next.
//!
//! The gap is computed from current positions, so the re-association itself causes no jump:
//! `gap0 = n·(X_r − Σ N_i X_i)` for the new segment makes g = gap0 + row·u equal to the current gap.
//! A point whose projection falls outside the master face has left the soil and loses contact. The
//! tributary length of each point is clipped to the part of the slave line that still faces the
//! master face, so the resistance falls smoothly as the embedded length shrinks. The law state
//! (slip, plastic slip, post-peak flag) is carried across.

use super::{ContactFace, Interface, NormalState};
use crate::mesh::{Mesh, NodeIndex};

/// One point moved to another master segment.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Reassociation {
    pub interface: String,
    pub face: String,
    pub slave_node: u64,
    /// Master nodes of the old and the new segment (`None`: out of contact).
    pub from: Option<[u64; 2]>,
    pub to: Option<[u64; 2]>,
    pub xi: f64,
}

fn current(mesh: &Mesh, u: &[f64], n: NodeIndex) -> [f64; 2] {
    let x = mesh.position(n);
    [x[0] + u[2 * n], x[1] + u[2 * n + 1]]
}

/// Arc-length coordinate of each segment's start along the deformed master path, and the path's
/// whole length.
fn arc_starts(mesh: &Mesh, u: &[f64], path: &[NodeIndex]) -> (Vec<f64>, f64) {
    let mut acc = 0.0;
    let mut starts = Vec::with_capacity(path.len().saturating_sub(1));
    for w in path.windows(2) {
        starts.push(acc);
        let (a, b) = (current(mesh, u, w[0]), current(mesh, u, w[1]));
        acc += ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    }
    (starts, acc)
}

/// Projection of `x` onto the deformed master path: (segment, ξ unclamped on it, arc-length
/// coordinate along the whole path, extended beyond its ends). `starts`: the path's
/// [`arc_starts`] (computed once for all the points of a face).
fn project_current(
    mesh: &Mesh,
    u: &[f64],
    path: &[NodeIndex],
    starts: &[f64],
    x: [f64; 2],
    keep: Option<usize>,
) -> (usize, f64, f64) {
    let seg = |s: usize| (current(mesh, u, path[s]), current(mesh, u, path[s + 1]));
    let raw_on = |s: usize| {
        let (a, b) = seg(s);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        (((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / len2, len2.sqrt())
    };
    let tol = 1e-9;
    // Stay on the current segment while the point is on it (no flip-flop at a shared node).
    if let Some(s) = keep.filter(|&s| s + 1 < path.len()) {
        let (raw, len) = raw_on(s);
        if (-tol..=1.0 + tol).contains(&raw) {
            return (s, raw.clamp(0.0, 1.0), starts[s] + raw.clamp(0.0, 1.0) * len);
        }
    }
    let mut best = (0usize, 0.0f64, f64::INFINITY, 0.0f64);
    for s in 0..path.len() - 1 {
        let (a, b) = seg(s);
        let (raw, len) = raw_on(s);
        let xi = raw.clamp(0.0, 1.0);
        let foot = [a[0] + xi * (b[0] - a[0]), a[1] + xi * (b[1] - a[1])];
        let dist = ((x[0] - foot[0]).powi(2) + (x[1] - foot[1]).powi(2)).sqrt();
        // beyond either end of the path, the arc coordinate extends linearly
        let arc = if (s == 0 && raw < 0.0) || (s + 2 == path.len() && raw > 1.0) {
            starts[s] + raw * len
        } else {
            starts[s] + xi * len
        };
        if dist < best.2 - 1e-14 * len {
            best = (s, raw, dist, arc);
        }
    }
    (best.0, best.1, best.3)
}

/// How a re-associated point is tied to the master face.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tie {
    /// To the master point it faces, N_i(ξ) on that segment.
    Segment,
    /// To the nearer node of that segment (the paper's approximation).
    NearestNode,
    /// To the master face averaged over the point's part of the slave line ([`dual_mortar_weights`]).
    Mortar,
}

/// Re-associate every point of every interface with the master segment it now faces. Returns the
/// points that moved to another segment (or out of contact).
pub fn reassociate(mesh: &Mesh, interfaces: &mut [Interface], u: &[f64], tie: Tie) -> Vec<Reassociation> {
    let mut log = Vec::new();
    for interface in interfaces.iter_mut() {
        if interface.is_tie() {
            continue; // a tie does not slide
        }
        let name = interface.name.clone();
        for face in interface.faces.iter_mut() {
            reassociate_face(mesh, &name, face, u, tie, &mut log);
        }
    }
    log
}

fn reassociate_face(
    mesh: &Mesh,
    interface: &str,
    face: &mut ContactFace,
    u: &[f64],
    tie: Tie,
    log: &mut Vec<Reassociation>,
) {
    let nearest_node = tie == Tie::NearestNode;
    let n_points = face.points.len();
    // Project every slave point on the deformed master face.
    let (starts, total) = arc_starts(mesh, u, &face.master);
    let projections: Vec<(usize, f64, f64)> = face
        .points
        .iter()
        .map(|p| {
            let keep = p.in_contact().then_some(p.segment);
            project_current(mesh, u, &face.master, &starts, current(mesh, u, p.slave), keep)
        })
        .collect();
    let arcs: Vec<f64> = projections.iter().map(|p| p.2).collect();
    // Tributary lengths clipped to what still faces the master face; a point keeps contact while
    // some of its tributary length does (it is then the integration point of that remainder).
    clip_face_tributaries(mesh, face, u, &arcs, total);
    for k in 0..n_points {
        let (segment, raw, arc) = projections[k];
        let beyond = arc < -1e-9 * total || arc > total * (1.0 + 1e-9);
        let point = &mut face.points[k];
        let outside = beyond && point.tributary <= 1e-12 * total;
        let from = point
            .in_contact()
            .then(|| [mesh.node_id(face.master[point.segment]), mesh.node_id(face.master[point.segment + 1])]);
        if outside {
            if !matches!(point.normal_state, NormalState::Outside | NormalState::Held { outside: true }) {
                point.normal_state = NormalState::Outside;
                log.push(Reassociation {
                    interface: interface.to_string(),
                    face: face.label.clone(),
                    slave_node: mesh.node_id(point.slave),
                    from,
                    to: None,
                    xi: raw,
                });
            }
            continue;
        }
        let mut xi = raw.clamp(0.0, 1.0);
        if nearest_node {
            xi = if xi < 0.5 { 0.0 } else { 1.0 };
        }
        let moved = segment != point.segment || (nearest_node && xi != point.xi);
        let was_outside = matches!(point.normal_state, NormalState::Outside | NormalState::Held { outside: true });
        point.segment = segment;
        point.xi = xi;
        if was_outside {
            point.normal_state = NormalState::Released; // back over the face: contact when the gap closes
        }
        if moved || was_outside {
            log.push(Reassociation {
                interface: interface.to_string(),
                face: face.label.clone(),
                slave_node: mesh.node_id(point.slave),
                from,
                to: Some([mesh.node_id(face.master[segment]), mesh.node_id(face.master[segment + 1])]),
                xi,
            });
        }
    }
    if tie == Tie::Mortar {
        let master_arcs = node_arcs(mesh, u, &face.master);
        for k in 0..n_points {
            let outside =
                matches!(face.points[k].normal_state, NormalState::Outside | NormalState::Held { outside: true });
            face.points[k].weights = if outside { None } else { dual_mortar_weights(&master_arcs, &arcs, k) };
        }
    }
    set_gap_offsets(mesh, face);
}

/// Gap offsets for the points' current ties: g = gap0 + row·u is the current gap.
fn set_gap_offsets(mesh: &Mesh, face: &mut ContactFace) {
    for k in 0..face.points.len() {
        let p = &face.points[k];
        let n = face.normal(mesh, p.segment);
        let m = face.tied_position(mesh, p);
        let xr = mesh.position(p.slave);
        face.points[k].gap0 = n[0] * (xr[0] - m[0]) + n[1] * (xr[1] - m[1]);
    }
}

/// Arc-length coordinate of every node of the deformed master path.
fn node_arcs(mesh: &Mesh, u: &[f64], path: &[NodeIndex]) -> Vec<f64> {
    let mut arcs = Vec::with_capacity(path.len());
    let mut acc = 0.0;
    arcs.push(0.0);
    for w in path.windows(2) {
        let (a, b) = (current(mesh, u, w[0]), current(mesh, u, w[1]));
        acc += ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        arcs.push(acc);
    }
    arcs
}

/// The master weights of slave point `k` by the dual mortar method (Wohlmuth 2000; Popp et al.
/// 2010 for contact): its row averages the gap over the slave segments either side of it with the
/// dual basis ψ_k (2 − 3η at its own end of a segment, 3η − 1 at the other), so that
/// D_kk = ∫ψ_k N_k is its tributary length and M_kj = ∫ψ_k N_j the master nodes' shares; the weights
/// are M_kj / Σ_j M_kj. `master_arcs` and `slave_arcs` are arc-length coordinates along the master
/// path (the slave points' projections). On a slave line matching the master nodes the weights are
/// those of node-to-segment. `None` where the point's segments reach beyond the master path (the
/// point then stays node-to-segment) or have no length.
pub fn dual_mortar_weights(master_arcs: &[f64], slave_arcs: &[f64], k: usize) -> Option<Vec<(usize, f64)>> {
    let (first, last) = (master_arcs[0], *master_arcs.last()?);
    let tol = 1e-9 * (last - first).abs().max(f64::MIN_POSITIVE);
    let hat = |j: usize, a: f64| -> f64 {
        let x = master_arcs[j];
        if j > 0 && a >= master_arcs[j - 1] && a <= x {
            (a - master_arcs[j - 1]) / (x - master_arcs[j - 1])
        } else if j + 1 < master_arcs.len() && a >= x && a <= master_arcs[j + 1] {
            (master_arcs[j + 1] - a) / (master_arcs[j + 1] - x)
        } else {
            0.0
        }
    };
    let mut m = vec![0.0; master_arcs.len()];
    let neighbours = [k.checked_sub(1), (k + 1 < slave_arcs.len()).then_some(k + 1)];
    for other in neighbours.into_iter().flatten() {
        let (own, far) = (slave_arcs[k], slave_arcs[other]);
        if (far - own).abs() <= tol {
            return None;
        }
        let (lo, hi) = (own.min(far), own.max(far));
        if lo < first - tol || hi > last + tol {
            return None;
        }
        // ψ_k along this segment, η = 0 at the point itself
        let psi = |a: f64| 2.0 - 3.0 * (a - own) / (far - own);
        // pieces between the master nodes inside [lo, hi]: ψ_k·N_j is quadratic on each (Simpson)
        let mut cuts: Vec<f64> = master_arcs.iter().copied().filter(|&x| x > lo && x < hi).collect();
        cuts.insert(0, lo);
        cuts.push(hi);
        for piece in cuts.windows(2) {
            let (p, q) = (piece[0], piece[1]);
            let mid = 0.5 * (p + q);
            for (j, mj) in m.iter_mut().enumerate() {
                let f = |a: f64| psi(a) * hat(j, a);
                let (fp, fm, fq) = (f(p), f(mid), f(q));
                if fp != 0.0 || fm != 0.0 || fq != 0.0 {
                    *mj += (q - p) / 6.0 * (fp + 4.0 * fm + fq);
                }
            }
        }
    }
    let d: f64 = m.iter().sum();
    if !(d > tol) {
        return None;
    }
    // (round-off shares of nodes the point does not reach, as on matching nodes, are dropped)
    Some(m.iter().enumerate().filter(|(_, &c)| c.abs() > 1e-12 * d).map(|(j, &c)| (j, c / d)).collect())
}

/// Clip every tributary length to the part of the slave line that now faces the master face, at the
/// current displacements (called in every iteration: the embedded length changes as the slave
/// slides, and the resistance must follow it within the increment, not one increment late).
pub fn clip_tributaries(mesh: &Mesh, interfaces: &mut [Interface], u: &[f64]) {
    for interface in interfaces.iter_mut() {
        if interface.is_tie() {
            continue;
        }
        for face in interface.faces.iter_mut() {
            let (starts, total) = arc_starts(mesh, u, &face.master);
            let arcs: Vec<f64> = face
                .points
                .iter()
                .map(|p| {
                    let x = current(mesh, u, p.slave);
                    project_current(mesh, u, &face.master, &starts, x, Some(p.segment)).2
                })
                .collect();
            clip_face_tributaries(mesh, face, u, &arcs, total);
        }
    }
}

/// Each point's (DOF, ∂ℓ/∂u) on one face.
pub type FaceRates = Vec<Vec<(usize, f64)>>;

/// How each point's tributary length, as [`clip_tributaries`] sets it, changes with the
/// displacements of the slave nodes: for each interface, face and point, (DOF, ∂ℓ/∂u) over the two
/// DOFs of the point's slave node and of its neighbours' (always these DOFs, zero where nothing
/// changes). ℓ follows the slave line's current length, the part of it that faces the master face
/// and, in axisymmetry, the radius. The master path's own movement (a soil strain's share of the
/// change) is left out. Empty for a tie, whose points have no spring.
pub fn tributary_rates(mesh: &Mesh, interfaces: &[Interface], u: &[f64]) -> Vec<Vec<FaceRates>> {
    interfaces
        .iter()
        .map(|interface| {
            interface
                .faces
                .iter()
                .map(|face| {
                    if interface.is_tie() {
                        vec![Vec::new(); face.points.len()]
                    } else {
                        face_tributary_rates(mesh, face, u)
                    }
                })
                .collect()
        })
        .collect()
}

/// Whether the arc of a point projected on `segment` of a path of `nodes` nodes at `raw`
/// (unclamped ξ, or clamped by a kept segment) moves with the point, by the segment's unit tangent:
/// on the segment, or beyond either end of the path; not where it is held at a node.
fn arc_moves(nodes: usize, segment: usize, raw: f64) -> bool {
    (raw > 0.0 && raw < 1.0) || (segment == 0 && raw < 0.0) || (segment + 2 == nodes && raw > 1.0)
}

/// [`tributary_rates`] of one face: the derivative of [`clip_face_tributaries`] by the slave nodes,
/// and, where a segment of the slave line is clipped, by the master path's nodes, which place the
/// ends of the part that faces the master face (the turning of a segment under a point off it, a
/// gap's share, is left out).
fn face_tributary_rates(mesh: &Mesh, face: &ContactFace, u: &[f64]) -> FaceRates {
    let n_points = face.points.len();
    let node_dofs = |n: NodeIndex| [2 * n, 2 * n + 1];
    let slave_dofs = |k: usize| node_dofs(face.points[k].slave);
    let mut rates: Vec<Vec<(usize, f64)>> = (0..n_points)
        .map(|k| (k.saturating_sub(1)..(k + 2).min(n_points)).flat_map(slave_dofs).map(|d| (d, 0.0)).collect())
        .collect();
    if n_points < 2 || face.master.len() < 2 {
        return rates;
    }
    let unit = |a: NodeIndex, b: NodeIndex| {
        let (xa, xb) = (current(mesh, u, a), current(mesh, u, b));
        let d = [xb[0] - xa[0], xb[1] - xa[1]];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if len > 0.0 {
            [d[0] / len, d[1] / len]
        } else {
            [0.0, 0.0]
        }
    };
    // each master segment's unit tangent: the path's length and every arc measured from its first
    // node move with them
    let tangents: Vec<[f64; 2]> = face.master.windows(2).map(|w| unit(w[0], w[1])).collect();
    // ∂total/∂x of master node i: t_{i−1} − t_i (t_{−1} = t_{last+1} = 0)
    let total_rate = |i: usize, axis: usize| {
        let before = if i > 0 { tangents[i - 1][axis] } else { 0.0 };
        let after = tangents.get(i).map_or(0.0, |t| t[axis]);
        before - after
    };
    // each point's arc, ∂arc/∂x of its slave node, and the segment and ξ it projects on
    let (starts, total) = arc_starts(mesh, u, &face.master);
    let projections: Vec<(f64, [f64; 2], usize, f64)> = face
        .points
        .iter()
        .map(|p| {
            let (segment, raw, arc) =
                project_current(mesh, u, &face.master, &starts, current(mesh, u, p.slave), Some(p.segment));
            let rate = if arc_moves(face.master.len(), segment, raw) { tangents[segment] } else { [0.0; 2] };
            (arc, rate, segment, raw)
        })
        .collect();
    // ∂arc/∂x of master node i for a point on `segment` at `raw`: the arc to the segment's start
    // (Σ of the lengths before it) and the projection on it, (x − x_a)·t_a
    let arc_master_rate = |i: usize, axis: usize, segment: usize, raw: f64| {
        // held at the path's first node: always 0
        if segment == 0 && raw == 0.0 {
            return 0.0;
        }
        let moving = arc_moves(face.master.len(), segment, raw);
        if i < segment {
            total_rate(i, axis)
        } else if i == segment {
            // the arc to the segment's start grows with t_{a−1}; the projection falls with t_a
            let before = if i > 0 { tangents[i - 1][axis] } else { 0.0 };
            before - if moving || raw >= 1.0 { tangents[i][axis] } else { 0.0 }
        } else if i == segment + 1 && !moving && raw >= 1.0 {
            // held at the segment's end node: the arc to that node
            tangents[segment][axis]
        } else {
            0.0
        }
    };
    let geometry = mesh.geometry;
    let mut add = |point: usize, dof: usize, value: f64| match rates[point].iter_mut().find(|(d, _)| *d == dof) {
        Some(entry) => entry.1 += value,
        None => rates[point].push((dof, value)),
    };
    for k in 0..n_points - 1 {
        let (xa, xb) = (current(mesh, u, face.points[k].slave), current(mesh, u, face.points[k + 1].slave));
        let d = [xb[0] - xa[0], xb[1] - xa[1]];
        let length = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let along = if length > 0.0 { [d[0] / length, d[1] / length] } else { [0.0, 0.0] };
        let ((sa, rate_a, seg_a, raw_a), (sb, rate_b, seg_b, raw_b)) = (projections[k], projections[k + 1]);
        // (e0, e1) as clip_face_tributaries finds them, and their derivatives by (sa, sb, total)
        let (e0, de0, e1, de1) = if (sb - sa).abs() < 1e-15 * total.max(1e-300) {
            let inside = (0.0..=total).contains(&sa);
            (0.0, [0.0; 3], if inside { 1.0 } else { 0.0 }, [0.0; 3])
        } else {
            let span = sb - sa;
            let (ea, eb) = ((0.0 - sa) / span, (total - sa) / span);
            let dea = [-sb / (span * span), sa / (span * span), 0.0];
            let deb = [(total - sb) / (span * span), -(total - sa) / (span * span), 1.0 / span];
            let ((lo, dlo), (hi, dhi)) = if ea <= eb { ((ea, dea), (eb, deb)) } else { ((eb, deb), (ea, dea)) };
            let clamped =
                |e: f64, de: [f64; 3]| if e > 0.0 && e < 1.0 { (e, de) } else { (e.clamp(0.0, 1.0), [0.0; 3]) };
            let ((lo, dlo), (hi, dhi)) = (clamped(lo, dlo), clamped(hi, dhi));
            (lo, dlo, hi, dhi)
        };
        let (ca, cb) = (geometry.circumference(xa), geometry.circumference(xb));
        // the circumference is linear in the position: its change over a unit step
        let rate_c = |x: [f64; 2]| {
            let c = geometry.circumference(x);
            [geometry.circumference([x[0] + 1.0, x[1]]) - c, geometry.circumference([x[0], x[1] + 1.0]) - c]
        };
        let (gca, gcb) = (rate_c(xa), rate_c(xb));
        let w_far = ca * (e1 * e1 - e0 * e0) / 2.0 + (cb - ca) * (e1 * e1 * e1 - e0 * e0 * e0) / 3.0;
        let w_near = ca * (e1 - e0) + (cb - ca) * (e1 * e1 - e0 * e0) / 2.0 - w_far;
        // partial derivatives of w_far and w_near by e0, e1, ca, cb
        let far = [
            -ca * e0 - (cb - ca) * e0 * e0,
            ca * e1 + (cb - ca) * e1 * e1,
            (e1 * e1 - e0 * e0) / 2.0 - (e1 * e1 * e1 - e0 * e0 * e0) / 3.0,
            (e1 * e1 * e1 - e0 * e0 * e0) / 3.0,
        ];
        let near = [
            -ca - (cb - ca) * e0 - far[0],
            ca + (cb - ca) * e1 - far[1],
            (e1 - e0) - (e1 * e1 - e0 * e0) / 2.0 - far[2],
            (e1 * e1 - e0 * e0) / 2.0 - far[3],
        ];
        // one coordinate's change: of the segment's length, of (sa, sb, total), of (ca, cb)
        let mut each = |dof: usize, d_length: f64, d_s: [f64; 3], d_c: [f64; 2]| {
            let d_e0: f64 = de0.iter().zip(&d_s).map(|(a, b)| a * b).sum();
            let d_e1: f64 = de1.iter().zip(&d_s).map(|(a, b)| a * b).sum();
            let change = [d_e0, d_e1, d_c[0], d_c[1]];
            let d_far: f64 = far.iter().zip(&change).map(|(a, b)| a * b).sum();
            let d_near: f64 = near.iter().zip(&change).map(|(a, b)| a * b).sum();
            add(k, dof, d_near * length + w_near * d_length);
            add(k + 1, dof, d_far * length + w_far * d_length);
        };
        for axis in 0..2 {
            each(slave_dofs(k)[axis], -along[axis], [rate_a[axis], 0.0, 0.0], [gca[axis], 0.0]);
            each(slave_dofs(k + 1)[axis], along[axis], [0.0, rate_b[axis], 0.0], [0.0, gcb[axis]]);
        }
        // a clipped segment's ends move with the master path's nodes
        if de0 != [0.0; 3] || de1 != [0.0; 3] {
            for (i, &node) in face.master.iter().enumerate() {
                for axis in 0..2 {
                    let d_s = [
                        arc_master_rate(i, axis, seg_a, raw_a),
                        arc_master_rate(i, axis, seg_b, raw_b),
                        total_rate(i, axis),
                    ];
                    if d_s != [0.0; 3] {
                        each(node_dofs(node)[axis], 0.0, d_s, [0.0; 2]);
                    }
                }
            }
        }
    }
    rates
}

fn clip_face_tributaries(mesh: &Mesh, face: &mut ContactFace, u: &[f64], arcs: &[f64], total: f64) {
    let n_points = face.points.len();
    let mut tributary = vec![0.0; n_points];
    for k in 0..n_points.saturating_sub(1) {
        let (xa, xb) = (current(mesh, u, face.points[k].slave), current(mesh, u, face.points[k + 1].slave));
        let length = ((xb[0] - xa[0]).powi(2) + (xb[1] - xa[1]).powi(2)).sqrt();
        let (sa, sb) = (arcs[k], arcs[k + 1]);
        // the part of the segment (η from 0 at point k to 1 at point k + 1) whose arc is in [0, total]
        let (e0, e1) = if (sb - sa).abs() < 1e-15 * total.max(1e-300) {
            if (0.0..=total).contains(&sa) {
                (0.0, 1.0)
            } else {
                (0.0, 0.0)
            }
        } else {
            let ea = (0.0 - sa) / (sb - sa);
            let eb = (total - sa) / (sb - sa);
            let (lo, hi) = (ea.min(eb).clamp(0.0, 1.0), ea.max(eb).clamp(0.0, 1.0));
            (lo, hi)
        };
        // the circumference (1 in plane strain, 2πr in axisymmetry) is linear along the segment:
        // c(η) = ca + (cb − ca)·η
        let (ca, cb) = (mesh.geometry.circumference(xa), mesh.geometry.circumference(xb));
        let w_far = ca * (e1 * e1 - e0 * e0) / 2.0 + (cb - ca) * (e1 * e1 * e1 - e0 * e0 * e0) / 3.0; // ∫ η c dη
        let w_near = ca * (e1 - e0) + (cb - ca) * (e1 * e1 - e0 * e0) / 2.0 - w_far; // ∫ (1 − η) c dη
        tributary[k] += w_near * length;
        tributary[k + 1] += w_far * length;
    }
    for (p, t) in face.points.iter_mut().zip(tributary) {
        if n_points > 1 {
            p.tributary = t;
        }
    }
}

/// Uncover the slit behind each reinforcement's tail: slit points the tail has slid past become
/// ordinary (released) soil-to-soil contact points, which close as soon as the faces overlap.
/// Returns the points uncovered.
pub fn uncover_slits(mesh: &Mesh, interfaces: &mut [Interface], u: &[f64]) -> Vec<Reassociation> {
    let mut tails = Vec::new();
    for (i, slit) in interfaces.iter().enumerate() {
        let Some(r) = slit.slit_of else { continue };
        let Some(tail) = interfaces[r].faces.first().and_then(|f| f.points.last()).map(|p| p.slave) else { continue };
        let face = &slit.faces[0];
        let (starts, total) = arc_starts(mesh, u, &face.master);
        let (_, _, tail_arc) = project_current(mesh, u, &face.master, &starts, current(mesh, u, tail), None);
        tails.push((i, tail_arc, total));
    }
    let mut log = Vec::new();
    for (i, tail_arc, total) in tails {
        let name = interfaces[i].name.clone();
        let face = &mut interfaces[i].faces[0];
        let (starts, _) = arc_starts(mesh, u, &face.master);
        for k in 0..face.points.len() {
            if !matches!(face.points[k].normal_state, NormalState::Covered) {
                continue;
            }
            let x = current(mesh, u, face.points[k].slave);
            let (segment, raw, arc) = project_current(mesh, u, &face.master, &starts, x, Some(face.points[k].segment));
            if arc > tail_arc + 1e-9 * total {
                let p = &mut face.points[k];
                p.normal_state = NormalState::Released;
                p.weights = None;
                p.segment = segment;
                p.xi = raw.clamp(0.0, 1.0);
                let n = face.normal(mesh, segment);
                let m = face.tied_position(mesh, &face.points[k]);
                let xr = mesh.position(face.points[k].slave);
                let xi = face.points[k].xi;
                face.points[k].gap0 = n[0] * (xr[0] - m[0]) + n[1] * (xr[1] - m[1]);
                log.push(Reassociation {
                    interface: name.clone(),
                    face: "slit".into(),
                    slave_node: mesh.node_id(face.points[k].slave),
                    from: None,
                    to: Some([mesh.node_id(face.master[segment]), mesh.node_id(face.master[segment + 1])]),
                    xi,
                });
            }
        }
    }
    log
}

#[cfg(test)]
mod tests {
    //! The dual mortar weights against what the dual basis guarantees (Wohlmuth 2000, §2):
    //! ∫ψ_k N_l = δ_kl ∫N_k, so a master face matching the slave line gives node-to-node weights, and
    //! any linear field of the master face is reproduced at the slave point.
    use super::dual_mortar_weights;

    #[test]
    fn matching_nodes_give_node_to_node_weights() {
        let master = [0.0, 0.1, 0.2, 0.3, 0.4];
        for k in 0..master.len() {
            let w = dual_mortar_weights(&master, &master, k).unwrap();
            assert_eq!(w.len(), 1, "point {k}: {w:?}");
            assert_eq!(w[0].0, k);
            assert!((w[0].1 - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn a_slid_line_reproduces_linear_fields_at_its_points() {
        // the slave line slid by 0.37 of a master segment, graded master spacing
        let master = [0.0, 0.05, 0.11, 0.18, 0.26, 0.35, 0.45];
        let slave: Vec<f64> = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3].iter().map(|a| a + 0.37 * 0.05).collect();
        for k in 0..slave.len() {
            let w = dual_mortar_weights(&master, &slave, k).unwrap();
            let total: f64 = w.iter().map(|(_, c)| c).sum();
            assert!((total - 1.0).abs() < 1e-13, "point {k}: weights sum to {total}");
            // x(a) = 3 + 2a: Σ w_j x(m_j) = x(a_k)
            let at: f64 = w.iter().map(|&(j, c)| c * (3.0 + 2.0 * master[j])).sum();
            assert!((at - (3.0 + 2.0 * slave[k])).abs() < 1e-13, "point {k}: {at}");
            // more than the one segment it faces: the tie is averaged
            assert!(w.len() >= 2);
        }
        // a point whose segments reach beyond the master face stays node-to-segment
        let beyond: Vec<f64> = slave.iter().map(|a| a + 0.2).collect();
        assert!(dual_mortar_weights(&master, &beyond, beyond.len() - 1).is_none());
    }
}
