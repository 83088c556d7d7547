//! The three grids a step is shown on in ParaView: the soil, the reinforcement and the interface
//! points, as plain arrays (points at their reference positions, cells, and the fields on them).
//! The VTK writer (`vtk.rs`) and the HDF5/XDMF writer (`results_h5.rs`) both write these, under the
//! same field names, so that a step looks the same in either.
//!
//! Soil cell values are element averages of the Gauss-point values: the sum over the element's
//! Gauss points in the order of `StepResults::stresses`, divided by their number.

use crate::analysis::results::ElementStress;
use crate::analysis::results::StepResults;
use crate::model::file::SolidKind;
use crate::model::Model;
use rayon::prelude::*;
use std::collections::HashMap;

/// The interface point state written as an integer: 0 stick, 1 slip, 2 open, 3 residual.
pub fn interface_state_code(normal_state: &str, sliding: bool, post_peak: bool) -> i32 {
    match normal_state {
        "active" | "redundant" => {
            if post_peak {
                3
            } else if sliding {
                1
            } else {
                0
            }
        }
        _ => 2,
    }
}

/// The contact state of an [`interface_state_code`], as interface.csv writes it.
pub fn contact_name(code: i32) -> &'static str {
    match code {
        0 => "stick",
        1 => "slip",
        3 => "residual",
        _ => "open",
    }
}

/// A bar's state written as an integer: 0 intact (or not placed yet), 1 slack, 2 ruptured.
pub fn bar_state_code(state: &str) -> i32 {
    match state {
        "slack" => 1,
        "ruptured" => 2,
        _ => 0,
    }
}

/// Node or element id → position in the mesh's list. Every step looks up each node and Gauss
/// point (10⁵ of them at 10⁵ unknowns): ids numbered from about 1 up, as Gmsh and the mesh
/// generator number them, are looked up in an array; scattered ids (more than twice the count
/// apart) in a hash map.
enum IdIndex {
    Dense(Vec<Option<u32>>),
    Scattered(HashMap<u64, usize>),
}

impl IdIndex {
    fn new(ids: impl Iterator<Item = u64> + Clone) -> IdIndex {
        let count = ids.clone().count();
        let largest = ids.clone().max().unwrap_or(0);
        if largest <= 2 * count as u64 + 1024 && count <= u32::MAX as usize {
            let mut position = vec![None; largest as usize + 1];
            for (i, id) in ids.enumerate() {
                position[id as usize] = Some(i as u32);
            }
            IdIndex::Dense(position)
        } else {
            IdIndex::Scattered(ids.enumerate().map(|(i, id)| (id, i)).collect())
        }
    }

    fn get(&self, id: u64) -> Option<usize> {
        match self {
            IdIndex::Dense(position) => position.get(usize::try_from(id).ok()?).copied().flatten().map(|i| i as usize),
            IdIndex::Scattered(map) => map.get(&id).copied(),
        }
    }
}

/// The grids' fixed parts, taken from the model once.
pub struct GridLayout {
    /// Each mesh node's reference position: the soil grid's points, in mesh order.
    pub node_x: Vec<[f64; 2]>,
    /// Node id → position in the mesh's node list.
    node_index: IdIndex,
    /// Each soil element: its kind and its mesh node indices (corners, then mid-sides, as VTK and
    /// XDMF list them).
    pub soil_cells: Vec<(SolidKind, Vec<usize>)>,
    /// Each soil element's material (index in name order).
    pub soil_material: Vec<i32>,
    pub soil_ids: Vec<u64>,
    /// Soil element id → position in `soil_ids`.
    soil_row: IdIndex,
    /// The reinforcement grid's points: the mesh nodes of the bars, in order of first appearance.
    pub bar_nodes: Vec<usize>,
    /// Each bar's two points (indices into `bar_nodes`).
    pub bar_cells: Vec<[usize; 2]>,
}

