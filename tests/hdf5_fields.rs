//! `results.h5` holds every field of every step exactly as the run computed it: the paper's pull-out
//! test in clay is run through the library (`output::run_and_write`) with every step kept in
//! memory (`analysis::sink::Collect`), and the HDF5 file is read back with the hdf5 crate, every
//! dataset of every step compared with the in-memory `StepResults`: with `--field-precision double`
//! f64 for f64 (`==`); by default (single) each field value stored as a 4-byte float equal to the
//! computed value rounded to the nearest f32 (`==`), the mesh and the history f64 for f64 either
//! way.
//!
//! Reference: docs/results.md (the layout of `results.h5`) and the XDMF model (xdmf.org, "XDMF
//! Model and Format": Topology, Geometry, Attribute): each grid's cells and points as the mesh and
//! the interface have them, the soil's cell values the element averages of its Gauss points
//! (symmetric tensors in VTK's order xx, yy, zz, xy, yz, xz; the shear strain as εxy = γxy/2),
//! the history one entry per step. Yi (1996), Figs. 7–10: 61 steps, a surcharge then a 60 mm pull,
//! with slip starting at 11 mm and the whole grid sliding at 44 mm, so that every interface state
//! code appears.
#![cfg(feature = "hdf5")]

use geoslip::analysis::results::StepResults;
use geoslip::analysis::{Collect, StepRecord};
use geoslip::model::Model;
use geoslip::output::options::FieldPrecision;
use geoslip::output::OutputOptions;
use std::collections::{BTreeSet, HashMap};
use std::path::Path;

