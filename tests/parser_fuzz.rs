//! In-process fuzzing of every reader of a file that may come from anyone: model files (TOML and
//! JSON), Gmsh meshes (2.2 ASCII, 4.1 ASCII and binary), saved steps, calibration files and their
//! CSV data, and the `.geo` scanner. No byte sequence may make a reader panic, run for more than a
//! few seconds, or allocate beyond the limit it names; each must return a value or an error.
//!
//! Reference: docs/reliability.md ("how the promise is tested"). Each target starts from a corpus
//! of real files of the repository and mutates them, with a ChaCha generator seeded by (target,
//! seed, case): bytes flipped, inserted, deleted, duplicated or moved, chunks of other corpus files
//! spliced in, numbers replaced by extreme ones (0, −1, 2^63, 2^64 − 1, 1e308, NaN, a long run of
//! digits), and lines repeated. Every input that failed once is kept in `tests/fuzz-regressions/
//! <target>/` and replayed first, on every run.
//!
//! `GEOSLIP_PARSER_FUZZ_CASES` (per target; default 400, a few seconds each in the test profile)
//! and `GEOSLIP_FUZZ_SEED` set the campaign; `scripts/fuzz.sh --parsers N` runs long ones. A failing
//! input is saved under `target/fuzz-failures/parsers/<target>/` with the reason; the test then
//! fails naming it.

use geoslip::analysis::RunStats;
use geoslip::analysis::{self, Checkpoint, RunOptions, StepSink};
use geoslip::gmsh::GmshMesh;
use geoslip::linsol::Backend;
use geoslip::model::Model;
use geoslip::output::checkpoints::{self, From};
use geoslip::output::OwnedFolder;
use proptest::prelude::Rng;
use proptest::test_runner::{RngAlgorithm, TestRng};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const DEFAULT_CASES: usize = 400;
const DEFAULT_SEED: u64 = 1;
/// The longest one input may take (a reader that loops shows here).
const SLOW: Duration = Duration::from_secs(5);
/// The memory any reader may use, MB: the limit the readers are given.
const MEMORY_MB: f64 = 256.0;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

struct Rand(TestRng);

impl Rand {
    fn new(target: &str, seed: u64, case: usize) -> Rand {
        let mut bytes = [0u8; 32];
        bytes[..8].copy_from_slice(&seed.to_le_bytes());
        bytes[8..16].copy_from_slice(&(case as u64).to_le_bytes());
        for (i, b) in target.bytes().take(16).enumerate() {
            bytes[16 + i] = b;
        }
        Rand(TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.0.next_u64() % n as u64) as usize
        }
    }
}

const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "1e308",
    "-1e308",
    "1e-320",
    "NaN",
    "inf",
    "99999999999999999999999999999999",
    "4294967296",
    "3",
];

/// One to four mutations of `input`, with `others` to splice from.
fn mutate(rng: &mut Rand, input: &[u8], others: &[Vec<u8>]) -> Vec<u8> {
    let mut bytes = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        let n = bytes.len();
        match rng.below(9) {
            0 if n > 0 => {
                let i = rng.below(n);
                bytes[i] ^= 1 << rng.below(8);
            }
            1 => {
                let i = rng.below(n + 1);
                bytes.insert(i, rng.below(256) as u8);
            }
            2 if n > 0 => {
                let i = rng.below(n);
                let len = 1 + rng.below(64.min(n - i));
                bytes.drain(i..i + len);
            }
            3 if n > 0 => {
                // a chunk repeated
                let i = rng.below(n);
                let len = 1 + rng.below(256.min(n - i));
                let chunk = bytes[i..i + len].to_vec();
                let at = rng.below(bytes.len() + 1);
                bytes.splice(at..at, chunk);
            }
            4 if !others.is_empty() => {
                let other = &others[rng.below(others.len())];
                if !other.is_empty() {
                    let i = rng.below(other.len());
                    let len = 1 + rng.below(512.min(other.len() - i));
                    let at = rng.below(bytes.len() + 1);
                    bytes.splice(at..at, other[i..i + len].iter().copied());
                }
            }
            5 | 6 => {
                // a number (a run of digits) replaced by an extreme one
                let starts: Vec<usize> = (0..n)
                    .filter(|&i| bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_digit()))
                    .collect();
                if !starts.is_empty() {
                    let s = starts[rng.below(starts.len())];
                    let mut e = s;
                    while e < n && (bytes[e].is_ascii_digit() || bytes[e] == b'.') {
                        e += 1;
                    }
                    let number = NUMBERS[rng.below(NUMBERS.len())];
                    bytes.splice(s..e, number.bytes());
                }
            }
            7 if n > 0 => {
                // a line repeated many times
                let lines: Vec<usize> = (0..n).filter(|&i| i == 0 || bytes[i - 1] == b'\n').collect();
                let s = lines[rng.below(lines.len())];
                let e = bytes[s..].iter().position(|&b| b == b'\n').map_or(n, |p| s + p + 1);
                let line = bytes[s..e].to_vec();
                for _ in 0..rng.below(200) {
                    bytes.splice(s..s, line.iter().copied());
                }
            }
            8 if n > 8 => {
                // an 8-byte word overwritten by an extreme little-endian integer (binary files)
                let i = rng.below(n - 8);
                let word = [u64::MAX, 1 << 63, 1 << 40, 0, 3][rng.below(5)];
                bytes[i..i + 8].copy_from_slice(&word.to_le_bytes());
            }
            _ => {}
        }
    }
    bytes
}

