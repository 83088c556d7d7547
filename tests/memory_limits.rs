//! A model too large for the memory it may use stops before the work that would not fit, with an
//! estimate and what to do; MUMPS's out-of-core mode (ICNTL(22) = 1) gives the in-core answers.
//!
//! Reference: MUMPS 5.5 user guide, INFOG(17) and INFOG(27) (the analysis's estimate of the
//! factorisation's memory in core and out of core, summed over the processes) and ICNTL(22); and
//! docs/verification.md §5: in the annotated example's first stage the oedometric σn on
//! the grid is q + γz = 20 + 19·0.2 = 23.8 kPa, out of core as in core.

use std::path::Path;
use std::process::Command;

fn geoslip() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geoslip"))
}

fn example(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name)
}

fn has_mumps() -> bool {
    let out = geoslip().arg("backends").output().unwrap();
    String::from_utf8_lossy(&out.stdout).lines().any(|l| l == "mumps")
}

#[test]
fn a_model_larger_than_the_limit_stops_before_its_first_step() {
    let out = tempfile::tempdir().unwrap();
    let run = geoslip()
        .args(["run", "-q", "--memory-limit", "0.01", "--out"])
        .arg(out.path())
        .arg(example("annotated-pullout.toml"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(4), "the solver exit code");
    let e = String::from_utf8_lossy(&run.stderr);
    assert!(
        e.contains("the model, its element matrices and the assembled system") && e.contains("has 0.0 MB for it"),
        "{e}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    assert_eq!(summary["steps"].as_array().unwrap().len(), 0);
}

#[test]
fn a_factorisation_larger_than_the_limit_stops_after_the_analysis_and_suggests_out_of_core() {
    if !has_mumps() {
        return; // the factorisation estimate is MUMPS's; this build has no MUMPS
    }
    let out = tempfile::tempdir().unwrap();
    // the paper's clay model: about 1.4 MB of model estimated, so a 1.5 MB limit lets it be
    // assembled; the process itself holds more than that already, which leaves nothing for the
    // factorisation that MUMPS estimates at 1 MB or more
    let run = geoslip()
        .args(["run", "-q", "--solver", "mumps", "--memory-limit", "1.5", "--out"])
        .arg(out.path())
        .arg(example("paper-pullout-clay.toml"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(4));
    let e = String::from_utf8_lossy(&run.stderr);
    assert!(
        e.contains("the factorisation (MUMPS's estimate after its analysis)") && e.contains("--out-of-core"),
        "{e}"
    );
}

#[test]
fn out_of_core_gives_the_in_core_answers() {
    if !has_mumps() {
        return; // ICNTL(22) is MUMPS's
    }
    let dir = tempfile::tempdir().unwrap();
    let (in_core, ooc) = (dir.path().join("in-core"), dir.path().join("ooc"));
    for (folder, extra) in [(&in_core, None), (&ooc, Some("--out-of-core"))] {
        let mut cmd = geoslip();
        cmd.args(["run", "-q", "--csv", "--solver", "mumps", "--out"])
            .arg(folder)
            .arg(example("annotated-pullout.toml"));
        if let Some(flag) = extra {
            cmd.arg(flag).env("MUMPS_OOC_TMPDIR", dir.path());
        }
        assert!(cmd.status().unwrap().success());
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(ooc.join("summary.json")).unwrap()).unwrap();
    assert!(summary["solver"].as_str().unwrap().contains("out of core"), "{}", summary["solver"]);
    let read = |dir: &Path, file: &str| -> Vec<Vec<f64>> {
        let mut r = csv::Reader::from_path(dir.join(file)).unwrap();
        r.records().map(|rec| rec.unwrap().iter().filter_map(|v| v.parse::<f64>().ok()).collect()).collect()
    };
    for file in
        ["stage-1-self-weight-and-surcharge/step-001/displacements.csv", "stage-2-pull-out/step-004/interface.csv"]
    {
        let (a, b) = (read(&in_core, file), read(&ooc, file));
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().flatten().zip(b.iter().flatten()) {
            assert!((x - y).abs() <= 1e-12 * (1.0 + x.abs()), "{file}: {x} in core, {y} out of core");
        }
    }
    // the closed form, from the out-of-core run
    let mut r = csv::Reader::from_path(ooc.join("stage-1-self-weight-and-surcharge/step-001/interface.csv")).unwrap();
    for rec in r.records() {
        let rec = rec.unwrap();
        let (x, sigma_n): (f64, f64) = (rec[3].parse().unwrap(), rec[11].parse().unwrap());
        if &rec[0] == "grid" && x > 0.15 && x < 0.55 {
            assert!((sigma_n - 23.8).abs() < 0.01 * 23.8, "σn = {sigma_n} at x = {x}");
        }
    }
}

#[test]
fn a_mesh_too_large_for_the_limit_is_refused_before_it_is_read() {
    // the landfill slope's .msh declares 1551 nodes and 3204 elements in its section headers; at
    // 64 matrix entries an element (a quad4's) and 70 bytes an entry, the model needs about 14 MB
    let out = tempfile::tempdir().unwrap();
    let run = geoslip()
        .args(["run", "-q", "--memory-limit", "5", "--out"])
        .arg(out.path())
        .arg(example("landfill-slope/landfill-slope.toml"))
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{e}");
    assert!(e.contains("landfill-slope.msh: the mesh has 1551 nodes and 3204 elements"), "{e}");
    assert!(e.contains("this run may use 5.0 MB"), "{e}");
    // nothing of a run was written: it stopped before the model was built
    assert!(!out.path().join("summary.json").exists());
}
