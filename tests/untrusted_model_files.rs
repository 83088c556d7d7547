//! A model file from anyone: it never makes geoslip write outside the output folder or run a
//! program the user did not ask for, and the results it writes are as readable as the user's other
//! files; a run leaves whole steps only, whatever an earlier run into the same folder left.
//!
//! Reference: the project's standards ("A model file may come from anyone. It never makes geoslip
//! write outside the output folder, run a program the user did not ask for …") and the Gmsh
//! reference manual, "General commands" (`SystemCall` runs a shell command; `Printf … > file`
//! writes a file).
//!
//! ```text
//!   q (edge traction named by the series' load)
//!   ┌───────┐
//!   │ quad4 │ 1 m × 1 m
//!   └───────┘
//!   ▲▲▲▲▲▲▲▲▲ fixed base
//! ```

use std::path::{Path, PathBuf};
use std::process::Command;

fn geoslip() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geoslip"))
}

/// A one-element model with a traction called `load`, and a `[series]` over it when `values` are
/// given.
fn block(load: &str, values: &[f64]) -> String {
    let mut m = format!(
        r#"units = {{ length = "m", force = "kN" }}
nodes = [[1, 0.0, 0.0], [2, 1.0, 0.0], [3, 1.0, 1.0], [4, 0.0, 1.0]]
elements = [{{ id = 1, type = "quad4", nodes = [1, 2, 3, 4], material = "clay" }}]

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
loads = [{{ type = "edge-traction", name = {load:?}, edge_set = "top", pressure = 10.0 }}]
"#
    );
    if !values.is_empty() {
        m += &format!("\n[series]\nload = {load:?}\nvalues = {values:?}\n");
    }
    m
}

/// Every file below `dir`, relative to it.
fn files_below(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                out.push(path.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    out
}

#[test]
fn series_runs_named_after_a_hostile_load_stay_inside_the_output_folder() {
    let long = "x".repeat(300);
    for load in ["../../escaped", "/tmp/geoslip-absolute-load-name", "..", "a/../../b", long.as_str()] {
        let base = tempfile::tempdir().unwrap();
        let models = base.path().join("models");
        std::fs::create_dir_all(&models).unwrap();
        let model = models.join("block.toml");
        std::fs::write(&model, block(load, &[5.0, 12.5])).unwrap();
        let out = models.join("out");
        let run = geoslip().args(["run", "-q", "--out"]).arg(&out).arg(&model).output().unwrap();
        assert!(run.status.success(), "load {load:?}: {}", String::from_utf8_lossy(&run.stderr));
        for file in files_below(base.path()) {
            assert!(
                file == Path::new("models/block.toml") || file.starts_with("models/out"),
                "load {load:?} wrote {} outside --out",
                file.display()
            );
        }
        assert!(!Path::new("/tmp/geoslip-absolute-load-name-5").exists());
        // one folder per run, each one path component no longer than 100 characters
        let runs: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap())
            .filter(|e| e.path().is_dir())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(runs.len(), 2, "load {load:?}: {runs:?}");
        for r in &runs {
            assert!(r.len() <= 100 && !r.contains(['/', '.']), "load {load:?}: run folder {r:?}");
        }
    }
}

/// A model meshed from `box.geo` (holding `geo`) in `dir`, and a `gmsh` stand-in that records being
/// started, ahead of any real one on the PATH. Returns the model, the PATH and the record's path.
fn geo_model_with_recording_gmsh(dir: &Path, geo: &str) -> (PathBuf, String, PathBuf) {
    std::fs::write(dir.join("box.geo"), geo).unwrap();
    let model = block("q", &[]).replace(
        "nodes = [[1, 0.0, 0.0], [2, 1.0, 0.0], [3, 1.0, 1.0], [4, 0.0, 1.0]]\nelements = [{ id = 1, type = \"quad4\", nodes = [1, 2, 3, 4], material = \"clay\" }]\n",
        "mesh = { file = \"box.geo\", materials = { box = \"clay\" } }\n",
    );
    std::fs::write(dir.join("model.toml"), model).unwrap();
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let started = dir.join("gmsh-was-started");
    let fake = bin.join("gmsh");
    std::fs::write(&fake, format!("#!/bin/sh\ntouch {}\nexit 1\n", started.display())).unwrap();
    #[cfg(unix)]
    std::fs::set_permissions(&fake, std::os::unix::fs::PermissionsExt::from_mode(0o755)).unwrap();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    (dir.join("model.toml"), path, started)
}

