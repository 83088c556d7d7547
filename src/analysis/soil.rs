//! The soil through a run: which elements are present, the effective stresses at their Gauss points,
//! the pore pressures, the soil's weight, and the forces and tangents all of these give.
//!
//! Total stress is σ = σ′ − p·m, with m = (1, 1, 0, 1) and p the pore pressure (compression
//! positive); the internal force of an element is ∫Bᵀσ′ dA − ∫Bᵀm·p dA.
//! - A linear-elastic element keeps a reference state (its stresses when placed or given K0
//!   stresses, and its displacements then): σ′ = σ′₀ + D·B·(u − u₀), so its force is
//!   ∫Bᵀσ′₀ dA + K_e·(u − u₀) and K_e is computed once.
//! - A Mohr–Coulomb or Duncan–Chang element keeps the committed σ′ at each Gauss point (and a
//!   Duncan–Chang point its largest stress state); each iteration updates it for the strain since
//!   the last converged increment ([`SoilLaw::update`]). A cutback restores the committed state
//!   with the rest of the run's state.

use crate::element::mohr_coulomb::{self, YieldState};
use crate::element::soil_law::SoilLaw;
use crate::element::soil_state::WaterTable;
pub use crate::element::soil_state::{element_force, ElementState, PointState, SoilField, SoilTrial, Tangent};
use crate::element::solid::{self, Integration, MappedPoint, PlaneStrain};
use crate::model::Model;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// What does not change through a run: each element's law, its DOFs, and the Gauss points of the
/// elements with a law (mapped once).
pub struct SoilSetup {
    pub laws: Vec<Option<SoilLaw>>,
    pub elastic: Vec<PlaneStrain>,
    pub dofs: Vec<Vec<usize>>,
    pub rule: Integration,
    points: Vec<Option<Vec<MappedPoint>>>,
}

impl SoilSetup {
    pub fn new(model: &Model) -> SoilSetup {
        let rule = model.integration();
        let mesh = &model.mesh;
        let laws: Vec<Option<SoilLaw>> = (0..mesh.solids.len()).map(|s| model.soil_law(s)).collect();
        let elastic = (0..mesh.solids.len()).map(|s| model.elasticity(s)).collect();
        let dofs = mesh.solids.iter().map(|e| e.nodes.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect()).collect();
        let points =
            mesh.solids.par_iter().zip(&laws).map(|(e, law)| law.map(|_| element_points(model, e, rule))).collect();
        SoilSetup { laws, elastic, dofs, rule, points }
    }

    /// Whether the element keeps its stresses (it has a law: it may yield, or its stiffness
    /// follows its stresses).
    pub fn is_plastic(&self, solid: usize) -> bool {
        self.laws[solid].is_some()
    }

    /// Whether any element keeps its stresses.
    pub fn any_plastic(&self) -> bool {
        self.laws.iter().any(|l| l.is_some())
    }
}

fn element_points(model: &Model, e: &crate::mesh::Solid, rule: Integration) -> Vec<MappedPoint> {
    let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| model.mesh.position(n)).collect();
    solid::mapped_points_of_checked(e.kind, &coords, rule, model.mesh.geometry)
        .expect("element Jacobians were checked when the model was read")
}

/// Strain (εxx, εyy, γxy, εzz) at a mapped point for element displacements `u_e`: εzz is zero in
/// plane strain and the hoop strain Σ N_i·u_xi/r in axisymmetry.
fn strain(p: &MappedPoint, u_e: &[f64]) -> [f64; 4] {
    let mut e = [0.0; 4];
    for (i, d) in p.dn_dx.iter().enumerate() {
        let (ux, uy) = (u_e[2 * i], u_e[2 * i + 1]);
        e[0] += d[0] * ux;
        e[1] += d[1] * uy;
        e[2] += d[1] * ux + d[0] * uy;
    }
    if let Some(inverse_radius) = p.inverse_radius {
        e[3] = p.n.iter().enumerate().map(|(i, n)| n * u_e[2 * i]).sum::<f64>() * inverse_radius;
    }
    e
}

/// Add Bᵀ·(σxx, σyy, τxy, σzz)·w to an element force vector (σzz, the hoop stress, only in
/// axisymmetry: in plane strain εzz = 0 does no work).
fn add_bt_sigma(p: &MappedPoint, s: [f64; 4], f: &mut [f64]) {
    for (i, d) in p.dn_dx.iter().enumerate() {
        f[2 * i] += (d[0] * s[0] + d[1] * s[2]) * p.weight;
        f[2 * i + 1] += (d[1] * s[1] + d[0] * s[2]) * p.weight;
    }
    if let Some(inverse_radius) = p.inverse_radius {
        for (i, n) in p.n.iter().enumerate() {
            f[2 * i] += n * inverse_radius * s[3] * p.weight;
        }
    }
}

