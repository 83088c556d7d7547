//! Numbers a run cannot trust are named as what they are: an ill-conditioned system is not called a
//! mechanism, and a law evaluated where its textbook form is 0/0 gives finite numbers.
//!
//! References:
//! - Golub & Van Loan, Matrix Computations, 4th ed. (2013), §3.5.1: a solution computed in double
//!   precision (unit round-off 1.1e-16) loses about log10 κ of its digits, κ the condition number.
//!   With stiffnesses 1e25 apart no digit of the soft part is left; the diagonal ratio is a lower
//!   bound of κ for a symmetric positive matrix.
//! - Clough & Duncan (1971), J. Soil Mech. Found. Div. 97(SM12), the hyperbolic interface law
//!   τ = Ks·δ/(1 + Ks·δ/τf), τf = c + σn·tan φ: with c = 0 and σn = 0, τf = 0 and τ = 0 for every
//!   slip, so a reinforcement under no normal stress is pulled out at zero force.
//!
//! ```text
//!   q (surcharge)
//!   ┌──────────────────────────────┐
//!   │ soil                         │
//!   │  grid ●──●──●──●──●──●──●──● │ ◀── head pulled
//!   │                              │
//!   └──────────────────────────────┘  (examples/pullout-box.toml)
//! ```

use std::path::{Path, PathBuf};
use std::process::Command;

fn geoslip() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geoslip"))
}

fn pullout_box() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/pullout-box.toml")).unwrap()
}

fn backends() -> Vec<String> {
    let out = geoslip().arg("backends").output().unwrap();
    String::from_utf8_lossy(&out.stdout).lines().map(str::to_string).collect()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn stiffnesses_25_orders_apart_are_called_ill_conditioned_on_every_backend() {
    // soil E = 1e-9 kPa against a grid of EA = 1e15 kN/m: a units mistake, not a mechanism
    let text = pullout_box()
        .replace("youngs_modulus = 20000.0", "youngs_modulus = 1e-9")
        .replace("axial_stiffness = 1000.0", "axial_stiffness = 1e15");
    assert!(text.contains("1e-9") && text.contains("1e15"), "the example changed: update this test");
    let dir = tempfile::tempdir().unwrap();
    let model = write(dir.path(), "ill.toml", &text);
    let backends = backends();
    assert!(backends.len() >= 2, "{backends:?}");
    for backend in backends {
        let out_dir = dir.path().join(&backend);
        let out =
            geoslip().args(["run", "-q", "--solver", &backend, "--out"]).arg(&out_dir).arg(&model).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("mechanism") && !stderr.contains("not held"), "{backend}: {stderr}");
        match out.status.code() {
            // the factorisation gave up: the error says why
            Some(4) => {
                assert!(stderr.contains("ill-conditioned, not shown to be singular"), "{backend}: {stderr}");
                assert!(stderr.contains("ratio of 8.3e25"), "{backend}: {stderr}");
            }
            // the factorisation went through: the results say they carry round-off
            Some(0) => {
                let summary = std::fs::read_to_string(out_dir.join("summary.json")).unwrap();
                assert!(summary.contains("the stiffness matrix is ill-conditioned"), "{backend}: no warning");
                assert!(stderr.contains("ill-conditioned"), "{backend}: {stderr}");
            }
            code => panic!("{backend}: exit {code:?}: {stderr}"),
        }
    }
}

#[test]
fn a_well_conditioned_model_carries_no_such_warning() {
    let dir = tempfile::tempdir().unwrap();
    let model = write(dir.path(), "box.toml", &pullout_box());
    let out = geoslip()
        .args(["run", "-q", "--solver", "faer", "--out"])
        .arg(dir.path().join("out"))
        .arg(&model)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary = std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap();
    assert!(!summary.contains("ill-conditioned"));
}

#[test]
fn a_hyperbolic_law_without_strength_pulls_out_at_zero_force_under_newton() {
    // no surcharge, no adhesion: τf = 0 everywhere, so the closed form's pull-out force is 0
    let text = pullout_box()
        .replace(
            "[interfaces.law]\ntype = \"linear\"\nshear_stiffness = 540.0",
            "[interfaces.law]\ntype = \"hyperbolic\"\nshear_stiffness = 540.0\ncohesion = 0.0\nfriction_angle = 30.0",
        )
        .replace("pressure = 50.0", "pressure = 0.0")
        .replace("scheme = \"constant-stiffness\"", "scheme = \"newton\"");
    assert!(text.contains("hyperbolic") && text.contains("newton\""), "the example changed: update this test");
    let dir = tempfile::tempdir().unwrap();
    let model = write(dir.path(), "hyperbolic.toml", &text);
    for backend in backends() {
        let out_dir = dir.path().join(&backend);
        let out =
            geoslip().args(["run", "-q", "--solver", &backend, "--out"]).arg(&out_dir).arg(&model).output().unwrap();
        assert!(out.status.success(), "{backend}: {}", String::from_utf8_lossy(&out.stderr));
        let history = std::fs::read_to_string(out_dir.join("history.csv")).unwrap();
        let pulls: Vec<f64> = history
            .lines()
            .filter(|l| l.starts_with("pull-out,"))
            .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
            .collect();
        assert_eq!(pulls.len(), 5, "{history}");
        for p in pulls {
            assert!(p.abs() < 1e-9, "{backend}: pull-out force {p} kN/m with no strength");
        }
    }
}

#[test]
fn a_megabyte_line_is_not_echoed_whole() {
    // an inline mesh on one line, broken at its end
    let nodes: Vec<String> = (1..40_000).map(|i| format!("[{i}, 0.0, 0.0]")).collect();
    let text = format!("units = {{ length = \"m\", force = \"kN\" }}\nnodes = [{}, [x]\n", nodes.join(", "));
    assert!(text.len() > 500_000);
    let dir = tempfile::tempdir().unwrap();
    let model = write(dir.path(), "long.toml", &text);
    let out = geoslip().arg("check").arg(&model).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.len() < 2_000, "{} characters", stderr.len());
    assert!(stderr.contains("line 2") && stderr.contains("[39999, 0.0, 0.0], [x]"), "{stderr}");
}
