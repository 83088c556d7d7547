//! Where a run's time goes (docs/results.md, "Where the time went"): `summary.json`'s `timings`
//! held against the process's wall time as measured from outside it, from its spawn to its exit:
//! a clock the run does not keep.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

#[test]
fn the_phases_and_other_make_up_the_wall_time_measured_from_outside_the_process() {
    let scratch = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/annotated-pullout.toml");
    let out = scratch.path().join("out");
    let spawned = Instant::now();
    let status = Command::new(env!("CARGO_BIN_EXE_geoslip"))
        .args(["run", "-q", "--out"])
        .arg(&out)
        .arg(&model)
        .status()
        .expect("geoslip runs");
    let outside = spawned.elapsed().as_secs_f64();
    assert!(status.success());
    let summary: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let timings = &summary["timings"];
    let wall = timings["wall_seconds"].as_f64().unwrap();
    let phases: Vec<(String, f64)> = timings["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["phase"].as_str().unwrap().to_string(), p["seconds"].as_f64().unwrap()))
        .collect();
    let other = timings["other_seconds"].as_f64().unwrap();
    let table: String = phases.iter().map(|(p, s)| format!("\n  {p}: {s:.4}")).collect();

    // the process's wall time, as the run counts it, is the wall time measured outside less the
    // spawn, the last summary and the exit (a few ms each), to the kernel's 10 ms clock tick
    assert!(wall <= outside + 0.011, "wall {wall} s, measured outside {outside} s{table}");
    assert!(wall >= 0.9 * outside - 0.1, "wall {wall} s, measured outside {outside} s{table}");
    // no phase is counted twice: each is at least zero, the increments' rest included (it is their
    // time less the phases inside them), and together they are at most the wall time
    for (phase, seconds) in &phases {
        assert!(*seconds >= 0.0, "{phase}: {seconds} s{table}");
    }
    assert!(other >= -1e-9, "other {other} s{table}");
    let named: Vec<&str> = phases.iter().map(|(p, _)| p.as_str()).collect();
    for expected in [
        "process start: program loaded",
        "model: file read",
        "model: file parsed",
        "model: interfaces split and paired",
        "increments: sparse factorisation",
    ] {
        assert!(named.contains(&expected), "{expected} missing from{table}");
    }
    // in the order they happen: the model before the run, the run before its end
    let at = |name: &str| named.iter().position(|p| *p == name).unwrap();
    assert!(at("model: file read") < at("model: file parsed"));
    assert!(at("model: file parsed") < at("run set-up: soil, element matrices, solver"));
}
