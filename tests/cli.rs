//! The command line as a new user meets it: `run`, `check`, `schema` and `backends` on the
//! annotated example, and the files a run leaves behind.
//!
//! Reference: docs/model-format.md (the output files and their unit-carrying headers) and
//! docs/verification.md §5: in the annotated example's first stage, the oedometric
//! vertical stress at the grid is q + γz = 20 + 19·0.2 = 23.8 kPa on both faces.

use std::path::Path;
use std::process::Command;

fn geoslip() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geoslip"))
}

fn example() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/annotated-pullout.toml")
}

#[test]
fn run_writes_every_result_file_with_units_in_the_headers() {
    let out = tempfile::tempdir().unwrap();
    let listed = geoslip().arg("backends").output().unwrap();
    let backends: Vec<String> = String::from_utf8_lossy(&listed.stdout).lines().map(str::to_string).collect();
    let mut solvers = vec!["auto".to_string()];
    solvers.extend(backends.iter().cloned());
    for solver in solvers.iter().map(String::as_str) {
        let dir = out.path().join(solver);
        let status =
            geoslip().args(["run", "--csv", "--solver", solver, "--out"]).arg(&dir).arg(example()).status().unwrap();
        assert!(status.success(), "geoslip run --solver {solver} failed");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
        assert_eq!(summary["status"], "completed");
        assert_eq!(summary["steps"].as_array().unwrap().len(), 5);
        // auto picks the first (best) backend of the build
        let expected_solver = if solver == "auto" { backends[0].as_str() } else { solver };
        assert!(summary["solver"].as_str().unwrap().starts_with(expected_solver), "{}", summary["solver"]);
        for step in summary["steps"].as_array().unwrap() {
            for r in step["linear_residuals"].as_array().unwrap() {
                assert!(r.as_f64().unwrap() < 1e-10);
            }
        }
        // the report's linear-algebra paragraph says when the interface iteration condensed the soil
        let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
        assert!(report.contains("Linear algebra:"), "{solver}");
        match summary["solver_stats"]["condensed_unknowns"].as_u64() {
            Some(kept) => {
                assert!(report.contains(&format!("condensed the soil onto {kept} kept unknowns")), "{solver}")
            }
            None => assert!(!report.contains("kept unknowns"), "{solver}"),
        }
        let step = dir.join("stage-1-self-weight-and-surcharge/step-001");
        let headers = [
            ("displacements.csv", "node,x [m],y [m],ux [m],uy [m]"),
            ("reactions.csv", "node,rx [kN/m],ry [kN/m]"),
            ("bar_forces.csv", "bar,node_a,node_b,x_mid [m],y_mid [m],T [kN/m],state"),
            ("interface.csv", "interface,face,slave_node,x [m],y [m],master_a,master_b,xi [-],state,tributary [m],lambda [kN/m],sigma_n [kPa],tau [kPa],bearing [kPa],dilation [m],slip [m],contact"),
            ("stresses.csv", "element,gauss_point,x [m],y [m],sxx [kPa],syy [kPa],sxy [kPa],szz [kPa],pore_pressure [kPa],yield,plastic_strain"),
        ];
        for (file, header) in headers {
            let text = std::fs::read_to_string(step.join(file)).unwrap();
            assert_eq!(text.lines().next().unwrap(), header, "{file}");
        }
        let interface = std::fs::read_to_string(step.join("interface.csv")).unwrap();
        for line in interface.lines().skip(1).filter(|l| l.starts_with("grid,")) {
            let sigma_n: f64 = line.split(',').nth(11).unwrap().parse().unwrap();
            assert!((sigma_n - 23.8).abs() < 1e-9, "{line}");
        }
        let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
        assert_eq!(history.lines().count(), 1 + 5);
        assert!(history.lines().next().unwrap().ends_with("displacement [m],reaction [kN/m]"));
        // no temporary files left behind
        assert!(walk(&dir).iter().all(|p| !p.file_name().unwrap().to_string_lossy().starts_with(".partial-")));
    }
}

fn walk(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

#[test]
fn check_accepts_the_example_and_lists_every_problem_of_a_broken_model() {
    let ok = geoslip().arg("check").arg(example()).output().unwrap();
    assert!(ok.status.success());
    assert!(String::from_utf8_lossy(&ok.stdout).contains("ok"));
    let bad = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-models/several-problems.toml");
    let out = geoslip().arg("check").arg(&bad).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("5 problems"), "{err}");
    assert!(err.lines().filter(|l| l.contains("several-problems.toml:")).count() >= 6, "{err}");
}