/// The soil as present in one step, on every mesh node.
pub struct SoilGrid {
    /// The soil elements present in this step (indices into `GridLayout::soil_cells`): a lift not
    /// yet placed, or excavated soil, has no Gauss-point results and is left out.
    pub present: Vec<usize>,
    /// Per mesh node (x, y, 0).
    pub displacement: Vec<[f64; 3]>,
    /// Per present element, symmetric tensors in VTK's order xx, yy, zz, xy, yz, xz; the shear
    /// strain as the tensor component εxy = γxy/2.
    pub stress: Vec<[f64; 6]>,
    pub strain: Vec<[f64; 6]>,
    pub pore_pressure: Vec<f64>,
    /// The share of the element's Gauss points on the yield surface, 0 to 1.
    pub plastic_fraction: Vec<f64>,
    pub plastic_strain: Vec<f64>,
    pub material: Vec<i32>,
    pub element_id: Vec<u64>,
}

/// The reinforcement bars in one step: points `GridLayout::bar_nodes`, cells `bar_cells`.
pub struct ReinforcementGrid {
    /// Per point (x, y, 0).
    pub displacement: Vec<[f64; 3]>,
    /// Per bar, in the mesh's bar order.
    pub axial_force: Vec<f64>,
    pub state: Vec<i32>,
    pub bar_id: Vec<u64>,
}

/// The interface points of one step, in the order of `StepResults::interface_points` (face by face,
/// each in the order of its slave line).
pub struct InterfaceGrid {
    /// Each point at its slave node's reference position.
    pub x: Vec<[f64; 2]>,
    pub displacement: Vec<[f64; 3]>,
    pub lambda: Vec<f64>,
    pub sigma_n: Vec<f64>,
    pub tau: Vec<f64>,
    /// The passive bearing's part of `tau`.
    pub bearing: Vec<f64>,
    /// The opening by dilatancy.
    pub dilation: Vec<f64>,
    pub slip: Vec<f64>,
    /// [`interface_state_code`].
    pub state: Vec<i32>,
    /// The point's face: 0, 1, … in order of appearance.
    pub face: Vec<i32>,
    /// Each face's name, `<interface>:<face>`, by its number.
    pub face_names: Vec<String>,
    /// Lines joining neighbouring points of one face (indices into the points).
    pub lines: Vec<[usize; 2]>,
}

/// The three grids of one step.
pub struct StepGrids {
    pub soil: SoilGrid,
    pub reinforcement: ReinforcementGrid,
    pub interface: InterfaceGrid,
}

/// One soil element's sums over its Gauss points, for the cell means.
#[derive(Clone, Copy, Default)]
struct CellSums {
    /// In VTK's order xx, yy, zz, xy, yz, xz.
    stress: [f64; 6],
    /// As `stress`, the shear as the tensor component εxy = γxy/2.
    strain: [f64; 6],
    pore: f64,
    /// Gauss points on the yield surface.
    plastic: f64,
    plastic_strain: f64,
    count: usize,
}

impl CellSums {
    /// The sums over `points`, in their order.
    fn of(points: &[ElementStress]) -> CellSums {
        let mut sums = CellSums::default();
        for g in points {
            sums.pore += g.pore_pressure;
            sums.plastic += if g.yield_state.is_plastic() { 1.0 } else { 0.0 };
            sums.plastic_strain += g.plastic_strain;
            let (s, e) = (g.stress, g.strain);
            for (k, v) in [s[0], s[1], s[3], s[2], 0.0, 0.0].into_iter().enumerate() {
                sums.stress[k] += v;
            }
            for (k, v) in [e[0], e[1], 0.0, 0.5 * e[2], 0.0, 0.0].into_iter().enumerate() {
                sums.strain[k] += v;
            }
            sums.count += 1;
        }
        sums
    }

    fn add(&mut self, other: &CellSums) {
        for (a, b) in self.stress.iter_mut().zip(other.stress) {
            *a += b;
        }
        for (a, b) in self.strain.iter_mut().zip(other.strain) {
            *a += b;
        }
        self.pore += other.pore;
        self.plastic += other.plastic;
        self.plastic_strain += other.plastic_strain;
        self.count += other.count;
    }
}

