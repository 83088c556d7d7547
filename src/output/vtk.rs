//! ParaView output as VTK files: three unstructured grids per kept step (soil, reinforcement,
//! interface; see `grids.rs`), encoded with the `vtkio` crate, and a `.pvd` collection over the
//! steps encoded here (vtkio has no `.pvd` writer). The writer thread writes each file atomically,
//! in the order they are handed to it, and the `.pvd` after the grids it lists, so it always lists
//! exactly the steps whose grids are complete.
//!
//! Points sit at their reference positions; ParaView's *Warp By Vector* on `displacement` shows the
//! deformed shape.

use super::grids::{GridLayout, StepGrids};
use crate::error::Error;
use crate::model::file::SolidKind;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

/// The `.vtu` files of the kept steps and their `.pvd` collection, as the bytes the result writer
/// writes.
pub struct VtkWriter {
    /// The output folder, to name a file that cannot be encoded.
    folder: PathBuf,
    /// (time, [soil, reinforcement, interface] file names relative to the `.pvd`), in time order.
    steps: Vec<(usize, [String; 3])>,
}

impl VtkWriter {
    pub fn new(folder: &Path) -> Self {
        VtkWriter { folder: folder.to_path_buf(), steps: Vec::new() }
    }

    /// The files of step number `time` (1, 2, …), by their names in the output folder; the
    /// `.pvd` lists the step from its next rewrite (`collection`).
    ///
    /// # Errors
    /// [`Error::Write`] naming the file that could not be encoded.
    pub fn step_files(
        &mut self,
        time: usize,
        layout: &GridLayout,
        grids: &StepGrids,
    ) -> Result<Vec<(String, Vec<u8>)>, Error> {
        let names = [
            format!("step-{time:04}-soil.vtu"),
            format!("step-{time:04}-reinforcement.vtu"),
            format!("step-{time:04}-interface.vtu"),
        ];
        let pieces = [soil(layout, grids), reinforcement(layout, grids), interface(grids)];
        let mut files = Vec::with_capacity(3);
        for (grid, name) in pieces.into_iter().zip(&names) {
            let rel = format!("vtk/{name}");
            let mut bytes = Vec::new();
            let vtk = Vtk {
                version: Version::new_xml(1, 0),
                title: String::new(),
                byte_order: ByteOrder::LittleEndian,
                data: DataSet::inline(grid),
                file_path: None,
            };
            vtk.write_xml(&mut bytes).map_err(|e| Error::Write {
                path: self.folder.join(&rel),
                source: std::io::Error::other(format!("VTK writer: {e}")),
            })?;
            files.push((rel, bytes));
        }
        let entry = (time, names.map(|n| format!("vtk/{n}")));
        let at = self.steps.partition_point(|(t, _)| *t < time);
        self.steps.insert(at, entry);
        Ok(files)
    }

    /// The `.pvd` collection over the steps handed out so far (rewritten at the steps where the
    /// files written whole are due, and at the end of the run: `pace.rs`).
    pub fn collection(&self) -> String {
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
}

fn soil(layout: &GridLayout, grids: &StepGrids) -> UnstructuredGridPiece {
    let g = &grids.soil;
    let (cells, types) = cells(g.present.iter().map(|&i| {
        let (kind, nodes) = &layout.soil_cells[i];
        let kind = match kind {
            SolidKind::Tri3 => CellType::Triangle,
            SolidKind::Tri6 => CellType::QuadraticTriangle,
            SolidKind::Quad4 => CellType::Quad,
            SolidKind::Quad8 => CellType::QuadraticQuad,
        };
        // VTK's quadratic cells list corners, then mid-sides, as geoslip (and Gmsh) do.
        (kind, nodes.iter().map(|&n| n as u64).collect())
    }));
    UnstructuredGridPiece {
        points: flat_points(layout.node_x.iter().copied()),
        cells: Cells { cell_verts: cells, types },
        data: Attributes {
            point: vec![Attribute::vectors("displacement").with_data(g.displacement.concat())],
            cell: vec![
                Attribute::generic("stress", 6).with_data(g.stress.concat()),
                Attribute::generic("strain", 6).with_data(g.strain.concat()),
                Attribute::scalars("pore_pressure", 1).with_data(g.pore_pressure.clone()),
                Attribute::scalars("plastic_fraction", 1).with_data(g.plastic_fraction.clone()),
                Attribute::scalars("plastic_strain", 1).with_data(g.plastic_strain.clone()),
                Attribute::scalars("material", 1).with_data(g.material.clone()),
                Attribute::scalars("element_id", 1).with_data(g.element_id.clone()),
            ],
        },
    }
}

fn reinforcement(layout: &GridLayout, grids: &StepGrids) -> UnstructuredGridPiece {
    let g = &grids.reinforcement;
    let (cells, types) = cells(layout.bar_cells.iter().map(|b| (CellType::Line, vec![b[0] as u64, b[1] as u64])));
    UnstructuredGridPiece {
        points: flat_points(layout.bar_nodes.iter().map(|&n| layout.node_x[n])),
        cells: Cells { cell_verts: cells, types },
        data: Attributes {
            point: vec![Attribute::vectors("displacement").with_data(g.displacement.concat())],
            cell: vec![
                Attribute::scalars("axial_force", 1).with_data(g.axial_force.clone()),
                Attribute::scalars("state", 1).with_data(g.state.clone()),
                Attribute::scalars("bar_id", 1).with_data(g.bar_id.clone()),
            ],
        },
    }
}

/// Interface points as polylines, one per face, points in the order of the face's slave line.
fn interface(grids: &StepGrids) -> UnstructuredGridPiece {
    let g = &grids.interface;
    let line_face: Vec<i32> = g.lines.iter().map(|l| g.face[l[0]]).collect();
    let (cells, types) = cells(g.lines.iter().map(|l| (CellType::Line, vec![l[0] as u64, l[1] as u64])));
    UnstructuredGridPiece {
        points: flat_points(g.x.iter().copied()),
        cells: Cells { cell_verts: cells, types },
        data: Attributes {
            point: vec![
                Attribute::vectors("displacement").with_data(g.displacement.concat()),
                Attribute::scalars("lambda", 1).with_data(g.lambda.clone()),
                Attribute::scalars("sigma_n", 1).with_data(g.sigma_n.clone()),
                Attribute::scalars("tau", 1).with_data(g.tau.clone()),
                Attribute::scalars("bearing", 1).with_data(g.bearing.clone()),
                Attribute::scalars("dilation", 1).with_data(g.dilation.clone()),
                Attribute::scalars("slip", 1).with_data(g.slip.clone()),
                Attribute::scalars("state", 1).with_data(g.state.clone()),
                Attribute::scalars("face", 1).with_data(g.face.clone()),
            ],
            cell: vec![Attribute::scalars("face", 1).with_data(line_face)],
        },
    }
}

fn flat_points(x: impl Iterator<Item = [f64; 2]>) -> vtkio::model::IOBuffer {
    x.flat_map(|p| [p[0], p[1], 0.0]).collect::<Vec<f64>>().into()
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
