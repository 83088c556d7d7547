//! Gmsh mesh files in any order. A 3 × 2 grid of quad4 soil elements with 2-node lines on its
//! bottom and top, written by this test in format 4.1 (ASCII and binary) and 2.2, with its nodes in
//! tag order, reversed, shuffled and split over two entity blocks, with dense and sparse tags and
//! its elements forwards and reversed, reads as the same nodes (tag → x, y) and elements (tag →
//! nodes, physical group), and loads as the same model (coordinates per node id, connectivity per
//! element id, the support on "bottom", the traction on "top"). The regression guarded: a valid
//! 4.1 file with dense tags (1..n) whose node rows are not in tag order must be read by the tags it
//! gives, not by row position. Malformed files are refused with a message naming the file, never a
//! panic; a device or a FIFO named as the mesh is refused as not a regular file, without hanging.
//!
//! Reference: Gmsh reference manual, §10.1 "MSH file format" (version 4.1: `$Entities`, `$Nodes`
//! and `$Elements` in entity blocks; a binary file writes `size_t` in 8 bytes, `int` in 4 and
//! `double` in 8, in the byte order the integer 1 after the `$MeshFormat` line shows) and §10.3
//! "Legacy formats" (version 2.2): nodes may be listed in any order within and across entity
//! blocks, elements in any order, tags need not be dense, and an element refers to nodes by tag.

use geoslip::gmsh::GmshMesh;
use geoslip::model::{Load, Model};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Physical groups: surface 1 "soil", curve 2 "bottom", curve 3 "top".
const NAMES: &str = "$PhysicalNames\n3\n1 2 \"bottom\"\n1 3 \"top\"\n2 1 \"soil\"\n$EndPhysicalNames\n";

/// The elements of one geometrical entity, all of one Gmsh type, in one physical group.
#[derive(Clone)]
struct Block {
    dim: i32,
    entity: i32,
    physical: i32,
    name: &'static str,
    /// Gmsh element type: 1 (2-node line) or 3 (4-node quadrangle).
    code: i32,
    /// Element tag and node tags.
    elements: Vec<(u64, Vec<u64>)>,
}

/// The mesh as data: node tags with (x, y), and the element blocks.
#[derive(Clone)]
struct Grid {
    nodes: Vec<(u64, [f64; 2])>,
    blocks: Vec<Block>,
}

/// 4 × 3 nodes 0.5 m × 0.4 m apart (node k at column k % 4, row k / 4, tagged `node_tag(k)`); six
/// quadrangles counter-clockwise, and three lines on each of the bottom and top edges.
fn grid(node_tag: fn(usize) -> u64, element_tag: fn(usize) -> u64) -> Grid {
    let n = |i: usize, j: usize| node_tag(4 * j + i);
    let nodes = (0..12).map(|k: usize| (node_tag(k), [0.5 * (k % 4) as f64, 0.4 * (k / 4) as f64])).collect();
    let quads: Vec<(u64, Vec<u64>)> = (0..6)
        .map(|c: usize| {
            let (i, j) = (c % 3, c / 3);
            (element_tag(c), vec![n(i, j), n(i + 1, j), n(i + 1, j + 1), n(i, j + 1)])
        })
        .collect();
    let bottom: Vec<(u64, Vec<u64>)> =
        (0..3).map(|i: usize| (element_tag(6 + i), vec![n(i, 0), n(i + 1, 0)])).collect();
    let top: Vec<(u64, Vec<u64>)> = (0..3).map(|i: usize| (element_tag(9 + i), vec![n(i + 1, 2), n(i, 2)])).collect();
    Grid {
        nodes,
        blocks: vec![
            Block { dim: 2, entity: 1, physical: 1, name: "soil", code: 3, elements: quads },
            Block { dim: 1, entity: 1, physical: 2, name: "bottom", code: 1, elements: bottom },
            Block { dim: 1, entity: 2, physical: 3, name: "top", code: 1, elements: top },
        ],
    }
}

/// The grid with its element blocks, and the elements in each, in reverse order.
fn reversed(mut g: Grid) -> Grid {
    g.blocks.reverse();
    for b in &mut g.blocks {
        b.elements.reverse();
    }
    g
}

/// The body of a 4.1 section: ASCII (a line per item) or binary (little-endian `size_t` as u64,
/// `int` as i32, `double` as f64, and no line ends).
struct Out {
    binary: bool,
    bytes: Vec<u8>,
}

