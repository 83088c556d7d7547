//! The design checks of a wall beside the analysis: `design-checks.csv`, the figure of T_max
//! against depth, and the report's section (`docs/design-checks.md`).

use super::figures::StepProfile;
use super::owned_folder::OwnedFolder;
use super::plots::{write_figure, Panel};
use crate::design::pullout::MINIMUM_EMBEDMENT_M;
use crate::design::{LayerCheck, Wall};
use crate::error::Error;
use crate::model::UnitLabels;
use std::fmt::Write;

/// Each layer's checks, with the largest tensions of the run's last step (`last`: one profile per
/// reinforcement named in `names`, in their order).
pub(super) fn checks(wall: &Wall, last: Option<&StepProfile>, names: &[&str]) -> Vec<LayerCheck> {
    wall.checks(&|layer| {
        let k = names.iter().position(|n| *n == layer)?;
        last?.reinforcements.get(k)?.largest_tension().map(|(t, x)| (t.max(0.0), x))
    })
}

/// `design-checks.csv` and `design-checks.png`/`.svg`; the figure's stem and caption.
pub(super) fn write_files(
    folder: &OwnedFolder,
    checks: &[LayerCheck],
    units: &UnitLabels,
) -> Result<(String, String), Error> {
    let (l, f, s) = (units.length, units.force_per_width.as_str(), units.stress.as_str());
    let mut csv = format!(
        "layer,elevation [{l}],depth Z [{l}],zone top [{l}],zone bottom [{l}],Svt [{l}],L [{l}],La [{l}],Le [{l}],\
         T_max analysis [{f}],at distance from face [{l}],sigma_H simplified [{s}],T_max simplified [{f}],\
         T_max simplified factored [{f}],F*,Pr [{f}],phi Pr [{f}],Pr/T_max analysis,Pr/T_max simplified,CDR pull-out\n"
    );
    for c in checks.iter().rev() {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            c.layer.name,
            c.layer.elevation,
            c.layer.depth,
            c.layer.zone_top,
            c.layer.zone_bottom,
            c.layer.spacing(),
            c.layer.length,
            c.pullout.active_length,
            c.pullout.embedment,
            c.fe_max_tension,
            c.fe_distance,
            c.simplified.horizontal_stress,
            c.simplified.max_tension,
            c.simplified.factored_max_tension,
            c.pullout.pullout_factor,
            c.pullout.resistance,
            c.pullout.factored_resistance,
            finite_or_blank(c.pullout_ratio_fe()),
            finite_or_blank(c.pullout_ratio_simplified()),
            finite_or_blank(c.pullout_cdr())
        );
    }
    folder.write("design-checks.csv", csv.as_bytes())?;
    // a ratio over a layer with no load is left out (the report says "no tension")
    let series = |value: &dyn Fn(&LayerCheck) -> f64| {
        checks.iter().map(|c| (c.layer.depth, value(c))).filter(|(_, v)| v.is_finite()).collect()
    };
    let depth = format!("depth below the crest [{l}]");
    let panels = [
        Panel {
            title: "Largest tension in each layer".into(),
            x_label: depth.clone(),
            y_label: format!("T_max [{f}]"),
            series: vec![
                ("analysis".into(), series(&|c| c.fe_max_tension)),
                ("Simplified Method".into(), series(&|c| c.simplified.max_tension)),
                ("Simplified Method × γP,EV".into(), series(&|c| c.simplified.factored_max_tension)),
            ],
            markers_only: vec!["analysis".into()],
        },
        Panel {
            title: "Pull-out: resistance over load".into(),
            x_label: depth,
            y_label: "ratio".into(),
            series: vec![
                ("φ·Pr / (γP,EV·T_max Simplified)".into(), series(&|c| c.pullout_cdr())),
                ("Pr / T_max analysis".into(), series(&|c| c.pullout_ratio_fe())),
                ("1 (the least allowed)".into(), series(&|_| 1.0)),
            ],
            markers_only: Vec::new(),
        },
    ];
    write_figure(folder, "design-checks", &panels, 2)?;
    Ok((
        "design-checks".into(),
        "Each layer's largest tension by the analysis and by the Simplified Method, and its pull-out resistance over those loads"
            .into(),
    ))
}

