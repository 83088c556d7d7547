//! Which steps' fields a run writes: `--keep events` keeps exactly the event steps, `--keep 5` every
//! fifth step with the events and the last, and a run without `--csv` writes no per-step CSV file;
//! the history and the summary cover every step whatever is kept.
//!
//! Reference: docs/results.md ("Which steps are kept"): the event steps are the first and the last
//! step of each stage, the steps the summary's events name (slip starts, every point in contact
//! slides, a reaction falls from its peak) and the step of that peak. The expected steps are made
//! here from `summary.json` (the steps and the events) and `history.csv` (the peak), and checked
//! against every field file: the step folders of `--csv`, the steps `results.xdmf` lists (a build
//! with HDF5) or `results.pvd` (without), and the summary's `kept_steps`.
//!
//! A peak-residual interface (φ = 30° falling to 15° once the peak is passed) under a 50 kPa
//! surcharge, pulled 50 mm in 40 steps: the pull-out force peaks after a few millimetres and falls.
//!
//! ```text
//!        q = 50 kPa
//!   ┌────┬────┬────┬────┐ 0.2 m
//!   │    │    │    │    │
//!  ═╪════╪════╪════┼    │  geogrid (peak-residual interface), pulled 50 mm in 40 steps
//!   │    │    │    │    │
//!   └────┴────┴────┴────┘
//!   ▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲  fixed base; front and back walls fixed in x; 0.4 m long
//! ```

mod common;

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

const PULL_STEPS: usize = 40;

/// The pull-out box (`common::small_pullout_box`) with a peak-residual interface.
fn pullout_box() -> String {
    common::small_pullout_box(
        "pull-out box, peak and residual",
        r#"{ type = "peak-residual", shear_stiffness = 5000.0, cohesion = 0.0, friction_angle = 30.0, residual_cohesion = 0.0, residual_friction_angle = 15.0 }"#,
        PULL_STEPS,
    )
}

