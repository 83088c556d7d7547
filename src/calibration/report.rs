//! What a calibration writes: `calibration.md` (each parameter with its standard error and 95 %
//! interval, the correlation matrix, the fit's quality, the warnings), `calibration.json` (the same
//! for programs), `interface-law.toml` (the `law = {…}` line ready to paste into a model's
//! interface) and `fitted-curves.png`/`.svg` (the measured points and the fitted curves).

use super::error::CalibrationError;
use super::spec::TestKind;
use super::Calibration;
use crate::output::plots::{write_figure, Panel};
use crate::output::OwnedFolder;
use std::fmt::Write as _;
use std::path::Path;

/// `v` with `digits` significant digits, as a plain decimal where that is short.
pub fn significant(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let magnitude = v.abs().log10().floor() as i32;
    if (-4..=6).contains(&magnitude) {
        let decimals = (digits as i32 - 1 - magnitude).max(0) as usize;
        let s = format!("{v:.decimals$}");
        // a decimal point is kept so that TOML reads a float
        if s.contains('.') {
            s
        } else {
            format!("{s}.0")
        }
    } else {
        format!("{v:.prec$e}", prec = digits - 1)
    }
}

/// The `law = {…}` line of the fitted law, with a comment saying where it comes from.
pub fn law_block(c: &Calibration) -> String {
    let fields: Vec<String> =
        c.parameters.iter().map(|p| format!("{} = {}", p.name, significant(p.value, 5))).collect();
    format!(
        "# {} law fitted by geoslip calibrate to {} ({} curves, {} points); lengths in m, stresses in kPa.\n\
         # Paste the law line into an [[interfaces]] entry of a model in metres and kilonewtons.\n\
         law = {{ type = \"{}\", {} }}\n",
        c.spec.law.name(),
        c.spec.data.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default(),
        c.curves.len(),
        c.fit.points,
        c.spec.law.name(),
        fields.join(", ")
    )
}

/// The report in Markdown.
pub fn markdown(c: &Calibration) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Calibration: {}\n", c.spec.title);
    let what = match c.spec.test {
        TestKind::DirectShear => "direct-shear curves (τ against slip; the law itself is the model)".to_string(),
        TestKind::PullOut => match (&c.spec.pull_out, c.box_embedded_length) {
            (Some(p), Some(l)) => format!(
                "pull-out curves, modelled by the finite-element pull-out box (reinforcement {l:.4} m on the box's \
                 element columns, EA = {} kN/m)",
                p.axial_stiffness
            ),
            (Some(p), None) => format!(
                "pull-out curves, modelled by the progressive-slip closed form on a rigid soil at σn = the \
                 surcharge (L = {} m, EA = {} kN/m, {} faces)",
                p.embedded_length, p.axial_stiffness, p.faces
            ),
            _ => "pull-out curves".into(),
        },
    };
    let conditions: Vec<String> = c.curves.iter().map(|k| format!("{}", k.condition)).collect();
    let _ = writeln!(
        s,
        "The `{}` law fitted by least squares (Levenberg–Marquardt) to {what}: {} curves at {} kPa, {} points, \
         {} degrees of freedom.\n",
        c.spec.law.name(),
        c.curves.len(),
        conditions.join(", "),
        c.fit.points,
        c.fit.degrees_of_freedom
    );
    let _ = writeln!(s, "| parameter | value | unit | standard error | 95 % interval |\n|---|---|---|---|---|");
    for p in &c.parameters {
        match (p.standard_error, p.interval) {
            (Some(se), Some((lo, hi))) => {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {} … {} |",
                    p.name,
                    significant(p.value, 5),
                    p.unit,
                    significant(se, 3),
                    significant(lo, 5),
                    significant(hi, 5)
                );
            }
            _ => {
                let how = if p.at_bound { "(at a bound of its range)" } else { "(fixed)" };
                let _ = writeln!(s, "| {} | {} | {} | {how} | |", p.name, significant(p.value, 5), p.unit);
            }
        }
    }
    let fitted: Vec<&str> = c.parameters.iter().filter(|p| p.fitted).map(|p| p.name).collect();
    let _ = writeln!(
        s,
        "\nThe intervals are value ± t·SE with Student's t({}) = {:.4}, the standard errors from s²·(JᵀJ)⁻¹ at the \
         fit (s² the residuals' sum of squares over the degrees of freedom): they hold as far as the model is \
         linear in its parameters near the fit and the scatter is independent and even.\n",
        c.fit.degrees_of_freedom, c.fit.t_quantile
    );
    let _ = writeln!(s, "## Correlation of the fitted parameters\n");
    let _ = writeln!(s, "| | {} |\n|---|{}", fitted.join(" | "), "---|".repeat(fitted.len()));
    for (a, row) in c.correlation.iter().enumerate() {
        let cells: Vec<String> = row.iter().map(|r| format!("{r:.3}")).collect();
        let _ = writeln!(s, "| {} | {} |", fitted[a], cells.join(" | "));
    }
    let unit = match c.spec.test {
        TestKind::DirectShear => "kPa",
        TestKind::PullOut => "kN/m",
    };
    let _ = writeln!(
        s,
        "\n## Fit\n\nEach curve's residuals are weighted by 1/(its largest measured value), so that every curve \
         counts alike; the weighted root mean square is {} ({:.2} % of a curve's largest value).\n",
        significant(c.fit.rms, 3),
        100.0 * c.fit.rms
    );
    let _ = writeln!(
        s,
        "| curve at [kPa] | points | RMS residual [{unit}] | largest measured [{unit}] |\n|---|---|---|---|"
    );
    for (k, m) in c.curves.iter().zip(&c.modelled) {
        let rms = (m.iter().zip(&k.y).map(|(m, y)| (m - y).powi(2)).sum::<f64>() / m.len() as f64).sqrt();
        let top = k.y.iter().copied().fold(f64::MIN, f64::max);
        let _ = writeln!(s, "| {} | {} | {} | {} |", k.condition, k.x.len(), significant(rms, 3), significant(top, 4));
    }
    if !c.warnings.is_empty() {
        let _ = writeln!(s, "\n## Warnings\n");
        for w in &c.warnings {
            let _ = writeln!(s, "- {w}");
        }
    }
    let plotted = plotted_curves(c.curves.len()).len();
    let _ = writeln!(
        s,
        "\n## The law for a model\n\n```toml\n{}```\n\nPlots: fitted-curves.png, fitted-curves.svg{}.",
        law_block(c),
        if plotted < c.curves.len() {
            format!(" ({plotted} of the {} curves, spread over them; calibration.json has them all)", c.curves.len())
        } else {
            String::new()
        }
    );
    s
}