impl Out {
    fn text(&mut self, s: &str) {
        self.bytes.extend_from_slice(s.as_bytes());
    }
    /// A number: its little-endian bytes, or its text and a space.
    fn put(&mut self, le_bytes: &[u8], text: String) {
        if self.binary {
            self.bytes.extend_from_slice(le_bytes);
        } else {
            self.text(&(text + " "));
        }
    }
    fn sizes(&mut self, v: &[u64]) {
        for &x in v {
            self.put(&x.to_le_bytes(), x.to_string());
        }
    }
    fn ints(&mut self, v: &[i32]) {
        for &x in v {
            self.put(&x.to_le_bytes(), x.to_string());
        }
    }
    fn reals(&mut self, v: &[f64]) {
        for &x in v {
            self.put(&x.to_le_bytes(), x.to_string());
        }
    }
    fn end_line(&mut self) {
        if !self.binary {
            self.text("\n");
        }
    }
    /// `$Name`, the body, `$EndName` (after a newline of its own in a binary file).
    fn section(&mut self, name: &str, body: impl FnOnce(&mut Out)) {
        self.text(&format!("${name}\n"));
        body(self);
        if self.binary {
            self.text("\n");
        }
        self.text(&format!("$End{name}\n"));
    }
}

/// Format 4.1 with the nodes in `node_blocks` (indices into `g.nodes`, a block each, the first on
/// the surface and the others on a curve: any entity may hold any node).
fn msh41(g: &Grid, node_blocks: &[Vec<usize>], binary: bool) -> Vec<u8> {
    let mut o = Out { binary, bytes: Vec::new() };
    o.text(if binary { "$MeshFormat\n4.1 1 8\n" } else { "$MeshFormat\n4.1 0 8\n" });
    if binary {
        o.ints(&[1]);
        o.text("\n");
    }
    o.text("$EndMeshFormat\n");
    o.text(NAMES);
    o.section("Entities", |o| {
        o.sizes(&[0, 2, 1, 0]); // points, curves, surfaces, volumes
        o.end_line();
        for dim in [1, 2] {
            for b in g.blocks.iter().filter(|b| b.dim == dim) {
                // tag, bounding box, one physical tag, no bounding entities
                o.ints(&[b.entity]);
                o.reals(&[0.0, 0.0, 0.0, 1.5, 0.8, 0.0]);
                o.sizes(&[1]);
                o.ints(&[b.physical]);
                o.sizes(&[0]);
                o.end_line();
            }
        }
    });
    o.section("Nodes", |o| {
        let tags: Vec<u64> = g.nodes.iter().map(|n| n.0).collect();
        let total: usize = node_blocks.iter().map(Vec::len).sum();
        let (min, max) = (*tags.iter().min().unwrap(), *tags.iter().max().unwrap());
        o.sizes(&[node_blocks.len() as u64, total as u64, min, max]);
        o.end_line();
        for (b, block) in node_blocks.iter().enumerate() {
            // entity dimension and tag, not parametric, node count
            o.ints(&[if b == 0 { 2 } else { 1 }, 1, 0]);
            o.sizes(&[block.len() as u64]);
            o.end_line();
            for &k in block {
                o.sizes(&[g.nodes[k].0]);
                o.end_line();
            }
            for &k in block {
                let [x, y] = g.nodes[k].1;
                o.reals(&[x, y, 0.0]);
                o.end_line();
            }
        }
    });
    o.section("Elements", |o| {
        let tags: Vec<u64> = g.blocks.iter().flat_map(|b| b.elements.iter().map(|e| e.0)).collect();
        let (min, max) = (*tags.iter().min().unwrap(), *tags.iter().max().unwrap());
        o.sizes(&[g.blocks.len() as u64, tags.len() as u64, min, max]);
        o.end_line();
        for b in &g.blocks {
            o.ints(&[b.dim, b.entity, b.code]);
            o.sizes(&[b.elements.len() as u64]);
            o.end_line();
            for (tag, nodes) in &b.elements {
                o.sizes(&[*tag]);
                o.sizes(nodes);
                o.end_line();
            }
        }
    });
    o.bytes
}

