//! What one converged step produced: displacements, reactions, bar forces, interface point results
//! and soil stresses, with the sign conventions of docs/model-format.md.

pub use super::soil::ElementStress;
use super::springs::SpringResult;
use super::state::State;
use crate::assembly::{add_spring_forces, ElementMatrices};
use crate::element::soil_state::SoilField;
use crate::interface::rows::{constraint_force, row_dofs, InterfaceRows};
use crate::interface::ShearLaw;
use crate::model::Model;
use std::sync::OnceLock;

#[derive(Debug, Clone)]
pub struct Reaction {
    pub node: u64,
    /// `None` where the DOF is free.
    pub rx: Option<f64>,
    pub ry: Option<f64>,
}

#[derive(Debug, Clone)]
pub struct BarForce {
    pub bar: u64,
    pub nodes: [u64; 2],
    pub midpoint: [f64; 2],
    /// Axial force per metre width, tension positive.
    pub axial_force: f64,
    /// `intact`, `slack` (a tension-only bar in compression) or `ruptured`.
    pub state: &'static str,
}

#[derive(Debug, Clone)]
pub struct InterfacePointResult {
    pub interface: String,
    pub face: String,
    pub slave_node: u64,
    pub x: [f64; 2],
    pub master_nodes: [u64; 2],
    pub xi: f64,
    pub state: &'static str,
    pub tributary: f64,
    /// Normal multiplier (force per metre width), compression positive.
    pub lambda: f64,
    /// The total normal stress the shear law used, compression positive: λ/ℓ, or its value frozen
    /// at the start of the stage; a point at a slit tip takes its neighbour's. λ/ℓ for a tied point
    /// and for a point out of contact.
    pub sigma_n: f64,
    /// Shear stress resisting positive slip.
    pub tau: f64,
    /// The passive bearing's part of `tau` (a geogrid's transverse members; zero without).
    pub bearing: f64,
    /// The face's opening by dilatancy (zero on a face that does not dilate) [length].
    pub dilation: f64,
    /// Slip along the slave line towards its first node (the pull-out direction), accumulated.
    pub slip: f64,
    /// The peak strength has been passed.
    pub post_peak: bool,
    /// The point is at its shear strength in this step.
    pub sliding: bool,
}

#[derive(Debug, Clone)]
pub struct StepResults {
    /// (node id, reference position, displacement).
    pub displacements: Vec<(u64, [f64; 2], [f64; 2])>,
    pub reactions: Vec<Reaction>,
    pub bar_forces: Vec<BarForce>,
    pub interface_points: Vec<InterfacePointResult>,
    /// The soil's Gauss-point results, made when first asked for ([`StepResults::stresses`]).
    soil: GaussResults,
    /// Reactions over every held DOF (2·node + d), zero where free.
    pub reaction_vector: Vec<f64>,
    pub displacement_vector: Vec<f64>,
    /// In a dynamic stage: the time, the base's acceleration and the velocities and accelerations
    /// relative to the base.
    pub motion: Option<crate::analysis::time_scheme::Motion>,
}