/// The most curves the plot draws (one colour each); more would hide one another.
pub const MAX_PLOTTED_CURVES: usize = 6;
/// The most measured points of a curve the plot marks: more overlap at the plot's size.
pub const MAX_PLOTTED_POINTS: usize = 400;

/// The curves the plot draws, of `count`: all of a few, or [`MAX_PLOTTED_CURVES`] spread evenly
/// from the first to the last.
pub fn plotted_curves(count: usize) -> Vec<usize> {
    if count <= MAX_PLOTTED_CURVES {
        return (0..count).collect();
    }
    let last = (count - 1) as f64;
    let mut picked: Vec<usize> =
        (0..MAX_PLOTTED_CURVES).map(|i| (last * i as f64 / (MAX_PLOTTED_CURVES - 1) as f64).round() as usize).collect();
    picked.dedup();
    picked
}

/// The points of a curve the plot marks: every one of up to [`MAX_PLOTTED_POINTS`], or that many
/// spread evenly from the first to the last.
pub fn plotted_points<T: Copy>(points: &[T]) -> Vec<T> {
    if points.len() <= MAX_PLOTTED_POINTS {
        return points.to_vec();
    }
    let last = (points.len() - 1) as f64;
    let mut picked: Vec<usize> =
        (0..MAX_PLOTTED_POINTS).map(|i| (last * i as f64 / (MAX_PLOTTED_POINTS - 1) as f64).round() as usize).collect();
    picked.dedup();
    picked.into_iter().map(|i| points[i]).collect()
}