/// The field at the start of a run: every element present but those a stage places later
/// (`absent`: [`Model::initially_absent`]).
pub fn initial_field(absent: &[bool]) -> SoilField {
    SoilField::new(absent.iter().map(|&a| ElementState { active: !a, ..ElementState::default() }).collect())
}

/// Nodes of present soil elements.
pub fn present_nodes(model: &Model, field: &SoilField) -> Vec<bool> {
    let mut present = vec![false; model.mesh.nodes.len()];
    for (e, s) in model.mesh.solids.iter().zip(field.elements()) {
        if s.active {
            for &n in &e.nodes {
                present[n] = true;
            }
        }
    }
    present
}

fn element_u(dofs: &[usize], u: &[f64]) -> Vec<f64> {
    dofs.iter().map(|&d| u[d]).collect()
}

/// Place soil elements: each starts stress-free on the deformed ground. A node that no present
/// element used before takes the displacement of the nearest node that one did (the ground it is
/// placed on), so that the new element's strains count from the deformed geometry.
///
/// `bar_nodes` are the nodes of reinforcements placed with these elements: they land on the ground
/// the same way.
pub fn activate(
    model: &Model,
    setup: &SoilSetup,
    field: &mut SoilField,
    solids: &[usize],
    bar_nodes: &[usize],
    u: &mut [f64],
) {
    let before = present_nodes(model, field);
    let old: Vec<usize> = (0..before.len()).filter(|&n| before[n]).collect();
    let mesh = &model.mesh;
    let mut moved = vec![false; before.len()];
    let new_nodes = solids.iter().flat_map(|&s| mesh.solids[s].nodes.iter().copied()).chain(bar_nodes.iter().copied());
    {
        for n in new_nodes {
            if before[n] || moved[n] {
                continue;
            }
            moved[n] = true;
            let x = mesh.position(n);
            let nearest = old.iter().copied().min_by(|&a, &b| {
                let (pa, pb) = (mesh.position(a), mesh.position(b));
                let da = (pa[0] - x[0]).powi(2) + (pa[1] - x[1]).powi(2);
                let db = (pb[0] - x[0]).powi(2) + (pb[1] - x[1]).powi(2);
                da.total_cmp(&db)
            });
            if let Some(m) = nearest {
                u[2 * n] = u[2 * m];
                u[2 * n + 1] = u[2 * m + 1];
            }
        }
    }
    for &s in solids {
        let state = &mut field.elements_mut()[s];
        if state.active {
            continue;
        }
        *state = ElementState {
            active: true,
            placed: Some(element_u(&setup.dofs[s], u)),
            points: Vec::new(),
            reference_force: None,
            pore: Vec::new(),
            pore_force: None,
        };
    }
}

/// Remove soil elements (excavation).
pub fn deactivate(field: &mut SoilField, solids: &[usize]) {
    for &s in solids {
        field.elements_mut()[s] = ElementState::default();
    }
}

/// The pore pressures of every present element under `water` (or none).
pub fn set_water(model: &Model, setup: &SoilSetup, field: &mut SoilField, water: Option<WaterTable>) {
    let mesh = &model.mesh;
    field.water = water;
    let water = field.water.clone();
    field.elements_mut().par_iter_mut().enumerate().for_each(|(s, state)| {
        state.pore.clear();
        state.pore_force = None;
        let (Some(w), true) = (&water, state.active) else { return };
        let points = element_points(model, &mesh.solids[s], setup.rule);
        let pore: Vec<f64> = points.iter().map(|p| w.pressure(p.x)).collect();
        if pore.iter().all(|&p| p == 0.0) {
            return;
        }
        let mut f = vec![0.0; setup.dofs[s].len()];
        for (p, &pw) in points.iter().zip(&pore) {
            add_bt_sigma(p, [pw, pw, 0.0, pw], &mut f);
        }
        state.pore = pore;
        state.pore_force = Some(f);
    });
}