#[test]
fn a_geo_script_that_runs_a_shell_command_is_refused_before_gmsh_starts() {
    let dir = tempfile::tempdir().unwrap();
    let marker = dir.path().join("the-script-ran");
    let geo = format!(
        "SystemCall \"touch {}\";\nPoint(1) = {{0, 0, 0, 0.5}};\nPoint(2) = {{1, 0, 0, 0.5}};\nLine(1) = {{1, 2}};\n",
        marker.display()
    );
    let (model, path, started) = geo_model_with_recording_gmsh(dir.path(), &geo);
    for command in ["check", "run"] {
        let out = geoslip().arg(command).arg(&model).env("PATH", &path).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{command}: {stderr}");
        assert!(stderr.contains("box.geo:1: `SystemCall` runs a shell command"), "{command}: {stderr}");
        assert!(stderr.contains("--trust-geo"), "{command}: {stderr}");
        assert!(!started.exists(), "{command} started gmsh");
        assert!(!marker.exists(), "{command} ran the script's shell command");
    }
    // asked to, geoslip hands the script to Gmsh (here the recording stand-in)
    let out = geoslip().args(["check", "--mesh", "--trust-geo"]).arg(&model).env("PATH", &path).output().unwrap();
    assert!(started.exists(), "check --trust-geo did not start gmsh: {}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn check_runs_no_program_unless_asked_to_mesh() {
    // a script that does nothing refused: check reads it but starts no Gmsh; with --mesh it does
    let dir = tempfile::tempdir().unwrap();
    let (model, path, started) =
        geo_model_with_recording_gmsh(dir.path(), "Point(1) = {0, 0, 0, 0.5};\nPoint(2) = {1, 0, 0, 0.5};\n");
    let out = geoslip().arg("check").arg(&model).env("PATH", &path).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("not checked") && stdout.contains("check --mesh"), "{stdout}");
    assert!(!started.exists(), "check started gmsh unasked");
    // with --mesh it runs Gmsh confined: the stand-in (a shell script, which needs /bin/sh, a program
    // the confinement does not let it execute, and writes outside its scratch folder) records nothing
    let out = geoslip().args(["check", "--mesh"]).arg(&model).env("PATH", &path).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!started.exists(), "a confined gmsh wrote outside its scratch folder");
    let _ = geoslip().args(["check", "--mesh", "--trust-geo"]).arg(&model).env("PATH", &path).output().unwrap();
    assert!(started.exists(), "check --mesh --trust-geo did not start gmsh");
    // a missing script is named
    std::fs::remove_file(dir.path().join("box.geo")).unwrap();
    let out = geoslip().arg("check").arg(&model).env("PATH", &path).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("mesh.file") && stderr.contains("box.geo: no such file"), "{stderr}");
}

#[cfg(unix)]
#[test]
fn result_files_are_as_readable_as_the_umask_allows() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("block.toml");
    std::fs::write(&model, block("q", &[])).unwrap();
    let out = dir.path().join("out");
    let status = Command::new("sh")
        .arg("-c")
        .arg("umask 022 && exec \"$0\" run -q --out \"$1\" \"$2\"")
        .arg(env!("CARGO_BIN_EXE_geoslip"))
        .arg(&out)
        .arg(&model)
        .status()
        .unwrap();
    assert!(status.success());
    for file in ["summary.json", "history.csv", "report.md"] {
        let mode = std::fs::metadata(out.join(file)).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o644, "{file}");
    }
}

/// `[analysis]` counts beyond their limits.
const COUNTS_OVER_LIMITS: &str =
    "\n[analysis]\nmax_iterations = 100000\nmax_cutbacks = 1000\nreserved_segments = 5000\n";

#[test]
fn counts_without_a_limit_are_refused_by_check_as_by_run() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("block.toml");
    let values: Vec<f64> = (1..=1001).map(f64::from).collect();
    std::fs::write(&model, block("q", &values) + COUNTS_OVER_LIMITS).unwrap();
    for command in ["check", "run"] {
        let out = geoslip().arg(command).arg(&model).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{command}: {stderr}");
        let expected = "series.values (load \"q\"): at most 1000 runs in a series, found 1001";
        assert!(stderr.contains(expected), "{command}: {stderr}");
    }
    // without the series, the analysis counts are named with their limits
    std::fs::write(&model, block("q", &[]) + COUNTS_OVER_LIMITS).unwrap();
    let out = geoslip().arg("check").arg(&model).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    for expected in [
        "analysis.max_iterations: must be in [1, 10000], found 100000",
        "analysis.max_cutbacks: must be in [0, 30], found 1000",
        "analysis.reserved_segments: must be in [0, 1000], found 5000",
    ] {
        assert!(stderr.contains(expected), "{stderr}");
    }
}

#[test]
fn a_series_value_given_twice_is_refused_by_check_as_by_run() {
    // both runs would write the folder q-10, the second over the first
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("block.toml");
    std::fs::write(&model, block("q", &[10.0, 20.0, 10.0])).unwrap();
    for command in ["check", "run"] {
        let out = geoslip().arg(command).arg(&model).current_dir(dir.path()).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{command}: {stderr}");
        assert!(
            stderr.contains("series.values[2] (load \"q\"): 10 is already series.values[0]"),
            "{command}: {stderr}"
        );
    }
    assert!(!dir.path().join("results").exists(), "run wrote results for a refused series");
}
