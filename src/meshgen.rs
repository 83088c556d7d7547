//! Structured meshes for tests, benchmarks and the generated examples: rectangular blocks of any
//! solid type, and a complete pull-out box model.

use crate::model::file::*;
use std::collections::BTreeMap;

/// A structured rectangular block.
#[derive(Debug, Clone)]
pub struct Block {
    pub nodes: Vec<NodeRow>,
    pub elements: Vec<SolidElementRow>,
    pub nx: usize,
    pub ny: usize,
    first_node: u64,
    /// Lattice step: 1 for linear elements, 2 for quadratic (mid-side nodes on the odd lattice).
    step: usize,
    /// Coordinates of the lattice lines (mid-side lines included for quadratic elements).
    xs: Vec<f64>,
    ys: Vec<f64>,
}

impl Block {
    /// A block from (x0, y0), `width` × `height`, `nx` × `ny` cells (each split in two triangles for
    /// tri3/tri6). Node ids start at `first_node`, element ids at `first_element`.
    pub fn new(
        kind: SolidKind,
        (x0, y0): (f64, f64),
        (width, height): (f64, f64),
        (nx, ny): (usize, usize),
        material: &str,
        first_node: u64,
        first_element: u64,
    ) -> Block {
        // Positions are computed as i·width/n (one rounding), so that 3·1.0/20 prints as 0.15.
        let lines = |origin: f64, size: f64, n: usize| -> Vec<f64> {
            let cells = n * if kind.is_quadratic() { 2 } else { 1 };
            (0..=cells).map(|k| origin + (k as f64 * size) / cells as f64).collect()
        };
        let xs = lines(x0, width, nx);
        let ys = lines(y0, height, ny);
        Block::build(kind, xs, ys, material, first_node, first_element)
    }

    /// A block whose cell boundaries lie at `x_lines` × `y_lines` (increasing; graded meshes).
    /// Mid-side nodes of quadratic elements sit half-way.
    pub fn graded(
        kind: SolidKind,
        x_lines: &[f64],
        y_lines: &[f64],
        material: &str,
        first_node: u64,
        first_element: u64,
    ) -> Block {
        let lines = |c: &[f64]| -> Vec<f64> {
            if !kind.is_quadratic() {
                return c.to_vec();
            }
            let mut out = vec![c[0]];
            for w in c.windows(2) {
                out.push(0.5 * (w[0] + w[1]));
                out.push(w[1]);
            }
            out
        };
        Block::build(kind, lines(x_lines), lines(y_lines), material, first_node, first_element)
    }

    fn build(
        kind: SolidKind,
        xs: Vec<f64>,
        ys: Vec<f64>,
        material: &str,
        first_node: u64,
        first_element: u64,
    ) -> Block {
        let step = if kind.is_quadratic() { 2 } else { 1 };
        let (nx, ny) = ((xs.len() - 1) / step, (ys.len() - 1) / step);
        let mut block = Block { nodes: Vec::new(), elements: Vec::new(), nx, ny, first_node, step, xs, ys };
        let (lx, ly) = (nx * step, ny * step);
        for j in 0..=ly {
            for i in 0..=lx {
                // quad8 has no centre node; triangles use the cell-diagonal mid-points
                let centre = step == 2 && i % 2 == 1 && j % 2 == 1;
                if centre && kind == SolidKind::Quad8 {
                    continue;
                }
                block.nodes.push(NodeRow(block.lattice_id(i, j), block.coordinate(0, i), block.coordinate(1, j)));
            }
        }
        let mut id = first_element;
        let mut elements = Vec::new();
        for cj in 0..ny {
            for ci in 0..nx {
                let (i, j) = (ci * step, cj * step);
                let s = step;
                let n = |a: usize, b: usize| block.lattice_id(i + a, j + b);
                let mut push = |nodes: Vec<u64>, kind: SolidKind| {
                    elements.push(SolidElementRow { id, kind, nodes, material: material.to_string() });
                    id += 1;
                };
                match kind {
                    SolidKind::Quad4 => push(vec![n(0, 0), n(1, 0), n(1, 1), n(0, 1)], kind),
                    SolidKind::Quad8 => {
                        push(vec![n(0, 0), n(2, 0), n(2, 2), n(0, 2), n(1, 0), n(2, 1), n(1, 2), n(0, 1)], kind)
                    }
                    SolidKind::Tri3 => {
                        push(vec![n(0, 0), n(s, 0), n(s, s)], kind);
                        push(vec![n(0, 0), n(s, s), n(0, s)], kind);
                    }
                    SolidKind::Tri6 => {
                        push(vec![n(0, 0), n(2, 0), n(2, 2), n(1, 0), n(2, 1), n(1, 1)], kind);
                        push(vec![n(0, 0), n(2, 2), n(0, 2), n(1, 1), n(1, 2), n(0, 1)], kind);
                    }
                }
            }
        }
        block.elements = elements;
        block
    }

