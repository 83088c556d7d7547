//! A geosynthetic-lined landfill side slope: the liner's tension and slip along the slope, the
//! anchor force, and the factor of safety with its mechanism.
//!
//! Description: runs `examples/landfill-slope/landfill-slope.toml` (the standard results go to
//! `results/landfill-slope/`) and adds, in `results/landfill-slope/slope/`:
//! - `layers.csv`: per geosynthetic layer, at the end of construction and at the factor of safety:
//!   the largest tension and where it lies, the anchor force (the tension where the layer leaves
//!   the crest for the anchor trench), and the largest slip on the face beneath it;
//! - `profiles.csv`: tension and slip of every layer along the liner line;
//! - `slope.png`/`.svg`: tension and slip along the slope after construction and at FS;
//! - `slope-report.md`: the tables, the figure, FS and the mechanism, the two-wedge value without
//!   the geosynthetics' tension for comparison.
//!
//! Sample run:
//!   cargo run --release --example landfill_slope
//!
//! Distances are measured along the liner line from the toe (negative on the cell floor).

use geoslip::analysis::results::StepResults;
use geoslip::analysis::RunStats;
use geoslip::analysis::{FactorOfSafety, StepRecord, StepSink};
use geoslip::model::Model;
use geoslip::output::plots::{write_figure, Panel};
use geoslip::output::{run_and_write, OwnedFolder};
use geoslip::Error;
use std::fmt::Write as _;
use std::path::Path;

/// The stack from the bottom up: (layer, face beneath it).
const LAYERS: [(&str, &str); 3] =
    [("geomembrane", "lower"), ("geotextile", "geotextile on geomembrane"), ("geogrid", "geogrid on geotextile")];
/// The crest, where the liner leaves the slope for the anchor trench.
const CREST: [f64; 2] = [30.0, 10.0];
const SLOPE_RUN: f64 = 30.0;
const SLOPE_HEIGHT: f64 = 10.0;

/// Keeps the last construction step, the step at FS, and FS.
#[derive(Default)]
struct Keep {
    built: Option<StepResults>,
    at_fs: Option<(f64, StepResults)>,
    fs: Option<FactorOfSafety>,
}

impl StepSink for Keep {
    fn step_done(
        &mut self,
        _: &geoslip::model::Model,
        step: &StepResults,
        record: &StepRecord,
        _: &RunStats,
    ) -> Result<(), Error> {
        match record.strength_factor {
            Some(f) => self.at_fs = Some((f, step.clone())),
            None => self.built = Some(step.clone()),
        }
        Ok(())
    }

    fn factor_of_safety(&mut self, fs: &FactorOfSafety) -> Result<(), Error> {
        self.fs = Some(fs.clone());
        Ok(())
    }
}

/// Distance along the liner line from the toe (0, 0): negative on the floor, along the slope up to
/// the crest, then on along the crest and into the trench.
fn along(x: [f64; 2]) -> f64 {
    let slope = SLOPE_RUN.hypot(SLOPE_HEIGHT);
    if x[0] <= 0.0 {
        x[0]
    } else if x[0] <= CREST[0] + 1e-9 && x[1] <= CREST[1] - 1e-9 {
        x[0] / SLOPE_RUN * slope
    } else {
        // the crest and the trench: the path length beyond the crest
        let on_crest = (x[0].min(31.5) - CREST[0]).max(0.0);
        let down = (CREST[1] - x[1]).max(0.0);
        let bottom = (x[0] - 31.5).max(0.0) * if x[1] < CREST[1] - 0.999 { 1.0 } else { 0.0 };
        slope + on_crest + down + bottom
    }
}

struct Profile {
    /// (distance, T) of each bar.
    tension: Vec<(f64, f64)>,
    /// (distance, slip) of each point of the face beneath the layer.
    slip: Vec<(f64, f64)>,
    ruptured: usize,
}

fn profile(model: &Model, step: &StepResults, layer: &str, face: &str) -> Profile {
    let nodes: std::collections::HashSet<u64> =
        model.node_sets[&format!("{layer}.reinforcement")].iter().map(|&n| model.mesh.node_id(n)).collect();
    let mut tension: Vec<(f64, f64)> = step
        .bar_forces
        .iter()
        .filter(|b| nodes.contains(&b.nodes[0]) && nodes.contains(&b.nodes[1]))
        .map(|b| (along(b.midpoint), b.axial_force))
        .collect();
    let ruptured = step.bar_forces.iter().filter(|b| nodes.contains(&b.nodes[0]) && b.state == "ruptured").count();
    let mut slip: Vec<(f64, f64)> = step
        .interface_points
        .iter()
        .filter(|p| p.interface == "geomembrane" && p.face == face)
        .map(|p| (along(p.x), p.slip))
        .collect();
    tension.sort_by(|a, b| a.0.total_cmp(&b.0));
    slip.sort_by(|a, b| a.0.total_cmp(&b.0));
    Profile { tension, slip, ruptured }
}

