//! The output folder is geoslip's only where geoslip wrote: a link below `--out` is neither written
//! through nor followed to delete, a file geoslip did not write is neither replaced nor removed, an
//! input of the run inside `--out` is never touched, and a second run removes exactly what the first
//! one wrote and nobody changed.
//!
//! Reference: docs/reliability.md ("the output folder"): every file operation under `--out` goes
//! through one handle on the folder that opens each component without following links
//! (`openat` with `O_NOFOLLOW`), and each run records what it made in `.geoslip-owned`.
//!
//! ```text
//!   q = 10 kPa
//!   ┌───────┐
//!   │ quad4 │ 1 m × 1 m, one elastic element on a fixed base
//!   └───────┘
//! ```

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn geoslip() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geoslip"))
}

const BLOCK: &str = r#"units = { length = "m", force = "kN" }
nodes = [[1, 0.0, 0.0], [2, 1.0, 0.0], [3, 1.0, 1.0], [4, 0.0, 1.0]]
elements = [{ id = 1, type = "quad4", nodes = [1, 2, 3, 4], material = "clay" }]

[materials.soil.clay]
youngs_modulus = 10000.0
poissons_ratio = 0.3
unit_weight = 18.0

[node_sets]
bottom = [1, 2]

[edge_sets]
top = [[3, 4]]

[[supports]]
set = "bottom"
fix = ["x", "y"]

[[stages]]
name = "load"
load_factors = [0.5, 1.0]
loads = [{ type = "edge-traction", edge_set = "top", pressure = 10.0 }]
"#;

fn run(model: &Path, out: &Path) -> Output {
    geoslip().args(["run", "-q", "--csv", "--vtu", "--out"]).arg(out).arg(model).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Every file below `dir` (links not followed), relative to it, with its bytes.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            let meta = std::fs::symlink_metadata(&path).unwrap();
            if meta.is_dir() {
                stack.push(path);
            } else if meta.is_file() {
                out.push((path.strip_prefix(dir).unwrap().to_path_buf(), std::fs::read(&path).unwrap()));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn a_link_below_the_output_folder_is_refused_and_its_target_left_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("block.toml");
    std::fs::write(&model, BLOCK).unwrap();
    // someone else's folder, with a file in it
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    std::fs::write(elsewhere.join("precious.txt"), "keep me").unwrap();
    for name in ["stage-1-load", "vtk", "restart"] {
        let out = dir.path().join(format!("out-{name}"));
        std::fs::create_dir(&out).unwrap();
        std::os::unix::fs::symlink(&elsewhere, out.join(name)).unwrap();
        let before = snapshot(&elsewhere);
        let o = run(&model, &out);
        assert_eq!(o.status.code(), Some(1), "{name}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains(&format!("{name}")) && e.contains("is a link"), "{name}: {e}");
        assert_eq!(snapshot(&elsewhere), before, "{name}: written through the link");
        // the link itself is left too
        assert!(std::fs::symlink_metadata(out.join(name)).unwrap().file_type().is_symlink());
    }
    // a link where a file goes (the report) is not written through either
    let out = dir.path().join("out-report");
    std::fs::create_dir(&out).unwrap();
    std::os::unix::fs::symlink(elsewhere.join("precious.txt"), out.join("summary.json")).unwrap();
    let o = run(&model, &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("summary.json") && stderr(&o).contains("is a link"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(elsewhere.join("precious.txt")).unwrap(), "keep me");
}

#[test]
fn a_second_run_removes_exactly_what_the_first_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("block.toml");
    std::fs::write(&model, BLOCK).unwrap();
    let out = dir.path().join("out");
    assert!(run(&model, &out).status.success());
    // the user's own files beside the results, under names like geoslip's
    std::fs::create_dir(out.join("stage-photos")).unwrap();
    std::fs::write(out.join("stage-photos/day-1.jpg"), "photo").unwrap();
    std::fs::write(out.join("pullout.by-hand.png"), "sketch").unwrap();
    std::fs::write(out.join("stage-1-load/notes.txt"), "notes").unwrap();
    // a model with another stage name: the first run's stage folder must go, the notes stay
    let renamed = BLOCK.replace("name = \"load\"", "name = \"surcharge\"");
    std::fs::write(&model, renamed).unwrap();
    let o = run(&model, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(out.join("stage-photos/day-1.jpg")).unwrap(), "photo");
    assert_eq!(std::fs::read_to_string(out.join("pullout.by-hand.png")).unwrap(), "sketch");
    assert_eq!(std::fs::read_to_string(out.join("stage-1-load/notes.txt")).unwrap(), "notes");
    // of the first run's stage folder, only the user's notes are left
    let left: Vec<PathBuf> = snapshot(&out.join("stage-1-load")).into_iter().map(|(p, _)| p).collect();
    assert_eq!(left, vec![PathBuf::from("notes.txt")]);
    assert!(out.join("stage-1-surcharge/step-002/displacements.csv").is_file());
    // no temporary file of either run is left
    let all = snapshot(&out);
    assert!(all.iter().all(|(p, _)| !p.to_string_lossy().contains(".partial-")), "{all:?}");
}

#[test]
fn a_file_of_an_earlier_run_changed_since_stops_the_next_run_before_it_writes() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("block.toml");
    std::fs::write(&model, BLOCK).unwrap();
    let out = dir.path().join("out");
    assert!(run(&model, &out).status.success());
    std::fs::write(out.join("report.md"), "my annotated report").unwrap();
    let before = snapshot(&out);
    let o = run(&model, &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("report.md") && stderr(&o).contains("changed since"), "{}", stderr(&o));
    assert_eq!(snapshot(&out), before, "the refused run changed the folder");
}

#[test]
fn a_file_geoslip_did_not_write_under_a_name_it_must_write_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("block.toml");
    std::fs::write(&model, BLOCK).unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("history.csv"), "the user's own history").unwrap();
    let o = run(&model, &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("history.csv") && stderr(&o).contains("did not write"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(out.join("history.csv")).unwrap(), "the user's own history");
}

#[test]
fn the_models_own_files_in_the_output_folder_are_never_touched() {
    // the model and its mesh in the folder the results go to (`--out .`), run twice
    let dir = tempfile::tempdir().unwrap();
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gmsh/two-quads-v22.msh");
    std::fs::copy(&mesh, dir.path().join("mesh.msh")).unwrap();
    let toml = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gmsh/two-quads.toml"))
        .unwrap()
        .replace("two-quads-v22.msh", "mesh.msh")
        .replace("two-quads.msh", "mesh.msh");
    std::fs::write(dir.path().join("model.toml"), &toml).unwrap();
    let inputs = [dir.path().join("mesh.msh"), dir.path().join("model.toml")];
    let before: Vec<Vec<u8>> = inputs.iter().map(|p| std::fs::read(p).unwrap()).collect();
    for _ in 0..2 {
        let o = geoslip().args(["run", "-q", "--out", "."]).arg("model.toml").current_dir(dir.path()).output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        let after: Vec<Vec<u8>> = inputs.iter().map(|p| std::fs::read(p).unwrap()).collect();
        assert_eq!(after, before, "an input was changed");
    }
}