/// Run the box into `out` with `flags`; its summary.
fn run(model: &Path, out: &Path, flags: &[&str]) -> serde_json::Value {
    let status = Command::new(env!("CARGO_BIN_EXE_geoslip"))
        .args(["run", "-q", "--solver", "faer"])
        .args(flags)
        .arg("--out")
        .arg(out)
        .arg(model)
        .status()
        .unwrap();
    assert!(status.success(), "geoslip run {flags:?} failed");
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// The event steps, by their number over the run (1, 2, …), from the summary and the history.
fn event_steps(summary: &serde_json::Value, history: &str) -> BTreeSet<usize> {
    let steps = summary["steps"].as_array().unwrap();
    let key = |s: &serde_json::Value| (s["stage"].as_str().unwrap().to_string(), s["step"].as_u64().unwrap() as usize);
    let keys: Vec<(String, usize)> = steps.iter().map(key).collect();
    let time_of = |stage: &str, step: usize| keys.iter().position(|k| k.0 == stage && k.1 == step).unwrap() + 1;
    let mut events = BTreeSet::new();
    // the first and the last step of each stage
    for (k, s) in keys.iter().enumerate() {
        if k == 0 || keys[k - 1].0 != s.0 {
            events.insert(k + 1);
        }
        if k + 1 == keys.len() || keys[k + 1].0 != s.0 {
            events.insert(k + 1);
        }
    }
    // the steps the events name: `stage "<name>" step <n> (…): …`
    let reactions: Vec<f64> =
        history.lines().skip(1).map(|l| l.rsplit(',').next().unwrap().parse::<f64>().unwrap().abs()).collect();
    assert_eq!(reactions.len(), steps.len(), "one target: a history row per step");
    for event in summary["events"].as_array().unwrap() {
        let e = event.as_str().unwrap();
        let stage = e.split('"').nth(1).unwrap();
        let step: usize = e.split("\" step ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
        let time = time_of(stage, step);
        events.insert(time);
        if e.contains("fell to") {
            // and the peak it fell from
            let peak = (1..time).max_by(|&a, &b| reactions[a - 1].total_cmp(&reactions[b - 1])).unwrap();
            events.insert(peak);
        }
    }
    events
}

/// The steps each field file holds: the step folders, the steps the ParaView index lists, and the
/// summary's `kept_steps`.
fn kept_in_files(out: &Path, summary: &serde_json::Value) -> [BTreeSet<usize>; 3] {
    let steps = summary["steps"].as_array().unwrap();
    let folders: BTreeSet<usize> = steps
        .iter()
        .enumerate()
        .filter(|(_, s)| {
            out.join(format!(
                "stage-{}-{}/step-{:03}",
                s["stage_index"].as_u64().unwrap() + 1,
                s["stage"].as_str().unwrap(),
                s["step"].as_u64().unwrap()
            ))
            .join("displacements.csv")
            .is_file()
        })
        .map(|(k, _)| k + 1)
        .collect();
    let (index, mark) =
        if cfg!(feature = "hdf5") { ("results.xdmf", "<Time Value=\"") } else { ("results.pvd", "timestep=\"") };
    let text = std::fs::read_to_string(out.join(index)).unwrap();
    let listed: BTreeSet<usize> =
        text.split(mark).skip(1).map(|s| s.split('"').next().unwrap().parse().unwrap()).collect();
    let summary: BTreeSet<usize> =
        summary["fields"]["kept_steps"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    [folders, listed, summary]
}

#[test]
fn keep_events_writes_the_event_steps_and_keep_5_adds_every_fifth_step() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("box.toml");
    std::fs::write(&model, pullout_box()).unwrap();

    let out = dir.path().join("events");
    let summary = run(&model, &out, &["--csv", "--keep", "events"]);
    let n = summary["steps"].as_array().unwrap().len();
    assert_eq!(n, 1 + PULL_STEPS, "the history and the summary cover every step");
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert_eq!(history.lines().count(), 1 + n);
    let events = event_steps(&summary, &history);
    let text = summary["events"].to_string();
    assert!(text.contains("slip starts") && text.contains("fell to") && text.contains("slides"), "{text}");
    // a peak that is no other event: the test sees the peak rule at work
    assert!(events.len() >= 6, "{events:?}");
    assert!(events.len() < n / 2, "{events:?}");
    for (what, kept) in ["step folders", "ParaView index", "summary"].iter().zip(kept_in_files(&out, &summary)) {
        assert_eq!(kept, events, "--keep events: the {what}");
    }

    let out = dir.path().join("every-5");
    let summary = run(&model, &out, &["--csv", "--keep", "5"]);
    let mut expected = events.clone();
    expected.extend((5..=n).step_by(5));
    expected.insert(n);
    assert!(expected.len() > events.len() + 4);
    for (what, kept) in ["step folders", "ParaView index", "summary"].iter().zip(kept_in_files(&out, &summary)) {
        assert_eq!(kept, expected, "--keep 5: the {what}");
    }
}

#[test]
fn without_csv_a_run_writes_no_step_csv_file_and_keeps_every_step() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("box.toml");
    std::fs::write(&model, pullout_box()).unwrap();
    let out = dir.path().join("out");
    let summary = run(&model, &out, &[]);
    let n = summary["steps"].as_array().unwrap().len();
    let mut csv_files = Vec::new();
    let mut stack = vec![out.clone()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            // (restart/ holds the saved states a run can continue from, one file per step)
            if path == out.join("restart") {
                continue;
            }
            assert!(!path.file_name().unwrap().to_string_lossy().starts_with("stage-"), "{}", path.display());
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "csv") {
                csv_files.push(path.strip_prefix(&out).unwrap().to_path_buf());
            }
        }
    }
    assert_eq!(csv_files, [Path::new("history.csv")]);
    let [folders, listed, kept] = kept_in_files(&out, &summary);
    assert!(folders.is_empty());
    let every: BTreeSet<usize> = (1..=n).collect();
    assert_eq!(listed, every);
    assert_eq!(kept, every);
    assert_eq!(summary["fields"]["csv"], false);
}
