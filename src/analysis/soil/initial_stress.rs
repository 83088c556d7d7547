//! The K0 initial stresses of the present soil, from the weight of the soil above each Gauss point.

use super::kinematics::add_bt_sigma;
use super::setup::{element_points, element_u, SoilSetup};
use crate::element::mohr_coulomb::YieldState;
use crate::element::soil_state::{PointState, SoilField};
use crate::model::Model;
use rayon::prelude::*;

/// The K0 initial stresses of every present element: at each Gauss point, σv is the weight of the
/// present soil in the vertical line above it (saturated below the water table), σ′v = σv − p,
/// σ′h = σ′zz = K0·σ′v and no shear. Exact for horizontal ground and layers; elsewhere the stresses
/// are not in equilibrium and the stage's iterations correct them.
pub fn set_k0(model: &Model, setup: &SoilSetup, field: &mut SoilField, u: &[f64]) {
    let mesh = &model.mesh;
    // The x-range and corner polygon of every present element, in buckets along x.
    let polygons: Vec<Option<Vec<[f64; 2]>>> = mesh
        .solids
        .iter()
        .zip(field.elements())
        .map(|(e, st)| st.active.then(|| e.nodes[..e.kind.corner_count()].iter().map(|&n| mesh.position(n)).collect()))
        .collect();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for poly in polygons.iter().flatten() {
        for q in poly {
            lo = lo.min(q[0]);
            hi = hi.max(q[0]);
        }
    }
    if !(hi >= lo) {
        return;
    }
    let count = ((polygons.iter().flatten().count() as f64).sqrt().ceil() as usize).max(1);
    let width = ((hi - lo) / count as f64).max(f64::MIN_POSITIVE);
    let bucket = |x: f64| (((x - lo) / width) as usize).min(count - 1);
    let mut buckets: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (s, poly) in polygons.iter().enumerate() {
        if let Some(poly) = poly {
            let (a, b) = poly.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| (a.min(q[0]), b.max(q[0])));
            for k in bucket(a)..=bucket(b) {
                buckets[k].push(s);
            }
        }
    }
    let water = field.water.clone();
    let vertical_stress = |x: [f64; 2]| -> f64 {
        let mut sigma = 0.0;
        for &s in &buckets[bucket(x[0])] {
            let poly = polygons[s].as_ref().expect("bucketed elements are present");
            let Some((y0, y1)) = vertical_chord(poly, x[0]) else { continue };
            let (from, to) = (y0.max(x[1]), y1);
            if to <= from {
                continue;
            }
            let m = model.soil(s);
            match &water {
                Some(w) => {
                    let h = w.level_at(x[0]);
                    let wet = (to.min(h) - from).max(0.0);
                    let dry = (to - from) - wet;
                    sigma += m.saturated_weight() * wet + m.unit_weight * dry;
                }
                None => sigma += m.unit_weight * (to - from),
            }
        }
        sigma
    };
    let stresses: Vec<Option<(Vec<PointState>, Vec<f64>)>> = (0..mesh.solids.len())
        .into_par_iter()
        .map(|s| {
            if !field.elements()[s].active {
                return None;
            }
            let points = element_points(model, &mesh.solids[s], setup.rule);
            let k0 = model.soil(s).k0();
            let mut force = vec![0.0; setup.dofs[s].len()];
            let states = points
                .iter()
                .map(|p| {
                    let pore = water.as_ref().map_or(0.0, |w| w.pressure(p.x));
                    let sv = vertical_stress(p.x) - pore;
                    let stress = [-k0 * sv, -sv, 0.0, -k0 * sv];
                    add_bt_sigma(p, stress, &mut force);
                    PointState {
                        stress,
                        plastic_strain: 0.0,
                        yield_state: YieldState::Elastic,
                        largest_stress_state: 0.0,
                        shear_hardening: 0.0,
                        preconsolidation: 0.0,
                    }
                })
                .collect();
            Some((states, force))
        })
        .collect();
    for (s, st) in stresses.into_iter().enumerate() {
        if let Some((points, force)) = st {
            let e = &mut field.elements_mut()[s];
            e.points = points;
            e.placed = Some(element_u(&setup.dofs[s], u));
            e.reference_force = if setup.is_plastic(s) { None } else { Some(force) };
        }
    }
}

/// The interval of y that the vertical line at `x` cuts from a convex polygon.
fn vertical_chord(poly: &[[f64; 2]], x: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let (xa, xb) = (a[0].min(b[0]), a[0].max(b[0]));
        if x < xa || x > xb {
            continue;
        }
        if xb - xa <= 1e-14 * (1.0 + xb.abs()) {
            lo = lo.min(a[1].min(b[1]));
            hi = hi.max(a[1].max(b[1]));
        } else {
            let y = a[1] + (x - a[0]) / (b[0] - a[0]) * (b[1] - a[1]);
            lo = lo.min(y);
            hi = hi.max(y);
        }
    }
    (hi >= lo).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::vertical_chord;

    #[test]
    fn vertical_chord_of_a_quadrilateral() {
        let quad = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 2.0]];
        let (lo, hi) = vertical_chord(&quad, 1.0).unwrap();
        assert!((lo - 0.0).abs() < 1e-15 && (hi - 1.5).abs() < 1e-15);
        assert!(vertical_chord(&quad, 2.5).is_none());
        let (lo, hi) = vertical_chord(&quad, 2.0).unwrap();
        assert!((lo - 0.0).abs() < 1e-15 && (hi - 1.0).abs() < 1e-15);
    }
}
