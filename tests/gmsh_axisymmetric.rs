//! An axisymmetric model meshed by Gmsh: the thick-walled cylinder of `tests/thick_cylinder.rs` as
//! a `.geo` file (quad8, graded towards the bore), its physical curves carrying the pressure and
//! the supports, exactly as a plane-strain model's do.
//!
//! Reference: Lamé's solution (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., §28) with
//! εz = 0: u_r = (1 + ν)/E·((1 − 2ν)·A·r + B/r), σr = A − B/r², σθ = A + B/r²,
//! A = p·a²/(b² − a²), B = p·a²·b²/(b² − a²). Tolerance 0.5 % (u_r at every node, stresses at every
//! Gauss point relative to p). Needs Debian's `gmsh` (scripts/test-all.sh installs it).

mod common;

use geoslip::analysis::{self, Collect, RunOptions};
use geoslip::linsol::Backend;
use geoslip::model::Model;

const GEO: &str = r#"// a thick-walled cylinder's meridian slice, a = 0.5 m to b = 2.0 m, 0.25 m high
a = 0.5; b = 2.0; h = 0.25;
Point(1) = {a, 0, 0}; Point(2) = {b, 0, 0}; Point(3) = {b, h, 0}; Point(4) = {a, h, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1} = 25 Using Progression 1.08;
Transfinite Curve{3} = 25 Using Progression 1/1.08;
Transfinite Curve{2, 4} = 2;
Transfinite Surface{1};
Recombine Surface{1};
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Physical Surface("ring") = {1};
Physical Curve("bore") = {4};
Physical Curve("ends") = {1, 3};
"#;

const MODEL: &str = r#"title = "thick-walled cylinder meshed by Gmsh"
units = { length = "m", force = "kN" }
[mesh]
file = "cylinder.geo"
materials = { ring = "soil" }
[materials.soil.soil]
youngs_modulus = 20000.0
poissons_ratio = 0.3
unit_weight = 0.0
[analysis]
geometry = "axisymmetric"
[[supports]]
set = "ends"
fix = ["y"]
[[stages]]
name = "pressure"
loads = [{ type = "edge-traction", edge_set = "bore", pressure = 100.0 }]
"#;

#[test]
fn a_gmsh_cylinder_matches_lame() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cylinder.geo"), GEO).unwrap();
    std::fs::write(dir.path().join("cylinder.toml"), MODEL).unwrap();
    let model = Model::load(&dir.path().join("cylinder.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert!(model.mesh.solids.iter().all(|s| s.kind == geoslip::model::file::SolidKind::Quad8));
    let (e, nu, a, b, p) = (20_000.0, 0.3, 0.5, 2.0, 100.0);
    let big_a = p * a * a / (b * b - a * a);
    let big_b = p * a * a * b * b / (b * b - a * a);
    for backend in Backend::available() {
        let mut c = Collect::default();
        let stats = analysis::run(&model, &RunOptions::for_model(&model, backend), &mut c).unwrap();
        assert!(stats.warnings.is_empty(), "{backend:?}: {:?}", stats.warnings);
        let r = c.last().unwrap();
        for (id, x, u) in &r.displacements {
            let exact = (1.0 + nu) / e * ((1.0 - 2.0 * nu) * big_a * x[0] + big_b / x[0]);
            assert!(common::relative_error(u[0], exact) < 0.005, "{backend:?}: node {id}: u_r {} vs {exact}", u[0]);
        }
        for s in r.stresses(&model) {
            let radius = s.x[0];
            let (sr, st) = (big_a - big_b / (radius * radius), big_a + big_b / (radius * radius));
            assert!((s.stress[0] - sr).abs() < 0.005 * p, "{backend:?}: σr {} vs {sr} at r = {radius}", s.stress[0]);
            assert!((s.stress[3] - st).abs() < 0.005 * p, "{backend:?}: σθ {} vs {st} at r = {radius}", s.stress[3]);
        }
    }
}