/// Format 2.2 (ASCII): the nodes of `node_blocks` one after the other; element rows
/// `tag type 2 physical entity nodes…`.
fn msh22(g: &Grid, node_blocks: &[Vec<usize>]) -> Vec<u8> {
    let listed: Vec<usize> = node_blocks.iter().flatten().copied().collect();
    let mut s = format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n{NAMES}$Nodes\n{}\n", listed.len());
    for k in listed {
        let (tag, [x, y]) = g.nodes[k];
        s += &format!("{tag} {x} {y} 0\n");
    }
    let count: usize = g.blocks.iter().map(|b| b.elements.len()).sum();
    s += &format!("$EndNodes\n$Elements\n{count}\n");
    for b in &g.blocks {
        for (tag, nodes) in &b.elements {
            let nodes: Vec<String> = nodes.iter().map(u64::to_string).collect();
            s += &format!("{tag} {} 2 {} {} {}\n", b.code, b.physical, b.entity, nodes.join(" "));
        }
    }
    s += "$EndElements\n";
    s.into_bytes()
}

/// A model on the mesh `mesh`: elastic clay on "soil", fixed on "bottom", pressed on "top".
fn model_toml(mesh: &str) -> String {
    format!(
        "title = \"grid\"\nunits = {{ length = \"m\", force = \"kN\" }}\n\
         mesh = {{ file = \"{mesh}\", materials = {{ soil = \"clay\" }} }}\n\
         materials.soil.clay = {{ youngs_modulus = 10000.0, poissons_ratio = 0.25 }}\n\
         supports = [{{ set = \"bottom\", fix = [\"x\", \"y\"] }}]\n\
         [[stages]]\nname = \"load\"\n\
         loads = [{{ type = \"edge-traction\", edge_set = \"top\", pressure = 10.0 }}]\n"
    )
}

fn block<'a>(g: &'a Grid, name: &str) -> &'a Block {
    g.blocks.iter().find(|b| b.name == name).unwrap()
}

/// Sorted node-tag pairs of a block's lines.
fn edges(g: &Grid, name: &str) -> BTreeSet<(u64, u64)> {
    block(g, name).elements.iter().map(|(_, n)| (n[0].min(n[1]), n[0].max(n[1]))).collect()
}

