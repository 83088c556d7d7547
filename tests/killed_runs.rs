//! A run killed at any moment leaves whole steps only, and the next run into the same folder
//! cleans up after it: no temporary file stays, and the results are those of a run never killed.
//!
//! Reference: the project's standards (a run leaves whole steps only, whatever an earlier run into
//! the same folder left) and issue 20, "Done when": "a run killed at 10 random moments never leaves
//! an incomplete step or a temporary file after the next run". A step's folder is written beside
//! its place as `.partial-step-NNN` and renamed into place, every other file through a
//! `.partial-*` temporary file (src/output/owned_folder.rs).
//!
//! A small pull-out box pulled in 100 increments (one step folder each) runs for half a second to a
//! second on this machine (a run syncs every file it writes); it is run once to completion, then 10 times into one output folder, each time
//! SIGKILLed at a moment drawn from a fixed seed over the clean run's duration and then run again
//! to completion. What each killed run left holds whole steps only (each step folder it left has
//! every file of that step, byte for byte as the clean run wrote it); after the run that follows,
//! the folder holds exactly the clean run's files, no `.partial-*` or other hidden file, the same
//! steps, and the same history.csv and summary.json (but for the timings). In a build with HDF5,
//! every step that the `results.xdmf` a killed run left lists is whole in its `results.h5` (read
//! by h5py), value for value the clean run's: `results.h5` is written in place, and only the
//! index, rewritten atomically after each flush, says which steps are complete.
//!
//! ```text
//!        q = 50 kPa
//!   ┌────┬────┬────┬────┐ 0.2 m
//!   │    │    │    │    │
//!  ═╪════╪════╪════┼    │  geogrid (Coulomb interface), pulled 50 mm in 100 steps
//!   │    │    │    │    │
//!   └────┴────┴────┴────┘
//!   ▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲  fixed base; front and back walls fixed in x; 0.4 m long
//! ```

mod common;

use proptest::prelude::Rng;
use proptest::test_runner::{RngAlgorithm, TestRng};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const KILLS: usize = 10;
const PULL_STEPS: usize = 100;

fn geoslip() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_geoslip"));
    c.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::null());
    c
}

/// The pull-out box (`common::small_pullout_box`) with a Coulomb interface.
fn pullout_box() -> String {
    common::small_pullout_box(
        "pull-out box, killed and run again",
        r#"{ type = "coulomb", shear_stiffness = 5000.0, cohesion = 0.0, friction_angle = 30.0 }"#,
        PULL_STEPS,
    )
}