fn read<T: hdf5::H5Type>(file: &hdf5::File, path: &str) -> (Vec<T>, Vec<usize>) {
    let d = file.dataset(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    (d.read_raw::<T>().unwrap_or_else(|e| panic!("{path}: {e}")), d.shape())
}

/// The dataset `path`, which must be `expected` (rows of `columns` values) value for value.
fn assert_exactly<T: hdf5::H5Type + PartialEq + std::fmt::Debug>(
    file: &hdf5::File,
    path: &str,
    expected: &[T],
    columns: usize,
) {
    let (values, shape) = read::<T>(file, path);
    let rows = expected.len() / columns;
    let expected_shape = if columns == 1 { vec![rows] } else { vec![rows, columns] };
    assert_eq!(shape, expected_shape, "{path}: shape");
    for (i, (a, b)) in values.iter().zip(expected).enumerate() {
        assert!(a == b, "{path}[{}][{}]: {a:?} in the file, {b:?} computed", i / columns, i % columns);
    }
}

/// The step field `path`, which must be `computed` as the run's `precision` stores it: the values
/// themselves in double precision, each rounded to the nearest f32 in single.
fn assert_field(file: &hdf5::File, path: &str, computed: &[f64], columns: usize, precision: FieldPrecision) {
    let size = file.dataset(path).unwrap().dtype().unwrap().size();
    let stored: Vec<f64> = match precision {
        FieldPrecision::Double => {
            assert_eq!(size, 8, "{path}: 8-byte floats");
            computed.to_vec()
        }
        FieldPrecision::Single => {
            assert_eq!(size, 4, "{path}: 4-byte floats");
            computed.iter().map(|&v| v as f32 as f64).collect()
        }
    };
    assert_exactly(file, path, &stored, columns);
}

/// The names of the datasets (and links) in group `path`.
fn members(file: &hdf5::File, path: &str) -> BTreeSet<String> {
    file.group(path).unwrap().member_names().unwrap().into_iter().collect()
}

fn names(list: &[&str]) -> BTreeSet<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// The soil fields of one step, each element's values summed over its Gauss points and divided by
/// their number: (element index, stress, strain, pore pressure, plastic fraction, plastic strain).
fn soil_averages(model: &Model, r: &StepResults) -> Vec<(usize, [f64; 6], [f64; 6], f64, f64, f64)> {
    let index: HashMap<u64, usize> = model.mesh.solids.iter().enumerate().map(|(i, s)| (s.id, i)).collect();
    let mut sums: Vec<Option<([f64; 4], [f64; 3], f64, f64, f64, usize)>> = vec![None; model.mesh.solids.len()];
    for g in r.stresses(&model) {
        let e = sums[index[&g.element]].get_or_insert(([0.0; 4], [0.0; 3], 0.0, 0.0, 0.0, 0));
        for k in 0..4 {
            e.0[k] += g.stress[k];
        }
        e.1[0] += g.strain[0];
        e.1[1] += g.strain[1];
        e.1[2] += 0.5 * g.strain[2];
        e.2 += g.pore_pressure;
        e.3 += if g.yield_state.is_plastic() { 1.0 } else { 0.0 };
        e.4 += g.plastic_strain;
        e.5 += 1;
    }
    sums.iter()
        .enumerate()
        .filter_map(|(i, s)| {
            let (s, e, p, y, ps, n) = (*s)?;
            let n = n as f64;
            let (xx, yy, xy, zz) = (s[0] / n, s[1] / n, s[2] / n, s[3] / n);
            let (exx, eyy, exy) = (e[0] / n, e[1] / n, e[2] / n);
            Some((i, [xx, yy, zz, xy, 0.0, 0.0], [exx, eyy, 0.0, exy, 0.0, 0.0], p / n, y / n, ps / n))
        })
        .collect()
}

fn check_step(
    file: &hdf5::File,
    model: &Model,
    time: usize,
    record: &StepRecord,
    r: &StepResults,
    precision: FieldPrecision,
) {
    let step = format!("steps/{time:04}");
    let g = file.group(&step).unwrap();
    let stage: hdf5::types::VarLenUnicode = g.attr("stage").unwrap().read_scalar().unwrap();
    assert_eq!(stage.as_str(), record.stage);
    assert_eq!(g.attr("stage_step").unwrap().read_scalar::<u64>().unwrap(), record.step as u64);
    assert_eq!(g.attr("load_factor").unwrap().read_scalar::<f64>().unwrap(), record.load_factor);
    let mesh = &model.mesh;
    let node_index: HashMap<u64, usize> = mesh.nodes.iter().enumerate().map(|(i, n)| (n.id, i)).collect();
    let u = |id: u64| -> [f64; 3] {
        let (_, _, d) = r.displacements[node_index[&id]];
        [d[0], d[1], 0.0]
    };

    // soil: every mesh node; the elements present in this step
    let soil = format!("{step}/soil");
    let expected = names(&[
        "displacement",
        "element_id",
        "geometry",
        "material",
        "plastic_fraction",
        "plastic_strain",
        "pore_pressure",
        "strain",
        "stress",
        "topology",
    ]);
    assert_eq!(members(file, &soil), expected, "{soil}");
    let x: Vec<f64> = mesh.nodes.iter().flat_map(|n| [n.x[0], n.x[1], 0.0]).collect();
    assert_exactly(file, &format!("{soil}/geometry"), &x, 3);
    let disp: Vec<f64> = mesh.nodes.iter().flat_map(|n| u(n.id)).collect();
    assert_field(file, &format!("{soil}/displacement"), &disp, 3, precision);
    let averages = soil_averages(model, r);
    assert!(!averages.is_empty());
    let cells: Vec<i64> =
        averages.iter().flat_map(|a| mesh.solids[a.0].nodes.iter().map(|&n| n as i64)).collect::<Vec<_>>();
    assert_exactly(file, &format!("{soil}/topology"), &cells, mesh.solids[averages[0].0].nodes.len());
    let ids: Vec<u64> = averages.iter().map(|a| mesh.solids[a.0].id).collect();
    assert_exactly(file, &format!("{soil}/element_id"), &ids, 1);
    let material: Vec<i32> = averages.iter().map(|a| mesh.solids[a.0].material as i32).collect();
    assert_exactly(file, &format!("{soil}/material"), &material, 1);
    assert_field(file, &format!("{soil}/stress"), &averages.iter().flat_map(|a| a.1).collect::<Vec<_>>(), 6, precision);
    assert_field(file, &format!("{soil}/strain"), &averages.iter().flat_map(|a| a.2).collect::<Vec<_>>(), 6, precision);
    assert_field(
        file,
        &format!("{soil}/pore_pressure"),
        &averages.iter().map(|a| a.3).collect::<Vec<_>>(),
        1,
        precision,
    );
    assert_field(
        file,
        &format!("{soil}/plastic_fraction"),
        &averages.iter().map(|a| a.4).collect::<Vec<_>>(),
        1,
        precision,
    );
    assert_field(
        file,
        &format!("{soil}/plastic_strain"),
        &averages.iter().map(|a| a.5).collect::<Vec<_>>(),
        1,
        precision,
    );

    // reinforcement: the bars' nodes in order of first appearance, one line per bar
    let bars = format!("{step}/reinforcement");
    let expected = names(&["axial_force", "bar_id", "displacement", "geometry", "state", "topology"]);
    assert_eq!(members(file, &bars), expected, "{bars}");
    let mut nodes: Vec<u64> = Vec::new();
    for b in &r.bar_forces {
        for n in b.nodes {
            if !nodes.contains(&n) {
                nodes.push(n);
            }
        }
    }
    let x: Vec<f64> = nodes.iter().flat_map(|id| mesh.nodes[node_index[id]].x.into_iter().chain([0.0])).collect();
    assert_exactly(file, &format!("{bars}/geometry"), &x, 3);
    let lines: Vec<i64> =
        r.bar_forces.iter().flat_map(|b| b.nodes.map(|n| nodes.iter().position(|&m| m == n).unwrap() as i64)).collect();
    assert_exactly(file, &format!("{bars}/topology"), &lines, 2);
    assert_field(
        file,
        &format!("{bars}/displacement"),
        &nodes.iter().flat_map(|&n| u(n)).collect::<Vec<_>>(),
        3,
        precision,
    );
    let force: Vec<f64> = r.bar_forces.iter().map(|b| b.axial_force).collect();
    assert_field(file, &format!("{bars}/axial_force"), &force, 1, precision);
    let state: Vec<i32> = r
        .bar_forces
        .iter()
        .map(|b| match b.state {
            "slack" => 1,
            "ruptured" => 2,
            _ => 0,
        })
        .collect();
    assert_exactly(file, &format!("{bars}/state"), &state, 1);
    assert_exactly(file, &format!("{bars}/bar_id"), &r.bar_forces.iter().map(|b| b.bar).collect::<Vec<_>>(), 1);

    // interface: one vertex per point, at its slave node
    let faces = format!("{step}/interface");
    let expected = names(&[
        "bearing",
        "dilation",
        "displacement",
        "face",
        "geometry",
        "lambda",
        "sigma_n",
        "slip",
        "state",
        "tau",
        "topology",
    ]);
    assert_eq!(members(file, &faces), expected, "{faces}");
    let p = &r.interface_points;
    let x: Vec<f64> = p.iter().flat_map(|p| mesh.nodes[node_index[&p.slave_node]].x.into_iter().chain([0.0])).collect();
    assert_exactly(file, &format!("{faces}/geometry"), &x, 3);
    assert_exactly(file, &format!("{faces}/topology"), &(0..p.len() as i64).collect::<Vec<_>>(), 1);
    assert_field(
        file,
        &format!("{faces}/displacement"),
        &p.iter().flat_map(|p| u(p.slave_node)).collect::<Vec<_>>(),
        3,
        precision,
    );
    assert_field(file, &format!("{faces}/lambda"), &p.iter().map(|p| p.lambda).collect::<Vec<_>>(), 1, precision);
    assert_field(file, &format!("{faces}/sigma_n"), &p.iter().map(|p| p.sigma_n).collect::<Vec<_>>(), 1, precision);
    assert_field(file, &format!("{faces}/tau"), &p.iter().map(|p| p.tau).collect::<Vec<_>>(), 1, precision);
    assert_field(file, &format!("{faces}/bearing"), &p.iter().map(|p| p.bearing).collect::<Vec<_>>(), 1, precision);
    assert_field(file, &format!("{faces}/dilation"), &p.iter().map(|p| p.dilation).collect::<Vec<_>>(), 1, precision);
    assert_field(file, &format!("{faces}/slip"), &p.iter().map(|p| p.slip).collect::<Vec<_>>(), 1, precision);
    // 0 stick, 1 slip, 2 open, 3 residual (docs/results.md)
    let state: Vec<i32> = p
        .iter()
        .map(|p| match (p.state, p.post_peak, p.sliding) {
            ("active" | "redundant", true, _) => 3,
            ("active" | "redundant", false, true) => 1,
            ("active" | "redundant", false, false) => 0,
            _ => 2,
        })
        .collect();
    assert_exactly(file, &format!("{faces}/state"), &state, 1);
    let mut seen: Vec<(&str, &str)> = Vec::new();
    let face: Vec<i32> = p
        .iter()
        .map(|p| {
            let key = (p.interface.as_str(), p.face.as_str());
            if !seen.contains(&key) {
                seen.push(key);
            }
            seen.iter().position(|k| *k == key).unwrap() as i32
        })
        .collect();
    assert_exactly(file, &format!("{faces}/face"), &face, 1);
    let names: Vec<hdf5::types::VarLenUnicode> = file.group(&faces).unwrap().attr("faces").unwrap().read_raw().unwrap();
    let names: Vec<&str> = names.iter().map(|n| n.as_str()).collect();
    let expected: Vec<String> = seen.iter().map(|(interface, face)| format!("{interface}:{face}")).collect();
    assert_eq!(names, expected, "{faces}: the faces' names");
}

#[test]
fn every_field_of_every_step_reads_back_from_results_h5_in_single_precision() {
    every_field_of_every_step_reads_back(FieldPrecision::Single);
}

#[test]
fn every_field_of_every_step_reads_back_from_results_h5_exactly_in_double_precision() {
    every_field_of_every_step_reads_back(FieldPrecision::Double);
}

fn every_field_of_every_step_reads_back(precision: FieldPrecision) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/paper-pullout-clay.toml");
    let model = Model::load(&path).unwrap();
    let out = tempfile::tempdir().unwrap();
    let mut steps = Collect::default();
    let options = OutputOptions { precision, ..OutputOptions::default() };
    geoslip::output::run_and_write(&model, out.path(), &options, &mut steps).unwrap();
    assert_eq!(steps.steps.len(), 61);

    let file = hdf5::File::open(out.path().join("results.h5")).unwrap();
    let kept = members(&file, "steps");
    assert_eq!(kept.len(), steps.steps.len(), "every step kept by default");
    let mut states = BTreeSet::new();
    for (k, (record, r)) in steps.steps.iter().enumerate() {
        check_step(&file, &model, k + 1, record, r, precision);
        states.extend(r.interface_points.iter().map(|p| (p.state, p.sliding)));
    }
    assert!(states.contains(&("active", true)) && states.contains(&("active", false)), "{states:?}");
    // the writer thread's CPU time, in the summary: some, and no more than the run and the
    // writer's end took
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("summary.json")).unwrap()).unwrap();
    let writer = summary["writer_thread_seconds"].as_f64().expect("the writer thread's CPU time");
    let total = summary["total_seconds"].as_f64().unwrap() + summary["write_seconds"].as_f64().unwrap();
    assert!(writer > 0.0 && writer < total, "writer thread {writer} s in a run and its writing of {total} s");

    // the history: one entry per step, and the pulled head's mean displacement and total reaction
    let n = steps.steps.len();
    let time: Vec<u64> = (1..=n as u64).collect();
    assert_exactly(&file, "history/time", &time, 1);
    let stage: Vec<u64> = steps.steps.iter().map(|(s, _)| s.stage_index as u64 + 1).collect();
    assert_exactly(&file, "history/stage", &stage, 1);
    assert_exactly(&file, "history/stage_step", &steps.steps.iter().map(|(s, _)| s.step as u64).collect::<Vec<_>>(), 1);
    assert_exactly(
        &file,
        "history/load_factor",
        &steps.steps.iter().map(|(s, _)| s.load_factor).collect::<Vec<_>>(),
        1,
    );
    assert_eq!(members(&file, "history"), names(&["grid.head (x)", "load_factor", "stage", "stage_step", "time"]));
    let head = model.node_set("grid.head").unwrap();
    let (u, _) = read::<f64>(&file, "history/grid.head (x)/displacement");
    let (f, _) = read::<f64>(&file, "history/grid.head (x)/reaction");
    assert_eq!((u.len(), f.len()), (n, n));
    for (k, (_, r)) in steps.steps.iter().enumerate() {
        let mean_u = head.iter().map(|&i| r.displacement_vector[2 * i]).sum::<f64>() / head.len() as f64;
        let reaction: f64 = head.iter().map(|&i| r.reaction_vector[2 * i]).sum();
        assert!((u[k] - mean_u).abs() <= 1e-14 * (1.0 + mean_u.abs()), "step {}: u {} against {mean_u}", k + 1, u[k]);
        assert!(
            (f[k] - reaction).abs() <= 1e-12 * (1.0 + reaction.abs()),
            "step {}: {} against {reaction}",
            k + 1,
            f[k]
        );
    }
}