/// Nodal forces of the water pressing on the soil's free boundary below the water table: p
/// against the outward normal of every side that one present element alone has and that is not an
/// interface face. (Inside the soil the pore pressure is carried by the elements' ∫Bᵀm·p; at a free
/// boundary the water outside balances it. At an interface the contact multiplier carries total
/// stress and the interface strength subtracts p itself.)
pub fn water_on_boundary(model: &Model, field: &SoilField, interfaces: &[crate::interface::Interface]) -> Vec<f64> {
    let mesh = &model.mesh;
    let mut f = vec![0.0; 2 * mesh.nodes.len()];
    let Some(water) = &field.water else { return f };
    let mut on_interface = vec![false; mesh.nodes.len()];
    for face in interfaces.iter().flat_map(|i| &i.faces) {
        for &n in &face.master {
            on_interface[n] = true;
        }
        for p in &face.points {
            on_interface[p.slave] = true;
        }
    }
    let mut count: std::collections::HashMap<(usize, usize), usize> = std::collections::HashMap::new();
    let key = |a: usize, b: usize| (a.min(b), a.max(b));
    for (e, st) in mesh.solids.iter().zip(field.elements()) {
        if st.active {
            for side in e.kind.sides() {
                *count.entry(key(e.nodes[side[0]], e.nodes[side[1]])).or_default() += 1;
            }
        }
    }
    let g = (0.6f64).sqrt();
    let rule = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
    for (e, st) in mesh.solids.iter().zip(field.elements()) {
        if !st.active {
            continue;
        }
        for side in e.kind.sides() {
            let nodes: Vec<usize> = side.iter().map(|&l| e.nodes[l]).collect();
            if count[&key(nodes[0], nodes[1])] != 1 || (on_interface[nodes[0]] && on_interface[nodes[1]]) {
                continue;
            }
            let coords: Vec<[f64; 2]> = nodes.iter().map(|&n| mesh.position(n)).collect();
            for (t, w) in rule {
                let (n, dn) = solid::side_shape(coords.len(), t);
                let (mut x, mut dx) = ([0.0; 2], [0.0; 2]);
                for ((ni, di), c) in n.iter().zip(&dn).zip(&coords) {
                    x[0] += ni * c[0];
                    x[1] += ni * c[1];
                    dx[0] += di * c[0];
                    dx[1] += di * c[1];
                }
                let p = water.pressure(x) * mesh.geometry.circumference(x);
                if p == 0.0 {
                    continue;
                }
                // sides run counter-clockwise: the outward normal is the right-hand normal of dx
                let outward = [dx[1], -dx[0]];
                for (i, &node) in nodes.iter().enumerate() {
                    f[2 * node] -= n[i] * p * outward[0] * w;
                    f[2 * node + 1] -= n[i] * p * outward[1] * w;
                }
            }
        }
    }
    f
}

/// The unit weight at a point: saturated below the water table.
pub(super) fn unit_weight(model: &Model, solid: usize, water: Option<&WaterTable>, x: [f64; 2]) -> f64 {
    let m = model.soil(solid);
    match water {
        Some(w) if x[1] < w.level_at(x[0]) => m.saturated_weight(),
        _ => m.unit_weight,
    }
}

/// Each soil element's mass matrix (`lumping`), its density its unit weight over `gravity` (g in
/// the model's length per s²; saturated below the water table).
pub fn masses(
    model: &Model,
    field: &SoilField,
    gravity: f64,
    lumping: crate::element::mass::Lumping,
) -> Vec<DMatrix<f64>> {
    let mesh = &model.mesh;
    mesh.solids
        .par_iter()
        .enumerate()
        .map(|(s, e)| {
            let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| mesh.position(n)).collect();
            let density = |x: [f64; 2]| unit_weight(model, s, field.water.as_ref(), x) / gravity;
            crate::element::mass::mass(e.kind, &coords, density, mesh.geometry, lumping)
        })
        .collect()
}

/// Consistent nodal forces of the weight (−y) of the present soil, times `factor`.
pub fn weight(model: &Model, setup: &SoilSetup, field: &SoilField, factor: f64) -> Vec<f64> {
    body_force(model, setup, field, [0.0, -factor])
}

