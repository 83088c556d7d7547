//! ParaView output read back by VTK itself (Debian's python3-vtk9: vtkXMLUnstructuredGridReader),
//! not by geoslip's writer crate: the `.pvd` lists every step's three grids, and the fields match
//! the step's CSV files value for value.
//!
//! Reference: the VTK file formats (VTK User's Guide, "VTK File Formats": XML UnstructuredGrid and
//! the ParaView Collection), and docs/verification.md §5: in the annotated example's
//! first stage the oedometric normal stress on the grid is q + γz = 20 + 19·0.2 = 23.8 kPa on both
//! faces, which the interface grid must carry as `sigma_n`.
//!
//! This test needs a Python 3 with the `vtk` module (scripts/test-all.sh installs python3-vtk9).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const READER: &str = r#"
import json, sys, os
import xml.etree.ElementTree as ET
import vtk

out = sys.argv[1]
pvd = ET.parse(os.path.join(out, "results.pvd")).getroot()
steps = {}
for ds in pvd.iter("DataSet"):
    steps.setdefault(int(ds.get("timestep")), {})[int(ds.get("part"))] = ds.get("file")

def grid(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    def arrays(data):
        d = {}
        for i in range(data.GetNumberOfArrays()):
            a = data.GetArray(i)
            n, c = a.GetNumberOfTuples(), a.GetNumberOfComponents()
            d[a.GetName()] = [list(a.GetTuple(k)) for k in range(n)]
        return d
    return {
        "points": [list(g.GetPoint(i)) for i in range(g.GetNumberOfPoints())],
        "cell_types": [g.GetCellType(i) for i in range(g.GetNumberOfCells())],
        "cells": [[g.GetCell(i).GetPointId(k) for k in range(g.GetCell(i).GetNumberOfPoints())] for i in range(g.GetNumberOfCells())],
        "point_data": arrays(g.GetPointData()),
        "cell_data": arrays(g.GetCellData()),
    }

result = {str(t): {str(p): grid(os.path.join(out, f)) for p, f in parts.items()} for t, parts in steps.items()}
json.dump(result, sys.stdout)
"#;

fn python_with_vtk() -> PathBuf {
    for candidate in ["/usr/bin/python3", "python3"] {
        let ok = Command::new(candidate).args(["-c", "import vtk"]).output().is_ok_and(|o| o.status.success());
        if ok {
            return PathBuf::from(candidate);
        }
    }
    panic!("no Python 3 with the vtk module: install python3-vtk9 (scripts/test-all.sh does)");
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
fn vtk_reads_back_every_step_and_the_fields_match_the_csv_files() {
    let out = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/annotated-pullout.toml");
    let status = Command::new(env!("CARGO_BIN_EXE_geoslip"))
        .args(["run", "-q", "--csv", "--vtu", "--solver", "dense", "--out"])
        .arg(out.path())
        .arg(&model)
        .status()
        .unwrap();
    assert!(status.success());

    let read = Command::new(python_with_vtk()).args(["-c", READER]).arg(out.path()).output().unwrap();
    assert!(read.status.success(), "VTK reader failed: {}", String::from_utf8_lossy(&read.stderr));
    let steps: serde_json::Value = serde_json::from_slice(&read.stdout).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("summary.json")).unwrap()).unwrap();
    let records = summary["steps"].as_array().unwrap();
    assert_eq!(steps.as_object().unwrap().len(), records.len(), "the .pvd lists every step");

    let tuples = |v: &serde_json::Value| -> Vec<Vec<f64>> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|t| t.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect())
            .collect()
    };
    let close = |a: f64, b: f64, what: &str| {
        assert!((a - b).abs() <= 1e-9 * (1.0 + b.abs()), "{what}: VTK {a}, CSV {b}");
    };

    for (k, record) in records.iter().enumerate() {
        let step = &steps[(k + 1).to_string()];
        let stage_dir = format!(
            "stage-{}-{}",
            record["stage_index"].as_u64().unwrap() + 1,
            record["stage"].as_str().unwrap().replace(' ', "-")
        );
        let dir = out.path().join(stage_dir).join(format!("step-{:03}", record["step"].as_u64().unwrap()));

        // soil: VTK quads (type 9); displacement at each node, positions at the reference x
        let soil = &step["0"];
        assert!(soil["cell_types"].as_array().unwrap().iter().all(|t| t == 9), "quad4 cells");
        let points = tuples(&soil["points"]);
        let disp = tuples(&soil["point_data"]["displacement"]);
        let rows = csv(&dir.join("displacements.csv"));
        assert_eq!(points.len(), rows.len(), "one VTK point per node");
        for (i, row) in rows.iter().enumerate() {
            close(points[i][0], f(row, "x"), "x");
            close(points[i][1], f(row, "y"), "y");
            close(disp[i][0], f(row, "ux"), "ux");
            close(disp[i][1], f(row, "uy"), "uy");
        }
        // element-average stress as a symmetric tensor xx, yy, zz, xy, yz, xz
        let stress = tuples(&soil["cell_data"]["stress"]);
        let ids = tuples(&soil["cell_data"]["element_id"]);
        let mut sums: HashMap<u64, ([f64; 4], f64)> = HashMap::new();
        for row in csv(&dir.join("stresses.csv")) {
            let e = sums.entry(f(&row, "element") as u64).or_insert(([0.0; 4], 0.0));
            for (j, key) in ["sxx", "syy", "szz", "sxy"].iter().enumerate() {
                e.0[j] += f(&row, key);
            }
            e.1 += 1.0;
        }
        for (c, s) in stress.iter().enumerate() {
            let (sum, n) = sums[&(ids[c][0] as u64)];
            for j in 0..4 {
                close(s[j], sum[j] / n, "stress");
            }
        }

        // reinforcement: VTK lines (type 3) carrying the bar forces
        let bars = &step["1"];
        assert!(bars["cell_types"].as_array().unwrap().iter().all(|t| t == 3));
        let force = tuples(&bars["cell_data"]["axial_force"]);
        let rows = csv(&dir.join("bar_forces.csv"));
        assert_eq!(force.len(), rows.len());
        for (i, row) in rows.iter().enumerate() {
            close(force[i][0], f(row, "T"), "axial force");
        }

        // interface: one point per interface point, in interface.csv's order
        let interface = &step["2"];
        let rows = csv(&dir.join("interface.csv"));
        let pd = &interface["point_data"];
        let (sn, tau, slip, state) =
            (tuples(&pd["sigma_n"]), tuples(&pd["tau"]), tuples(&pd["slip"]), tuples(&pd["state"]));
        let (bearing, dilation) = (tuples(&pd["bearing"]), tuples(&pd["dilation"]));
        assert_eq!(sn.len(), rows.len());
        for (i, row) in rows.iter().enumerate() {
            close(sn[i][0], f(row, "sigma_n"), "sigma_n");
            close(tau[i][0], f(row, "tau"), "tau");
            close(bearing[i][0], f(row, "bearing"), "bearing");
            close(dilation[i][0], f(row, "dilation"), "dilation");
            close(slip[i][0], f(row, "slip"), "slip");
            let open = !matches!(row["state"].as_str(), "active" | "redundant");
            assert_eq!(state[i][0] == 2.0, open, "state code at point {i}: {}", row["state"]);
        }
        // lines join neighbouring points of one face
        for cell in interface["cells"].as_array().unwrap() {
            let c: Vec<usize> = cell.as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
            assert_eq!(rows[c[0]]["face"], rows[c[1]]["face"]);
        }

        // the closed form: oedometric σn on the grid after the first stage
        if k == 0 {
            for (i, row) in rows.iter().enumerate() {
                let x = f(row, "x");
                if row["interface"] == "grid" && x > 0.15 && x < 0.55 {
                    assert!((sn[i][0] - 23.8).abs() < 0.01 * 23.8, "σn = {} at x = {x}", sn[i][0]);
                }
            }
        }
    }
}

#[test]
fn every_file_the_pvd_names_exists_and_no_partial_file_is_left() {
    let out = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/pullout-box.toml");
    let status = Command::new(env!("CARGO_BIN_EXE_geoslip"))
        .args(["run", "-q", "--vtu", "--out"])
        .arg(out.path())
        .arg(&model)
        .status()
        .unwrap();
    assert!(status.success());
    let pvd = std::fs::read_to_string(out.path().join("results.pvd")).unwrap();
    let files: Vec<&str> = pvd.split("file=\"").skip(1).map(|s| s.split('"').next().unwrap()).collect();
    assert_eq!(files.len(), 3 * 6, "three grids for each of the six steps");
    for f in files {
        assert!(out.path().join(f).is_file(), "{f}");
    }
    for entry in std::fs::read_dir(out.path().join("vtk")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().to_string();
        assert!(name.ends_with(".vtu"), "stray file {name}");
    }
}
