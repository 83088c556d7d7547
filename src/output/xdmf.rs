//! The light data of `results.xdmf`: an XDMF 3 document whose every array is a reference into
//! `results.h5` (the heavy data, `results_h5.rs`). It holds one Temporal collection per grid
//! (reinforcement, interface, soil) with one Uniform grid per kept step, its `Time` the step's
//! number over the run (1, 2, …, as in `summary.json` and `results.pvd`). ParaView opens it as a
//! time series of three blocks; meshio's `TimeSeriesReader` reads the last collection, the soil.
//!
//! XDMF conventions used here: topologies `Triangle`, `Quadrilateral`, `Triangle_6`,
//! `Quadrilateral_8` (corners, then mid-sides, as geoslip and VTK list them), `Mixed` when the
//! soil present in a step has several kinds (each cell its XDMF type number, then its nodes),
//! `Polyline` with two nodes per cell (bars) and `Polyvertex` (interface points); geometry `XYZ`;
//! symmetric tensors as six-column `Matrix` attributes in VTK's order (xx, yy, zz, xy, yz, xz),
//! which ParaView's XDMF readers pass to VTK unchanged (XDMF's own `Tensor6` lists xx, xy, xz, yy,
//! yz, zz, which they would not reorder).

use crate::model::file::SolidKind;

/// How the numbers of an array are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberType {
    Float4,
    Float8,
    Int4,
    Int8,
    UInt8,
}

impl NumberType {
    fn xml(self) -> &'static str {
        match self {
            NumberType::Float4 => "NumberType=\"Float\" Precision=\"4\"",
            NumberType::Float8 => "NumberType=\"Float\" Precision=\"8\"",
            NumberType::Int4 => "NumberType=\"Int\" Precision=\"4\"",
            NumberType::Int8 => "NumberType=\"Int\" Precision=\"8\"",
            NumberType::UInt8 => "NumberType=\"UInt\" Precision=\"8\"",
        }
    }
}

/// An array in the HDF5 file: its path there, its dimensions and its number type.
#[derive(Debug, Clone, PartialEq)]
pub struct DataRef {
    pub path: String,
    pub dims: Vec<usize>,
    pub number: NumberType,
}

/// The cell kind of a topology.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TopologyType {
    Triangle,
    Quadrilateral,
    Triangle6,
    Quadrilateral8,
    /// Several kinds: each cell as its XDMF type number followed by its nodes.
    Mixed,
    /// Two-node lines.
    Polyline,
    /// One point per cell.
    Polyvertex,
}

impl TopologyType {
    pub fn of(kind: SolidKind) -> Self {
        match kind {
            SolidKind::Tri3 => TopologyType::Triangle,
            SolidKind::Tri6 => TopologyType::Triangle6,
            SolidKind::Quad4 => TopologyType::Quadrilateral,
            SolidKind::Quad8 => TopologyType::Quadrilateral8,
        }
    }

    /// The cell type number in a `Mixed` topology (XDMF's XdmfTopologyType ids).
    pub fn mixed_id(kind: SolidKind) -> i64 {
        match kind {
            SolidKind::Tri3 => 4,
            SolidKind::Quad4 => 5,
            SolidKind::Tri6 => 0x24,
            SolidKind::Quad8 => 0x25,
        }
    }

    fn xml(self) -> &'static str {
        match self {
            TopologyType::Triangle => "TopologyType=\"Triangle\"",
            TopologyType::Quadrilateral => "TopologyType=\"Quadrilateral\"",
            TopologyType::Triangle6 => "TopologyType=\"Triangle_6\"",
            TopologyType::Quadrilateral8 => "TopologyType=\"Quadrilateral_8\"",
            TopologyType::Mixed => "TopologyType=\"Mixed\"",
            TopologyType::Polyline => "TopologyType=\"Polyline\" NodesPerElement=\"2\"",
            TopologyType::Polyvertex => "TopologyType=\"Polyvertex\" NodesPerElement=\"1\"",
        }
    }
}

/// A grid's cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Topology {
    pub kind: TopologyType,
    pub cells: usize,
    pub data: DataRef,
}

/// Where a field's values sit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Center {
    Node,
    Cell,
}

/// A field on a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    pub name: &'static str,
    pub center: Center,
    pub data: DataRef,
}

/// One grid of one step.
#[derive(Debug, Clone, PartialEq)]
pub struct GridStep {
    pub topology: Topology,
    pub geometry: DataRef,
    pub fields: Vec<Field>,
}

