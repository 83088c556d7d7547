//! ParaView output: three VTK unstructured grids per step (soil, reinforcement, interface), written
//! with the `vtkio` crate, and a `.pvd` collection over the steps written here (vtkio has no `.pvd`
//! writer). Every file is written atomically; the `.pvd` is rewritten after each step, so it always
//! lists exactly the steps whose grids are complete.
//!
//! Points sit at their reference positions; ParaView's *Warp By Vector* on `displacement` shows the
//! deformed shape.

use super::write_atomically;
use crate::analysis::results::StepResults;
use crate::error::Error;
use crate::model::file::SolidKind;
use crate::model::Model;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

/// The interface point state written to VTK as an integer: 0 stick, 1 slip, 2 open, 3 residual.
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

/// The grids' fixed parts, taken from the model once.
pub struct VtkWriter {
    dir: PathBuf,
    pvd: PathBuf,
    node_ids: Vec<u64>,
    /// Node id → position in `node_ids`, made once.
    node_index: HashMap<u64, usize>,
    node_x: Vec<[f64; 2]>,
    soil_cells: Vec<(CellType, Vec<u64>)>,
    soil_material: Vec<i32>,
    soil_ids: Vec<u64>,
    /// Per bar: the two node indices into `node_ids`.
    bars: Vec<[usize; 2]>,
    /// (time, [soil, reinforcement, interface] file names relative to the `.pvd`).
    steps: Vec<(usize, [String; 3])>,
}

impl VtkWriter {
    pub fn new(model: &Model, out: &Path) -> Self {
        let mesh = &model.mesh;
        let soil_cells = mesh
            .solids
            .iter()
            .map(|s| {
                let kind = match s.kind {
                    SolidKind::Tri3 => CellType::Triangle,
                    SolidKind::Tri6 => CellType::QuadraticTriangle,
                    SolidKind::Quad4 => CellType::Quad,
                    SolidKind::Quad8 => CellType::QuadraticQuad,
                };
                // VTK's quadratic cells list corners, then mid-sides, as geoslip (and Gmsh) do.
                (kind, s.nodes.iter().map(|&n| n as u64).collect())
            })
            .collect();
        VtkWriter {
            dir: out.join("vtk"),
            pvd: out.join("results.pvd"),
            node_ids: mesh.nodes.iter().map(|n| n.id).collect(),
            node_index: mesh.nodes.iter().enumerate().map(|(i, n)| (n.id, i)).collect(),
            node_x: mesh.nodes.iter().map(|n| n.x).collect(),
            soil_cells,
            soil_material: mesh.solids.iter().map(|s| s.material as i32).collect(),
            soil_ids: mesh.solids.iter().map(|s| s.id).collect(),
            bars: mesh.bars.iter().map(|b| b.nodes).collect(),
            steps: Vec::new(),
        }
    }

    /// Write step number `time` (1, 2, …) and rewrite the `.pvd`.
    ///
    /// # Errors
    /// [`Error::Write`] naming the file that could not be written.
    pub fn write_step(&mut self, time: usize, r: &StepResults) -> Result<(), Error> {
        let names = [
            format!("step-{time:04}-soil.vtu"),
            format!("step-{time:04}-reinforcement.vtu"),
            format!("step-{time:04}-interface.vtu"),
        ];
        let index = &self.node_index;
        let mut u = vec![[0.0; 2]; self.node_ids.len()];
        for (id, _, d) in &r.displacements {
            if let Some(&i) = index.get(id) {
                u[i] = *d;
            }
        }
        let grids = [self.soil(r, &u), self.reinforcement(r, &u), interface(r, &u, index, &self.node_x)];
        for (grid, name) in grids.into_iter().zip(&names) {
            let path = self.dir.join(name);
            let mut bytes = Vec::new();
            let vtk = Vtk {
                version: Version::new_xml(1, 0),
                title: String::new(),
                byte_order: ByteOrder::LittleEndian,
                data: DataSet::inline(grid),
                file_path: None,
            };
            vtk.write_xml(&mut bytes).map_err(|e| Error::Write {
                path: path.clone(),
                source: std::io::Error::other(format!("VTK writer: {e}")),
            })?;
            write_atomically(&path, &bytes)?;
        }
        self.steps.push((time, names.map(|n| format!("vtk/{n}"))));
        write_atomically(&self.pvd, self.collection().as_bytes())
    }