/// Tension where the layer leaves the crest (the anchor force), interpolated between bars.
fn anchor_force(p: &Profile) -> f64 {
    let crest = along(CREST);
    let after = p.tension.iter().position(|t| t.0 >= crest).unwrap_or(p.tension.len() - 1);
    if after == 0 {
        return p.tension[0].1;
    }
    let (a, b) = (p.tension[after - 1], p.tension[after]);
    a.1 + (b.1 - a.1) * (crest - a.0) / (b.0 - a.0)
}

fn largest(v: &[(f64, f64)]) -> (f64, f64) {
    v.iter().copied().fold((0.0, 0.0), |m, t| if t.1.abs() > m.1.abs() { t } else { m })
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Error> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/landfill-slope/landfill-slope.toml");
    let out = Path::new("results/landfill-slope");
    let model = Model::load(&path)?;
    let mut keep = Keep::default();
    let seconds = run_and_write(&model, out, &Default::default(), &mut keep)?;
    let Keep { built, at_fs, fs } = keep;
    let built = built.expect("a completed run has construction steps");
    let (factor, at_fs) = at_fs.expect("the strength-reduction stage found at least F = 1");
    let fs = fs.expect("the strength-reduction stage reports FS");

    let profiles: Vec<(&str, Profile, Profile)> = LAYERS
        .iter()
        .map(|&(layer, face)| (layer, profile(&model, &built, layer, face), profile(&model, &at_fs, layer, face)))
        .collect();
    let dir = out.join("slope");
    let folder = OwnedFolder::open(&dir, &[])?;

    let mut csv = String::from(
        "layer,state,T_max [kN/m],at distance [m],anchor force [kN/m],max slip beneath [m],at distance [m],ruptured bars\n",
    );
    for (layer, b, f) in &profiles {
        for (state, p) in [("built", b), ("at FS", f)] {
            let (xt, t) = largest(&p.tension);
            let (xs, s) = largest(&p.slip);
            let _ =
                writeln!(csv, "{layer},{state},{t:.3},{xt:.2},{:.3},{s:.5},{xs:.2},{}", anchor_force(p), p.ruptured);
        }
    }
    folder.write("layers.csv", csv.as_bytes())?;
    let mut pcsv = String::from("layer,state,quantity,distance [m],value\n");
    for (layer, b, f) in &profiles {
        for (state, p) in [("built", b), ("at FS", f)] {
            for (d, t) in &p.tension {
                let _ = writeln!(pcsv, "{layer},{state},T [kN/m],{d:.3},{t:.5}");
            }
            for (d, s) in &p.slip {
                let _ = writeln!(pcsv, "{layer},{state},slip beneath [m],{d:.3},{s:.6}");
            }
        }
    }
    folder.write("profiles.csv", pcsv.as_bytes())?;

    let tension_series = |at_fs: bool| -> Vec<(String, Vec<(f64, f64)>)> {
        profiles.iter().map(|(l, b, f)| (l.to_string(), if at_fs { f } else { b }.tension.clone())).collect()
    };
    let slip_series = |at_fs: bool| -> Vec<(String, Vec<(f64, f64)>)> {
        profiles
            .iter()
            .map(|(l, b, f)| {
                let p = if at_fs { f } else { b };
                (format!("beneath the {l}"), p.slip.iter().map(|s| (s.0, 1e3 * s.1)).collect())
            })
            .collect()
    };
    let x_label = "distance along the liner from the toe [m] (crest at 31.6)";
    let panels = vec![
        Panel {
            title: "Tension after construction".into(),
            x_label: x_label.into(),
            y_label: "T [kN/m]".into(),
            series: tension_series(false),
            markers_only: Vec::new(),
        },
        Panel {
            title: format!("Tension at FS = {:.2} (strengths / {factor:.3})", fs.value),
            x_label: x_label.into(),
            y_label: "T [kN/m]".into(),
            series: tension_series(true),
            markers_only: Vec::new(),
        },
        Panel {
            title: "Slip after construction (down the slope > 0)".into(),
            x_label: x_label.into(),
            y_label: "slip [mm]".into(),
            series: slip_series(false),
            markers_only: Vec::new(),
        },
        Panel {
            title: format!("Slip at FS = {:.2}", fs.value),
            x_label: x_label.into(),
            y_label: "slip [mm]".into(),
            series: slip_series(true),
            markers_only: Vec::new(),
        },
    ];
    write_figure(&folder, "slope", &panels, 2)?;

    let mut md = String::new();
    let _ = writeln!(md, "# Lined landfill side slope, 3H:1V, 10 m high\n");
    let _ = writeln!(
        md,
        "Model `examples/landfill-slope/landfill-slope.toml`: a geogrid / geotextile / geomembrane stack on a clay liner, \
         anchored in a trench at the crest, with 0.6 m of cover soil placed from the toe up in six parts; then the \
         factor of safety by strength reduction of the soil and the interfaces together. Run in {seconds:.1} s. The run's \
         own report is `../report.md`.\n"
    );
    let _ = writeln!(md, "![slope](slope.png)\n");
    let _ = writeln!(md, "## Factor of safety\n");
    match fs.failed_at {
        Some(f) => {
            let _ = writeln!(
                md,
                "FS = **{:.3}** ({} reduced): equilibrium at F = {factor:.4}, none at F = {f:.4}.\n",
                fs.value, fs.reduced
            );
            if let Some(why) = &fs.failure {
                let _ = writeln!(md, "At F = {f:.4}: {why}.\n");
            }
        }
        None => {
            let _ = writeln!(
                md,
                "FS ≥ **{:.3}** ({} reduced): the search stopped at its largest factor.\n",
                fs.value, fs.reduced
            );
        }
    }
    // the two-wedge method (docs/verification.md §7) on the cover alone, with the critical interface's
    // peak and residual friction and no geosynthetic tension
    let cover = &model.soils.iter().find(|(n, _)| n == "cover").expect("the model has a cover").1;
    let two_wedge = |phi_i: f64| {
        let (h, beta) = (0.6, (SLOPE_HEIGHT / SLOPE_RUN).atan());
        let length = SLOPE_RUN.hypot(SLOPE_HEIGHT) + h / beta.sin();
        let (sb, cb) = (beta.sin(), beta.cos());
        let gamma = cover.unit_weight;
        let w_a = gamma * h * h * (length / h - 1.0 / sb - beta.tan() / 2.0);
        let n_a = w_a * cb;
        let w_p = gamma * h * h / (2.0 * beta).sin();
        let c = cover.cohesion * h / sb;
        let (tp, ti) = (cover.friction_angle.to_radians().tan(), phi_i.to_radians().tan());
        let x = w_a - n_a * cb;
        let (a, b, c0) = (x * cb, -(x * sb * tp + n_a * ti * sb * cb + sb * (c + w_p * tp)), n_a * ti * sb * sb * tp);
        (-b + (b * b - 4.0 * a * c0).sqrt()) / (2.0 * a)
    };
    let _ = writeln!(
        md,
        "For comparison, the two-wedge method (Koerner & Soong 1998) on the cover alone, sliding on the geotextile / \
         geomembrane interface with no geosynthetic tension: FS = {:.3} at its peak friction (24°), {:.3} at its \
         residual (16°). Construction has taken that interface past its peak over most of the slope (see the slip), \
         so the slope stands on the residual strength, the toe, and what the anchored geotextile and geogrid carry.\n",
        two_wedge(24.0),
        two_wedge(16.0)
    );
    let _ = writeln!(
        md,
        "Factors tried: {}.\n",
        fs.trials
            .iter()
            .map(|(f, ok)| format!("{f:.3} {}", if *ok { "✓" } else { "✗" }))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(md, "## Tension, anchor force and slip\n");
    let _ = writeln!(md, "| layer | state | T_max [kN/m] | at [m] | anchor force [kN/m] | largest slip beneath [mm] | at [m] | ruptured bars |");
    let _ = writeln!(md, "|---|---|---:|---:|---:|---:|---:|---:|");
    for (layer, b, f) in &profiles {
        for (state, p) in [("after construction", b), ("at FS", f)] {
            let (xt, t) = largest(&p.tension);
            let (xs, s) = largest(&p.slip);
            let _ = writeln!(
                md,
                "| {layer} | {state} | {t:.2} | {xt:.1} | {:.2} | {:.1} | {xs:.1} | {} |",
                anchor_force(p),
                1e3 * s,
                p.ruptured
            );
        }
    }
    let _ = writeln!(
        md,
        "\nDistances run along the liner line from the toe; the crest is at {:.1} m, the anchor trench beyond it. \
        The anchor force is the tension where the layer leaves the crest for the trench. A slip is the sliding of the \
        layer over what lies beneath it (positive down the slope).\n",
        along(CREST)
    );
    let _ = writeln!(md, "## Mechanism at FS\n");
    let mut faces: Vec<(String, usize, usize)> = Vec::new();
    for p in at_fs.interface_points.iter().filter(|p| p.interface == "geomembrane") {
        match faces.iter_mut().find(|f| f.0 == p.face) {
            Some(f) => {
                f.1 += p.sliding as usize;
                f.2 += 1;
            }
            None => faces.push((p.face.clone(), p.sliding as usize, 1)),
        }
    }
    for (face, sliding, all) in &faces {
        let _ = writeln!(md, "- {face}: {sliding} of {all} points at their (reduced) strength");
    }
    let yielding = at_fs.stresses(&model).iter().filter(|s| s.yield_state.is_plastic()).count();
    let _ = writeln!(md, "- soil: {yielding} Gauss points on the (reduced) yield surface\n");
    folder.write("slope-report.md", md.as_bytes())?;
    println!("{}", std::fs::read_to_string(dir.join("layers.csv")).unwrap_or_default());
    println!("FS = {:.3} ({} reduced). Report: {}", fs.value, fs.reduced, dir.join("slope-report.md").display());
    Ok(())
}