/// A fuzz target: its corpus and what is done with one input (the input is in `scratch/<name>`).
struct Target {
    name: &'static str,
    corpus: Vec<Vec<u8>>,
    file_name: &'static str,
    /// Read the input; `Ok` or `Err` are both fine, only a panic or a hang is not.
    read: Box<dyn Fn(&Path) -> bool>,
}

fn corpus(paths: &[PathBuf]) -> Vec<Vec<u8>> {
    paths.iter().map(|p| std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).collect()
}

fn files_in(dir: &str, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v
}

fn load_model(path: &Path) -> bool {
    let options = geoslip::model::LoadOptions { memory_limit_mb: Some(MEMORY_MB), ..Default::default() };
    Model::load_with(path, options).is_ok()
}

#[derive(Default)]
struct Saved(Vec<Checkpoint>);

impl StepSink for Saved {
    fn step_done(
        &mut self,
        _: &geoslip::model::Model,
        _: &analysis::results::StepResults,
        _: &analysis::StepRecord,
        _: &RunStats,
    ) -> Result<(), geoslip::Error> {
        Ok(())
    }
    fn keeps_checkpoints(&self) -> bool {
        true
    }
    fn checkpoint(&mut self, checkpoint: Checkpoint) -> Result<(), geoslip::Error> {
        self.0.push(checkpoint);
        Ok(())
    }
}

fn targets() -> Vec<Target> {
    let seeds = files_in("tests/fuzz-seeds", "toml");
    let json: Vec<Vec<u8>> = seeds
        .iter()
        .map(|p| {
            let value: toml::Value = toml::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
            serde_json::to_vec_pretty(&value).unwrap()
        })
        .collect();
    let meshes = |ext| files_in("tests/gmsh", ext);
    let mut msh41_ascii = corpus(&[root().join("examples/lab-pullout/lab-pullout.msh")]);
    msh41_ascii.extend(corpus(&meshes("msh")).into_iter().filter(|b| b.starts_with(b"$MeshFormat\n4.1 0")));
    let msh22: Vec<Vec<u8>> =
        corpus(&meshes("msh")).into_iter().filter(|b| b.starts_with(b"$MeshFormat\n2.2")).collect();
    let msh41_binary = binary_meshes();

    // a saved step of a small pull-out, and the model it belongs to
    let model_path = root().join("tests/fuzz-seeds/small-pullout.toml");
    let model = Model::load(&model_path).unwrap();
    let mut saved = Saved::default();
    analysis::run(&model, &RunOptions::for_model(&model, Backend::Faer), &mut saved).unwrap();
    let step = saved.0.last().unwrap().clone();
    let scratch = tempfile::tempdir().unwrap();
    checkpoints::write(&OwnedFolder::open(scratch.path(), &[]).unwrap(), &step).unwrap();
    let saved_file = std::fs::read_dir(scratch.path().join("restart")).unwrap().next().unwrap().unwrap().path();
    let saved_bytes = std::fs::read(&saved_file).unwrap();
    let saved_name: &'static str =
        Box::leak(saved_file.file_name().unwrap().to_string_lossy().into_owned().into_boxed_str());
    let from = From { stage: (step.stage_index + 1).to_string(), step: step.step };

    vec![
        Target { name: "model-toml", corpus: corpus(&seeds), file_name: "model.toml", read: Box::new(load_model) },
        Target { name: "model-json", corpus: json, file_name: "model.json", read: Box::new(load_model) },
        Target {
            name: "msh-2.2",
            corpus: msh22,
            file_name: "mesh.msh",
            read: Box::new(|p| GmshMesh::read_within(p, Some(MEMORY_MB)).is_ok()),
        },
        Target {
            name: "msh-4.1-ascii",
            corpus: msh41_ascii,
            file_name: "mesh.msh",
            read: Box::new(|p| GmshMesh::read_within(p, Some(MEMORY_MB)).is_ok()),
        },
        Target {
            name: "msh-4.1-binary",
            corpus: msh41_binary,
            file_name: "mesh.msh",
            read: Box::new(|p| GmshMesh::read_within(p, Some(MEMORY_MB)).is_ok()),
        },
        Target {
            name: "saved-step",
            corpus: vec![saved_bytes],
            file_name: saved_name,
            read: Box::new(move |p| {
                let results = p.parent().unwrap().parent().unwrap();
                checkpoints::read(results, &from, &model, Some(MEMORY_MB)).is_ok()
            }),
        },
        Target {
            name: "calibration-spec",
            corpus: corpus(&files_in("examples/calibration", "toml")),
            file_name: "calibration.toml",
            read: Box::new(|p| geoslip::calibration::spec::load(p).is_ok()),
        },
        Target {
            name: "calibration-csv",
            corpus: corpus(&files_in("examples/calibration", "csv")),
            file_name: "data.csv",
            read: Box::new(|p| {
                let a =
                    geoslip::calibration::curves::read(p, geoslip::calibration::spec::TestKind::DirectShear).is_ok();
                let b = geoslip::calibration::curves::read(p, geoslip::calibration::spec::TestKind::PullOut).is_ok();
                a || b
            }),
        },
        Target {
            name: "geo-script",
            corpus: corpus(&[
                root().join("examples/lab-pullout/lab-pullout.geo"),
                root().join("examples/embedded-pullout/embedded-pullout.geo"),
            ]),
            file_name: "mesh.geo",
            read: Box::new(|p| geoslip::geo_script::actions(p).is_empty()),
        },
    ]
}

