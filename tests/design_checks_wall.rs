//! The design checks read the wall a model builds and set the analysis's tensions beside the
//! methods.
//!
//! Reference: the geometry of the wall as it is built in tests/fuzz-seeds/design-wall.toml
//! (docs/verification.md §12): a fill 3 m wide and 1.5 m high with its face at x = 0, two geogrids
//! 2 m long at y = 0.5 and 1.0 m, a 10 kPa surcharge on the crest. So H = 1.5 m; the layers lie at
//! Z = 1.0 and 0.5 m below the crest; the tributary zones of FHWA-NHI-10-025 Table E4-7.1 run from
//! the crest to 0.75 m and from 0.75 m to the base; L = 2 m; q = 10 kPa read from the crest's edge
//! traction. The methods themselves are checked against the manual's worked examples
//! (design_checks_fhwa_e1.rs, design_checks_fhwa_e4.rs). The run's `design-checks.csv` must give
//! each layer's largest bar tension of the last step, and the report its section and figure.

use geoslip::analysis::Collect;
use geoslip::model::Model;
use std::path::Path;

/// The wall's model file (also a seed of the model fuzzer), with its `[design]` table replaced by
/// `design` when one is given.
fn wall_model(design: Option<&str>) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-seeds/design-wall.toml");
    let text = std::fs::read_to_string(path).unwrap();
    match design {
        None => text,
        Some(table) => {
            format!("{}[design]\n{table}\n", &text[..text.find("[design]").expect("the seed has a [design] table")])
        }
    }
}

fn load(text: &str) -> Result<Model, geoslip::Error> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wall.toml");
    std::fs::write(&path, text).unwrap();
    Model::load(&path)
}

#[test]
fn the_wall_is_read_from_the_model() {
    let model = load(&wall_model(None)).unwrap_or_else(|e| panic!("{e}"));
    let wall = model.design.as_ref().expect("the model has a [design] table");
    assert!((wall.height() - 1.5).abs() < 1e-12 && wall.face_x.abs() < 1e-12, "{wall:?}");
    assert!((wall.surcharge - 10.0).abs() < 1e-12, "q = {} from {}", wall.surcharge, wall.surcharge_source);
    let expected = [("grid-1", 1.0, 0.75, 1.5), ("grid-2", 0.5, 0.0, 0.75)];
    assert_eq!(wall.layers.len(), 2);
    for (layer, (name, depth, top, bottom)) in wall.layers.iter().zip(expected) {
        assert_eq!(layer.name, name);
        assert!((layer.depth - depth).abs() < 1e-12, "{layer:?}");
        assert!((layer.zone_top - top).abs() < 1e-12 && (layer.zone_bottom - bottom).abs() < 1e-12, "{layer:?}");
        assert!((layer.length - 2.0).abs() < 1e-12, "{layer:?}");
    }
}

#[test]
fn the_report_sets_the_analysis_beside_the_methods() {
    let model = load(&wall_model(None)).unwrap_or_else(|e| panic!("{e}"));
    let out = tempfile::tempdir().unwrap();
    let mut steps = Collect::default();
    geoslip::output::run_and_write(&model, out.path(), &Default::default(), &mut steps)
        .unwrap_or_else(|e| panic!("{e}"));
    let (_, last) = steps.steps.last().expect("the run has steps");
    let csv = std::fs::read_to_string(out.path().join("design-checks.csv")).unwrap();
    let mut rows = csv.lines();
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let column =
        |name: &str| header.iter().position(|h| h.starts_with(name)).unwrap_or_else(|| panic!("{name}: {csv}"));
    let (name, fe) = (column("layer"), column("T_max analysis"));
    let mut seen = 0;
    for row in rows {
        let cells: Vec<&str> = row.split(',').collect();
        let y = if cells[name] == "grid-1" { 0.5 } else { 1.0 };
        let largest = last
            .bar_forces
            .iter()
            .filter(|b| (b.midpoint[1] - y).abs() < 1e-9)
            .map(|b| b.axial_force)
            .fold(f64::MIN, f64::max);
        let t: f64 = cells[fe].parse().unwrap();
        assert!(largest > 0.0 && (t - largest).abs() <= 1e-12 * largest, "{}: {t} against {largest}", cells[name]);
        seen += 1;
    }
    assert_eq!(seen, 2, "{csv}");
    let report = std::fs::read_to_string(out.path().join("report.md")).unwrap();
    assert!(report.contains("## Design checks") && report.contains("| grid-2 |"), "{report}");
    assert!(out.path().join("design-checks.png").is_file());
}

#[test]
fn a_design_table_that_does_not_fit_the_model_is_named() {
    let cases = [
        (
            "reinforced_soil = \"backfill\"\nreinforcement = \"geogrid\"",
            "design.reinforced_soil",
            "is not a soil material",
        ),
        ("reinforced_soil = \"fill\"\nreinforcement = \"bar-mat\"", "design.reinforcement", "transverse_bar_thickness"),
        (
            "reinforced_soil = \"fill\"\nreinforcement = \"geogrid\"\nscale_correction = 1.5",
            "design.scale_correction",
            "is 1.5",
        ),
        (
            "reinforced_soil = \"fill\"\nreinforcement = \"geogrid\"\n\n[analysis]\ngeometry = \"axisymmetric\"",
            "design",
            "this model is axisymmetric",
        ),
    ];
    for (table, field, message) in cases {
        let err = load(&wall_model(Some(table))).err().expect("refused").to_string();
        assert!(err.contains(field) && err.contains(message), "{err}");
    }
}

#[test]
fn check_prints_the_wall_as_read() {
    let seed = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-seeds/design-wall.toml");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_geoslip")).arg("check").arg(&seed).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("design checks: a geogrid wall of `fill`, H = 1.5000")
            && text.contains("surcharge 10 (from the model's edge tractions on the crest)")
            && text.contains(
                "grid-2 (Z = 0.5000, Svt = 0.7500, L = 2.0000), grid-1 (Z = 1.0000, Svt = 0.7500, L = 2.0000)"
            ),
        "{text}"
    );
}