#[test]
fn a_failed_run_leaves_a_failed_summary() {
    let out = tempfile::tempdir().unwrap();
    let bad = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-models/run-singular-hanging-bar.toml");
    let status = geoslip().args(["run", "--out"]).arg(out.path()).arg(&bad).status().unwrap();
    assert!(!status.success());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    assert!(summary["error"].as_str().unwrap().contains("node 7 uy"));
}

#[test]
fn schema_and_backends() {
    let out = geoslip().arg("schema").output().unwrap();
    let schema: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in ["units", "materials", "nodes", "elements", "interfaces", "stages"] {
        assert!(schema["properties"][key].is_object(), "schema lacks {key}");
    }
    let out = geoslip().arg("backends").output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("faer") && text.contains("dense"));
}

#[test]
fn the_documentation_shows_the_annotated_example_as_it_is() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/model-format.md")).unwrap();
    let example = std::fs::read_to_string(example()).unwrap();
    assert!(doc.contains(&example), "docs/model-format.md must include examples/annotated-pullout.toml verbatim");
}

#[test]
fn a_backend_that_is_not_built_in_fails_with_how_to_get_it() {
    let listed = geoslip().arg("backends").output().unwrap();
    let backends = String::from_utf8_lossy(&listed.stdout).to_string();
    for (backend, package) in [("mumps", "libmumps-seq-dev"), ("umfpack", "libsuitesparse-dev")] {
        if backends.lines().any(|l| l == backend) {
            continue;
        }
        let out = geoslip().args(["run", "--solver", backend]).arg(example()).output().unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("not available in this build") && err.contains(package), "{err}");
    }
}

#[test]
fn exit_codes_tell_bad_input_from_solver_failures_and_quiet_is_quiet() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = tempfile::tempdir().unwrap();
    // bad input: 2
    let bad = geoslip().arg("check").arg(root.join("tests/bad-models/several-problems.toml")).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let bad_run = geoslip()
        .args(["run", "--out"])
        .arg(out.path().join("a"))
        .arg(root.join("tests/bad-models/unknown-node-in-element.toml"))
        .output()
        .unwrap();
    assert_eq!(bad_run.status.code(), Some(2));
    // a singular model: the solver failed, 4
    let singular = geoslip()
        .args(["-q", "run", "--out"])
        .arg(out.path().join("b"))
        .arg(root.join("tests/bad-models/run-singular-hanging-bar.toml"))
        .output()
        .unwrap();
    assert_eq!(singular.status.code(), Some(4));
    // success, quietly: nothing on stdout, and a report beside the results
    let ok = geoslip().args(["-q", "run", "--out"]).arg(out.path().join("c")).arg(example()).output().unwrap();
    assert_eq!(ok.status.code(), Some(0));
    assert!(ok.stdout.is_empty(), "{}", String::from_utf8_lossy(&ok.stdout));
    let report = std::fs::read_to_string(out.path().join("c/report.md")).unwrap();
    for section in [
        "## Model",
        "## Key results",
        "## Events",
        "## Warnings and notes",
        "## Convergence history",
        "## Re-associations",
    ] {
        assert!(report.contains(section), "report.md lacks {section}");
    }
    // verbose: a line per step
    let verbose = geoslip().args(["-v", "run", "--out"]).arg(out.path().join("d")).arg(example()).output().unwrap();
    let text = String::from_utf8_lossy(&verbose.stderr).to_string() + &String::from_utf8_lossy(&verbose.stdout);
    assert!(text.matches("iterations").count() >= 5, "{text}");
}

/// The plots a run writes: the pull-out curve and the profiles along the reinforcement, as PNG and
/// SVG, with units on the axes, and embedded in report.md.
#[test]
fn a_run_writes_its_plots_and_embeds_them_in_the_report() {
    let out = tempfile::tempdir().unwrap();
    let status = geoslip().args(["-q", "run", "--out"]).arg(out.path()).arg(example()).status().unwrap();
    assert!(status.success());
    for stem in ["pullout", "profiles-grid"] {
        let png = std::fs::read(out.path().join(format!("{stem}.png"))).unwrap();
        assert!(png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 10_000, "{stem}.png is not a PNG image");
        let svg = std::fs::read_to_string(out.path().join(format!("{stem}.svg"))).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("</svg>"));
    }
    let svg = std::fs::read_to_string(out.path().join("pullout.svg")).unwrap();
    assert!(svg.contains("[kN/m]") && svg.contains("[m]"), "axis labels carry units");
    let profiles = std::fs::read_to_string(out.path().join("profiles-grid.svg")).unwrap();
    for label in ["T [kN/m]", "ux [m]", "τ [kPa]", "σn [kPa]"] {
        assert!(profiles.contains(label), "profiles lack {label}");
    }
    let report = std::fs::read_to_string(out.path().join("report.md")).unwrap();
    assert!(report.contains("(pullout.png)") && report.contains("(profiles-grid.png)"));
}