/// Every file and folder below `dir`, relative to it.
fn files_below(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for entry in entries {
            let path = entry.unwrap().path();
            out.push(path.strip_prefix(dir).unwrap().to_path_buf());
            if path.is_dir() {
                stack.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The step folders below `out` (`stage-*/step-*`, not the `.partial-step-*` ones) and the files
/// in each.
fn step_folders(out: &Path) -> BTreeMap<PathBuf, Vec<PathBuf>> {
    let mut steps = BTreeMap::new();
    for stage in std::fs::read_dir(out).into_iter().flatten().flatten() {
        if !stage.file_name().to_string_lossy().starts_with("stage-") || !stage.path().is_dir() {
            continue;
        }
        for step in std::fs::read_dir(stage.path()).unwrap().flatten() {
            if step.file_name().to_string_lossy().starts_with("step-") {
                let rel = step.path().strip_prefix(out).unwrap().to_path_buf();
                steps.insert(rel, files_below(&step.path()));
            }
        }
    }
    steps
}

fn run_to_completion(model: &Path, out: &Path) -> Duration {
    let started = Instant::now();
    let status =
        geoslip().args(["run", "-q", "--csv", "--solver", "faer", "--out"]).arg(out).arg(model).status().unwrap();
    assert!(status.success(), "a run into {} failed: {status}", out.display());
    started.elapsed()
}

/// The numbers of a CSV file, row by row (text fields kept as text).
fn csv_cells(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path).unwrap().lines().map(|l| l.split(',').map(str::to_string).collect()).collect()
}

fn same_number(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

fn assert_same_csv(clean: &Path, other: &Path) {
    let (a, b) = (csv_cells(clean), csv_cells(other));
    assert_eq!(a.len(), b.len(), "{}: {} rows against the clean run's {}", other.display(), b.len(), a.len());
    for (row, (ra, rb)) in a.iter().zip(&b).enumerate() {
        assert_eq!(ra.len(), rb.len(), "{} row {row}", other.display());
        for (x, y) in ra.iter().zip(rb) {
            let same = match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => same_number(x, y),
                _ => x == y,
            };
            assert!(same, "{} row {row}: {y} against the clean run's {x}", other.display());
        }
    }
}

/// `summary.json` without what depends on time (every `*seconds` field).
fn summary_without_timings(path: &Path) -> serde_json::Value {
    fn strip(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(o) => {
                o.retain(|k, _| !k.ends_with("seconds"));
                o.values_mut().for_each(strip);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    strip(&mut v);
    v
}

fn assert_same_json(a: &serde_json::Value, b: &serde_json::Value, at: &str) {
    use serde_json::Value::*;
    match (a, b) {
        (Number(x), Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!(same_number(x, y), "summary.json{at}: {y} against the clean run's {x}");
        }
        (Array(x), Array(y)) => {
            assert_eq!(x.len(), y.len(), "summary.json{at}: length");
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                assert_same_json(x, y, &format!("{at}[{i}]"));
            }
        }
        (Object(x), Object(y)) => {
            assert_eq!(x.keys().collect::<Vec<_>>(), y.keys().collect::<Vec<_>>(), "summary.json{at}: fields");
            for (k, xv) in x {
                assert_same_json(xv, &y[k], &format!("{at}.{k}"));
            }
        }
        _ => assert_eq!(a, b, "summary.json{at}"),
    }
}

/// Start a run of `model` into `out` and SIGKILL it `moment` after it started; whether it had
/// finished by then.
fn run_killed_at(model: &Path, out: &Path, moment: Duration) -> bool {
    let mut child =
        geoslip().args(["run", "-q", "--csv", "--solver", "faer", "--out"]).arg(out).arg(model).spawn().unwrap();
    std::thread::sleep(moment);
    let finished = child.try_wait().unwrap().is_some_and(|s| s.success());
    let _ = child.kill();
    let _ = child.wait();
    finished
}

/// Each step folder below `out` is whole: it has every file the clean run's has, byte for byte.
/// Returns how many there are.
fn assert_whole_steps(out: &Path, clean: &Path, clean_steps: &BTreeMap<PathBuf, Vec<PathBuf>>, what: &str) -> usize {
    let left = step_folders(out);
    for (step, files) in &left {
        let Some(clean_files) = clean_steps.get(step) else {
            panic!("{what}: {} is no step of the run", step.display())
        };
        assert_eq!(files, clean_files, "{what}: {} is not whole", step.display());
        for f in files {
            let (a, b) = (clean.join(step).join(f), out.join(step).join(f));
            assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap(), "{what}: {} differs", b.display());
        }
    }
    left.len()
}

/// In a build with HDF5: what `results.xdmf` in `out` lists (if a killed run left one) is whole in
/// `results.h5`, read back by h5py (the HDF5 library's own Python binding), each array of the shape
/// the index gives and value for value the clean run's. Returns how many steps it lists.
#[cfg(feature = "hdf5")]
fn assert_listed_steps_whole(out: &Path, clean: &Path, what: &str) -> usize {
    const READER: &str = r#"
import os, sys
import xml.etree.ElementTree as ET
import h5py, numpy as np
out, clean = sys.argv[1], sys.argv[2]
index = os.path.join(out, "results.xdmf")
if not os.path.exists(index):
    print(0)
    sys.exit(0)
root = ET.parse(index).getroot()
with h5py.File(os.path.join(out, "results.h5"), "r") as f, h5py.File(os.path.join(clean, "results.h5"), "r") as g:
    for item in root.iter("DataItem"):
        name, path = item.text.strip().split(":")
        assert name == "results.h5", name
        dims = [int(d) for d in item.get("Dimensions").split()]
        a = f[path][()]
        assert list(a.shape) == dims, (path, a.shape, dims)
        assert np.array_equal(a, g[path][()]), path
print(len({t.get("Value") for t in root.iter("Time")}))
"#;
    let read = Command::new("/usr/bin/python3")
        .args(["-c", READER])
        .arg(out)
        .arg(clean)
        .output()
        .unwrap_or_else(|e| panic!("cannot run /usr/bin/python3 ({e}): install python3-h5py"));
    assert!(
        read.status.success(),
        "{what}: the steps results.xdmf lists are not whole in results.h5: {}",
        String::from_utf8_lossy(&read.stderr)
    );
    String::from_utf8_lossy(&read.stdout).trim().parse().unwrap()
}

/// The model written to a fresh folder, and its clean run there: (folder, model, clean output, its
/// step folders, its duration).
fn clean_run() -> (tempfile::TempDir, PathBuf, PathBuf, BTreeMap<PathBuf, Vec<PathBuf>>, Duration) {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("pullout.toml");
    std::fs::write(&model, pullout_box()).unwrap();
    let clean = dir.path().join("clean");
    let duration = run_to_completion(&model, &clean);
    let clean_steps = step_folders(&clean);
    println!("the clean run: {} steps in {:.0} ms", clean_steps.len(), duration.as_secs_f64() * 1e3);
    assert_eq!(clean_steps.len(), 1 + PULL_STEPS, "{:?}", clean_steps.keys());
    assert!(duration > Duration::from_millis(300), "the run takes {duration:?}: too short to be killed mid-way");
    (dir, model, clean, clean_steps, duration)
}

/// `n` moments drawn from a fixed seed, uniformly over `[0, span)`.
fn moments(seed: &[u8; 32], n: usize, span: Duration) -> Vec<Duration> {
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, seed);
    (0..n).map(|_| span.mul_f64((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64)).collect()
}

#[test]
fn a_run_killed_at_ten_moments_leaves_whole_steps_and_the_next_run_leaves_the_clean_results() {
    let (dir, model, clean, clean_steps, duration) = clean_run();
    let clean_files = files_below(&clean);
    let out = dir.path().join("out");
    let mut killed_mid_run = 0;
    for (k, moment) in moments(b"geoslip killed-runs test, seed 1", KILLS, duration).into_iter().enumerate() {
        let finished = run_killed_at(&model, &out, moment);
        if !finished {
            killed_mid_run += 1;
        }
        // what the killed run left: each step folder there is whole, as the clean run wrote it
        let what = format!("kill {k} at {moment:?}");
        let whole = assert_whole_steps(&out, &clean, &clean_steps, &what);
        #[cfg(feature = "hdf5")]
        println!("kill {k}: results.xdmf lists {} whole steps", assert_listed_steps_whole(&out, &clean, &what));
        let partial = files_below(&out)
            .iter()
            .filter(|f| f.file_name().is_some_and(|n| n.to_string_lossy().starts_with(".partial-")))
            .count();
        println!(
            "kill {k} at {:>5.0} ms: {}, {whole} whole steps and {partial} .partial-* files or folders left",
            moment.as_secs_f64() * 1e3,
            if finished { "the run had finished" } else { "killed mid-run" },
        );

        // the next run into the same folder: the clean run's files exactly, nothing else
        run_to_completion(&model, &out);
        let files = files_below(&out);
        let hidden: Vec<&PathBuf> = files
            .iter()
            .filter(|f| f.components().any(|c| c.as_os_str().to_string_lossy().starts_with('.')))
            // the record of what the run wrote (src/output/owned_folder.rs)
            .filter(|f| f.as_path() != Path::new(".geoslip-owned"))
            .collect();
        assert!(hidden.is_empty(), "{what}: temporary files left after the next run: {hidden:?}");
        assert_eq!(files, clean_files, "{what}: the files after the next run are not the clean run's");
        assert_eq!(step_folders(&out), clean_steps, "{what}: the steps after the next run are not the clean run's");
        assert_same_csv(&clean.join("history.csv"), &out.join("history.csv"));
        assert_same_json(
            &summary_without_timings(&clean.join("summary.json")),
            &summary_without_timings(&out.join("summary.json")),
            "",
        );
    }
    assert!(killed_mid_run >= KILLS / 2, "only {killed_mid_run} of {KILLS} kills came before the run ended");
}

/// The first tenth of a run into a folder that holds an earlier run's results is mostly the removal
/// of those results. A run killed then must still leave whole steps only.
#[test]
fn a_run_killed_while_it_removes_an_earlier_run_leaves_whole_steps() {
    let (dir, model, clean, clean_steps, duration) = clean_run();
    let out = dir.path().join("out");
    for (k, moment) in moments(b"geoslip killed-runs test, seed 2", KILLS, duration / 10).into_iter().enumerate() {
        run_to_completion(&model, &out);
        run_killed_at(&model, &out, moment);
        let whole = assert_whole_steps(&out, &clean, &clean_steps, &format!("kill {k} at {moment:?}"));
        #[cfg(feature = "hdf5")]
        assert_listed_steps_whole(&out, &clean, &format!("kill {k} at {moment:?}"));
        println!("kill {k} at {:>5.1} ms: {whole} whole steps left", moment.as_secs_f64() * 1e3);
    }
}

/// A run into a folder where a run was killed early (before it wrote its first summary) replaces
/// what is there: nothing of the killed run's model stays beside the new model's results.
#[test]
fn a_run_of_another_model_after_an_early_kill_leaves_nothing_of_the_first() {
    let (dir, model, _clean, _clean_steps, duration) = clean_run();
    let other = dir.path().join("block.toml");
    // the same box with its first stage named otherwise and the pull in one step
    let factors: Vec<String> = (1..=PULL_STEPS).map(|k| format!("{}", k as f64 / PULL_STEPS as f64)).collect();
    let text = pullout_box()
        .replace("name = \"surcharge\"", "name = \"load\"")
        .replace(&format!("load_factors = [{}]", factors.join(", ")), "load_factors = [1.0]");
    std::fs::write(&other, text).unwrap();
    let other_alone = dir.path().join("other-alone");
    run_to_completion(&other, &other_alone);
    let expected = files_below(&other_alone);
    let out = dir.path().join("out");
    for (k, moment) in moments(b"geoslip killed-runs test, seed 3", KILLS, duration / 10).into_iter().enumerate() {
        run_to_completion(&model, &out);
        run_killed_at(&model, &out, moment);
        run_to_completion(&other, &out);
        let stale: Vec<PathBuf> = files_below(&out).into_iter().filter(|f| !expected.contains(f)).collect();
        assert!(
            stale.is_empty(),
            "kill {k} at {moment:?}, then another model: {} files that its run does not write stayed, such as {:?}",
            stale.len(),
            &stale[..stale.len().min(4)]
        );
    }
}