impl StepResults {
    /// The step's results at the equilibrium `state`, whose soil and bars exert `element_force`
    /// (`assembly::soil_and_bar_force`, found by the increment's closing check for the same
    /// displacements) and whose springs are `springs`.
    pub fn compute(
        model: &Model,
        elements: &ElementMatrices,
        rows: &InterfaceRows,
        springs: &[SpringResult],
        state: &State,
        element_force: &[f64],
        held: &[bool],
    ) -> Self {
        let mesh = &model.mesh;
        let n_dof = state.u.len();
        let taus: Vec<f64> = springs.iter().map(|r| r.tau).collect();
        let mut f_int = element_force.to_vec();
        add_spring_forces(&mut f_int, rows, &taus);
        let f_c = constraint_force(rows, &state.lambda, n_dof);
        let reaction_vector: Vec<f64> =
            (0..n_dof).map(|d| if held[d] { f_int[d] + f_c[d] - state.f_ext[d] } else { 0.0 }).collect();

        let displacements =
            mesh.nodes.iter().enumerate().map(|(i, n)| (n.id, n.x, [state.u[2 * i], state.u[2 * i + 1]])).collect();
        let reactions = mesh
            .nodes
            .iter()
            .enumerate()
            .filter(|(i, _)| held[2 * i] || held[2 * i + 1])
            .map(|(i, n)| Reaction {
                node: n.id,
                rx: held[2 * i].then(|| reaction_vector[2 * i]),
                ry: held[2 * i + 1].then(|| reaction_vector[2 * i + 1]),
            })
            .collect();
        let bar_forces = elements
            .bars
            .iter()
            .enumerate()
            .map(|(i, law)| {
                let b = &mesh.bars[i];
                let (a, c) = (mesh.position(b.nodes[0]), mesh.position(b.nodes[1]));
                let dl = &elements.blocks[law.block].0;
                BarForce {
                    bar: b.id,
                    nodes: [mesh.node_id(b.nodes[0]), mesh.node_id(b.nodes[1])],
                    midpoint: [0.5 * (a[0] + c[0]), 0.5 * (a[1] + c[1])],
                    axial_force: law.force(&state.u, dl, &state.bars, i),
                    state: if state.bars.ruptured[i] {
                        "ruptured"
                    } else if state.bars.absent[i] {
                        "not placed"
                    } else if law.slack(&state.u, dl, &state.bars, i) {
                        "slack"
                    } else {
                        "intact"
                    },
                }
            })
            .collect();

        // Interface points: multipliers are in dofs::multipliers order; the springs' τ in theirs.
        let mut interface_points = Vec::new();
        let mut k = 0usize;
        let mut spring = 0usize;
        for interface in &state.interfaces {
            for face in &interface.faces {
                for point in &face.points {
                    let lambda = state.lambda[k];
                    k += 1;
                    let lambda_stress = if point.tributary > 0.0 { lambda / point.tributary } else { 0.0 };
                    let (tau, sliding, sigma_n, bearing, dilation) = match &face.law {
                        ShearLaw::Tie => {
                            let lt = state.lambda[k];
                            k += 1;
                            (lt / point.tributary.max(f64::MIN_POSITIVE), false, lambda_stress, 0.0, 0.0)
                        }
                        _ => {
                            spring += 1;
                            match springs.get(spring - 1) {
                                // a point with no length left facing its master face (it slid off
                                // its end within the step) holds its node there by the point force
                                // λ alone: no stress is spread over it, and 0 is written
                                Some(r) if point.in_contact() && point.tributary == 0.0 => {
                                    (0.0, r.sliding, 0.0, 0.0, r.dilation)
                                }
                                Some(r) if point.in_contact() => (r.tau, r.sliding, r.sigma_n, r.bearing, r.dilation),
                                Some(r) => (r.tau, r.sliding, lambda_stress, r.bearing, r.dilation),
                                None => (0.0, false, lambda_stress, 0.0, 0.0),
                            }
                        }
                    };
                    let slip = if interface.is_tie() {
                        row_dofs(&face.tangential_row(point)).iter().map(|&(d, c)| c * state.u[d]).sum()
                    } else {
                        point.shear.slip
                    };
                    interface_points.push(InterfacePointResult {
                        interface: interface.name.clone(),
                        face: face.label.clone(),
                        slave_node: mesh.node_id(point.slave),
                        x: mesh.position(point.slave),
                        master_nodes: [
                            mesh.node_id(face.master[point.segment]),
                            mesh.node_id(face.master[point.segment + 1]),
                        ],
                        xi: point.xi,
                        state: point.normal_state.name(),
                        tributary: point.tributary,
                        lambda,
                        sigma_n,
                        tau,
                        bearing,
                        dilation,
                        slip,
                        post_peak: point.shear.post_peak,
                        sliding,
                    });
                }
            }
        }

        StepResults {
            displacements,
            reactions,
            bar_forces,
            interface_points,
            soil: GaussResults { field: Some(state.soil.clone()), made: OnceLock::new() },
            reaction_vector,
            displacement_vector: state.u.clone(),
            motion: state.motion.clone(),
        }
    }