/// `geoslip calibrate` on the shipped example: the curves of examples/calibration/make_curves.py
/// (the softening law with Ks = 18 000 kPa/m, c = 12 kPa, φ = 31°, c_r = 6 kPa, φ_r = 23°, softening
/// slip 8 mm, 2 % noise) give those values back within 3 %, in the report, the law block and the
/// JSON; a peak-residual fit is refused with the reason (exit code 2).
#[test]
fn calibrate_fits_the_example_and_writes_the_law_to_paste() {
    let out = tempfile::tempdir().unwrap();
    let spec = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration/direct-shear.toml");
    let run = geoslip().arg("calibrate").arg(&spec).arg("--out").arg(out.path()).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("calibration.json")).unwrap()).unwrap();
    let truth = [
        ("shear_stiffness", 18_000.0),
        ("cohesion", 12.0),
        ("friction_angle", 31.0),
        ("residual_cohesion", 6.0),
        ("residual_friction_angle", 23.0),
        ("softening_slip", 0.008),
    ];
    for (name, value) in truth {
        let p = json["parameters"].as_array().unwrap().iter().find(|p| p["name"] == name).unwrap();
        let fitted = p["value"].as_f64().unwrap();
        assert!((fitted - value).abs() < 0.03 * value, "{name}: {fitted} against {value}");
    }
    let block = std::fs::read_to_string(out.path().join("interface-law.toml")).unwrap();
    assert!(block.contains("law = { type = \"softening\", shear_stiffness = "), "{block}");
    for f in ["calibration.md", "fitted-curves.png", "fitted-curves.svg"] {
        assert!(out.path().join(f).is_file(), "{f}");
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration/direct-shear.csv"),
        dir.path().join("direct-shear.csv"),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("c.toml"),
        "test = \"direct-shear\"\ndata = \"direct-shear.csv\"\nlaw = \"peak-residual\"\n",
    )
    .unwrap();
    let refused = geoslip().arg("calibrate").arg(dir.path().join("c.toml")).output().unwrap();
    assert_eq!(refused.status.code(), Some(2));
    let message = String::from_utf8_lossy(&refused.stderr);
    assert!(message.contains("c.toml: law: the peak-residual law drops at once"), "{message}");
}

/// `run --restart RESULTS --from STAGE:STEP` (docs/model-format.md, "Continuing a run"): the
/// continued run's history is the straight run's from the step after STAGE:STEP on, as the same
/// text; a missing step, a changed model and the results folder itself as `--out` are refused with
/// exit code 2, naming the file.
#[test]
fn a_run_continues_from_a_saved_step() {
    let dir = tempfile::tempdir().unwrap();
    let (straight, continued) = (dir.path().join("straight"), dir.path().join("continued"));
    let status =
        geoslip().args(["run", "-q", "--solver", "faer", "--out"]).arg(&straight).arg(example()).status().unwrap();
    assert!(status.success());
    assert!(straight.join("restart/stage-2-step-00002.bin").is_file(), "no saved steps in restart/");
    let run = |from: &str, out: &Path| {
        geoslip()
            .args(["run", "-q", "--solver", "faer", "--restart"])
            .arg(&straight)
            .args(["--from", from, "--out"])
            .arg(out)
            .arg(example())
            .output()
            .unwrap()
    };
    let done = run("2:2", &continued);
    assert!(done.status.success(), "{}", String::from_utf8_lossy(&done.stderr));
    let history = |d: &Path| std::fs::read_to_string(d.join("history.csv")).unwrap();
    let (a, b) = (history(&straight), history(&continued));
    let rows_a: Vec<&str> = a.lines().collect();
    let rows_b: Vec<&str> = b.lines().collect();
    // the header, then the straight run's rows after stage 2 step 2 (one stage-1 step, two of stage 2)
    assert_eq!(rows_b[0], rows_a[0]);
    assert_eq!(&rows_b[1..], &rows_a[4..], "the continued history differs from the straight run's");
    let report = std::fs::read_to_string(continued.join("report.md")).unwrap();
    assert!(report.contains("continued from step 2 of stage"), "{report}");

    let missing = run("2:99", &dir.path().join("missing"));
    assert_eq!(missing.status.code(), Some(2));
    let message = String::from_utf8_lossy(&missing.stderr);
    assert!(message.contains("stage-2-step-00099.bin") && message.contains("no saved step 2:99"), "{message}");

    let itself = run("2:2", &straight);
    assert_eq!(itself.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&itself.stderr).contains("would replace these results"));
}
