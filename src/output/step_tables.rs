//! A kept step's fields as CSV files (`geoslip run --csv`): displacements, reactions, bar forces,
//! interface points and Gauss-point stresses, each with its units in the header.

use super::folder::{csv_bytes, num};
use super::grids;
use crate::analysis::results::{ElementStress, StepResults};
use crate::model::UnitLabels;

/// The step's tables, by their file names in the step's folder.
pub(super) fn step_files(units: &UnitLabels, r: &StepResults, stresses: &[ElementStress]) -> Vec<(String, Vec<u8>)> {
    let mut files = Vec::with_capacity(5);
    let u = units;
    let (l, f, s) = (u.length, u.force_per_width.as_str(), u.stress.as_str());
    let h = |names: &[String]| names.to_vec();
    files.push((
        "displacements.csv".to_string(),
        csv_bytes(
            &h(&["node".into(), format!("x [{l}]"), format!("y [{l}]"), format!("ux [{l}]"), format!("uy [{l}]")]),
            r.displacements.iter().map(|(id, x, d)| vec![id.to_string(), num(x[0]), num(x[1]), num(d[0]), num(d[1])]),
        ),
    ));
    let opt = |v: Option<f64>| v.map(num).unwrap_or_default();
    files.push((
        "reactions.csv".to_string(),
        csv_bytes(
            &h(&["node".into(), format!("rx [{f}]"), format!("ry [{f}]")]),
            r.reactions.iter().map(|re| vec![re.node.to_string(), opt(re.rx), opt(re.ry)]),
        ),
    ));
    files.push((
        "bar_forces.csv".to_string(),
        csv_bytes(
            &h(&[
                "bar".into(),
                "node_a".into(),
                "node_b".into(),
                format!("x_mid [{l}]"),
                format!("y_mid [{l}]"),
                format!("T [{f}]"),
                "state".into(),
            ]),
            r.bar_forces.iter().map(|b| {
                vec![
                    b.bar.to_string(),
                    b.nodes[0].to_string(),
                    b.nodes[1].to_string(),
                    num(b.midpoint[0]),
                    num(b.midpoint[1]),
                    num(b.axial_force),
                    b.state.to_string(),
                ]
            }),
        ),
    ));
    files.push((
        "interface.csv".to_string(),
        csv_bytes(
            &h(&[
                "interface".into(),
                "face".into(),
                "slave_node".into(),
                format!("x [{l}]"),
                format!("y [{l}]"),
                "master_a".into(),
                "master_b".into(),
                "xi [-]".into(),
                "state".into(),
                format!("tributary [{}]", u.tributary),
                format!("lambda [{f}]"),
                format!("sigma_n [{s}]"),
                format!("tau [{s}]"),
                format!("bearing [{s}]"),
                format!("dilation [{l}]"),
                format!("slip [{l}]"),
                "contact".into(),
            ]),
            r.interface_points.iter().map(|p| {
                vec![
                    p.interface.clone(),
                    p.face.clone(),
                    p.slave_node.to_string(),
                    num(p.x[0]),
                    num(p.x[1]),
                    p.master_nodes[0].to_string(),
                    p.master_nodes[1].to_string(),
                    num(p.xi),
                    p.state.to_string(),
                    num(p.tributary),
                    num(p.lambda),
                    num(p.sigma_n),
                    num(p.tau),
                    num(p.bearing),
                    num(p.dilation),
                    num(p.slip),
                    grids::contact_name(grids::interface_state_code(p.state, p.sliding, p.post_peak)).to_string(),
                ]
            }),
        ),
    ));
    files.push((
        "stresses.csv".to_string(),
        csv_bytes(
            &h(&[
                "element".into(),
                "gauss_point".into(),
                format!("x [{l}]"),
                format!("y [{l}]"),
                format!("sxx [{s}]"),
                format!("syy [{s}]"),
                format!("sxy [{s}]"),
                format!("szz [{s}]"),
                format!("pore_pressure [{s}]"),
                "yield".into(),
                "plastic_strain".into(),
            ]),
            stresses.iter().map(|e| {
                vec![
                    e.element.to_string(),
                    e.point.to_string(),
                    num(e.x[0]),
                    num(e.x[1]),
                    num(e.stress[0]),
                    num(e.stress[1]),
                    num(e.stress[2]),
                    num(e.stress[3]),
                    num(e.pore_pressure),
                    e.yield_state.name().to_string(),
                    num(e.plastic_strain),
                ]
            }),
        ),
    ));
    files
}
