//! Gmsh input: Debian's `gmsh` regenerates the lab pull-out box from its `.geo`, the result matches
//! the shipped `.msh`, formats 4.1 (ASCII and binary) and 2.2 read as the same mesh, and the mesh's
//! physical groups carry the supports, the airbag pressure and the reinforcement into a model that
//! solves.
//!
//! Reference: Gmsh reference manual, §10.1 "MSH file format" (versions 4.1 and 2.2); and
//! docs/verification.md §5: in a frictionless rigid box under a uniform pressure q, the
//! vertical stress at depth h is oedometric, σv = q + γ·h, so the normal stress on the geogrid at
//! h = 0.3 m is 50 + 18·0.3 = 55.4 kPa on both faces once the box is confined.
//!
//! These tests need Debian's `gmsh` (scripts/test-all.sh installs it).

mod common;

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::gmsh::GmshMesh;
use geoslip::linsol::Backend;
use geoslip::model::Model;
use std::path::{Path, PathBuf};
use std::process::Command;

fn example_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/lab-pullout")
}

fn gmsh(geo: &Path, out: &Path, format: &[&str]) {
    let status = Command::new("gmsh")
        .arg(geo)
        .args(["-2", "-v", "1", "-o"])
        .arg(out)
        .args(format)
        .status()
        .unwrap_or_else(|e| panic!("cannot run gmsh ({e}): install Debian's gmsh (scripts/test-all.sh does)"));
    assert!(status.success(), "gmsh failed on {}", geo.display());
}