    fn coordinate(&self, axis: usize, k: usize) -> f64 {
        if axis == 0 {
            self.xs[k]
        } else {
            self.ys[k]
        }
    }

    fn lattice_id(&self, i: usize, j: usize) -> u64 {
        self.first_node + (j * (self.nx * self.step + 1) + i) as u64
    }

    /// Id of the corner-lattice node at column `i` (0..=nx), row `j` (0..=ny).
    pub fn node(&self, i: usize, j: usize) -> u64 {
        self.lattice_id(i * self.step, j * self.step)
    }

    /// Position of corner-lattice node (i, j).
    pub fn position(&self, i: usize, j: usize) -> [f64; 2] {
        [self.coordinate(0, i * self.step), self.coordinate(1, j * self.step)]
    }

    /// Every node on row `j` of the corner lattice, including mid-side nodes between them.
    pub fn row_nodes(&self, j: usize) -> Vec<u64> {
        (0..=self.nx * self.step).map(|i| self.lattice_id(i, j * self.step)).collect()
    }

    /// Every node on column `i` of the corner lattice, including mid-side nodes.
    pub fn column_nodes(&self, i: usize) -> Vec<u64> {
        (0..=self.ny * self.step).map(|j| self.lattice_id(i * self.step, j)).collect()
    }

    /// The element sides along row `j`, left to right, as edge-set entries.
    pub fn row_edges(&self, j: usize) -> Vec<Vec<u64>> {
        (0..self.nx)
            .map(|i| {
                let (a, b) = (self.node(i, j), self.node(i + 1, j));
                if self.step == 2 {
                    vec![a, b, self.lattice_id(2 * i + 1, 2 * j)]
                } else {
                    vec![a, b]
                }
            })
            .collect()
    }

    /// The element sides along column `i`, bottom to top, as edge-set entries.
    pub fn column_edges(&self, i: usize) -> Vec<Vec<u64>> {
        (0..self.ny)
            .map(|j| {
                let (a, b) = (self.node(i, j), self.node(i, j + 1));
                if self.step == 2 {
                    vec![a, b, self.lattice_id(2 * i, 2 * j + 1)]
                } else {
                    vec![a, b]
                }
            })
            .collect()
    }
}

/// A pull-out box: a soil block `length` × `height` with a reinforcement at mid-height (or `layers`
/// reinforcements at equal spacing, `grid-1` from the bottom up) from the front face (x = 0) over
/// `embedded` metres, a surcharge on top, a fixed base, and rigid front and
/// back walls (ux = 0). Stage 1 applies the surcharge; stage 2 pulls the head by `pull` (towards −x)
/// in `steps` increments.
#[derive(Debug, Clone)]
pub struct PullOutBox {
    pub length: f64,
    pub height: f64,
    pub embedded: f64,
    /// Elements along x and (per half) along y.
    pub nx: usize,
    pub ny_half: usize,
    pub kind: SolidKind,
    pub youngs_modulus: f64,
    pub poissons_ratio: f64,
    pub unit_weight: f64,
    pub axial_stiffness: f64,
    pub law: ShearLawSpec,
    pub surcharge: f64,
    pub pull: f64,
    pub steps: usize,
    /// Reinforcement layers: 1 is the grid at mid-height, named `grid`.
    pub layers: usize,
}

