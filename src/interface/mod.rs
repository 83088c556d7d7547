//! Interfaces: a slave line pressed against a master face, with a shear law (DESIGN §1).
//!
//! Each slave point r faces a master point at parameter ξ on a master segment (a, b). With n the
//! unit normal pointing into that face's soil and t the slip direction, the point contributes
//! - a normal constraint row `+n` on r and `−N_i(ξ)·n` on a, b, holding the gap
//!   g = n·(x_r − Σ N_i x_i) at zero, with multiplier λ (λ > 0 is compression);
//! - a tangential spring of stiffness Ks·ℓ on the relative displacement along t (slip
//!   s = t·(u_r − Σ N_i u_i)), or, for a `tie` law, a second constraint row along t.
//!
//! A point's association (segment, ξ) and state are kept so that the slip mechanics can release a
//! row (it stays in the pattern with a unit diagonal), and re-associate the point as it slides.

pub mod active_set;
pub mod bearing;
pub mod embed;
pub mod law;
pub mod pair;
pub mod reassociate;
pub mod rows;
pub mod split;

use crate::mesh::{Mesh, NodeIndex};
pub use bearing::Bearing;
pub use law::{ShearLaw, ShearResponse, ShearState};

/// State of a point's normal constraint row.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum NormalState {
    /// The row holds the gap at zero.
    Active,
    /// The faces have separated: the row stays in the pattern with a unit diagonal and λ = 0.
    Released,
    /// The row repeats another one on the free DOFs (for example both faces of a bar on a fixed,
    /// rigid bed, or both sides held by supports); the force is carried by `carried_by`.
    Redundant { carried_by: String, multiplier: Option<usize> },
    /// Released, but holding the transverse position of a reinforcement node whose faces are all
    /// open, or that has left the soil (a 2-node bar has no transverse stiffness): the row acts on
    /// the slave node only. `outside` remembers that the point no longer faces the master face.
    Held { outside: bool },
    /// The slave point no longer faces the master face (it has been pulled out of the soil).
    Outside,
    /// A point of the slit behind a reinforcement, still filled by the reinforcement: no contact
    /// until the reinforcement's tail has slid past it.
    Covered,
}

impl NormalState {
    pub fn name(&self) -> &'static str {
        match self {
            NormalState::Active => "active",
            NormalState::Released => "released",
            NormalState::Redundant { .. } => "redundant",
            NormalState::Held { .. } => "held",
            NormalState::Outside => "outside",
            NormalState::Covered => "covered",
        }
    }
}

/// One slave point of one face.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ContactPoint {
    pub slave: NodeIndex,
    /// Slip direction: unit tangent of the slave line, pointing towards its first node.
    pub tangent: [f64; 2],
    /// Tributary length ℓ of the point along the slave line [length]; in axisymmetry its area
    /// ∫N·2πr ds [length²], so that λ/ℓ is still a stress and τ·ℓ a force.
    pub tributary: f64,
    /// Master segment index (into the face's master path) and parameter ξ ∈ [0, 1] on it.
    pub segment: usize,
    pub xi: f64,
    pub normal_state: NormalState,
    pub tangential_state: NormalState,
    /// Reference gap n·(X_r − Σ N_i X_i) of the current association, so that the gap from current
    /// positions is g = gap0 + row·u (zero when the point was associated by projection).
    pub gap0: f64,
    /// Tangential law history (carried across re-associations).
    pub shear: ShearState,
    /// The lower face's point at a slit tip (a reinforcement tail inside the soil): both faces meet
    /// at one soil node there, so its normal row always repeats the upper face's and is carried by it.
    pub slit_tip: bool,
    /// The point of the same face whose normal stress this point's shear law takes. At a slit tip
    /// the faces meet at one soil node: the one row there holds the reinforcement's tail against
    /// that node, and its multiplier is the difference of the faces' pressures (about zero), not the
    /// pressure on either face; the tail's tributary length then takes its neighbour's σn, so that
    /// the reinforcement has friction to its tail.
    pub pressure_from: Option<usize>,
    /// Master segments `lo..=hi` whose nodes the point's rows keep in the sparsity pattern (as zeros
    /// where they carry nothing), so that sliding within them needs no new analysis; `None`: only
    /// the current segment. Set by [`reserve_windows`].
    pub reserved: Option<(usize, usize)>,
    /// Segment-to-segment (dual mortar) weights of the master nodes, `(index into the master path,
    /// weight)`, summing to one: the rows then tie the point to the master face averaged over its
    /// part of the slave line rather than to the one master point it faces. `None`: N_i(ξ) on its
    /// segment (node-to-segment). Set by the `mortar` re-association.
    pub weights: Option<Vec<(usize, f64)>>,
}