    /// The soil's stresses, strains and pore pressures at every Gauss point of every present
    /// element (element by element), of the step run on `model`: made at the first call, from the
    /// soil's states and displacements the step kept.
    pub fn stresses(&self, model: &Model) -> &[ElementStress] {
        let GaussResults { field, made } = &self.soil;
        made.get_or_init(|| match field {
            Some(field) => super::soil::gauss_results(model, field, &self.displacement_vector),
            None => Vec::new(),
        })
    }

    /// A copy of the step to keep: its Gauss-point results made now, without the soil's states
    /// they are made of (which would otherwise be copied when the run changes them).
    pub fn kept(&self, model: &Model) -> StepResults {
        StepResults {
            displacements: self.displacements.clone(),
            reactions: self.reactions.clone(),
            bar_forces: self.bar_forces.clone(),
            interface_points: self.interface_points.clone(),
            soil: GaussResults { field: None, made: OnceLock::from(self.stresses(model).to_vec()) },
            reaction_vector: self.reaction_vector.clone(),
            displacement_vector: self.displacement_vector.clone(),
            motion: self.motion.clone(),
        }
    }
}

/// A step's Gauss-point results, made only when asked for: a run that writes the fields of one
/// step in fifty (a dynamic stage's thousands of time steps) makes them for that one. The soil's
/// states are shared with the run's until the run changes them.
#[derive(Debug, Clone)]
struct GaussResults {
    /// The soil's states at the step (`None` once the results are made, in a kept copy).
    field: Option<SoilField>,
    made: OnceLock<Vec<ElementStress>>,
}

/// The force balance of one reinforcement in one step: the forces applied to its nodes (reactions
/// of prescribed DOFs and loads) against the forces its interfaces carry (springs and multipliers).
/// The bars' own forces cancel node by node, so the two must agree.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ReinforcementBalance {
    pub interface: String,
    /// Applied to the reinforcement's nodes (x, y): the pull.
    pub applied: [f64; 2],
    /// Carried by its interface faces (x, y).
    pub interface_force: [f64; 2],
    /// The part of `interface_force` that its transverse members' passive bearing carries (x, y),
    /// when its faces have any; the rest is friction and the normal forces.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bearing_force: Option<[f64; 2]>,
    /// |applied − interface_force| relative to `scale` (or absolute when that is zero).
    pub mismatch: f64,
    /// What `mismatch` is relative to: |applied|, or the model's largest nodal force (applied or
    /// reaction) when that is more.
    pub scale: f64,
}

