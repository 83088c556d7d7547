//! The active set: which normal rows hold, point by point (DESIGN §1).
//!
//! - A row whose λ turns tensile (beyond a band) is released; a released row is re-activated when
//!   its faces clearly overlap again. A point that keeps switching within an increment is kept in
//!   contact after [`CHATTER_LIMIT`] changes.
//! - A reinforcement node with no row that holds (every face open, or the node out of the soil) has
//!   its transverse DOF held through one of its rows, and gets it back when another row holds.
//! - Rows that repeat another row on the free DOFs (both faces of a bar on a fixed bed, a slit tip)
//!   would make the system singular: they are carried by the other row and reported.
//! - As stages place and remove soil and reinforcement, a point whose node or master segment is not
//!   in place has no contact; one that a stage puts in place starts in contact.

use super::rows::InterfaceRows;
use super::{multipliers, ContactFace, ContactPoint, Interface, MultiplierRef, NormalState};
use crate::mesh::{Mesh, NodeIndex};
use std::collections::HashMap;

/// How many state changes of one point an increment allows before the point is kept in contact.
pub const CHATTER_LIMIT: usize = 4;

/// State changes per multiplier within one increment.
pub type Flips = HashMap<usize, usize>;

/// What the active-set rules read besides the interfaces' own state.
pub struct ActiveSet<'a> {
    pub mesh: &'a Mesh,
    /// The multipliers in DOF order.
    pub multipliers: &'a [MultiplierRef],
    /// Equation number of each displacement DOF (`None`: held).
    pub equation: &'a [Option<usize>],
    /// Nodes that belong to no soil element (reinforcement nodes): their transverse DOF has no
    /// stiffness of its own.
    pub bar_only: &'a [bool],
    /// Nodes in place now (empty: every node); see [`in_place`].
    pub placed: &'a [bool],
}

/// Hysteresis bands: a row is released only when clearly tensile, re-activated only when the faces
/// clearly overlap, so that states do not ping-pong on round-off.
#[derive(Debug, Clone, Copy)]
pub struct Bands {
    /// λ below this releases an active row.
    pub release_below: f64,
    /// A gap above this re-activates a released row.
    pub close_above: f64,
}

impl Bands {
    /// The bands for multipliers `lambda`: the scale of a contact force is the largest multiplier,
    /// but never below `force_floor` (the applied forces, or a force that moves the soil by 10⁻⁶ of
    /// its size), so that multipliers that are zero up to round-off (a reinforcement turned off the
    /// axes, pulled along itself) are not taken for tension; the gap band is 10⁻⁶ of the
    /// `characteristic` length.
    pub fn new(lambda: &[f64], force_floor: f64, characteristic: f64) -> Bands {
        let lambda_scale = lambda.iter().fold(0.0f64, |m, l| m.max(l.abs())).max(force_floor).max(f64::MIN_POSITIVE);
        Bands { release_below: -1e-4 * lambda_scale, close_above: 1e-6 * characteristic }
    }
}

/// Whether a point (its node and its master segment) is in place; `placed` empty: every node is.
pub fn in_place(placed: &[bool], face: &ContactFace, point: &ContactPoint) -> bool {
    placed.is_empty()
        || (placed[point.slave]
            && face.master[point.segment..=(point.segment + 1).min(face.master.len() - 1)].iter().all(|&n| placed[n]))
}

/// "interface "name" face at node id": how messages name a multiplier's point.
pub fn describe(mesh: &Mesh, interfaces: &[Interface], m: MultiplierRef) -> String {
    let i = &interfaces[m.interface];
    let f = &i.faces[m.face];
    format!("interface \"{}\" {} at node {}", i.name, f.named(), mesh.node_id(f.points[m.point].slave))
}

/// Contacts as a stage places and removes soil and reinforcement. A point not in place, or whose
/// master segment is not (a reinforcement still to be laid; a liner under cover soil still to come,
/// or soil excavated off it), is released: it would bear on nodes held where they were. A point that
/// this stage puts in place (a sheet laid on the ground, soil placed on it) starts in contact.
pub fn place_contacts(interfaces: &mut [Interface], lambda: &mut [f64], placed: &[bool], placed_before: &[bool]) {
    for (k, m) in multipliers(interfaces).iter().enumerate() {
        let face = &interfaces[m.interface].faces[m.face];
        if m.tangential || interfaces[m.interface].slit_of.is_some() || interfaces[m.interface].is_tie() {
            continue;
        }
        let point = &face.points[m.point];
        let now = in_place(placed, face, point);
        let before = !placed_before.is_empty() && in_place(placed_before, face, point);
        let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
        match (before, now, &point.normal_state) {
            (_, false, NormalState::Active) => {
                point.normal_state = NormalState::Released;
                lambda[k] = 0.0;
            }
            (false, true, NormalState::Released | NormalState::Held { outside: false }) => {
                // laid now: its slip and shear count from here
                point.normal_state = NormalState::Active;
                point.shear = Default::default();
            }
            _ => {}
        }
    }
}