    fn collection(&self) -> String {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (time, files) in &self.steps {
            for (part, file) in files.iter().enumerate() {
                s.push_str(&format!("    <DataSet timestep=\"{time}\" part=\"{part}\" file=\"{file}\"/>\n"));
            }
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        s
    }

    fn soil(&self, r: &StepResults, u: &[[f64; 2]]) -> UnstructuredGridPiece {
        let points = flat_points(self.node_x.iter().copied());
        // Element averages of the Gauss-point stress and strain, as symmetric tensors (xx, yy, zz, xy, yz, xz).
        let row: HashMap<u64, usize> = self.soil_ids.iter().enumerate().map(|(i, &id)| (id, i)).collect();
        let mut stress = vec![[0.0; 6]; self.soil_ids.len()];
        let mut strain = vec![[0.0; 6]; self.soil_ids.len()];
        let mut count = vec![0usize; self.soil_ids.len()];
        let mut pore = vec![0.0; self.soil_ids.len()];
        let mut plastic = vec![0.0; self.soil_ids.len()];
        let mut plastic_strain = vec![0.0; self.soil_ids.len()];
        for g in &r.stresses {
            let Some(&i) = row.get(&g.element) else { continue };
            pore[i] += g.pore_pressure;
            plastic[i] += if g.yield_state.is_plastic() { 1.0 } else { 0.0 };
            plastic_strain[i] += g.plastic_strain;
            let s = g.stress;
            let e = g.strain;
            for (k, v) in [s[0], s[1], s[3], s[2], 0.0, 0.0].into_iter().enumerate() {
                stress[i][k] += v;
            }
            for (k, v) in [e[0], e[1], 0.0, 0.5 * e[2], 0.0, 0.0].into_iter().enumerate() {
                strain[i][k] += v;
            }
            count[i] += 1;
        }
        for i in 0..count.len() {
            let n = count[i].max(1) as f64;
            stress[i].iter_mut().for_each(|v| *v /= n);
            strain[i].iter_mut().for_each(|v| *v /= n);
            pore[i] /= n;
            plastic[i] /= n;
            plastic_strain[i] /= n;
        }
        // Only the soil present in this step (a lift not yet placed, or excavated soil, has no
        // Gauss-point results): the grid of each step shows the soil as built so far.
        let present: Vec<bool> = count.iter().map(|&c| c > 0).collect();
        let keep = |i: &usize| present[*i];
        let (cells, types) = cells((0..self.soil_ids.len()).filter(keep).map(|i| self.soil_cells[i].clone()));
        let pick = |v: &[f64]| -> Vec<f64> { (0..v.len()).filter(keep).map(|i| v[i]).collect() };
        let stress: Vec<[f64; 6]> = (0..stress.len()).filter(keep).map(|i| stress[i]).collect();
        let strain: Vec<[f64; 6]> = (0..strain.len()).filter(keep).map(|i| strain[i]).collect();
        let (pore, plastic, plastic_strain) = (pick(&pore), pick(&plastic), pick(&plastic_strain));
        let material: Vec<_> = (0..self.soil_ids.len()).filter(keep).map(|i| self.soil_material[i]).collect();
        let ids: Vec<_> = (0..self.soil_ids.len()).filter(keep).map(|i| self.soil_ids[i]).collect();
        UnstructuredGridPiece {
            points,
            cells: Cells { cell_verts: cells, types },
            data: Attributes {
                point: vec![Attribute::vectors("displacement").with_data(vectors(u))],
                cell: vec![
                    Attribute::generic("stress", 6).with_data(stress.concat()),
                    Attribute::generic("strain", 6).with_data(strain.concat()),
                    Attribute::scalars("pore_pressure", 1).with_data(pore),
                    Attribute::scalars("plastic_fraction", 1).with_data(plastic),
                    Attribute::scalars("plastic_strain", 1).with_data(plastic_strain),
                    Attribute::scalars("material", 1).with_data(material),
                    Attribute::scalars("element_id", 1).with_data(ids),
                ],
            },
        }
    }

    fn reinforcement(&self, r: &StepResults, u: &[[f64; 2]]) -> UnstructuredGridPiece {
        // Only the bars' nodes, renumbered.
        let mut local: HashMap<usize, u64> = HashMap::new();
        let mut order = Vec::new();
        for b in &self.bars {
            for &n in b {
                local.entry(n).or_insert_with(|| {
                    order.push(n);
                    (order.len() - 1) as u64
                });
            }
        }
        let (cells, types) = cells(self.bars.iter().map(|b| (CellType::Line, vec![local[&b[0]], local[&b[1]]])));
        let state: Vec<i32> = r
            .bar_forces
            .iter()
            .map(|b| match b.state {
                "slack" => 1,
                "ruptured" => 2,
                _ => 0,
            })
            .collect();
        UnstructuredGridPiece {
            points: flat_points(order.iter().map(|&n| self.node_x[n])),
            cells: Cells { cell_verts: cells, types },
            data: Attributes {
                point: vec![Attribute::vectors("displacement")
                    .with_data(vectors(&order.iter().map(|&n| u[n]).collect::<Vec<_>>()))],
                cell: vec![
                    Attribute::scalars("axial_force", 1)
                        .with_data(r.bar_forces.iter().map(|b| b.axial_force).collect::<Vec<f64>>()),
                    Attribute::scalars("state", 1).with_data(state),
                    Attribute::scalars("bar_id", 1).with_data(r.bar_forces.iter().map(|b| b.bar).collect::<Vec<u64>>()),
                ],
            },
        }
    }
}

/// Interface points as polylines, one per face, points in the order of the face's slave line.
fn interface(
    r: &StepResults,
    u: &[[f64; 2]],
    index: &HashMap<u64, usize>,
    node_x: &[[f64; 2]],
) -> UnstructuredGridPiece {
    let mut x = Vec::new();
    let mut disp = Vec::new();
    let (mut sigma_n, mut tau, mut slip, mut state, mut face_id) = (vec![], vec![], vec![], vec![], vec![]);
    let mut lines = Vec::new();
    let mut faces: Vec<(&str, &str)> = Vec::new();
    for (k, p) in r.interface_points.iter().enumerate() {
        let key = (p.interface.as_str(), p.face.as_str());
        let face = match faces.iter().position(|f| *f == key) {
            Some(f) => f,
            None => {
                faces.push(key);
                faces.len() - 1
            }
        };
        if k > 0 && face_id.last() == Some(&(face as i32)) {
            lines.push((CellType::Line, vec![(k - 1) as u64, k as u64]));
        }
        let node = index.get(&p.slave_node).copied();
        x.push(node.map_or(p.x, |n| node_x[n]));
        disp.push(node.map_or([0.0; 2], |n| u[n]));
        sigma_n.push(p.sigma_n);
        tau.push(p.tau);
        slip.push(p.slip);
        state.push(interface_state_code(p.state, p.sliding, p.post_peak));
        face_id.push(face as i32);
    }
    let line_face: Vec<i32> = lines.iter().map(|(_, v)| face_id[v[0] as usize]).collect();
    let (cells, types) = cells(lines.into_iter());
    UnstructuredGridPiece {
        points: flat_points(x.into_iter()),
        cells: Cells { cell_verts: cells, types },
        data: Attributes {
            point: vec![
                Attribute::vectors("displacement").with_data(vectors(&disp)),
                Attribute::scalars("sigma_n", 1).with_data(sigma_n),
                Attribute::scalars("tau", 1).with_data(tau),
                Attribute::scalars("slip", 1).with_data(slip),
                Attribute::scalars("state", 1).with_data(state),
                Attribute::scalars("face", 1).with_data(face_id),
            ],
            cell: vec![Attribute::scalars("face", 1).with_data(line_face)],
        },
    }
}

fn flat_points(x: impl Iterator<Item = [f64; 2]>) -> vtkio::model::IOBuffer {
    x.flat_map(|p| [p[0], p[1], 0.0]).collect::<Vec<f64>>().into()
}

fn vectors(u: &[[f64; 2]]) -> Vec<f64> {
    u.iter().flat_map(|d| [d[0], d[1], 0.0]).collect()
}

fn cells(list: impl Iterator<Item = (CellType, Vec<u64>)>) -> (VertexNumbers, Vec<CellType>) {
    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    let mut types = Vec::new();
    for (t, nodes) in list {
        connectivity.extend(nodes);
        offsets.push(connectivity.len() as u64);
        types.push(t);
    }
    (VertexNumbers::XML { connectivity, offsets }, types)
}