/// The calibration as JSON.
pub fn json(c: &Calibration) -> serde_json::Value {
    serde_json::json!({
        "title": c.spec.title,
        "test": c.spec.test.name(),
        "law": c.spec.law.name(),
        "data": c.spec.data,
        "parameters": c.parameters,
        "fitted": c.parameters.iter().filter(|p| p.fitted).map(|p| p.name).collect::<Vec<_>>(),
        "correlation": c.correlation,
        "weighted_rms": c.fit.rms,
        "points": c.fit.points,
        "degrees_of_freedom": c.fit.degrees_of_freedom,
        "t_quantile": c.fit.t_quantile,
        "evaluations": c.fit.evaluations,
        "warnings": c.warnings,
        "box_embedded_length": c.box_embedded_length,
        "law_block": law_block(c),
        "curves": c.curves.iter().zip(&c.modelled).zip(&c.smooth).map(|((k, m), sm)| serde_json::json!({
            "condition": k.condition,
            "x": k.x,
            "measured": k.y,
            "modelled": m,
            "smooth_x": sm.iter().map(|p| p.0).collect::<Vec<_>>(),
            "smooth_y": sm.iter().map(|p| p.1).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    })
}

/// Write the report, the JSON, the law block and the plots into `out`.
///
/// # Errors
/// [`CalibrationError::Write`] naming the file.
pub fn write(c: &Calibration, out: &Path) -> Result<(), CalibrationError> {
    let fail = |e: crate::Error| match e {
        crate::Error::Write { path, source } => CalibrationError::Write { path, source },
        other => CalibrationError::Write { path: out.into(), source: std::io::Error::other(other.to_string()) },
    };
    // the folder is owned as a run's is: only what an earlier calibration wrote there is replaced,
    // never through a link, and never the calibration's own inputs
    let folder = OwnedFolder::open(out, &[c.spec.path.as_path(), c.spec.data.as_path()]).map_err(fail)?;
    folder.write("calibration.md", markdown(c).as_bytes()).map_err(fail)?;
    let text = serde_json::to_string_pretty(&json(c)).unwrap_or_default();
    folder.write("calibration.json", text.as_bytes()).map_err(fail)?;
    folder.write("interface-law.toml", law_block(c).as_bytes()).map_err(fail)?;
    let (x_label, y_label, what) = match c.spec.test {
        TestKind::DirectShear => ("slip [mm]", "shear stress τ [kPa]", "σn"),
        TestKind::PullOut => ("head displacement [mm]", "pull-out force [kN/m]", "q"),
    };
    // a bounded number of curves and points: the plot's size does not grow with the file's
    let mut series = Vec::new();
    let mut markers = Vec::new();
    let shown = plotted_curves(c.curves.len());
    for &i in &shown {
        let (k, sm) = (&c.curves[i], &c.smooth[i]);
        let measured: Vec<(f64, f64)> = k.x.iter().zip(&k.y).map(|(x, y)| (1e3 * x, *y)).collect();
        let label = format!("{what} = {} kPa, measured", k.condition);
        series.push((label.clone(), plotted_points(&measured)));
        markers.push(label);
        series.push((format!("{what} = {} kPa, fitted", k.condition), sm.iter().map(|(x, y)| (1e3 * x, *y)).collect()));
    }
    let of = if shown.len() < c.curves.len() {
        format!(" ({} of {} curves)", shown.len(), c.curves.len())
    } else {
        String::new()
    };
    let panel = Panel {
        title: format!("{}: {} law fitted{of}", c.spec.title, c.spec.law.name()),
        x_label: x_label.into(),
        y_label: y_label.into(),
        series,
        markers_only: markers,
    };
    write_figure(&folder, "fitted-curves", &[panel], 1).map_err(fail)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibration::{calibrate_curves, CalibrationSpec, Curve, LawFamily};
    use std::path::PathBuf;

    #[test]
    fn the_plot_marks_a_bounded_number_of_points_and_curves() {
        let few: Vec<usize> = (0..10).collect();
        assert_eq!(plotted_points(&few), few);
        let many: Vec<usize> = (0..60_000).collect();
        let marked = plotted_points(&many);
        assert_eq!(marked.len(), 400);
        assert_eq!((marked[0], marked[399]), (0, 59_999));
        assert!(marked.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(plotted_curves(3), vec![0, 1, 2]);
        assert_eq!(plotted_curves(11), vec![0, 2, 4, 6, 8, 10]);
        assert_eq!(plotted_curves(20_000).len(), 6);
        assert_eq!(plotted_curves(20_000)[5], 19_999);
    }

    /// 2000 direct-shear curves of 3 points (τ = min(Ks·δ, c + σn·tan φ), Ks = 10 000 kPa/m, c = 5
    /// kPa, φ = 30°, ±1 % alternately): what is written grows with the 6000 points given, not with
    /// the curves × a fixed count of fitted points (which made 2000 × 201 × 2 numbers in the JSON and
    /// as many circles in the SVG, some 100 MB).
    #[test]
    fn what_is_written_for_many_curves_is_bounded_by_the_points_given() {
        let curves: Vec<Curve> = (0..2000)
            .map(|k| {
                let sigma = 10.0 + 0.05 * k as f64;
                let x = vec![0.0, 0.001, 0.005];
                let y = x
                    .iter()
                    .enumerate()
                    .map(|(i, &d)| {
                        let tau = (1e4 * d as f64).min(5.0 + sigma * 30f64.to_radians().tan());
                        tau * (1.0 + if (i + k) % 2 == 0 { 0.01 } else { -0.01 })
                    })
                    .collect();
                Curve { condition: sigma, x, y }
            })
            .collect();
        let dir = tempfile::tempdir().unwrap();
        let spec = CalibrationSpec {
            path: dir.path().join("fit.toml"),
            title: "many".into(),
            test: TestKind::DirectShear,
            data: dir.path().join("ds.csv"),
            law: LawFamily::Coulomb,
            initial: Vec::new(),
            fixed: Vec::new(),
            pull_out: None,
        };
        let c = calibrate_curves(&spec, curves).unwrap_or_else(|e| panic!("{e}"));
        let smooth: usize = c.smooth.iter().map(Vec::len).sum();
        assert!(smooth <= 20_000, "{smooth} fitted points");
        let out: PathBuf = dir.path().join("out");
        write(&c, &out).unwrap_or_else(|e| panic!("{e}"));
        let size = |name: &str| std::fs::metadata(out.join(name)).map(|m| m.len()).unwrap_or(0);
        for name in ["calibration.json", "calibration.md", "fitted-curves.svg", "fitted-curves.png"] {
            assert!(size(name) > 0, "{name} missing");
        }
        // the plot: 6 curves of at most 3 marks and 201 fitted points each
        assert!(size("fitted-curves.svg") < 1_000_000, "fitted-curves.svg: {} bytes", size("fitted-curves.svg"));
        // the JSON: 3 numbers a point given and at most 20 000 fitted points of 2
        assert!(size("calibration.json") < 4_000_000, "calibration.json: {} bytes", size("calibration.json"));
    }
}
