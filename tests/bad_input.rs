//! The bad-input corpus.
//!
//! Reference: the project's issue on bad input: every message names the file, the field and the
//! entity. "Bad input gets an error that names the file, the field and the entity. This covers: an
//! unknown node; a duplicate id; a zero- or negative-area element; a negative or NaN material value;
//! a reinforcement path that does not run through the mesh; an unconstrained model (name the free
//! body or node). There are no panics on user input. A test holds at least 30 broken model files,
//! each with its message asserted."
//!
//! Goal: every file in `tests/bad-models/` is a small, broken model. Each one states what geoslip
//! must say about it:
//!
//! - `# expect: <substring>` lines at the top of a TOML file (or `expect: <substring>` lines in a
//!   sibling `<name>.expect` file for a JSON model, which cannot hold comments): loading the model
//!   must fail, and the error must name the file and contain every expected substring. When the
//!   error is a list of model problems, every problem line must name the file too, so a file with
//!   several problems proves that all of them are listed, not only the first.
//! - `# expect-run: <substring>`: the problem is only found at run time. The model must load, and
//!   `analysis::run` must then fail with every expected substring in its message.
//!
//! Loading or running a broken model must never panic: a panic is reported as a failure that names
//! the file. Every file is checked before the test fails, so one run lists every broken expectation.

use geoslip::analysis::results::StepResults;
use geoslip::analysis::RunStats;
use geoslip::analysis::{self, RunOptions, StepRecord, StepSink};
use geoslip::model::Model;
use geoslip::Error;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// Fewer broken models than this and the corpus no longer meets the issue.
const MIN_FILES: usize = 30;

/// A sink that keeps nothing: the run-time cases only need the error.
struct Discard;

impl StepSink for Discard {
    fn step_done(
        &mut self,
        _: &geoslip::model::Model,
        _: &StepResults,
        _: &StepRecord,
        _: &RunStats,
    ) -> Result<(), Error> {
        Ok(())
    }
}

/// What one model file must produce.
#[derive(Debug, Default)]
struct Expectations {
    /// Substrings of the error that `Model::load` returns.
    load: Vec<String>,
    /// Substrings of the error that `analysis::run` returns after a successful load.
    run: Vec<String>,
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("bad-models")
}

