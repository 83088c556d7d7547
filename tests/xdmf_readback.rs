//! `results.xdmf` read back by an independent reader: meshio's XDMF `TimeSeriesReader` (Debian's
//! python3-meshio, over h5py and the HDF5 library), not by geoslip's writer crate. It lists every
//! step of the run, at times 1, 2, … (the steps' numbers, as in `summary.json`), and the soil
//! displacement it reads for each step is the one `--csv` wrote to the step's `displacements.csv` in
//! the same run (to the single precision the file holds it in); the reinforcement and interface
//! collections (read with ElementTree and h5py) list
//! the same steps, with one value per bar and per interface point.
//!
//! Reference: the XDMF model (xdmf.org, "XDMF Model and Format": a Temporal collection of Uniform
//! grids, each with its Time, Topology, Geometry and Attributes, heavy data in HDF5), and
//! docs/verification.md §5: in the annotated example's first stage the oedometric
//! normal stress on the grid is q + γz = 20 + 19·0.2 = 23.8 kPa on both faces, which the interface
//! collection must carry as `sigma_n`.
//!
//! This test needs /usr/bin/python3 with meshio and h5py (scripts/test-all.sh installs
//! python3-meshio and python3-h5py); without them it fails, saying so.
#![cfg(feature = "hdf5")]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const READER: &str = r#"
import json, os, sys
import xml.etree.ElementTree as ET
import h5py
import meshio

out = sys.argv[1]
index = os.path.join(out, "results.xdmf")
result = {"soil": [], "collections": {}}
with meshio.xdmf.TimeSeriesReader(index) as reader:
    points, cells = reader.read_points_cells()
    result["points"] = points.tolist()
    result["cells"] = [[c.type, len(c.data)] for c in cells]
    for k in range(reader.num_steps):
        t, point_data, cell_data = reader.read_data(k)
        result["soil"].append({"time": t, "displacement": point_data["displacement"].tolist(),
                               "stress_components": int(cell_data["stress"][0].shape[1])})
root = ET.parse(index).getroot()
with h5py.File(os.path.join(out, "results.h5"), "r") as f:
    for collection in root.find("Domain"):
        steps = []
        for grid in collection:
            fields = {}
            for attribute in grid.findall("Attribute"):
                name, path = attribute.find("DataItem").text.strip().split(":")
                fields[attribute.get("Name") + "@" + attribute.get("Center")] = f[path][()].tolist()
            topology = grid.find("Topology")
            steps.append({"time": float(grid.find("Time").get("Value")), "cells": int(topology.get("NumberOfElements")),
                          "type": topology.get("TopologyType"), "fields": fields})
        result["collections"][collection.get("Name")] = steps
json.dump(result, sys.stdout)
"#;

fn python_with_meshio() -> PathBuf {
    let python = PathBuf::from("/usr/bin/python3");
    let ok = Command::new(&python).args(["-c", "import meshio, h5py"]).output().is_ok_and(|o| o.status.success());
    assert!(
        ok,
        "no /usr/bin/python3 with meshio and h5py: install python3-meshio and python3-h5py (scripts/test-all.sh does)"
    );
    python
}

fn csv(path: &Path) -> Vec<HashMap<String, String>> {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let headers: Vec<String> = r.headers().unwrap().iter().map(|h| h.split(" [").next().unwrap().to_string()).collect();
    r.records().map(|rec| headers.iter().cloned().zip(rec.unwrap().iter().map(str::to_string)).collect()).collect()
}

fn f(row: &HashMap<String, String>, key: &str) -> f64 {
    row[key].parse().unwrap_or_else(|_| panic!("{key} = {}", row[key]))
}