/// Consistent nodal forces of the present soil's weight times `coefficients` (x, y): a body force
/// γ·(kx, ky) (the weight is `[0, −1]`, a pseudo-static seismic force `[kh, kv]`).
pub fn body_force(model: &Model, setup: &SoilSetup, field: &SoilField, coefficients: [f64; 2]) -> Vec<f64> {
    let mesh = &model.mesh;
    let mut f = vec![0.0; 2 * mesh.nodes.len()];
    if coefficients == [0.0, 0.0] {
        return f;
    }
    for (s, e) in mesh.solids.iter().enumerate() {
        if !field.elements()[s].active {
            continue;
        }
        for p in element_points(model, e, setup.rule) {
            let gamma = unit_weight(model, s, field.water.as_ref(), p.x);
            // (in this order, the weight's forces are those of −(factor·γ)·N·w to the last bit)
            let (gx, gy) = (coefficients[0] * gamma, coefficients[1] * gamma);
            for (i, &n) in e.nodes.iter().enumerate() {
                f[2 * n] += p.n[i] * gx * p.weight;
                f[2 * n + 1] += p.n[i] * gy * p.weight;
            }
        }
    }
    f
}

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

/// Update every present element with a law for the displacements since the last converged
/// increment. A Duncan–Chang or hardening-soil element always gives its tangent (its stiffness
/// follows its stresses); with [`Tangent::Elastic`], its moduli at the updated stresses without the
/// plastic part; with [`Tangent::Committed`], the law's predictor elasticity
/// ([`SoilLaw::predictor_elasticity`]).
pub fn evaluate(setup: &SoilSetup, field: &SoilField, u: &[f64], u_committed: &[f64], tangent: Tangent) -> SoilTrial {
    let n = setup.laws.len();
    if !setup.any_plastic() {
        return SoilTrial { forces: vec![None; n], tangents: vec![None; n], points: vec![None; n], yielding: 0 };
    }
    type ElementTrial = (Option<Vec<f64>>, Option<DMatrix<f64>>, Option<Vec<PointState>>, usize);
    let consistent = matches!(tangent, Tangent::Consistent | Tangent::Symmetric);
    let results: Vec<ElementTrial> = (0..n)
        .into_par_iter()
        .map(|s| {
            let (Some(law), Some(points), true) = (&setup.laws[s], &setup.points[s], field.elements()[s].active) else {
                return (None, None, None, 0);
            };
            let dofs = &setup.dofs[s];
            let du: Vec<f64> = dofs.iter().map(|&d| u[d] - u_committed[d]).collect();
            let committed = &field.elements()[s].points;
            let mut force = vec![0.0; dofs.len()];
            let mut k = DMatrix::zeros(dofs.len(), dofs.len());
            let mut states = Vec::with_capacity(points.len());
            let mut yielding = 0;
            for (g, p) in points.iter().enumerate() {
                let old = committed.get(g).copied().unwrap_or_default();
                let (update, state, elasticity) = law.update(&setup.elastic[s], &old, strain(p, &du), consistent);
                add_bt_sigma(p, update.stress, &mut force);
                if update.state.is_plastic() {
                    yielding += 1;
                }
                // At the apex the stress cannot change at all (its tangent is zero); a patch of
                // such points, as at a cohesionless surface, would be a mechanism of the iteration
                // matrix alone, so they keep the elastic matrix there.
                let plastic = update.state.is_plastic() && update.state != YieldState::Apex;
                let c = match tangent {
                    Tangent::Committed => {
                        law.predictor_elasticity(&setup.elastic[s], &old).unwrap_or(elasticity).d_matrix_with_hoop()
                    }
                    Tangent::Consistent if plastic => update.tangent,
                    Tangent::Symmetric if plastic => 0.5 * (update.tangent + update.tangent.transpose()),
                    _ => elasticity.d_matrix_with_hoop(),
                };
                k += solid::point_stiffness(p, &c);
                states.push(state);
            }
            let elastic = matches!(tangent, Tangent::Elastic | Tangent::Committed);
            let tangent = ((yielding > 0 && !elastic) || law.is_nonlinear_elastic()).then_some(k);
            (Some(force), tangent, Some(states), yielding)
        })
        .collect();
    let mut trial = SoilTrial::default();
    for (f, k, p, y) in results {
        trial.forces.push(f);
        trial.tangents.push(k);
        trial.points.push(p);
        trial.yielding += y;
    }
    trial
}

/// Keep the converged Gauss-point states.
pub fn commit(field: &mut SoilField, trial: &SoilTrial) {
    // (an elastic soil's trial has no points: its field stays as it is, shared with its copies)
    if trial.points.iter().all(Option::is_none) {
        return;
    }
    for (state, points) in field.elements_mut().iter_mut().zip(&trial.points) {
        if let Some(points) = points {
            state.points = points.clone();
        }
    }
}