/// The lab example's model file with its mesh replaced and only the confinement stage kept.
fn confined_box(dir: &Path, mesh: &Path) -> Model {
    let text = std::fs::read_to_string(example_dir().join("lab-pullout.toml")).unwrap();
    let mut file = geoslip::model::parse(Path::new("lab-pullout.toml"), &text).unwrap();
    file.mesh.as_mut().unwrap().file = mesh.display().to_string();
    file.series = None;
    file.stages.truncate(1);
    Model::from_file(&dir.join("lab-pullout.toml"), &file).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn regenerated_mesh_matches_the_shipped_one_and_the_confined_box_is_oedometric() {
    let dir = tempfile::tempdir().unwrap();
    let fresh = dir.path().join("lab-pullout.msh");
    gmsh(&example_dir().join("lab-pullout.geo"), &fresh, &["-format", "msh41"]);
    let shipped = GmshMesh::read(&example_dir().join("lab-pullout.msh")).unwrap();
    let regenerated = GmshMesh::read(&fresh).unwrap();
    assert_eq!(regenerated.format, "4.1");
    assert_eq!(shipped.nodes.len(), regenerated.nodes.len(), "node count");
    for ((ta, xa), (tb, xb)) in shipped.nodes.iter().zip(&regenerated.nodes) {
        assert_eq!(ta, tb);
        for d in 0..3 {
            assert!((xa[d] - xb[d]).abs() < 1e-12, "node {ta} moved");
        }
    }
    assert_eq!(shipped.elements.len(), regenerated.elements.len(), "element count");
    for (a, b) in shipped.elements.iter().zip(&regenerated.elements) {
        assert_eq!((a.tag, a.kind, &a.nodes), (b.tag, b.kind, &b.nodes));
    }
    assert_eq!(shipped.groups, regenerated.groups);

    // 30 × 12 quadrangles of 50 mm; the grid's 24 segments split the soil.
    let model = confined_box(dir.path(), &fresh);
    assert_eq!(model.mesh.solids.len(), 360);
    assert_eq!(model.mesh.bars.len(), 24);
    let mut sink = Collect::default();
    analysis::run(&model, &RunOptions::for_model(&model, Backend::Auto), &mut sink).unwrap_or_else(|e| panic!("{e}"));
    let last = sink.last().unwrap();
    let expected = 50.0 + 18.0 * 0.3;
    let mut checked = 0;
    for p in last.interface_points.iter().filter(|p| p.interface == "grid" && p.x[0] > 0.22 && p.x[0] < 0.98) {
        assert!(
            common::relative_error(p.sigma_n, expected) < 0.005,
            "{} face at x = {}: σn = {} kPa, expected {expected}",
            p.face,
            p.x[0],
            p.sigma_n
        );
        checked += 1;
    }
    assert_eq!(checked, 2 * 15, "both faces, 15 points each");
}

#[test]
fn formats_22_and_binary_41_read_as_the_same_model() {
    let dir = tempfile::tempdir().unwrap();
    let geo = example_dir().join("lab-pullout.geo");
    let variants = [
        ("ascii41.msh", vec!["-format", "msh41"]),
        ("binary41.msh", vec!["-format", "msh41", "-bin"]),
        ("ascii22.msh", vec!["-format", "msh22"]),
    ];
    let mut models = Vec::new();
    for (name, flags) in &variants {
        let path = dir.path().join(name);
        gmsh(&geo, &path, flags);
        models.push(confined_box(dir.path(), &path));
    }
    let reference = &models[0];
    for (m, (name, _)) in models.iter().zip(&variants).skip(1) {
        assert_eq!(m.mesh.nodes.len(), reference.mesh.nodes.len(), "{name}: nodes");
        assert_eq!(m.mesh.solids.len(), reference.mesh.solids.len(), "{name}: elements");
        for (a, b) in m.mesh.nodes.iter().zip(&reference.mesh.nodes) {
            assert_eq!(a.id, b.id, "{name}");
            assert!((a.x[0] - b.x[0]).abs() < 1e-12 && (a.x[1] - b.x[1]).abs() < 1e-12, "{name}: node {}", a.id);
        }
        for (a, b) in m.mesh.solids.iter().zip(&reference.mesh.solids) {
            assert_eq!((a.id, &a.nodes), (b.id, &b.nodes), "{name}");
        }
        assert_eq!(m.node_sets.keys().collect::<Vec<_>>(), reference.node_sets.keys().collect::<Vec<_>>(), "{name}");
    }
    // the counts the section headers declare (read before a file is parsed, for the memory limit)
    // are the file's: nodes in every format, elements in the ASCII ones
    for (name, _) in &variants {
        let bytes = std::fs::read(dir.path().join(name)).unwrap();
        let parsed = GmshMesh::from_bytes(Path::new(name), &bytes).unwrap();
        let (nodes, elements) = geoslip::gmsh::declared_counts(&bytes).expect(name);
        assert_eq!(nodes, parsed.nodes.len(), "{name}");
        if !name.starts_with("binary") {
            assert_eq!(elements, parsed.elements.len(), "{name}");
        }
    }
}

#[test]
fn the_model_can_name_the_geo_file_and_geoslip_meshes_it() {
    let model = Model::load(&example_dir().join("lab-pullout.toml"));
    let model = model.unwrap_or_else(|e| panic!("{e}"));
    let source = model.mesh_source.as_ref().unwrap();
    let generated = source.generated.as_ref().expect("meshed from the .geo");
    assert!(generated.gmsh_version.starts_with('4'), "gmsh --version said {}", generated.gmsh_version);
    assert_eq!(source.soil_elements, 360);
    let shipped = std::fs::read(example_dir().join("lab-pullout.msh")).unwrap();
    let shipped = GmshMesh::from_bytes(Path::new("shipped"), &shipped).unwrap();
    assert_eq!(source.nodes, shipped.nodes.len(), "every node of the mesh is on a soil element");
}

#[test]
fn a_clockwise_element_is_renumbered_and_a_hand_written_22_file_solves() {
    // Two unit quads on a fixed floor with frictionless sides under q = 10 kPa: σyy = −q everywhere.
    let model = Model::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gmsh/two-quads.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(model.notes.iter().any(|n| n.contains("1 element(s)") && n.contains("clockwise")), "{:?}", model.notes);
    let c = common::run(&model, Backend::Dense);
    for s in c.last().unwrap().stresses(&model) {
        assert!((s.stress[1] + 10.0).abs() < 1e-9, "element {}: σyy = {}", s.element, s.stress[1]);
    }
}

fn problems_of(toml: &str, dir: &Path) -> String {
    let path = dir.join("model.toml");
    std::fs::write(&path, toml).unwrap();
    match Model::load(&path) {
        Ok(_) => panic!("the model was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn mesh_problems_name_the_file_the_group_and_the_entity() {
    let dir = tempfile::tempdir().unwrap();
    let msh = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gmsh/two-quads-v22.msh");
    let head = |materials: &str, extra: &str| {
        format!(
            "units = {{ length = \"m\", force = \"kN\" }}\nmesh = {{ file = \"{}\", materials = {{ {materials} }} }}\n\
             materials.soil.clay = {{ youngs_modulus = 1e4, poissons_ratio = 0.25 }}\n\
             materials.reinforcement.grid = {{ axial_stiffness = 1e3 }}\n{extra}\n[[stages]]\nname = \"s\"\n",
            msh.display()
        )
    };
    // a group the mesh does not have; the message lists the ones it has
    let e = problems_of(&head("sand = \"clay\"", ""), dir.path());
    assert!(
        e.contains("mesh.materials.sand") && e.contains("no physical surface named \"sand\"") && e.contains("\"clay\""),
        "{e}"
    );
    // surface elements left without a material
    assert!(e.contains("2 surface element(s)") && e.contains("physical surface clay"), "{e}");
    // a reinforcement line that is not a physical curve
    let e = problems_of(
        &head(
            "clay = \"clay\"",
            "[[interfaces]]\nname = \"g\"\nreinforcement = { line = \"grid\", material = \"grid\" }\nlaw = { type = \"tie\" }",
        ),
        dir.path(),
    );
    assert!(e.contains("interfaces[0].reinforcement.line") && e.contains("no physical curve named \"grid\""), "{e}");
    assert!(e.contains("\"floor\"") && e.contains("\"top\""), "the message lists the curves: {e}");
    // a material that does not exist is caught by the ordinary checks, naming the element
    let e = problems_of(&head("clay = \"peat\"", ""), dir.path());
    assert!(e.contains("peat"), "{e}");
    // a missing mesh file
    let e = problems_of(&head("clay = \"clay\"", "").replace("two-quads-v22.msh", "nowhere.msh"), dir.path());
    assert!(e.contains("mesh.file") && e.contains("nowhere.msh") && e.contains("cannot read"), "{e}");
}

#[test]
fn unsupported_elements_and_missing_nodes_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    let msh = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gmsh/no-physical-names.msh");
    let toml = format!(
        "units = {{ length = \"m\", force = \"kN\" }}\nmesh = {{ file = \"{}\", materials = {{ 7 = \"clay\" }} }}\n\
         materials.soil.clay = {{ youngs_modulus = 1e4, poissons_ratio = 0.25 }}\n[[stages]]\nname = \"s\"\n",
        msh.display()
    );
    let e = problems_of(&toml, dir.path());
    // element 2 is a 9-node quadrangle in physical surface 7 (unnamed, so named by its number)
    assert!(e.contains("element 2") && e.contains("9-node quadrangle") && e.contains("SecondOrderIncomplete"), "{e}");
    // element 1 is in no physical surface
    assert!(e.contains("(no physical surface)"), "{e}");
}

#[test]
fn a_geo_file_without_gmsh_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_geoslip"))
        .args(["check", "--mesh"])
        .arg(example_dir().join("lab-pullout.toml"))
        .env("GEOSLIP_GMSH", dir.path().join("no-gmsh-here"))
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(2));
    let e = String::from_utf8_lossy(&status.stderr);
    assert!(e.contains("lab-pullout.geo") && e.contains("needs Gmsh") && e.contains("apt-get install gmsh"), "{e}");
}