#[test]
fn meshio_reads_every_step_of_results_xdmf_and_the_displacements_match_the_csv_files() {
    let out = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/annotated-pullout.toml");
    let status = Command::new(env!("CARGO_BIN_EXE_geoslip"))
        .args(["run", "-q", "--csv", "--solver", "dense", "--out"])
        .arg(out.path())
        .arg(&model)
        .status()
        .unwrap();
    assert!(status.success());
    let read = Command::new(python_with_meshio()).args(["-c", READER]).arg(out.path()).output().unwrap();
    assert!(read.status.success(), "meshio could not read results.xdmf: {}", String::from_utf8_lossy(&read.stderr));
    let data: serde_json::Value = serde_json::from_slice(&read.stdout).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("summary.json")).unwrap()).unwrap();
    let records = summary["steps"].as_array().unwrap();
    assert_eq!(records.len(), 5);

    // the soil, through meshio: one quad per element, every step at its number
    assert_eq!(data["cells"], serde_json::json!([["quad", 8]]));
    let points = data["points"].as_array().unwrap();
    let soil = data["soil"].as_array().unwrap();
    assert_eq!(soil.len(), records.len(), "meshio reads every step");
    for (k, record) in records.iter().enumerate() {
        let step = &soil[k];
        assert_eq!(step["time"].as_f64().unwrap(), (k + 1) as f64, "step {} at time {}", k + 1, step["time"]);
        assert_eq!(step["stress_components"], 6, "stress as a symmetric tensor, six components");
        let dir = out.path().join(format!(
            "stage-{}-{}/step-{:03}",
            record["stage_index"].as_u64().unwrap() + 1,
            record["stage"].as_str().unwrap().replace(' ', "-"),
            record["step"].as_u64().unwrap()
        ));
        let rows = csv(&dir.join("displacements.csv"));
        let disp = step["displacement"].as_array().unwrap();
        assert_eq!(disp.len(), rows.len(), "one point per node");
        for (i, row) in rows.iter().enumerate() {
            let close = |a: &serde_json::Value, b: f64, what: &str| {
                let a = a.as_f64().unwrap();
                // the CSV holds 11 significant digits; a field of results.h5 is in single precision
                // by default (each value rounded to the nearest f32: a relative error ≤ 2⁻²⁴)
                let single = if what.starts_with('u') { 2f64.powi(-24) * b.abs() } else { 0.0 };
                assert!(
                    (a - b).abs() <= 1e-9 * (1.0 + b.abs()) + single,
                    "step {} node {}: {what} {a} in the XDMF, {b} in the CSV",
                    k + 1,
                    row["node"]
                );
            };
            close(&points[i][0], f(row, "x"), "x");
            close(&points[i][1], f(row, "y"), "y");
            close(&disp[i][0], f(row, "ux"), "ux");
            close(&disp[i][1], f(row, "uy"), "uy");
            assert_eq!(disp[i][2], 0.0);
        }
    }

    // the other collections list the same steps
    let collections = &data["collections"];
    assert_eq!(
        collections.as_object().unwrap().keys().collect::<Vec<_>>(),
        ["interface", "reinforcement", "soil"],
        "three collections"
    );
    for name in ["reinforcement", "interface"] {
        let times: Vec<f64> =
            collections[name].as_array().unwrap().iter().map(|s| s["time"].as_f64().unwrap()).collect();
        assert_eq!(times, [1.0, 2.0, 3.0, 4.0, 5.0], "{name}");
    }
    for (k, step) in collections["reinforcement"].as_array().unwrap().iter().enumerate() {
        assert_eq!(step["type"], "Polyline");
        assert_eq!(step["cells"], 4, "four bars");
        assert_eq!(step["fields"]["axial_force@Cell"].as_array().unwrap().len(), 4, "step {}", k + 1);
    }
    for (k, step) in collections["interface"].as_array().unwrap().iter().enumerate() {
        assert_eq!(step["type"], "Polyvertex");
        let sigma_n = step["fields"]["sigma_n@Node"].as_array().unwrap();
        assert_eq!(sigma_n.len(), 15, "one vertex per interface point");
        assert_eq!(step["fields"]["face@Cell"], step["fields"]["face@Node"], "a vertex's face is its point's");
        if k == 0 {
            // the closed form: oedometric σn on the grid's points that lie fully in the soil
            let rows = csv(&out.path().join("stage-1-self-weight-and-surcharge/step-001/interface.csv"));
            for (i, row) in rows.iter().enumerate() {
                let x = f(row, "x");
                if row["interface"] == "grid" && x > 0.15 && x < 0.55 {
                    let s = sigma_n[i].as_f64().unwrap();
                    assert!((s - 23.8).abs() < 0.01 * 23.8, "σn = {s} at x = {x}");
                }
            }
        }
    }
}
