//! Gmsh runs confined: a `.geo` script that gets past geoslip's scanner still cannot run a program,
//! write a file outside Gmsh's scratch folder, or run past the time limit, whatever way in it takes
//! (a script included under another extension, the `<script>.opt` file Gmsh merges by itself,
//! plugins, loops).
//!
//! Reference: docs/reliability.md ("Gmsh"), and the Gmsh reference manual, "General commands"
//! (`SystemCall` runs a shell command, `Printf … > file` writes a file, `Include` reads any file as
//! script, `Sleep` waits). These tests need Debian's `gmsh` (scripts/test-all.sh installs it) and
//! a kernel with Landlock ABI 6; on a kernel without it, every script is refused unless trusted,
//! which the tests check instead.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Instant;

fn geoslip() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geoslip"))
}

/// A box meshed from `box.geo` in `dir`, whose first line is `head`.
fn model_with_script(dir: &Path, head: &str) -> PathBuf {
    let geo = format!(
        "{head}\nPoint(1) = {{0, 0, 0, 0.5}};\nPoint(2) = {{1, 0, 0, 0.5}};\nPoint(3) = {{1, 1, 0, 0.5}};\n\
         Point(4) = {{0, 1, 0, 0.5}};\nLine(1) = {{1, 2}};\nLine(2) = {{2, 3}};\nLine(3) = {{3, 4}};\n\
         Line(4) = {{4, 1}};\nCurve Loop(1) = {{1, 2, 3, 4}};\nPlane Surface(1) = {{1}};\n\
         Physical Surface(\"box\") = {{1}};\nPhysical Curve(\"bottom\") = {{1}};\nPhysical Curve(\"top\") = {{3}};\n"
    );
    std::fs::write(dir.join("box.geo"), geo).unwrap();
    let model = r#"units = { length = "m", force = "kN" }
mesh = { file = "box.geo", materials = { box = "clay" } }
materials.soil.clay = { youngs_modulus = 10000.0, poissons_ratio = 0.3 }
supports = [{ set = "bottom", fix = ["x", "y"] }]
[[stages]]
name = "load"
loads = [{ type = "edge-traction", edge_set = "top", pressure = 10.0 }]
"#;
    std::fs::write(dir.join("model.toml"), model).unwrap();
    dir.join("model.toml")
}

fn check_mesh(model: &Path, extra: &[&str]) -> Output {
    geoslip().args(["check", "--mesh"]).args(extra).arg(model).output().unwrap()
}

fn landlock_refused(o: &Output) -> bool {
    String::from_utf8_lossy(&o.stderr).contains("this kernel cannot confine Gmsh")
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
    out.sort();
    out
}

#[test]
fn a_script_that_gets_past_the_scanner_runs_nothing_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let outside = tempfile::tempdir().unwrap();
    let marker = |n: usize| outside.path().join(format!("written-{n}"));
    // the commands sit in files the scanner does not read as script: an included .txt, and the
    // .opt file Gmsh merges by itself
    std::fs::write(
        dir.path().join("more.txt"),
        format!(
            "SystemCall \"touch {}\";\nPrintf(\"x\") > \"{}\";\nCreateDir \"{}\";\nPrintf(\"x\") > \"{}\";\n",
            marker(1).display(),
            marker(2).display(),
            marker(3).display(),
            dir.path().join("written-beside-the-model").display()
        ),
    )
    .unwrap();
    std::fs::write(dir.path().join("box.geo.opt"), format!("SystemCall \"touch {}\";\n", marker(4).display())).unwrap();
    let model = model_with_script(dir.path(), "Include \"more.txt\";");
    let before = files_below(dir.path());
    let o = check_mesh(&model, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    for n in 1..=4 {
        assert!(!marker(n).exists(), "the script wrote or ran something outside: {}", marker(n).display());
    }
    assert_eq!(files_below(dir.path()), before, "the script wrote beside the model");
    if !landlock_refused(&o) {
        // Gmsh ran and its attempts failed: its own messages say so
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains("gmsh could not mesh"), "{e}");
    }
}

#[test]
fn gmsh_is_stopped_at_the_time_limit() {
    let dir = tempfile::tempdir().unwrap();
    let model = model_with_script(dir.path(), "Sleep 60;");
    let started = Instant::now();
    let o = check_mesh(&model, &["--gmsh-time-limit", "2"]);
    let took = started.elapsed().as_secs_f64();
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    if !landlock_refused(&o) {
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains("stopped after 2 s (--gmsh-time-limit)"), "{e}");
        // 2 s and the start of geoslip and Gmsh; far from the script's 60 s
        assert!(took < 10.0, "took {took:.1} s");
    }
}

#[test]
fn a_plain_script_is_meshed_and_its_model_checks() {
    let dir = tempfile::tempdir().unwrap();
    let model = model_with_script(dir.path(), "// a plain box");
    let o = check_mesh(&model, &[]);
    if landlock_refused(&o) {
        assert_eq!(o.status.code(), Some(2));
        let trusted = check_mesh(&model, &["--trust-geo"]);
        assert!(trusted.status.success(), "{}", String::from_utf8_lossy(&trusted.stderr));
    } else {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stdout).contains("ok"), "{}", String::from_utf8_lossy(&o.stdout));
    }
    // Gmsh wrote nothing beside the model (its preference files went to its scratch folder)
    assert_eq!(files_below(dir.path()), vec![PathBuf::from("box.geo"), PathBuf::from("model.toml")]);
}