impl Default for PullOutBox {
    fn default() -> Self {
        PullOutBox {
            length: 1.0,
            height: 0.6,
            embedded: 0.8,
            nx: 20,
            ny_half: 3,
            kind: SolidKind::Quad4,
            youngs_modulus: 20_000.0,
            poissons_ratio: 0.3,
            unit_weight: 18.0,
            axial_stiffness: 1000.0,
            law: ShearLawSpec::Linear { shear_stiffness: 540.0 },
            surcharge: 50.0,
            pull: 0.01,
            steps: 5,
            layers: 1,
        }
    }
}

impl PullOutBox {
    /// The pull-out test in clay of Yi (1996), Figs. 7–10 (`examples/paper-pullout-clay.toml`): a
    /// grid embedded 1.0 m in a 1.3 m × 0.6 m clay box (E = 8 MPa, ν = 0.3, γ = 18 kN/m³) of 26 × 12
    /// quad4, 20 kPa surcharge, EA = 260 kN/m, Coulomb faces (Ks = 540 kN/m³, c = 2 kPa,
    /// φ = 12.6°), pulled 60 mm in 60 steps.
    pub fn paper_clay() -> Self {
        PullOutBox {
            length: 1.3,
            height: 0.6,
            embedded: 1.0,
            nx: 26,
            ny_half: 6,
            kind: SolidKind::Quad4,
            youngs_modulus: 8000.0,
            poissons_ratio: 0.3,
            unit_weight: 18.0,
            axial_stiffness: 260.0,
            law: ShearLawSpec::Coulomb { shear_stiffness: 540.0, cohesion: 2.0, friction_angle: 12.6 },
            surcharge: 20.0,
            pull: 0.06,
            steps: 60,
            layers: 1,
        }
    }

    /// The model file. The reinforcement ends at the last lattice column within `embedded`.
    pub fn model(&self) -> ModelFile {
        let block =
            Block::new(self.kind, (0.0, 0.0), (self.length, self.height), (self.nx, 2 * self.ny_half), "soil", 1, 1);
        let cells_embedded =
            ((self.embedded / self.length) * self.nx as f64).round().clamp(1.0, self.nx as f64) as usize;
        let layers = self.layers.max(1);
        let rows = 2 * self.ny_half;
        let mut levels: Vec<usize> =
            (1..=layers).map(|k| ((k * rows) as f64 / (layers + 1) as f64).round() as usize).collect();
        levels.retain(|&j| j > 0 && j < rows);
        levels.dedup();
        let names: Vec<String> =
            if layers == 1 { vec!["grid".into()] } else { (1..=levels.len()).map(|k| format!("grid-{k}")).collect() };
        let mut node_sets = BTreeMap::new();
        node_sets.insert("base".into(), block.row_nodes(0));
        node_sets.insert("front".into(), block.column_nodes(0));
        node_sets.insert("back".into(), block.column_nodes(self.nx));
        let mut edge_sets = BTreeMap::new();
        edge_sets.insert("top".into(), block.row_edges(2 * self.ny_half));
        let mut soil = BTreeMap::new();
        soil.insert(
            "soil".into(),
            SoilMaterial::linear_elastic(self.youngs_modulus, self.poissons_ratio, self.unit_weight),
        );
        let mut reinforcement = BTreeMap::new();
        reinforcement.insert(
            "grid".into(),
            ReinforcementMaterial {
                axial_stiffness: self.axial_stiffness,
                tension_only: false,
                rupture_strength: None,
                weight: None,
            },
        );
        let factors = (1..=self.steps).map(|k| k as f64 / self.steps as f64).collect();
        ModelFile {
            title: "pull-out box".into(),
            units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
            materials: Materials { soil, reinforcement },
            nodes: block.nodes.clone(),
            elements: block.elements.clone(),
            bars: Vec::new(),
            node_sets,
            edge_sets,
            element_sets: BTreeMap::new(),
            supports: vec![
                support("base", &[Direction::X, Direction::Y]),
                support("front", &[Direction::X]),
                support("back", &[Direction::X]),
            ],
            interfaces: levels
                .iter()
                .zip(&names)
                .map(|(&j, name)| InterfaceSpec {
                    name: name.clone(),
                    reinforcement: Some(ReinforcementPath {
                        path: (0..=cells_embedded).map(|i| block.node(i, j)).collect(),
                        line: None,
                        head: None,
                        material: "grid".into(),
                        stack: Vec::new(),
                        free_length: None,
                        mode: Default::default(),
                    }),
                    law: self.law.clone(),
                    ..Default::default()
                })
                .collect(),
            stages: vec![
                Stage {
                    name: "surcharge".into(),
                    load_factors: vec![1.0],
                    loads: vec![LoadSpec::EdgeTraction {
                        name: None,
                        edge_set: "top".into(),
                        pressure: self.surcharge,
                        shear: 0.0,
                    }],
                    prescribed: Vec::new(),
                    ..Default::default()
                },
                Stage {
                    name: "pull-out".into(),
                    load_factors: factors,
                    loads: Vec::new(),
                    prescribed: names
                        .iter()
                        .map(|name| PrescribedDisplacement {
                            node: None,
                            nodes: None,
                            set: Some(format!("{name}.head")),
                            ux: Some(-self.pull),
                            uy: None,
                        })
                        .collect(),
                    ..Default::default()
                },
            ],
            analysis: Default::default(),
            mesh: None,
            series: None,
            design: None,
        }
    }
}