/// Read `bytes` as a mesh and load the model on it, and check both against the data `g`.
fn check_variant(dir: &Path, name: &str, bytes: &[u8], g: &Grid) {
    let mesh_path = dir.join(format!("{name}.msh"));
    std::fs::write(&mesh_path, bytes).unwrap();
    let expected_nodes: BTreeMap<u64, [f64; 2]> = g.nodes.iter().copied().collect();

    let mesh = GmshMesh::read(&mesh_path).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(mesh.nodes.len(), 12, "{name}: nodes");
    assert!(mesh.nodes.iter().all(|(_, x)| x[2] == 0.0), "{name}: z");
    let read: BTreeMap<u64, [f64; 2]> = mesh.nodes.iter().map(|&(t, x)| (t, [x[0], x[1]])).collect();
    assert_eq!(read, expected_nodes, "{name}: node tag → (x, y)");
    let group_names = |groups: &[usize]| groups.iter().map(|&k| mesh.groups[k].name.clone()).collect::<Vec<_>>();
    let read: BTreeMap<u64, (Vec<u64>, Vec<String>)> =
        mesh.elements.iter().map(|e| (e.tag, (e.nodes.clone(), group_names(e.groups.as_slice())))).collect();
    let expected: BTreeMap<u64, (Vec<u64>, Vec<String>)> = g
        .blocks
        .iter()
        .flat_map(|b| b.elements.iter().map(move |(t, n)| (*t, (n.clone(), vec![b.name.to_string()]))))
        .collect();
    assert_eq!(mesh.elements.len(), 12, "{name}: elements");
    assert_eq!(read, expected, "{name}: element tag → (nodes, physical group)");

    let model_path = dir.join(format!("{name}.toml"));
    std::fs::write(&model_path, model_toml(&format!("{name}.msh"))).unwrap();
    let model = Model::load(&model_path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = &model.mesh;
    assert_eq!(m.nodes.len(), 12, "{name}: model nodes");
    let nodes: BTreeMap<u64, [f64; 2]> = m.nodes.iter().map(|n| (n.id, n.x)).collect();
    assert_eq!(nodes, expected_nodes, "{name}: node id → (x, y)");
    let solids: BTreeMap<u64, Vec<u64>> =
        m.solids.iter().map(|s| (s.id, s.nodes.iter().map(|&i| m.node_id(i)).collect::<Vec<u64>>())).collect();
    let expected: BTreeMap<u64, Vec<u64>> = block(g, "soil").elements.iter().cloned().collect();
    assert_eq!(solids, expected, "{name}: element id → node ids");
    let supported: BTreeSet<u64> = model.supports.iter().map(|&(i, _)| m.node_id(i)).collect();
    let bottom: BTreeSet<u64> = edges(g, "bottom").into_iter().flat_map(|(a, b)| [a, b]).collect();
    assert_eq!(supported, bottom, "{name}: supported nodes");
    let Load::EdgeTraction { sides, .. } = &model.stages[0].loads[0] else { panic!("{name}: no edge traction") };
    let loaded: BTreeSet<(u64, u64)> = sides
        .iter()
        .map(|s| {
            let solid = &m.solids[s.solid];
            let side = solid.kind.sides()[s.side];
            let (a, b) = (m.node_id(solid.nodes[side[0]]), m.node_id(solid.nodes[side[1]]));
            (a.min(b), a.max(b))
        })
        .collect();
    assert_eq!(loaded, edges(g, "top"), "{name}: loaded sides");
}

#[test]
fn every_node_and_element_order_gives_the_same_model() {
    let dir = tempfile::tempdir().unwrap();
    // a fixed permutation of 0..12
    const SHUFFLED: [usize; 12] = [7, 2, 11, 0, 5, 9, 1, 10, 4, 8, 3, 6];
    let orders: [(&str, Vec<Vec<usize>>); 4] = [
        ("in-order", vec![(0..12).collect()]),
        ("reversed", vec![(0..12).rev().collect()]),
        ("shuffled", vec![SHUFFLED.to_vec()]),
        ("two-blocks", vec![vec![11, 9, 7, 5, 3, 1], vec![4, 0, 8, 2, 10, 6]]),
    ];
    let dense = grid(|k| k as u64 + 1, |e| e as u64 + 1);
    let sparse = grid(|k| 10 * k as u64 + 7, |e| 100 * e as u64 + 3);
    for (tags, data) in [("dense", dense), ("sparse", sparse)] {
        for (elements, g) in [("elements", data.clone()), ("elements-reversed", reversed(data))] {
            for (order, node_blocks) in &orders {
                let name = format!("{tags}-{order}-{elements}");
                check_variant(dir.path(), &format!("{name}-41"), &msh41(&g, node_blocks, false), &g);
                check_variant(dir.path(), &format!("{name}-41-binary"), &msh41(&g, node_blocks, true), &g);
                check_variant(dir.path(), &format!("{name}-22"), &msh22(&g, node_blocks), &g);
            }
        }
    }
}

/// `GmshMesh::read` of `bytes` saved as `name`: its error, which must name the file.
fn refused(dir: &Path, name: &str, bytes: &[u8]) -> String {
    std::fs::write(dir.join(name), bytes).unwrap();
    let message = GmshMesh::read(&dir.join(name)).err().unwrap_or_else(|| panic!("{name} was read")).to_string();
    assert!(message.contains(name), "the message does not name {name}: {message}");
    message
}

/// A 2.2 file of these node and element rows, counted.
fn v22(nodes: &[&str], elements: &[&str]) -> Vec<u8> {
    let rows = |r: &[&str]| format!("{}\n{}", r.len(), r.iter().map(|l| format!("{l}\n")).collect::<String>());
    let (n, e) = (rows(nodes), rows(elements));
    format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{n}$EndNodes\n$Elements\n{e}$EndElements\n").into_bytes()
}

/// A 4.1 ASCII file of this `$Nodes` body and, when given, `$Elements` body.
fn v41(nodes: &str, elements: Option<&str>) -> Vec<u8> {
    let mut s = format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n{nodes}$EndNodes\n");
    if let Some(e) = elements {
        s += &format!("$Elements\n{e}$EndElements\n");
    }
    s.into_bytes()
}

/// A binary `$MeshFormat` with this header line and this integer one.
fn binary_head(line: &str, one: [u8; 4]) -> Vec<u8> {
    let mut b = format!("$MeshFormat\n{line}\n").into_bytes();
    b.extend_from_slice(&one);
    b.extend_from_slice(b"\n$EndMeshFormat\n");
    b
}

/// `Model::load`'s error, from a thread so that a read that blocks fails the test, not hangs it.
fn load_error(model: PathBuf) -> String {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(Model::load(&model).map(|_| ()).map_err(|e| e.to_string()));
    });
    match receive.recv_timeout(Duration::from_secs(60)) {
        Ok(Err(e)) => e,
        Ok(Ok(())) => panic!("the model was accepted"),
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => panic!("Model::load did not return within a minute"),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => panic!("Model::load panicked"),
    }
}