fn is_json(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Model files in the corpus, sorted (the `.expect` side files are not models).
fn model_files() -> Vec<PathBuf> {
    let dir = corpus_dir();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: cannot list the bad-model corpus: {e}", dir.display()))
        .map(|entry| entry.expect("a readable directory entry").path())
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml" || e == "json"))
        .collect();
    files.sort();
    files
}

/// Read `expect:` / `expect-run:` lines: the leading `#` comment lines of a TOML file, or every line
/// of the `.expect` side file of a JSON one.
fn expectations(path: &Path) -> Result<Expectations, String> {
    let (source, text, commented) = if is_json(path) {
        let side = path.with_extension("expect");
        let text = std::fs::read_to_string(&side)
            .map_err(|e| format!("a JSON model needs its expectations in {}: {e}", side.display()))?;
        (side, text, false)
    } else {
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read: {e}"))?;
        (path.to_path_buf(), text, true)
    };
    let mut out = Expectations::default();
    for line in text.lines() {
        let line = line.trim();
        let body = if commented {
            if line.is_empty() {
                continue;
            }
            match line.strip_prefix('#') {
                Some(rest) => rest.trim(),
                None => break, // the header ends at the first line that is not a comment
            }
        } else {
            line
        };
        if let Some(s) = body.strip_prefix("expect-run:") {
            out.run.push(s.trim().to_string());
        } else if let Some(s) = body.strip_prefix("expect:") {
            out.load.push(s.trim().to_string());
        }
    }
    if out.load.iter().chain(&out.run).any(|s| s.is_empty()) {
        return Err(format!("{}: an `expect:` line has no text", source.display()));
    }
    match (out.load.is_empty(), out.run.is_empty()) {
        (true, true) => Err(format!(
            "{}: no `expect:` or `expect-run:` line: every broken model must state its message",
            source.display()
        )),
        (false, false) => Err(format!("{}: give either `expect:` or `expect-run:` lines, not both", source.display())),
        _ => Ok(out),
    }
}

/// The substrings of `wanted` that `message` lacks, as failure lines.
fn missing(message: &str, wanted: &[String]) -> Vec<String> {
    wanted.iter().filter(|w| !message.contains(w.as_str())).map(|w| format!("missing expected text: {w}")).collect()
}

/// Check one model file; the returned lines describe what went wrong.
fn check(path: &Path) -> Vec<String> {
    let expect = match expectations(path) {
        Ok(e) => e,
        Err(e) => return vec![e],
    };
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default().to_string();
    let loaded = match catch_unwind(AssertUnwindSafe(|| Model::load(path))) {
        Ok(r) => r,
        Err(_) => return vec!["PANIC while loading the model: user input must never panic".into()],
    };
    let mut failures = Vec::new();
    if expect.run.is_empty() {
        let error = match loaded {
            Ok(_) => return vec!["the model loaded without an error".into()],
            Err(e) => e,
        };
        let message = error.to_string();
        if !message.contains(&name) {
            failures.push("the error does not name the file".into());
        }
        if let Error::Model(list) = &error {
            // One line per problem, each naming the file.
            let prefix = format!("  {}: ", list.file.display());
            for line in message.lines().skip(1) {
                if !line.starts_with(&prefix) {
                    failures.push(format!("a problem line does not name the file: {line}"));
                }
            }
            if message.lines().count() != list.problems.len() + 1 {
                failures.push("the error does not list every problem on its own line".into());
            }
        }
        failures.extend(missing(&message, &expect.load));
        if !failures.is_empty() {
            failures.push(format!("the error was:\n{message}"));
        }
    } else {
        let model = match loaded {
            Ok(m) => m,
            Err(e) => return vec![format!("`expect-run:` needs a model that loads, but loading failed:\n{e}")],
        };
        let ran = catch_unwind(AssertUnwindSafe(|| analysis::run(&model, &RunOptions::default(), &mut Discard)));
        match ran {
            Err(_) => failures.push("PANIC while running the model: user input must never panic".into()),
            Ok(Ok(_)) => failures.push("the run finished without an error".into()),
            Ok(Err(e)) => {
                let message = e.to_string();
                // Run-time errors name the file like load errors do (a solve failure also names the
                // stage, the step and the unknowns).
                if !message.contains(&name) {
                    failures.push("the error does not name the file".into());
                }
                failures.extend(missing(&message, &expect.run));
                if !failures.is_empty() {
                    failures.push(format!("the error was:\n{message}"));
                }
            }
        }
    }
    failures
}

#[test]
fn every_bad_model_gets_a_message_that_names_the_file_the_field_and_the_entity() {
    let files = model_files();
    assert!(
        files.len() >= MIN_FILES,
        "{}: the bad-input corpus holds {} model files; the issue asks for at least {MIN_FILES}",
        corpus_dir().display(),
        files.len()
    );
    // Keep panics from the library quiet here: `check` reports them with the file's name.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let results: Vec<(PathBuf, Vec<String>)> = files.iter().map(|f| (f.clone(), check(f))).collect();
    std::panic::set_hook(hook);

    let mut report = String::new();
    for (file, failures) in &results {
        if !failures.is_empty() {
            report.push_str(&format!("\n{}:\n", file.display()));
            for f in failures {
                report.push_str(&format!("  - {}\n", f.replace('\n', "\n    ")));
            }
        }
    }
    let failed = results.iter().filter(|(_, f)| !f.is_empty()).count();
    assert!(report.is_empty(), "{failed} of {} bad models did not get the expected message:{report}", files.len());
}

#[test]
fn every_json_model_has_its_expect_file_and_every_expect_file_its_model() {
    let dir = corpus_dir();
    let mut problems = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("the corpus folder").map(|e| e.expect("an entry").path()) {
        match entry.extension().and_then(|e| e.to_str()) {
            Some("json") if !entry.with_extension("expect").is_file() => {
                problems.push(format!("{}: no {} beside it", entry.display(), entry.with_extension("expect").display()))
            }
            Some("expect") if !entry.with_extension("json").is_file() => {
                problems.push(format!("{}: no JSON model beside it", entry.display()))
            }
            Some("toml" | "json" | "expect") => {}
            // the records the broken models' dynamic stages read
            None if entry.ends_with("records") && entry.is_dir() => {}
            _ => problems.push(format!("{}: not a model (.toml, .json), an .expect file or records/", entry.display())),
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
