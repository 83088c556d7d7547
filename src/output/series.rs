//! A test series: one run per value of a load (for example a pull-out test at three normal
//! stresses), summarised in `series.csv`, `series.json`, a plot of the peak force against the value
//! and `report.md`. For a pull-out series on a Coulomb-type interface, the peaks are fitted by
//! P = 2·L·(c_a + σ·tan φ_a) and the apparent friction angle φ_a is set against the input angle.
//!
//! With both faces of an extensible reinforcement at the same strength, the peak pull-out force is
//! 2·τp·L once the whole embedded length L slides (Yi 1996; docs/verification.md §2).

use super::{plots, OwnedFolder, TargetPeak};
use crate::error::Error;
use crate::model::{Model, UnitLabels};
use std::path::Path;

/// What one run of the series produced.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CaseOutcome {
    pub label: String,
    pub value: f64,
    /// The run's folder, relative to the series folder.
    pub folder: String,
    pub peaks: Vec<TargetPeak>,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
}

/// The pulled reinforcement and its interface's peak strength parameters.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PulloutReference {
    pub interface: String,
    /// The target whose peak is the pull-out force (`<interface>.head`).
    pub target: String,
    /// Embedded length at the start [length].
    pub embedded_length: f64,
    /// Input peak strength: τp = c + σn·tan φ.
    pub cohesion: f64,
    pub friction_angle_deg: f64,
}

impl PulloutReference {
    /// The reinforcement pulled by a `<name>.head` target of `model`, if its law has a peak strength.
    pub fn of(model: &Model, peaks: &[TargetPeak]) -> Option<PulloutReference> {
        for peak in peaks {
            let Some(name) = peak.label.strip_suffix(".head") else { continue };
            let Some(interface) = model.interfaces.iter().find(|i| i.name == name) else { continue };
            let Some(nodes) = model.node_set(&format!("{name}.reinforcement")) else { continue };
            // the closed form needs one law on both faces (no stack)
            let law = &interface.faces[0].law;
            if interface.faces.iter().any(|f| f.law != *law) || interface.faces.len() != 2 {
                continue;
            }
            let cohesion = law.peak_strength(0.0);
            let tan_phi = law.peak_strength(1.0) - cohesion;
            if !(tan_phi.is_finite() && cohesion.is_finite()) || law.is_tie() {
                continue;
            }
            let length: f64 = model
                .mesh
                .bars
                .iter()
                .filter(|b| nodes.contains(&b.nodes[0]) && nodes.contains(&b.nodes[1]))
                .map(|b| {
                    let (a, c) = (model.mesh.position(b.nodes[0]), model.mesh.position(b.nodes[1]));
                    (c[0] - a[0]).hypot(c[1] - a[1])
                })
                .sum();
            return Some(PulloutReference {
                interface: name.to_string(),
                target: peak.label.clone(),
                embedded_length: length,
                cohesion,
                friction_angle_deg: tan_phi.atan().to_degrees(),
            });
        }
        None
    }
}

/// The straight line P = a + b·σ through the peaks (least squares), and what it means.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Envelope {
    pub intercept: f64,
    pub slope: f64,
    /// tan φ_a = b / 2L.
    pub apparent_friction_angle_deg: f64,
    /// c_a = a / 2L; it includes the weight of the soil above the reinforcement (γ·h·tan φ).
    pub apparent_adhesion: f64,
    /// φ_a − φ_input [degrees].
    pub friction_angle_difference_deg: f64,
}

/// Least-squares line through (x, y); `None` with fewer than two distinct x.
pub fn fit_line(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
    let (mx, my) = (sx / n, sy / n);
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if !(sxx > 0.0) {
        return None;
    }
    let slope = sxy / sxx;
    Some((my - slope * mx, slope))
}

fn peak_of<'a>(c: &'a CaseOutcome, target: Option<&str>) -> Option<&'a TargetPeak> {
    let t = target?;
    c.peaks.iter().find(|p| p.label == t)
}

/// Everything the series writes, also returned to the caller.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SeriesSummary {
    pub model: String,
    pub load: String,
    pub cases: Vec<CaseOutcome>,
    pub pullout: Option<PulloutReference>,
    pub envelope: Option<Envelope>,
}