/// A support on a named set.
pub fn support(set: &str, fix: &[Direction]) -> Support {
    Support { node: None, nodes: None, set: Some(set.into()), fix: fix.to_vec() }
}

/// A direct-shear box as docs/verification.md §4's Coulomb block: a 1 m × 0.5 m weightless quad4 block (4 × 2 elements,
/// E = 10 MPa, ν = 0.3) on a rigid base from x = −0.5 to 1.5 m (its nodes fixed, the block's base the
/// slave line of interface `base` with `law`); stage "surcharge" applies `q` on top with every
/// block node held in x, stage "shear" moves every block node `d` in x by `load_factors`. The node
/// set `block` holds the block's nodes.
pub fn block_on_rigid_base(law: ShearLawSpec, q: f64, d: f64, load_factors: Vec<f64>) -> ModelFile {
    let block = Block::new(SolidKind::Quad4, (0.0, 0.0), (1.0, 0.5), (4, 2), "soil", 1, 1);
    let mut nodes = block.nodes.clone();
    // the base runs from x = −0.5 to 1.5, so that the block stays on it as it slides
    let base: Vec<u64> = (0..=8).map(|i| 100 + i as u64).collect();
    for (i, id) in base.iter().enumerate() {
        nodes.push(NodeRow(*id, -0.5 + 0.25 * i as f64, 0.0));
    }
    let mut node_sets = BTreeMap::new();
    node_sets.insert("block".into(), block.nodes.iter().map(|n| n.0).collect());
    node_sets.insert("base".into(), base.clone());
    let mut edge_sets = BTreeMap::new();
    edge_sets.insert("top".into(), block.row_edges(2));
    let mut soil = BTreeMap::new();
    soil.insert("soil".into(), SoilMaterial::linear_elastic(1.0e4, 0.3, 0.0));
    let on_block =
        |ux: f64| PrescribedDisplacement { node: None, nodes: None, set: Some("block".into()), ux: Some(ux), uy: None };
    ModelFile {
        title: "Coulomb block".into(),
        units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
        materials: Materials { soil, reinforcement: BTreeMap::new() },
        nodes,
        elements: block.elements.clone(),
        bars: Vec::new(),
        node_sets,
        edge_sets,
        element_sets: BTreeMap::new(),
        supports: vec![support("base", &[Direction::X, Direction::Y])],
        interfaces: vec![InterfaceSpec {
            name: "base".into(),
            slave: Some(block.row_nodes(0)),
            master: Some(base),
            master_normal: Some([0.0, -1.0]),
            law,
            ..Default::default()
        }],
        stages: vec![
            Stage {
                name: "surcharge".into(),
                load_factors: vec![1.0],
                loads: vec![LoadSpec::EdgeTraction { name: None, edge_set: "top".into(), pressure: q, shear: 0.0 }],
                prescribed: vec![on_block(0.0)],
                ..Default::default()
            },
            Stage {
                name: "shear".into(),
                load_factors,
                loads: Vec::new(),
                prescribed: vec![on_block(d)],
                ..Default::default()
            },
        ],
        analysis: AnalysisSettings::default(),
        mesh: None,
        series: None,
        design: None,
    }
}