/// Check, for every interface whose slave nodes belong to no soil element (a reinforcement), that
/// the interface forces balance what is applied to it. In a stack of geosynthetics the faces
/// between layers act on both and cancel: the faces against the soil carry the stack.
pub fn reinforcement_balance(model: &Model, results: &StepResults, state: &State) -> Vec<ReinforcementBalance> {
    if state.interfaces.is_empty() {
        return Vec::new();
    }
    let mut in_soil = vec![false; model.mesh.nodes.len()];
    for s in &model.mesh.solids {
        for &n in &s.nodes {
            in_soil[n] = true;
        }
    }
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); model.mesh.nodes.len()];
    for bar in &model.mesh.bars {
        let [a, b] = bar.nodes;
        neighbours[a].push(b);
        neighbours[b].push(a);
    }
    // the model's force scale (its largest nodal force, applied or reaction): a reinforcement
    // that carries nothing yet (a grid just placed, one under a surcharge only) has an applied
    // force and interface forces of round-off or of the iteration's tolerance, whose ratio means
    // nothing; its mismatch is measured against this scale instead
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let floor = largest(&results.reaction_vector).max(largest(&state.f_ext));
    let mut out = Vec::new();
    let mut k = 0usize;
    for interface in &state.interfaces {
        let mut slaves: Vec<usize> = interface.faces.iter().flat_map(|f| f.points.iter().map(|p| p.slave)).collect();
        slaves.sort_unstable();
        slaves.dedup();
        let mut carried = [0.0; 2];
        let mut bearing_carried = [0.0; 2];
        let has_bearing = interface.faces.iter().any(|f| f.bearing.is_some());
        for face in &interface.faces {
            // a face between two layers of a stack: its master is another layer of this reinforcement
            let between_layers = face.master.iter().all(|n| slaves.binary_search(n).is_ok());
            for point in &face.points {
                let n = face.normal(&model.mesh, point.segment);
                // the force on the slave node from the row: −λ·n (λ > 0 pushes it off the master)
                let lambda = state.lambda[k];
                k += 1;
                let t = point.tangent;
                let (shear_force, bearing_force) = if interface.is_tie() {
                    let lt = state.lambda[k];
                    k += 1;
                    (lt, 0.0)
                } else {
                    let (tau, bearing) = results
                        .interface_points
                        .iter()
                        .find(|r| {
                            r.interface == interface.name
                                && r.face == face.label
                                && r.slave_node == model.mesh.node_id(point.slave)
                        })
                        .map_or((0.0, 0.0), |r| (r.tau, r.bearing));
                    let area = point.tributary * face.sides();
                    (tau * area, bearing * area)
                };
                // the soil resists positive slip: force −τℓ·t on the slave (between two layers of a
                // stack the same force, reversed, acts on the layer beneath: nothing on the stack)
                if !between_layers {
                    carried[0] -= lambda * n[0] + shear_force * t[0];
                    carried[1] -= lambda * n[1] + shear_force * t[1];
                    bearing_carried[0] -= bearing_force * t[0];
                    bearing_carried[1] -= bearing_force * t[1];
                }
            }
        }
        if slaves.is_empty() || slaves.iter().any(|&n| in_soil[n]) {
            continue;
        }
        // the reinforcement: every node its bars reach from the slave line (a grip or a free
        // length pulled off the line); one tied to the soil by a bar has no balance of its own
        let Some(nodes) = reinforcement_nodes(&neighbours, &slaves, &in_soil) else { continue };
        let mut applied = [0.0; 2];
        for &n in &nodes {
            for d in 0..2 {
                applied[d] += results.reaction_vector[2 * n + d] + state.f_ext[2 * n + d];
            }
        }
        let diff = ((applied[0] + carried[0]).powi(2) + (applied[1] + carried[1]).powi(2)).sqrt();
        let size = (applied[0].powi(2) + applied[1].powi(2)).sqrt();
        out.push(ReinforcementBalance {
            interface: interface.name.clone(),
            applied,
            interface_force: [-carried[0], -carried[1]],
            bearing_force: has_bearing.then_some([-bearing_carried[0], -bearing_carried[1]]),
            // relative to the applied force, or to the model's force scale below it
            mismatch: if size.max(floor) > 0.0 { diff / size.max(floor) } else { diff },
            scale: size.max(floor),
        });
    }
    out
}

/// The nodes that the bars (`neighbours`: each node's bar neighbours) connect to `slaves`
/// (themselves included), sorted; `None` when a bar leads to a soil node.
fn reinforcement_nodes(neighbours: &[Vec<usize>], slaves: &[usize], in_soil: &[bool]) -> Option<Vec<usize>> {
    let mut reached = vec![false; neighbours.len()];
    let mut stack: Vec<usize> = slaves.to_vec();
    for &n in slaves {
        reached[n] = true;
    }
    while let Some(n) = stack.pop() {
        for &m in &neighbours[n] {
            if in_soil[m] {
                return None;
            }
            if !reached[m] {
                reached[m] = true;
                stack.push(m);
            }
        }
    }
    Some((0..reached.len()).filter(|&n| reached[n]).collect())
}
