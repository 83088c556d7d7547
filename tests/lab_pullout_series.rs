//! The laboratory pull-out box, run as a user runs it: one command from the model that names the
//! `.geo` file, three airbag pressures, and the series report with the apparent friction angle.
//!
//! Reference: docs/verification.md §2: once the whole embedded length slides, the
//! pull-out force of a reinforcement with n_f = 2 faces is P_ult = 2·τmax·L, τmax = c + σn·tan φ_i;
//! and §5: in the frictionless box σn on the grid is q + γ·h before the pull (h = 0.3 m of sand,
//! γ = 18 kN/m³). The box can only lower the peak below 2·(q + γh)·tan φ_i·L: the soil relaxes at
//! the front slot, and the embedded length shrinks by the tail's slip before the whole grid slides.
//!
//! Needs Debian's `gmsh` (scripts/test-all.sh installs it).

use std::path::Path;
use std::process::Command;

#[test]
fn three_pressures_from_the_geo_give_the_input_friction_angle() {
    let out = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/lab-pullout/lab-pullout.toml");
    let run = Command::new(env!("CARGO_BIN_EXE_geoslip"))
        .args(["run", "--out"])
        .arg(out.path())
        .arg(&model)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&run.stderr));
    assert!(stdout.contains("apparent interface friction angle"), "{stdout}");

    // every run has its ParaView series (results.h5 and its .xdmf in a build with HDF5, .vtu files
    // without), plots, report and the mesh Gmsh made for it
    let paraview: &[&str] = if cfg!(feature = "hdf5") { &["results.xdmf", "results.h5"] } else { &["results.pvd"] };
    for q in ["25", "50", "100"] {
        let dir = out.path().join(format!("airbag-{q}"));
        let files = ["report.md", "pullout.png", "pullout.svg", "profiles-grid.png", "mesh.msh", "summary.json"];
        for file in paraview.iter().chain(&files) {
            assert!(dir.join(file).is_file(), "airbag-{q}/{file}");
        }
    }
    for file in ["series.csv", "series.json", "envelope.png", "envelope.svg", "report.md"] {
        assert!(out.path().join(file).is_file(), "{file}");
    }

    let series: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("series.json")).unwrap()).unwrap();
    let pullout = &series["pullout"];
    let length = pullout["embedded_length"].as_f64().unwrap();
    assert!((length - 1.2).abs() < 1e-9, "embedded length {length}");
    let tan_phi = 30f64.to_radians().tan();
    for case in series["cases"].as_array().unwrap() {
        assert!(case["error"].is_null(), "{case}");
        let q = case["value"].as_f64().unwrap();
        let peak = case["peaks"].as_array().unwrap().iter().find(|p| p["label"] == "grid.head").unwrap();
        let p = peak["reaction"].as_f64().unwrap();
        let ideal = 2.0 * (q + 18.0 * 0.3) * tan_phi * length;
        let ratio = p / ideal;
        // measured 1.4–2.1 % below (README): 4 % allowed, and never above
        assert!(
            (0.96..=1.0).contains(&ratio),
            "q = {q}: peak {p:.3} kN/m is {ratio:.4} of 2(q + γh)tanφ·L = {ideal:.3}"
        );
    }
    let envelope = &series["envelope"];
    let phi = envelope["apparent_friction_angle_deg"].as_f64().unwrap();
    // measured 29.4°: each peak falls short by about the same fraction, so the fitted angle sits a
    // little below the input; 1.2° allowed below, none above
    assert!((28.8..=30.0).contains(&phi), "apparent friction angle {phi:.2}°, input 30°");
    // the intercept is the overburden's share: c_a ≈ γh·tan φ = 3.1 kPa (c = 0)
    let adhesion = envelope["apparent_adhesion"].as_f64().unwrap();
    assert!(adhesion > 0.0 && adhesion < 18.0 * 0.3 * tan_phi * 1.1, "apparent adhesion {adhesion:.3} kPa");

    let report = std::fs::read_to_string(out.path().join("report.md")).unwrap();
    assert!(report.contains("Apparent friction angle") && report.contains("envelope.png"), "{report}");
    for q in ["25", "50", "100"] {
        assert!(report.contains(&format!("(airbag-{q}/report.md)")), "the series report links each run");
    }
}