/// One Gauss point's results.
#[derive(Debug, Clone)]
pub struct ElementStress {
    pub element: u64,
    pub point: usize,
    pub x: [f64; 2],
    /// σxx, σyy, τxy, σzz; tension positive.
    pub stress: [f64; 4],
    /// εxx, εyy, γxy since the element was placed; extension positive.
    pub strain: [f64; 3],
    /// Pore pressure, compression positive (the stresses above are effective: σ = σ′ − p).
    pub pore_pressure: f64,
    pub yield_state: crate::element::mohr_coulomb::YieldState,
    /// Accumulated equivalent plastic strain.
    pub plastic_strain: f64,
}

/// The Gauss-point results of every present element: effective stress, strain since placement,
/// pore pressure and yield state.
pub fn gauss_results(model: &Model, field: &SoilField, u: &[f64]) -> Vec<ElementStress> {
    // (each worker's elements gathered in one list, and the lists joined once; each worker reuses
    // its buffers from element to element)
    (0..model.mesh.solids.len())
        .into_par_iter()
        .map_init(ResultBuffers::default, |buffers, s| element_results(model, field, u, s, buffers))
        .flat_map_iter(|points| points)
        .collect()
}

/// What one worker reuses from element to element for the Gauss-point results: the element's node
/// coordinates, its displacements and its mapped points.
#[derive(Default)]
struct ResultBuffers {
    coords: Vec<[f64; 2]>,
    u_e: Vec<f64>,
    points: Vec<MappedPoint>,
}

/// The Gauss-point results of soil element `s` (none when it is absent): a linear-elastic
/// element's stress from the displacements `u`, the stress of an element with a law as last
/// committed.
fn element_results(
    model: &Model,
    field: &SoilField,
    u: &[f64],
    s: usize,
    buffers: &mut ResultBuffers,
) -> Vec<ElementStress> {
    let state = &field.elements()[s];
    if !state.active {
        return Vec::new();
    }
    let e = &model.mesh.solids[s];
    let ResultBuffers { coords, u_e, points } = buffers;
    u_e.clear();
    u_e.extend(e.nodes.iter().flat_map(|&n| [u[2 * n], u[2 * n + 1]]));
    if let Some(p) = &state.placed {
        for (a, b) in u_e.iter_mut().zip(p) {
            *a -= b;
        }
    }
    coords.clear();
    coords.extend(e.nodes.iter().map(|&n| model.mesh.position(n)));
    solid::mapped_points_of_checked_into(e.kind, coords, model.integration(), model.mesh.geometry, points)
        .expect("element Jacobians were checked when the model was read");
    // (a law's stress is read as committed: the elasticity is wanted for linear-elastic soil only,
    // and neither the law nor the elasticity is built per element of every step's results)
    let elastic = (!model.keeps_stresses(s)).then(|| model.elasticity(s));
    points
        .iter()
        .enumerate()
        .map(|(g, p)| {
            let eps = strain(p, u_e);
            let point = state.points.get(g).copied().unwrap_or_default();
            let stress = match &elastic {
                None => point.stress,
                Some(elastic) => mohr_coulomb::trial_stress(elastic, point.stress, eps),
            };
            ElementStress {
                element: e.id,
                point: g + 1,
                x: p.x,
                stress,
                strain: [eps[0], eps[1], eps[2]],
                pore_pressure: state.pore.get(g).copied().unwrap_or(0.0),
                yield_state: point.yield_state,
                plastic_strain: point.plastic_strain,
            }
        })
        .collect()
}

/// The soil's total normal stress (compression positive) across a line of unit normal `n` that
/// runs between the soil elements `solids`: for each present one, the mean over its Gauss points of
/// −n·σ′·n + p, and the mean of those. On a side shared by two linear elements this is exact for a
/// stress that varies linearly across it (the two element means straddle the line). `None` when no
/// element there is present.
pub fn normal_stress_across(model: &Model, field: &SoilField, u: &[f64], solids: &[usize], n: [f64; 2]) -> Option<f64> {
    let per_element: Vec<f64> = solids
        .iter()
        .filter_map(|&s| {
            let points = element_results(model, field, u, s, &mut ResultBuffers::default());
            (!points.is_empty()).then(|| {
                let sum: f64 = points
                    .iter()
                    .map(|p| {
                        let [sxx, syy, sxy, _] = p.stress;
                        -(n[0] * n[0] * sxx + 2.0 * n[0] * n[1] * sxy + n[1] * n[1] * syy) + p.pore_pressure
                    })
                    .sum();
                sum / points.len() as f64
            })
        })
        .collect();
    (!per_element.is_empty()).then(|| per_element.iter().sum::<f64>() / per_element.len() as f64)
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