impl GridLayout {
    pub fn new(model: &Model) -> Self {
        let mesh = &model.mesh;
        let mut bar_nodes = Vec::new();
        let mut local: HashMap<usize, usize> = HashMap::new();
        let bar_cells = mesh
            .bars
            .iter()
            .map(|b| {
                b.nodes.map(|n| {
                    *local.entry(n).or_insert_with(|| {
                        bar_nodes.push(n);
                        bar_nodes.len() - 1
                    })
                })
            })
            .collect();
        GridLayout {
            node_x: mesh.nodes.iter().map(|n| n.x).collect(),
            node_index: IdIndex::new(mesh.nodes.iter().map(|n| n.id)),
            soil_cells: mesh.solids.iter().map(|s| (s.kind, s.nodes.clone())).collect(),
            soil_material: mesh.solids.iter().map(|s| s.material as i32).collect(),
            soil_ids: mesh.solids.iter().map(|s| s.id).collect(),
            soil_row: IdIndex::new(mesh.solids.iter().map(|s| s.id)),
            bar_nodes,
            bar_cells,
        }
    }

    /// The three grids of step `r`, whose Gauss-point results are `stresses`.
    pub fn step(&self, r: &StepResults, stresses: &[ElementStress]) -> StepGrids {
        let mut u = vec![[0.0; 3]; self.node_x.len()];
        for (id, _, d) in &r.displacements {
            if let Some(i) = self.node_index.get(*id) {
                u[i] = [d[0], d[1], 0.0];
            }
        }
        StepGrids {
            soil: self.soil(stresses, &u),
            reinforcement: self.reinforcement(r, &u),
            interface: self.interface(r, &u),
        }
    }

    fn soil(&self, stresses: &[ElementStress], u: &[[f64; 3]]) -> SoilGrid {
        let n = self.soil_ids.len();
        // an element's Gauss points come one after another (`StepResults::stresses` lists them
        // element by element): each run of them summed in parallel, the runs added up by element
        let runs: Vec<(usize, CellSums)> = stresses
            .par_chunk_by(|a, b| a.element == b.element)
            .filter_map(|points| Some((self.soil_row.get(points[0].element)?, CellSums::of(points))))
            .collect();
        let mut sums = vec![CellSums::default(); n];
        for (i, run) in &runs {
            sums[*i].add(run);
        }
        let present: Vec<usize> = (0..n).filter(|&i| sums[i].count > 0).collect();
        let mean = |sum: f64, i: usize| sum / sums[i].count as f64;
        SoilGrid {
            displacement: u.to_vec(),
            stress: present.iter().map(|&i| sums[i].stress.map(|v| mean(v, i))).collect(),
            strain: present.iter().map(|&i| sums[i].strain.map(|v| mean(v, i))).collect(),
            pore_pressure: present.iter().map(|&i| mean(sums[i].pore, i)).collect(),
            plastic_fraction: present.iter().map(|&i| mean(sums[i].plastic, i)).collect(),
            plastic_strain: present.iter().map(|&i| mean(sums[i].plastic_strain, i)).collect(),
            material: present.iter().map(|&i| self.soil_material[i]).collect(),
            element_id: present.iter().map(|&i| self.soil_ids[i]).collect(),
            present,
        }
    }

    fn reinforcement(&self, r: &StepResults, u: &[[f64; 3]]) -> ReinforcementGrid {
        ReinforcementGrid {
            displacement: self.bar_nodes.iter().map(|&n| u[n]).collect(),
            axial_force: r.bar_forces.iter().map(|b| b.axial_force).collect(),
            state: r.bar_forces.iter().map(|b| bar_state_code(b.state)).collect(),
            bar_id: r.bar_forces.iter().map(|b| b.bar).collect(),
        }
    }