impl ContactPoint {
    /// The point transmits forces (its normal row holds, or another row carries its force).
    pub fn in_contact(&self) -> bool {
        matches!(self.normal_state, NormalState::Active | NormalState::Redundant { .. })
    }
}

/// One face of an interface: a master path and the slave points pressed against it.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ContactFace {
    /// `upper`, `lower` (a reinforcement's two faces) or `face` (a hand-made pair).
    pub label: String,
    pub master: Vec<NodeIndex>,
    /// The master face's soil lies to the left of each master segment a → b.
    pub soil_on_left: bool,
    /// For a master face with no soil element (a rigid base): the normal the model gave, which
    /// picked its side (`soil_on_left`); each segment's normal is its own all the same.
    pub fixed_normal: Option<[f64; 2]>,
    pub points: Vec<ContactPoint>,
    /// The shear law of this face's points (the faces of a stack of geosynthetics differ).
    pub law: ShearLaw,
    /// A reinforcement embedded in continuous soil: the master path runs through the soil (soil on
    /// both sides), and the face stands for both of the reinforcement's faces.
    pub embedded: Option<Embedding>,
    /// The face dilates as it slides (`None`: the tie holds the gap at zero).
    pub dilation: Option<Dilation>,
    /// The passive bearing of a geogrid's transverse members, added to the face's shear law.
    pub bearing: Option<Bearing>,
}

/// Dilatancy of a face: its normal tie holds the faces apart by min(tan ψ·κ, max), κ the plastic
/// slip accumulated in either direction (the gap g = n·(x_r − Σ Nᵢxᵢ) is held at −opening).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Dilation {
    pub tan_angle: f64,
    pub max: f64,
}

impl Dilation {
    /// The opening after a plastic slip path κ.
    pub fn opening(&self, plastic_path: f64) -> f64 {
        (self.tan_angle * plastic_path.max(0.0)).min(self.max)
    }
}

/// What an embedded reinforcement's face needs beyond a contact face's: its points are tied
/// normally to a line inside one continuous soil, each stands for both faces of the reinforcement,
/// and the shear law's σn is the soil's normal stress on the line there, not the row's multiplier
/// (which only holds the reinforcement on the line, and is about zero).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Embedding {
    /// Per master segment: the soil elements either side of it, whose stress gives σn there.
    pub hosts: Vec<Vec<usize>>,
}

/// The faces of a reinforcement one embedded face stands for.
pub const EMBEDDED_SIDES: f64 = 2.0;

impl ContactFace {
    /// How many faces of the reinforcement each point stands for: 2 for an embedded reinforcement,
    /// 1 for a face of a split one or of a pair. A point's shear force is τ·ℓ times this.
    pub fn sides(&self) -> f64 {
        if self.embedded.is_some() {
            EMBEDDED_SIDES
        } else {
            1.0
        }
    }

    /// The face as a message names it: `upper face`, `geotextile on geomembrane face`, or `face`
    /// for a hand-made pair's one face.
    pub fn named(&self) -> String {
        if self.label == "face" {
            "face".to_string()
        } else {
            format!("{} face", self.label)
        }
    }
}

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Interface {
    pub name: String,
    pub faces: Vec<ContactFace>,
    /// For the slit that a reinforcement leaves behind its tail as it slides: the index of that
    /// reinforcement's interface. The slit's two soil faces come into contact as they are uncovered.
    pub slit_of: Option<usize>,
}

/// Which row a multiplier belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MultiplierRef {
    pub interface: usize,
    pub face: usize,
    pub point: usize,
    pub tangential: bool,
}

/// The list of multipliers of a set of interfaces, in their fixed order.
pub fn multipliers(interfaces: &[Interface]) -> Vec<MultiplierRef> {
    let mut out = Vec::new();
    for (i, interface) in interfaces.iter().enumerate() {
        for (f, face) in interface.faces.iter().enumerate() {
            for p in 0..face.points.len() {
                out.push(MultiplierRef { interface: i, face: f, point: p, tangential: false });
                if interface.is_tie() {
                    out.push(MultiplierRef { interface: i, face: f, point: p, tangential: true });
                }
            }
        }
    }
    out
}

/// A row over displacement DOFs: `(node, [coefficient on ux, coefficient on uy])`.
pub type Row = Vec<(NodeIndex, [f64; 2])>;