#[test]
fn malformed_meshes_are_refused_with_the_file_and_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let square = ["1 0 0 0", "2 1 0 0", "3 1 1 0", "4 0 1 0"];
    let check = |name: &str, bytes: Vec<u8>, keyword: &str| {
        let e = refused(d, name, &bytes);
        assert!(e.contains(keyword), "{name}: expected `{keyword}` in: {e}");
    };

    // 2.2: a tag count that overflows any sum with the row's length
    check("tag-count.msh", v22(&square, &["1 3 18446744073709551615 1 1 1 2 3 4"]), "tag count");
    // 4.1 binary: a data size other than 8, and one beyond every integer type
    check("data-size-3.msh", binary_head("4.1 1 3", 1i32.to_le_bytes()), "data size");
    check("data-size-huge.msh", binary_head("4.1 1 99999999999999999999999", 1i32.to_le_bytes()), "data size");
    // a node tag listed twice, at two places
    check("twice-41.msh", v41("1 3 1 2\n2 1 0 3\n1\n2\n1\n0 0 0\n1 0 0\n5 5 0\n", None), "listed twice");
    check("twice-22.msh", v22(&["1 0 0 0", "2 1 0 0", "1 5 5 0"], &[]), "listed twice");
    // counts no file this small could hold: 2^62 nodes, and a block of 2^64 − 1
    let huge = "4611686018427387904"; // 2^62
    check("huge-total.msh", v41(&format!("1 {huge} 1 {huge}\n2 1 0 1\n1\n0 0 0\n"), None), huge);
    check("huge-block.msh", v41("1 1 1 1\n2 1 0 18446744073709551615\n1\n0 0 0\n", None), "18446744073709551615");
    // an element of a type Gmsh does not have
    let one_node = "1 1 1 1\n2 1 0 1\n1\n0 0 0\n";
    check("unknown-type-41.msh", v41(one_node, Some("1 1 1 1\n2 1 999 1\n1 1\n")), "999");
    check("unknown-type-22.msh", v22(&square, &["1 999 2 1 1 1 2 3 4"]), "999");
    // a big-endian binary file: the integer one byte-swapped
    let mut big = binary_head("4.1 1 8", 1i32.to_be_bytes());
    big.extend_from_slice(b"$Nodes\n");
    big.extend_from_slice(&[0; 32]);
    big.extend_from_slice(b"\n$EndNodes\n");
    check("swapped.msh", big, "big-endian");

    // a binary file cut in the middle of $Nodes, with and without its $EndNodes line
    let g = grid(|k| k as u64 + 1, |e| e as u64 + 1);
    let whole = msh41(&g, &[vec![11, 9, 7, 5, 3, 1], vec![4, 0, 8, 2, 10, 6]], true);
    let find = |s: &[u8]| whole.windows(s.len()).position(|w| w == s).unwrap();
    let (start, end) = (find(&b"$Nodes\n"[..]) + 7, find(&b"\n$EndNodes"[..]));
    for cut in (start..end - 1).step_by(23) {
        refused(d, "cut.msh", &whole[..cut]);
        let mut closed = whole[..cut].to_vec();
        closed.extend_from_slice(b"\n$EndNodes\n");
        refused(d, "cut-closed.msh", &closed);
    }

    // a device and a FIFO named as the mesh: refused before a byte is read
    let fifo = d.join("pipe.msh");
    let status = std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(status.success());
    for mesh in ["/dev/zero", "pipe.msh"] {
        let model = d.join("model.toml");
        std::fs::write(&model, model_toml(mesh)).unwrap();
        let e = load_error(model);
        assert!(e.contains(mesh) && e.contains("regular files only"), "{mesh}: {e}");
    }
}