/// The lab pull-out mesh in binary 4.1, written by Gmsh when it is installed (else none).
fn binary_meshes() -> Vec<Vec<u8>> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("mesh.msh");
    let made = std::process::Command::new("gmsh")
        .arg(root().join("examples/lab-pullout/lab-pullout.msh"))
        .args(["-save", "-bin", "-format", "msh41", "-v", "0", "-o"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if made {
        vec![std::fs::read(&out).unwrap()]
    } else {
        Vec::new()
    }
}

/// Where the input goes: the saved step in a `restart/` folder, the rest alone in the scratch.
fn input_path(scratch: &Path, target: &Target) -> PathBuf {
    if target.name == "saved-step" {
        std::fs::create_dir_all(scratch.join("restart")).unwrap();
        scratch.join("restart").join(target.file_name)
    } else {
        scratch.join(target.file_name)
    }
}

/// Run `input` through `target`; a failure's reason.
fn try_input(target: &Target, scratch: &Path, input: &[u8]) -> Option<String> {
    let path = input_path(scratch, target);
    std::fs::write(&path, input).unwrap();
    let started = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| (target.read)(&path)));
    let took = started.elapsed();
    match outcome {
        Err(panic) => {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Some(format!("panicked: {message}"))
        }
        Ok(_) if took > SLOW => Some(format!("took {:.1} s", took.as_secs_f64())),
        Ok(_) => None,
    }
}

#[test]
fn no_input_makes_a_reader_panic_or_hang() {
    let cases: usize =
        std::env::var("GEOSLIP_PARSER_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(DEFAULT_CASES);
    let seed: u64 = std::env::var("GEOSLIP_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(DEFAULT_SEED);
    let scratch = tempfile::tempdir().unwrap();
    // the panics are counted, not printed
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut failures = Vec::new();
    let mut counts = Vec::new();
    for target in targets() {
        if target.corpus.is_empty() {
            println!("{}: no corpus on this machine, skipped", target.name);
            continue;
        }
        let mut tried = 0;
        // the kept regressions first
        let kept = root().join("tests/fuzz-regressions").join(target.name);
        if let Ok(entries) = std::fs::read_dir(&kept) {
            for entry in entries.flatten() {
                let input = std::fs::read(entry.path()).unwrap();
                tried += 1;
                if let Some(why) = try_input(&target, scratch.path(), &input) {
                    failures.push(format!("{}: kept input {}: {why}", target.name, entry.path().display()));
                }
            }
        }
        // the corpus as it is, then mutated
        for (k, input) in target.corpus.iter().enumerate() {
            tried += 1;
            if let Some(why) = try_input(&target, scratch.path(), input) {
                failures.push(format!("{}: corpus file {k}: {why}", target.name));
            }
        }
        for case in 0..cases {
            let mut rng = Rand::new(target.name, seed, case);
            let base = &target.corpus[rng.below(target.corpus.len())];
            let input = mutate(&mut rng, base, &target.corpus);
            tried += 1;
            if let Some(why) = try_input(&target, scratch.path(), &input) {
                let dir = root().join("target/fuzz-failures/parsers").join(target.name);
                std::fs::create_dir_all(&dir).unwrap();
                let file = dir.join(format!("seed-{seed}-case-{case}"));
                std::fs::write(&file, &input).unwrap();
                std::fs::write(file.with_extension("reason"), &why).unwrap();
                failures.push(format!("{}: case {case} ({}): {why}", target.name, file.display()));
            }
        }
        counts.push(format!("{} {tried}", target.name));
    }
    std::panic::set_hook(hook);
    println!("inputs per target (seed {seed}): {}", counts.join(", "));
    assert!(failures.is_empty(), "{} inputs failed:\n{}", failures.len(), failures.join("\n"));
}