impl Interface {
    /// Tied in both directions (validation keeps `tie` from mixing with sliding laws in one interface).
    pub fn is_tie(&self) -> bool {
        self.faces.first().is_some_and(|f| f.law.is_tie())
    }
}

impl ContactFace {
    /// Unit normal into the master face's soil on segment `segment`, in the reference geometry.
    pub fn normal(&self, mesh: &Mesh, segment: usize) -> [f64; 2] {
        let (a, b) = (mesh.position(self.master[segment]), mesh.position(self.master[segment + 1]));
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let left = [-d[1] / len, d[0] / len];
        if self.soil_on_left {
            left
        } else {
            [-left[0], -left[1]]
        }
    }

    /// `+v` on the slave node and `−N_i(ξ)·v` on the master segment's nodes, and zeros on the other
    /// nodes of the point's reserved segments (in master order, so that the pattern is the same for
    /// every segment within them).
    pub fn relative_row(&self, point: &ContactPoint, v: [f64; 2]) -> Row {
        let (na, nb) = (1.0 - point.xi, point.xi);
        let (mut first, mut last) = match point.reserved {
            Some((lo, hi)) => (lo.min(point.segment), hi.max(point.segment) + 1),
            None => (point.segment, point.segment + 1),
        };
        if let Some(w) = &point.weights {
            for &(j, _) in w {
                first = first.min(j);
                last = last.max(j);
            }
        }
        let mut row = Vec::with_capacity(last - first + 2);
        row.push((point.slave, v));
        for k in first..=last {
            let n = match &point.weights {
                Some(w) => w.iter().find(|(j, _)| *j == k).map_or(0.0, |(_, c)| *c),
                None if k == point.segment => na,
                None if k == point.segment + 1 => nb,
                None => 0.0,
            };
            row.push((self.master[k], [-n * v[0], -n * v[1]]));
        }
        row
    }

    /// The master point a point's rows tie it to, in the reference geometry: Σ N_i X_i.
    pub fn tied_position(&self, mesh: &Mesh, point: &ContactPoint) -> [f64; 2] {
        let pairs: Vec<(usize, f64)> = match &point.weights {
            Some(w) => w.clone(),
            None => vec![(point.segment, 1.0 - point.xi), (point.segment + 1, point.xi)],
        };
        pairs.iter().fold([0.0, 0.0], |m, &(j, c)| {
            let x = mesh.position(self.master[j]);
            [m[0] + c * x[0], m[1] + c * x[1]]
        })
    }

    /// The normal constraint row of a point.
    pub fn normal_row(&self, mesh: &Mesh, point: &ContactPoint) -> Row {
        self.relative_row(point, self.normal(mesh, point.segment))
    }

    /// The tangential row (slip s = row · u) of a point.
    pub fn tangential_row(&self, point: &ContactPoint) -> Row {
        self.relative_row(point, point.tangent)
    }
}

/// Reserve `each_side` master segments on either side of each point's segment in its rows'
/// sparsity pattern. The reservation is kept while every point stays within its own; once one
/// leaves (the pattern changes, so a new analysis is due anyway) every window is centred again on
/// its point's segment. The points then leave together, and a run needs about
/// 1 + (largest slip ÷ `each_side` segments) analyses. Returns whether the windows were reset.
pub fn reserve_windows(interfaces: &mut [Interface], each_side: usize) -> bool {
    // a tie does not slide
    let sliding = || interfaces.iter().filter(|i| !i.is_tie()).flat_map(|i| i.faces.iter());
    let all_inside = sliding()
        .flat_map(|f| f.points.iter())
        .all(|p| p.reserved.is_some_and(|(lo, hi)| (lo..=hi).contains(&p.segment)));
    if all_inside {
        return false;
    }
    for face in interfaces.iter_mut().filter(|i| !i.is_tie()).flat_map(|i| i.faces.iter_mut()) {
        let last = face.master.len().saturating_sub(2);
        for p in &mut face.points {
            p.reserved = Some((p.segment.saturating_sub(each_side), (p.segment + each_side).min(last)));
        }
    }
    true
}