/// Write `series.csv`, `series.json`, `envelope.png/.svg` and `report.md` in `out`.
///
/// # Errors
/// [`Error::Write`] naming the file.
pub fn write(
    out: &OwnedFolder,
    model_path: &Path,
    load: &str,
    units: &UnitLabels,
    cases: Vec<CaseOutcome>,
    pullout: Option<PulloutReference>,
) -> Result<SeriesSummary, Error> {
    let (s, f, l) = (units.stress.as_str(), units.force_per_width.as_str(), units.length);
    let target = pullout
        .as_ref()
        .map(|p| p.target.clone())
        .or_else(|| cases.iter().find_map(|c| c.peaks.first().map(|p| p.label.clone())));
    let peak_of = |c| peak_of(c, target.as_deref());
    let points: Vec<(f64, f64)> =
        cases.iter().filter(|c| c.error.is_none()).filter_map(|c| Some((c.value, peak_of(c)?.reaction))).collect();
    let envelope = match (&pullout, fit_line(&points)) {
        (Some(p), Some((a, b))) if p.embedded_length > 0.0 => {
            let two_l = 2.0 * p.embedded_length;
            let phi = (b / two_l).atan().to_degrees();
            Some(Envelope {
                intercept: a,
                slope: b,
                apparent_friction_angle_deg: phi,
                apparent_adhesion: a / two_l,
                friction_angle_difference_deg: phi - p.friction_angle_deg,
            })
        }
        _ => None,
    };

    // series.csv
    let mut csv =
        format!("case,{load} [{s}],target,peak force [{f}],displacement at peak [{l}],peak / 2L [{s}],status\n");
    for c in &cases {
        let peak = peak_of(c);
        let per_2l = match (&pullout, peak) {
            (Some(p), Some(k)) if p.embedded_length > 0.0 => format!("{:.6e}", k.reaction / (2.0 * p.embedded_length)),
            _ => String::new(),
        };
        csv.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            c.label,
            c.value,
            target.as_deref().unwrap_or(""),
            peak.map(|k| format!("{:.6e}", k.reaction)).unwrap_or_default(),
            peak.map(|k| format!("{:.6e}", k.displacement.abs())).unwrap_or_default(),
            per_2l,
            c.error
                .as_deref()
                .map(|e| format!("\"failed: {}\"", e.replace('"', "'")))
                .unwrap_or_else(|| "completed".into())
        ));
    }
    out.write("series.csv", csv.as_bytes())?;

    // envelope plot
    let mut curves = vec![("peaks".to_string(), points.clone())];
    if let Some(e) = &envelope {
        let (x0, x1) = points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
        let x0 = x0.min(0.0);
        curves.push((
            format!("fit: φa = {:.2}°, ca = {:.2} {s}", e.apparent_friction_angle_deg, e.apparent_adhesion),
            vec![(x0, e.intercept + e.slope * x0), (x1, e.intercept + e.slope * x1)],
        ));
    }
    let has_plot = !points.is_empty();
    if has_plot {
        plots::write_figure(
            out,
            "envelope",
            &[plots::Panel {
                title: format!("Peak {} force against {load} pressure", target.as_deref().unwrap_or("")),
                x_label: format!("{load} pressure [{s}]"),
                y_label: format!("peak force [{f}]"),
                series: curves,
                markers_only: vec!["peaks".to_string()],
            }],
            1,
        )?;
    }

    let summary =
        SeriesSummary { model: model_path.display().to_string(), load: load.to_string(), cases, pullout, envelope };
    let json = serde_json::to_vec_pretty(&summary).unwrap_or_default();
    out.write("series.json", &json)?;
    out.write("report.md", report(&summary, units, has_plot).as_bytes())?;
    Ok(summary)
}

fn report(summary: &SeriesSummary, units: &UnitLabels, has_plot: bool) -> String {
    let (s, f, l) = (units.stress.as_str(), units.force_per_width.as_str(), units.length);
    let mut r = format!("# Test series: {}\n\nModel: `{}`. One run per value of the load `{}`; each run has its own folder with its results and report.\n\n", summary.load, summary.model, summary.load);
    r.push_str(&format!(
        "| run | {} [{s}] | peak force [{f}] | displacement at peak [{l}] | status |\n|---|---:|---:|---:|---|\n",
        summary.load
    ));
    let target = summary.pullout.as_ref().map(|p| p.target.as_str());
    for c in &summary.cases {
        let peak = c.peaks.iter().find(|p| Some(p.label.as_str()) == target).or(c.peaks.first());
        r.push_str(&format!(
            "| [{}]({}/report.md) | {} | {} | {} | {} |\n",
            c.label,
            c.folder,
            c.value,
            peak.map(|p| format!("{:.3}", p.reaction)).unwrap_or_default(),
            peak.map(|p| format!("{:.4}", p.displacement.abs())).unwrap_or_default(),
            c.error.as_deref().map(|e| format!("failed: {e}")).unwrap_or_else(|| "completed".into())
        ));
    }
    if has_plot {
        r.push_str("\n![Peak force against the series value](envelope.png)\n");
    }
    if let Some(p) = &summary.pullout {
        r.push_str(&format!(
            "\n## Apparent interface strength\n\nReinforcement `{}`: embedded length L = {:.4} {l}; input peak strength τp = {} + σn·tan {:.2}°.\n\n",
            p.interface, p.embedded_length, p.cohesion, p.friction_angle_deg
        ));
        match &summary.envelope {
            Some(e) => r.push_str(&format!(
                "The peaks are fitted by P = 2L·(ca + σ·tan φa): slope {:.4}, intercept {:.4} {f}.\n\n\
                 - Apparent friction angle φa = **{:.2}°** against the input {:.2}° (difference {:+.2}°).\n\
                 - Apparent adhesion ca = {:.3} {s}. It includes the weight of the soil above the reinforcement \
                 (γ·h·tan φ) and any cohesion (input {}).\n\n\
                 A difference in φa comes from the normal stress on the reinforcement differing from the applied \
                 value (relaxation at the front wall and slot, arching in the box) and from the embedded length \
                 shrinking by the tail's slip before the whole length slides. The run reports' σn(x) plots \
                 show the first.\n",
                e.slope,
                e.intercept,
                e.apparent_friction_angle_deg,
                p.friction_angle_deg,
                e.friction_angle_difference_deg,
                e.apparent_adhesion,
                p.cohesion
            )),
            None => r.push_str("Fewer than two runs completed with distinct values: no envelope was fitted.\n"),
        }
    }
    r
}