/// A ratio as the CSV writes it: blank where its load is zero (no tension in the layer, or no
/// step completed), not "inf".
fn finite_or_blank(ratio: f64) -> String {
    if ratio.is_finite() {
        ratio.to_string()
    } else {
        String::new()
    }
}

/// The report's section: the wall as the methods see it, and the table of the layers.
pub(super) fn report_section(r: &mut String, wall: &Wall, checks: &[LayerCheck], units: &UnitLabels) {
    let (l, f, s) = (units.length, units.force_per_width.as_str(), units.stress.as_str());
    let _ = writeln!(r, "\n## Design checks\n");
    let fstar = match wall.parameters.pullout_factor {
        Some(v) => format!("F* = {v} (given)"),
        None if wall.reinforcement().is_extensible() => {
            format!("F* = 0.67·tan φ = {:.4}", crate::design::pullout::geosynthetic_pullout_factor(wall.friction_angle))
        }
        None => "F* = 20·t/St at the crest to 10·t/St at 6 m".to_string(),
    };
    let _ = writeln!(
        r,
        "The wall as the design methods see it (AASHTO LRFD §11.10.6, FHWA GEC 011; `docs/design-checks.md`): \
         reinforced fill `{}` from y = {} to {} (H = {} {l}), face at x = {}; γ = {}, φ = {:.1}°, Ka = {:.4}; \
         surcharge q = {} {s} (from {}); {} {} layers; {fstar}, α = {}, C = 2, Rc = {}. The analysis's tensions are \
         those of its last step.\n",
        wall.parameters.reinforced_soil,
        wall.base,
        wall.crest,
        wall.height(),
        wall.face_x,
        wall.unit_weight,
        wall.friction_angle.to_degrees(),
        crate::design::simplified::active_coefficient(wall.friction_angle),
        wall.surcharge,
        wall.surcharge_source,
        wall.layers.len(),
        wall.reinforcement().name(),
        wall.scale_correction(),
        wall.coverage_ratio()
    );
    let _ = writeln!(
        r,
        "| layer | Z [{l}] | Svt [{l}] | L [{l}] | Le [{l}] | T_max analysis [{f}] | T_max Simplified [{f}] | factored [{f}] | Pr [{f}] | φ·Pr [{f}] | Pr / T_max analysis | Pr / T_max Simplified | CDR pull-out |"
    );
    let _ = writeln!(r, "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mark = |ok: bool| if ok { "" } else { " ✗" };
    for c in checks.iter().rev() {
        let _ = writeln!(
            r,
            "| {} | {:.3} | {:.3} | {:.3} | {:.3}{} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {:.2} | {:.2}{} |",
            c.layer.name,
            c.layer.depth,
            c.layer.spacing(),
            c.layer.length,
            c.pullout.embedment,
            mark(c.pullout.embedment >= MINIMUM_EMBEDMENT_M * wall.metre),
            c.fe_max_tension,
            c.simplified.max_tension,
            c.simplified.factored_max_tension,
            c.pullout.resistance,
            c.pullout.factored_resistance,
            if c.fe_max_tension > 0.0 { format!("{:.2}", c.pullout_ratio_fe()) } else { "— (no tension)".into() },
            c.pullout_ratio_simplified(),
            c.pullout_cdr(),
            mark(c.pullout_cdr() >= 1.0)
        );
    }
    let _ = writeln!(
        r,
        "\n✗ marks a layer that fails a check: Le shorter than 0.9 m, or a capacity-to-demand ratio \
         φ·Pr / (γP,EV·T_max) below 1 (φ = 0.90, γP,EV = 1.35). The Simplified Method gives a design load at the \
         limit state the method was calibrated for; the analysis's T_max is that of this model's soil, facing and \
         construction sequence at working load, and usually lower (`docs/design-checks.md`). Not checked here: the \
         reinforcement's tensile resistance (it needs the long-term design strength) and the connection to the \
         facing. The table is in `design-checks.csv`."
    );
}