/// Closest-point projection of `x` onto the polyline `path`: `(segment, ξ, signed distance along
/// the left normal, outside)`, where `outside` says that the foot lies beyond either end.
pub fn project(mesh: &Mesh, path: &[NodeIndex], x: [f64; 2]) -> (usize, f64, f64, bool) {
    let mut best = (0usize, 0.0f64, f64::INFINITY, f64::INFINITY, true);
    for s in 0..path.len().saturating_sub(1) {
        let (a, b) = (mesh.position(path[s]), mesh.position(path[s + 1]));
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let raw = ((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / len2;
        let xi = raw.clamp(0.0, 1.0);
        let foot = [a[0] + xi * d[0], a[1] + xi * d[1]];
        let dist = ((x[0] - foot[0]).powi(2) + (x[1] - foot[1]).powi(2)).sqrt();
        let tol = 1e-9;
        let outside = (s == 0 && raw < -tol) || (s + 2 == path.len() && raw > 1.0 + tol);
        let len = len2.sqrt();
        let signed = ((x[0] - a[0]) * -d[1] + (x[1] - a[1]) * d[0]) / len;
        if dist < best.3 - 1e-14 * len {
            best = (s, xi, signed, dist, outside);
        }
    }
    (best.0, best.1, best.2, best.4)
}

/// One thing wrong with the geometry of an interface's input: the place in the interface's own
/// input (`path[3]`, `master[2..3]`, `master_normal`) and what is wrong there.
#[derive(Debug, Clone, PartialEq)]
pub struct GeometryProblem {
    pub place: String,
    pub message: String,
}

/// The problems found while building one interface's geometry.
#[derive(Debug, Default)]
pub struct GeometryProblems(pub Vec<GeometryProblem>);

impl GeometryProblems {
    pub fn push(&mut self, place: impl Into<String>, message: impl Into<String>) {
        self.0.push(GeometryProblem { place: place.into(), message: message.into() });
    }

    /// `Err` with every problem found so far, if there is one.
    pub fn check(&mut self) -> Result<(), Vec<GeometryProblem>> {
        if self.0.is_empty() {
            Ok(())
        } else {
            Err(std::mem::take(&mut self.0))
        }
    }
}

pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

pub(crate) fn unit(a: [f64; 2]) -> [f64; 2] {
    let l = (a[0] * a[0] + a[1] * a[1]).sqrt();
    [a[0] / l, a[1] / l]
}

/// Slip directions (towards the first node) and tributary lengths of a slave line (areas ∫N·2πr ds
/// in axisymmetry).
fn slave_line_geometry(mesh: &Mesh, line: &[NodeIndex]) -> Vec<([f64; 2], f64)> {
    let m = line.len();
    (0..m)
        .map(|k| {
            let prev = if k > 0 { Some(sub(mesh.position(line[k - 1]), mesh.position(line[k]))) } else { None };
            let next = if k + 1 < m { Some(sub(mesh.position(line[k]), mesh.position(line[k + 1]))) } else { None };
            let len = |v: Option<[f64; 2]>| v.map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt()).unwrap_or(0.0);
            let dir = match (prev, next) {
                (Some(p), Some(n)) => {
                    let (p, n) = (unit(p), unit(n));
                    unit([p[0] + n[0], p[1] + n[1]])
                }
                (Some(p), None) => unit(p),
                (None, Some(n)) => unit(n),
                (None, None) => [1.0, 0.0],
            };
            let tributary = if mesh.geometry.is_axisymmetric() {
                // ∫ N_k·2πr ds over the two segments, r linear along each
                let c = |j: usize| mesh.geometry.circumference(mesh.position(line[j]));
                let before = if k > 0 { len(prev) * (c(k - 1) / 6.0 + c(k) / 3.0) } else { 0.0 };
                let after = if k + 1 < m { len(next) * (c(k) / 3.0 + c(k + 1) / 6.0) } else { 0.0 };
                before + after
            } else {
                0.5 * (len(prev) + len(next))
            };
            (dir, tributary)
        })
        .collect()
}

/// The slave points of `slave` on a face whose master path is `face_master`, each associated with
/// the segment it projects onto, in contact, with no slip yet.
pub(crate) fn points_on(mesh: &Mesh, face_master: &[NodeIndex], slave: &[NodeIndex]) -> Vec<ContactPoint> {
    slave_line_geometry(mesh, slave)
        .into_iter()
        .zip(slave)
        .map(|((tangent, tributary), &s)| {
            let (segment, xi, _, _) = project(mesh, face_master, mesh.position(s));
            ContactPoint {
                slave: s,
                tangent,
                tributary,
                segment,
                xi,
                normal_state: NormalState::Active,
                tangential_state: NormalState::Active,
                gap0: 0.0,
                shear: Default::default(),
                slit_tip: false,
                pressure_from: None,
                reserved: None,
                weights: None,
            }
        })
        .collect()
}