    fn interface(&self, r: &StepResults, u: &[[f64; 3]]) -> InterfaceGrid {
        let points = &r.interface_points;
        let mut faces: Vec<(&str, &str)> = Vec::new();
        let mut face = Vec::with_capacity(points.len());
        let mut lines = Vec::new();
        for (k, p) in points.iter().enumerate() {
            let key = (p.interface.as_str(), p.face.as_str());
            let f = match faces.iter().position(|f| *f == key) {
                Some(f) => f,
                None => {
                    faces.push(key);
                    faces.len() - 1
                }
            } as i32;
            if k > 0 && face.last() == Some(&f) {
                lines.push([k - 1, k]);
            }
            face.push(f);
        }
        let node = |id: u64| self.node_index.get(id);
        InterfaceGrid {
            x: points.iter().map(|p| node(p.slave_node).map_or(p.x, |n| self.node_x[n])).collect(),
            displacement: points.iter().map(|p| node(p.slave_node).map_or([0.0; 3], |n| u[n])).collect(),
            lambda: points.iter().map(|p| p.lambda).collect(),
            sigma_n: points.iter().map(|p| p.sigma_n).collect(),
            tau: points.iter().map(|p| p.tau).collect(),
            bearing: points.iter().map(|p| p.bearing).collect(),
            dilation: points.iter().map(|p| p.dilation).collect(),
            slip: points.iter().map(|p| p.slip).collect(),
            state: points.iter().map(|p| interface_state_code(p.state, p.sliding, p.post_peak)).collect(),
            face,
            face_names: faces.iter().map(|(interface, face)| format!("{interface}:{face}")).collect(),
            lines,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::mohr_coulomb::YieldState;

    fn point(element: u64, point: usize, v: f64, yielding: bool) -> ElementStress {
        ElementStress {
            element,
            point,
            x: [0.0; 2],
            stress: [v, 2.0 * v, 3.0 * v, 4.0 * v],
            strain: [v, -v, 2.0 * v],
            pore_pressure: 10.0 * v,
            yield_state: if yielding { YieldState::Shear } else { YieldState::Elastic },
            plastic_strain: 0.5 * v,
        }
    }

    /// Each present element's cell values are the means over its Gauss points, wherever in the
    /// list they come (one element's points split in two runs here), in the layout's element
    /// order; an element with no points is left out, as are points of an unknown element.
    #[test]
    fn cell_values_are_the_means_of_each_elements_gauss_points() {
        let soil_ids = vec![3u64, 7, 9];
        let layout = GridLayout {
            node_x: vec![],
            node_index: IdIndex::new(std::iter::empty()),
            soil_cells: vec![(SolidKind::Tri3, vec![]); 3],
            soil_material: vec![0, 1, 2],
            soil_row: IdIndex::new(soil_ids.iter().copied()),
            soil_ids,
            bar_nodes: vec![],
            bar_cells: vec![],
        };
        let stresses = vec![
            point(7, 1, 1.0, false),
            point(7, 2, 2.0, true),
            point(3, 1, 5.0, false),
            point(42, 1, 100.0, false),
            point(7, 3, 6.0, false),
        ];
        let g = layout.soil(&stresses, &[]);
        assert_eq!(g.present, vec![0, 1]);
        assert_eq!(g.element_id, vec![3, 7]);
        assert_eq!(g.material, vec![0, 1]);
        // element 3: one point of 5; element 7: the mean of 1, 2 and 6 is 3
        assert_eq!(g.stress, vec![[5.0, 10.0, 20.0, 15.0, 0.0, 0.0], [3.0, 6.0, 12.0, 9.0, 0.0, 0.0]]);
        assert_eq!(g.strain, vec![[5.0, -5.0, 0.0, 5.0, 0.0, 0.0], [3.0, -3.0, 0.0, 3.0, 0.0, 0.0]]);
        assert_eq!(g.pore_pressure, vec![50.0, 30.0]);
        assert_eq!(g.plastic_fraction, vec![0.0, 1.0 / 3.0]);
        assert_eq!(g.plastic_strain, vec![2.5, 1.5]);
    }
}