impl ActiveSet<'_> {
    fn name(&self, interfaces: &[Interface], k: usize) -> String {
        describe(self.mesh, interfaces, self.multipliers[k])
    }

    /// Release rows whose λ turned tensile, re-activate released rows whose gap closed, and hold the
    /// transverse DOF of a reinforcement node whose faces are all open. `gaps` are the rows' current
    /// gaps. Returns what changed.
    pub fn update(
        &self,
        interfaces: &mut [Interface],
        lambda: &mut [f64],
        gaps: &[f64],
        bands: Bands,
        flips: &mut Flips,
    ) -> Vec<String> {
        let mut changes = Vec::new();
        for (k, m) in self.multipliers.iter().enumerate() {
            if m.tangential || interfaces[m.interface].is_tie() {
                continue;
            }
            let placed = {
                let face = &interfaces[m.interface].faces[m.face];
                in_place(self.placed, face, &face.points[m.point])
            };
            // one continuous soil does not open: an embedded reinforcement's rows are never released
            let bilateral = interfaces[m.interface].faces[m.face].embedded.is_some();
            let p = &mut interfaces[m.interface].faces[m.face].points[m.point];
            // A point that has already switched CHATTER_LIMIT times in this increment stays in
            // contact: its λ is then slightly tensile at most, and it is reported.
            let locked = flips.get(&k).is_some_and(|&n| n >= CHATTER_LIMIT);
            let new = match p.normal_state {
                NormalState::Active if lambda[k] < bands.release_below && !locked && !bilateral => {
                    Some(NormalState::Released)
                }
                NormalState::Released | NormalState::Held { outside: false }
                    if gaps[k] > bands.close_above && placed =>
                {
                    Some(NormalState::Active)
                }
                // a row holding a sheet's node that pushes it as contact would (a layer above
                // presses it onto this face): the contact is back
                NormalState::Held { outside: false } if lambda[k] > -bands.release_below && placed => {
                    Some(NormalState::Active)
                }
                _ => None,
            };
            if let Some(new) = new {
                let what =
                    if matches!(new, NormalState::Active) { "re-activated (gap closed)" } else { "released (tension)" };
                p.normal_state = new;
                *flips.entry(k).or_default() += 1;
                changes.push(format!("{} {what}", self.name(interfaces, k)));
                if !matches!(interfaces[m.interface].faces[m.face].points[m.point].normal_state, NormalState::Active) {
                    lambda[k] = 0.0;
                }
            }
        }
        changes.extend(self.hold_free_reinforcement_nodes(interfaces, lambda));
        changes
    }

    /// A reinforcement node with no active normal row (every face open, or the node out of the
    /// soil) keeps its transverse position through one of its rows (held), and gives it back when
    /// another row becomes active. Returns what changed.
    pub fn hold_free_reinforcement_nodes(&self, interfaces: &mut [Interface], lambda: &mut [f64]) -> Vec<String> {
        let mut changes = Vec::new();
        let mut by_slave: HashMap<NodeIndex, Vec<usize>> = HashMap::new();
        for (k, m) in self.multipliers.iter().enumerate() {
            if !m.tangential {
                let slave = interfaces[m.interface].faces[m.face].points[m.point].slave;
                by_slave.entry(slave).or_default().push(k);
            }
        }
        let mut slaves: Vec<_> = by_slave.into_iter().collect();
        slaves.sort_by_key(|(s, _)| *s);
        for (slave, ks) in slaves {
            // a node not yet placed is held where it is anyway
            if !self.bar_only[slave] || (self.equation[2 * slave].is_none() && self.equation[2 * slave + 1].is_none()) {
                continue;
            }
            let st = |k: usize| {
                let m = self.multipliers[k];
                interfaces[m.interface].faces[m.face].points[m.point].normal_state.clone()
            };
            // a row carried by another counts only while its carrier holds (a carrier released in
            // tension leaves the node free)
            let holds = |k: usize| match st(k) {
                NormalState::Active => true,
                NormalState::Redundant { multiplier: Some(carrier), .. } => matches!(st(carrier), NormalState::Active),
                NormalState::Redundant { multiplier: None, .. } => true,
                _ => false,
            };
            let any_active = ks.iter().any(|&k| holds(k));
            let held: Vec<usize> = ks.iter().copied().filter(|&k| matches!(st(k), NormalState::Held { .. })).collect();
            if !any_active && held.is_empty() {
                if let Some(&k) = ks.iter().find(|&&k| matches!(st(k), NormalState::Released | NormalState::Outside)) {
                    let m = self.multipliers[k];
                    let outside = matches!(st(k), NormalState::Outside);
                    interfaces[m.interface].faces[m.face].points[m.point].normal_state = NormalState::Held { outside };
                    changes.push(format!(
                        "node {} transverse DOF held ({})",
                        self.mesh.node_id(slave),
                        if outside { "it has left the soil" } else { "every face of the reinforcement is open there" }
                    ));
                }
            } else if any_active {
                for k in held {
                    let m = self.multipliers[k];
                    let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
                    point.normal_state = match point.normal_state {
                        NormalState::Held { outside: true } => NormalState::Outside,
                        _ => NormalState::Released,
                    };
                    lambda[k] = 0.0;
                }
            }
        }
        changes
    }

    /// Rows with no free DOF, or that repeat an earlier row on the free DOFs, would make the system
    /// singular; they are set on a unit diagonal and reported. Returns the report lines.
    pub fn mark_redundant(&self, interfaces: &mut [Interface]) -> Vec<String> {
        let rows = InterfaceRows::new(self.mesh, interfaces, self.multipliers);
        let mut seen: HashMap<Vec<(usize, i64)>, usize> = HashMap::new();
        // the rows already kept, per slave node: (multiplier, free part of its row)
        type KeptRows = Vec<(usize, Vec<(usize, f64)>)>;
        let mut by_slave: HashMap<usize, KeptRows> = HashMap::new();
        let mut report = Vec::new();
        for (k, row) in rows.constraint_rows.iter().enumerate() {
            let m = self.multipliers[k];
            let current = {
                let p = &interfaces[m.interface].faces[m.face].points[m.point];
                if m.tangential {
                    &p.tangential_state
                } else {
                    &p.normal_state
                }
            };
            if !matches!(current, NormalState::Active | NormalState::Redundant { .. }) {
                continue; // released, held, covered or outside rows carry nothing to repeat
            }
            let mut free: Vec<(usize, f64)> = row
                .iter()
                .filter_map(|&(d, c)| self.equation[d].map(|e| (e, c)))
                .filter(|&(_, c)| c.abs() > 1e-12)
                .collect();
            free.sort_by_key(|&(e, _)| e);
            let carried_by = if free.is_empty() {
                Some(("the supports (every DOF of the row is held)".to_string(), None))
            } else {
                let scale = free[0].1;
                let key: Vec<(usize, i64)> = free.iter().map(|&(e, c)| (e, (c / scale * 1e9).round() as i64)).collect();
                // Rows of the same slave node that are nearly parallel (both faces of a
                // reinforcement tied to segments that end at the same soil node, as at a slit tip)
                // make the system singular or ill-conditioned: the later one is carried by the
                // earlier one.
                let slave = interfaces[m.interface].faces[m.face].points[m.point].slave;
                let near = by_slave.get(&slave).and_then(|earlier: &KeptRows| {
                    earlier.iter().find(|(_, other)| nearly_parallel(&free, other)).map(|(j, _)| *j)
                });
                let tip = interfaces[m.interface].faces[m.face].points[m.point].slit_tip && !m.tangential;
                let tip_partner =
                    if tip { by_slave.get(&slave).and_then(|e| e.first()).map(|(j, _)| *j) } else { None };
                match seen.get(&key).copied().or(near).or(tip_partner) {
                    Some(first) => Some((self.name(interfaces, first), Some(first))),
                    // a stack's tail inside the soil: the lower face's row there is the sum of the
                    // upper face's and the rows between the layers, which carry it together
                    None if tip && interfaces[m.interface].faces.len() > 2 => {
                        Some(("the other faces of the stack at the slit tip".to_string(), None))
                    }
                    None => {
                        seen.insert(key, k);
                        by_slave.entry(slave).or_default().push((k, free.clone()));
                        None
                    }
                }
            };
            let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
            let state = if m.tangential { &mut point.tangential_state } else { &mut point.normal_state };
            match carried_by {
                Some((by, multiplier)) => {
                    report.push(format!(
                        "{} ({}): carried by {by}",
                        self.name(interfaces, k),
                        if m.tangential { "tangential" } else { "normal" }
                    ));
                    let point = &mut interfaces[m.interface].faces[m.face].points[m.point];
                    let state = if m.tangential { &mut point.tangential_state } else { &mut point.normal_state };
                    *state = NormalState::Redundant { carried_by: by, multiplier };
                }
                None => {
                    if matches!(state, NormalState::Redundant { .. }) {
                        *state = NormalState::Active;
                    }
                }
            }
        }
        report
    }
}

/// Whether two sparse rows (sorted by equation) are parallel or antiparallel to within an angle of
/// about 10⁻³ rad (|cos| > 1 − 5·10⁻⁷).
fn nearly_parallel(a: &[(usize, f64)], b: &[(usize, f64)]) -> bool {
    let norm = |r: &[(usize, f64)]| r.iter().map(|(_, c)| c * c).sum::<f64>().sqrt();
    let (na, nb) = (norm(a), norm(b));
    if na == 0.0 || nb == 0.0 {
        return false;
    }
    let mut dot = 0.0;
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].0.cmp(&b[j].0) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                dot += a[i].1 * b[j].1;
                i += 1;
                j += 1;
            }
        }
    }
    (dot / (na * nb)).abs() > 1.0 - 5e-7
}
