//! `mpirun -np 2 geoslip-mpi run MODEL` against the sequential `geoslip run --ordering pord MODEL`:
//! the same analysis, with MUMPS's factorisation and solves distributed over two ranks.
//!
//! Reference: shared/DESIGN.md §2 ("Distributed"): with the same ordering (PORD; Debian's MPI build
//! has neither Scotch nor METIS) the MPI run must give the sequential answers, linear solves to
//! 1e-10 relative and nonlinear runs to the convergence tolerance. The linear case is the annotated
//! example's first stage, whose oedometric σn on the grid is q + γz = 23.8 kPa
//! (docs/verification.md §5); the nonlinear case is the paper's pull-out in clay (slip, re-association,
//! release).
//!
//! Built only with `--features mpi` (scripts/test-all.sh: `cargo test --features mpi --target-dir
//! target/mpi --test mpi_agreement`), which needs Debian's libmumps-dev and openmpi-bin. The
//! sequential program is `GEOSLIP_SEQUENTIAL` or, by default, target/debug/geoslip from the ordinary
//! build.
#![cfg(feature = "mpi")]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn sequential() -> PathBuf {
    let path = std::env::var_os("GEOSLIP_SEQUENTIAL")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/debug/geoslip"));
    assert!(
        path.is_file(),
        "no sequential geoslip at {} (cargo build first, or set GEOSLIP_SEQUENTIAL)",
        path.display()
    );
    path
}

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name)
}

fn mpirun(ranks: usize, model: &Path, out: &Path) {
    let run = Command::new("mpirun")
        .args(["-np", &ranks.to_string(), "--oversubscribe"])
        // root in a container: OpenMPI refuses without these
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .arg(env!("CARGO_BIN_EXE_geoslip-mpi"))
        .args(["run", "-q", "--csv", "--solver", "mumps", "--out"])
        .arg(out)
        .arg(model)
        .output()
        .unwrap_or_else(|e| panic!("cannot run mpirun ({e}): install Debian's openmpi-bin"));
    assert!(
        run.status.success(),
        "mpirun -np {ranks} failed:\n{}\n{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
}

fn sequential_run(model: &Path, out: &Path) {
    let run = Command::new(sequential())
        .args(["run", "-q", "--csv", "--solver", "mumps", "--ordering", "pord", "--out"])
        .arg(out)
        .arg(model)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
}

/// Every step's displacements: (stage folder/step folder, node) → (ux, uy).
fn displacements(out: &Path) -> HashMap<(String, u64), [f64; 2]> {
    let mut all = HashMap::new();
    for stage in std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir() && p.file_name().unwrap().to_string_lossy().starts_with("stage-"))
    {
        for step in std::fs::read_dir(&stage).unwrap().map(|e| e.unwrap().path()) {
            let key = format!(
                "{}/{}",
                stage.file_name().unwrap().to_string_lossy(),
                step.file_name().unwrap().to_string_lossy()
            );
            let mut r = csv::Reader::from_path(step.join("displacements.csv")).unwrap();
            for rec in r.records() {
                let rec = rec.unwrap();
                all.insert((key.clone(), rec[0].parse().unwrap()), [rec[3].parse().unwrap(), rec[4].parse().unwrap()]);
            }
        }
    }
    all
}

/// Largest difference between the runs, relative to the largest displacement of the step.
fn largest_difference(a: &HashMap<(String, u64), [f64; 2]>, b: &HashMap<(String, u64), [f64; 2]>) -> f64 {
    assert_eq!(a.len(), b.len(), "both runs wrote the same steps and nodes");
    let mut scale: HashMap<&str, f64> = HashMap::new();
    for ((step, _), u) in a {
        let s = scale.entry(step.as_str()).or_insert(0.0);
        *s = s.max(u[0].abs()).max(u[1].abs());
    }
    a.iter()
        .map(|(key, u)| {
            let v = b[key];
            let s = scale[key.0.as_str()].max(f64::MIN_POSITIVE);
            ((u[0] - v[0]).abs().max((u[1] - v[1]).abs())) / s
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_linear_solve_on_two_ranks_matches_the_sequential_one() {
    let dir = tempfile::tempdir().unwrap();
    // The annotated example, first stage only: one linear solve per step (elastic soil, tied normal rows).
    let text = std::fs::read_to_string(example("annotated-pullout.toml")).unwrap();
    let mut file = geoslip::model::parse(Path::new("annotated-pullout.toml"), &text).unwrap();
    file.stages.truncate(1);
    let model = dir.path().join("surcharge.toml");
    std::fs::write(&model, toml::to_string(&file).unwrap()).unwrap();
    let (seq, par) = (dir.path().join("sequential"), dir.path().join("mpi"));
    sequential_run(&model, &seq);
    mpirun(2, &model, &par);
    let difference = largest_difference(&displacements(&seq), &displacements(&par));
    eprintln!("linear: largest relative difference {difference:e}");
    assert!(difference < 1e-10, "largest relative difference {difference:e}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(par.join("summary.json")).unwrap()).unwrap();
    assert!(summary["solver"].as_str().unwrap().contains("MPI build"), "{}", summary["solver"]);
    // the closed form, from the distributed run
    let mut r = csv::Reader::from_path(par.join("stage-1-self-weight-and-surcharge/step-001/interface.csv")).unwrap();
    for rec in r.records() {
        let rec = rec.unwrap();
        let (x, sigma_n): (f64, f64) = (rec[3].parse().unwrap(), rec[11].parse().unwrap());
        if &rec[0] == "grid" && x > 0.15 && x < 0.55 {
            assert!((sigma_n - 23.8).abs() < 0.01 * 23.8, "σn = {sigma_n} at x = {x}");
        }
    }
}

#[test]
fn the_paper_pullout_on_two_ranks_matches_the_sequential_run() {
    let dir = tempfile::tempdir().unwrap();
    let model = example("paper-pullout-clay.toml");
    let (seq, par) = (dir.path().join("sequential"), dir.path().join("mpi"));
    sequential_run(&model, &seq);
    mpirun(2, &model, &par);
    // Each increment converges to 1e-9 (force and displacement tolerances of the model); the two
    // factorisations round differently, so the runs may differ by up to that, not more.
    let difference = largest_difference(&displacements(&seq), &displacements(&par));
    eprintln!("paper pull-out: largest relative difference {difference:e}");
    assert!(difference < 1e-9, "largest relative difference {difference:e}");
    let history = |dir: &Path| std::fs::read_to_string(dir.join("history.csv")).unwrap();
    assert_eq!(history(&seq).lines().count(), history(&par).lines().count(), "the same steps");
}