/// One kept step: its number over the run, a label, and its grids by name.
#[derive(Debug, Clone, PartialEq)]
pub struct KeptStep {
    pub time: usize,
    pub label: String,
    pub grids: Vec<(&'static str, GridStep)>,
}

/// The grids in the order of their collections in the document: the soil last, where meshio's
/// `TimeSeriesReader` looks.
pub const GRIDS: [&str; 3] = ["reinforcement", "interface", "soil"];

/// The XDMF document over `steps` (in time order), its arrays in the HDF5 file `h5_name` beside it.
pub fn document(h5_name: &str, steps: &[KeptStep]) -> String {
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n");
    for grid in GRIDS {
        if !steps.iter().any(|k| k.grids.iter().any(|(name, _)| *name == grid)) {
            continue;
        }
        s.push_str(&format!("    <Grid Name=\"{grid}\" GridType=\"Collection\" CollectionType=\"Temporal\">\n"));
        for step in steps {
            let Some((_, g)) = step.grids.iter().find(|(name, _)| *name == grid) else { continue };
            s.push_str(&format!("      <Grid Name=\"{}\" GridType=\"Uniform\">\n", escape(&step.label)));
            s.push_str(&format!("        <Time Value=\"{}\"/>\n", step.time));
            s.push_str(&format!(
                "        <Topology {} NumberOfElements=\"{}\">\n",
                g.topology.kind.xml(),
                g.topology.cells
            ));
            data_item(&mut s, h5_name, &g.topology.data);
            s.push_str("        </Topology>\n        <Geometry GeometryType=\"XYZ\">\n");
            data_item(&mut s, h5_name, &g.geometry);
            s.push_str("        </Geometry>\n");
            for f in &g.fields {
                let kind = match f.data.dims.get(1) {
                    None | Some(1) => "Scalar",
                    Some(3) => "Vector",
                    Some(9) => "Tensor",
                    Some(_) => "Matrix",
                };
                let center = match f.center {
                    Center::Node => "Node",
                    Center::Cell => "Cell",
                };
                s.push_str(&format!(
                    "        <Attribute Name=\"{}\" AttributeType=\"{kind}\" Center=\"{center}\">\n",
                    f.name
                ));
                data_item(&mut s, h5_name, &f.data);
                s.push_str("        </Attribute>\n");
            }
            s.push_str("      </Grid>\n");
        }
        s.push_str("    </Grid>\n");
    }
    s.push_str("  </Domain>\n</Xdmf>\n");
    s
}

fn data_item(s: &mut String, h5_name: &str, d: &DataRef) {
    let dims: Vec<String> = d.dims.iter().map(usize::to_string).collect();
    s.push_str(&format!(
        "          <DataItem Dimensions=\"{}\" {} Format=\"HDF\">{}:{}</DataItem>\n",
        dims.join(" "),
        d.number.xml(),
        escape(h5_name),
        escape(&d.path)
    ));
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(time: usize, label: &str) -> KeptStep {
        let data = |path: &str, dims: Vec<usize>, number| DataRef { path: path.into(), dims, number };
        KeptStep {
            time,
            label: label.into(),
            grids: vec![(
                "soil",
                GridStep {
                    topology: Topology {
                        kind: TopologyType::Quadrilateral,
                        cells: 2,
                        data: data("/mesh/soil/topology-1", vec![2, 4], NumberType::Int8),
                    },
                    geometry: data("/mesh/soil/geometry", vec![6, 3], NumberType::Float8),
                    fields: vec![Field {
                        name: "displacement",
                        center: Center::Node,
                        data: data(&format!("/steps/{time}/soil/displacement"), vec![6, 3], NumberType::Float8),
                    }],
                },
            )],
        }
    }

    #[test]
    fn a_document_lists_each_step_of_each_grid_with_its_time_and_its_arrays() {
        let text = document("results.h5", &[step(1, "load step 1"), step(4, "pull & \"hold\" step 2")]);
        assert_eq!(text.matches("<Grid Name=\"soil\" GridType=\"Collection\" CollectionType=\"Temporal\">").count(), 1);
        assert!(!text.contains("Name=\"interface\""), "no collection for a grid no step has");
        assert!(text.contains("<Time Value=\"1\"/>") && text.contains("<Time Value=\"4\"/>"));
        assert!(text.contains("Name=\"pull &amp; &quot;hold&quot; step 2\""));
        assert_eq!(
            text.matches("results.h5:/mesh/soil/geometry</DataItem>").count(),
            2,
            "one geometry, referenced twice"
        );
        assert!(text.contains(
            "<DataItem Dimensions=\"6 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">results.h5:/steps/4/soil/displacement</DataItem>"
        ));
        assert!(text.contains("<Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">"));
        assert!(text.contains("<Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"2\">"));
    }
}
