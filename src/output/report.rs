//! `report.md`: what a run did and found, for a reader who opens one file.

use super::folder::num;
use super::history::HistoryRow;
use super::summary::RunSummary;
use crate::model::Model;
use std::fmt::Write;

/// The design checks of the wall a model builds, for the report.
pub struct DesignSection<'a> {
    pub wall: &'a crate::design::Wall,
    pub checks: Vec<crate::design::LayerCheck>,
    /// The figure's stem and caption.
    pub figure: (String, String),
}

/// The Markdown report of a run (finished or failed).
/// The report's section on the dynamic stages: their histories and its figure.
pub struct ShakingSection<'a> {
    pub(super) history: &'a super::motion::MotionHistory,
    pub(super) figure: Option<(String, String)>,
}

pub fn markdown(
    model: &Model,
    summary: &RunSummary,
    history: &[HistoryRow],
    units: &crate::model::UnitLabels,
    figures: &[(String, String)],
    design: Option<&DesignSection>,
    shaking: Option<&ShakingSection>,
) -> String {
    let mut r = String::new();
    model_section(&mut r, model, summary, units);
    key_results(&mut r, summary, history, units, figures);
    if let Some(s) = shaking {
        s.history.report_section(&mut r, units);
        if let Some((stem, caption)) = &s.figure {
            figure(&mut r, stem, caption);
        }
    }
    if let Some(d) = design {
        super::design_checks::report_section(&mut r, d.wall, &d.checks, units);
        figure(&mut r, &d.figure.0, &d.figure.1);
    }
    run_history(&mut r, summary);
    field_files(&mut r, summary);
    r
}

/// Where the fields of the kept steps are, and the curves.
fn field_files(r: &mut String, summary: &RunSummary) {
    let f = &summary.fields;
    let steps = match f.keep.as_str() {
        "every" => "every step".to_string(),
        "events" => format!("the {} event steps", f.kept_steps.len()),
        n => format!("every {n}th step and the event steps, {} in all", f.kept_steps.len()),
    };
    let files: Vec<String> = f.files.iter().map(|name| format!("`{name}`")).collect();
    let mut text = format!("\nThe fields of {steps} are in {}", files.join(", "));
    if f.files.iter().any(|name| name == "results.xdmf") {
        text.push_str(" (open `results.xdmf` in ParaView)");
    }
    if f.csv {
        text.push_str(", and as CSV files in `stage-<k>-<name>/step-<nnn>/`");
    }
    let _ = writeln!(r, "{text}; `history.csv` holds the curves, `summary.json` all of the above.");
}

/// The title, the run's facts and the model: its size, mesh, interfaces and analysis settings.
fn model_section(r: &mut String, model: &Model, summary: &RunSummary, units: &crate::model::UnitLabels) {
    let _ =
        writeln!(r, "# geoslip run report: {}", if summary.title.is_empty() { &summary.model } else { &summary.title });
    let _ = writeln!(r);
    let _ = writeln!(r, "- Model file: `{}`", summary.model);
    let _ = writeln!(r, "- geoslip {}; solver backend **{}**", summary.geoslip_version, summary.solver);
    let _ = writeln!(
        r,
        "- Status: **{}**{}",
        summary.status,
        summary.error.as_ref().map(|e| format!(": {e}")).unwrap_or_default()
    );
    let _ = writeln!(r, "- Units: length {}, force {}, stress {}", units.length, units.force, units.stress);
    let _ = writeln!(
        r,
        "- Geometry: {}",
        if model.mesh.geometry.is_axisymmetric() {
            format!(
                "**axisymmetric** about x = 0 (x = r, y = z, the fourth stress σzz is the hoop stress σθ): forces, reactions, bar forces and multipliers are totals over the whole circumference [{}], not per radian",
                units.force
            )
        } else {
            format!("plane strain: forces per metre width [{}]", units.force_per_width)
        }
    );
    let _ = writeln!(r, "- Wall time: {:.2} s", summary.total_seconds);

    let _ = writeln!(r, "\n## Model\n");
    let u = &summary.unknowns;
    let _ = writeln!(r, "| nodes | soil elements | bars | interface points | stages |");
    let _ = writeln!(r, "|---:|---:|---:|---:|---:|");
    let _ = writeln!(
        r,
        "| {} | {} | {} | {} | {} |",
        u.nodes,
        u.soil_elements,
        u.bars,
        u.interface_points,
        model.stages.len()
    );
    if let Some(m) = &model.mesh_source {
        let names = |dim: usize| -> String {
            let v: Vec<String> = m.groups.iter().filter(|g| g.0 == dim).map(|g| format!("`{}`", g.1)).collect();
            if v.is_empty() {
                "none".into()
            } else {
                v.join(", ")
            }
        };
        let how = match &m.generated {
            Some(g) => format!("meshed for this run by Gmsh {} (saved as `mesh.msh`)", g.gmsh_version),
            None => format!("Gmsh format {}", m.format),
        };
        let _ = writeln!(
            r,
            "\nMesh: `{}`, {how}; physical surfaces {}, curves {}, points {}.",
            m.file.display(),
            names(2),
            names(1),
            names(0)
        );
    }
    let _ = writeln!(r, "\n| interface | law | faces | points |");
    let _ = writeln!(r, "|---|---|---:|---:|");
    for i in &model.interfaces {
        let points: usize = i.faces.iter().map(|f| f.points.len()).sum();
        // an embedded reinforcement's one face stands for both of its faces
        let faces = if i.faces.iter().any(|f| f.embedded.is_some()) {
            "2 (embedded: one set of points for both)".to_string()
        } else {
            i.faces.len().to_string()
        };
        let _ = writeln!(
            r,
            "| {} | {} | {} | {} |",
            i.name,
            i.faces.iter().map(|f| f.law.name()).collect::<Vec<_>>().join(" / "),
            faces,
            points
        );
    }
    let a = &model.analysis;
    let _ = writeln!(
        r,
        "\nIteration: `{:?}`, re-association `{:?}`, force tolerance {:e}, at most {} iterations{} and {} cutbacks per increment.",
        a.scheme,
        a.reassociation,
        a.force_tolerance,
        a.max_iterations,
        match a.stall_iterations {
            0 => String::new(),
            n => format!(" ({n} without progress)"),
        },
        a.max_cutbacks
    );
}

/// The key results (the peak of each curve, the factors of safety, the last step) and the figures.
fn key_results(
    r: &mut String,
    summary: &RunSummary,
    history: &[HistoryRow],
    units: &crate::model::UnitLabels,
    figures: &[(String, String)],
) {
    let _ = writeln!(r, "\n## Key results\n");
    if history.is_empty() {
        let _ = writeln!(r, "No prescribed displacement is followed in this model.");
    } else {
        let _ = writeln!(
            r,
            "| target | direction | final displacement [{}] | final reaction [{}] | peak \\|reaction\\| [{}] |",
            units.length, units.force_per_width, units.force_per_width
        );
        let _ = writeln!(r, "|---|---|---:|---:|---:|");
        let mut targets: Vec<(String, &str)> = history.iter().map(|h| (h.target.clone(), h.direction)).collect();
        targets.dedup();
        targets.sort();
        targets.dedup();
        for (t, d) in targets {
            let rows: Vec<&HistoryRow> = history.iter().filter(|h| h.target == t && h.direction == d).collect();
            let peak = rows.iter().fold(0.0f64, |m, h| m.max(h.reaction.abs()));
            if let Some(last) = rows.last() {
                let _ = writeln!(r, "| {t} | {d} | {} | {} | {peak:.6e} |", num(last.displacement), num(last.reaction));
            }
        }
    }
    for fs in &summary.factors_of_safety {
        let _ = writeln!(
            r,
            "\n**Factor of safety** (stage \"{}\", strength reduction of the {}): **FS = {:.3}**{}. Factors tried: {}. The \
             results of the stage's last step are the state at FS: the interface points sliding there and the \
             reinforcement forces show the mechanism.",
            fs.stage,
            fs.reduced,
            fs.value,
            match fs.failed_at {
                Some(f) => format!(" (no equilibrium at {f:.4})"),
                None => " (at least: equilibrium at every factor tried)".to_string(),
            },
            fs.trials
                .iter()
                .map(|(f, ok)| format!("{f:.4} {}", if *ok { "✓" } else { "✗" }))
                .collect::<Vec<_>>()
                .join(", ")
        );
        if let (Some(f), Some(why)) = (fs.failed_at, &fs.failure) {
            let _ = writeln!(
                r,
                "
At F = {f:.4}: {why}."
            );
        }
    }
    if let Some(last) = summary.steps.last() {
        for b in &last.balance {
            let _ = writeln!(
                r,
                "\nForce balance of `{}` at the last step: applied ({:.6e}, {:.6e}), carried by its interfaces ({:.6e}, {:.6e}) [{}]; mismatch {:.1e}.",
                b.interface, b.applied[0], b.applied[1], b.interface_force[0], b.interface_force[1], units.force_per_width, b.mismatch
            );
            if let Some(bearing) = b.bearing_force {
                let friction = [b.interface_force[0] - bearing[0], b.interface_force[1] - bearing[1]];
                let _ = writeln!(
                    r,
                    "Of the force its interfaces carry, the transverse members' passive bearing carries ({:.6e}, {:.6e}) and friction with the normal forces ({:.6e}, {:.6e}) [{}].",
                    bearing[0], bearing[1], friction[0], friction[1], units.force_per_width
                );
            }
        }
    }

    for (stem, caption) in figures {
        figure(r, stem, caption);
    }
}

/// A figure written as `<stem>.png` and `.svg`, with its caption.
fn figure(r: &mut String, stem: &str, caption: &str) {
    let _ = writeln!(r, "\n![{caption}]({stem}.png)\n\n*{caption}* ([SVG]({stem}.svg))");
}

/// Events, warnings, the convergence history and the re-associations.
fn run_history(r: &mut String, summary: &RunSummary) {
    let _ = writeln!(r, "\n## Events\n");
    if summary.events.is_empty() {
        let _ = writeln!(r, "None.");
    }
    for e in &summary.events {
        let _ = writeln!(r, "- {e}");
    }

    let _ = writeln!(r, "\n## Warnings and notes\n");
    let warnings: Vec<String> =
        summary.solver_stats.warnings.texts().into_iter().chain(summary.notes.iter().cloned()).collect();
    if warnings.is_empty() {
        let _ = writeln!(r, "None.");
    }
    for w in warnings {
        let _ = writeln!(r, "- {w}");
    }

    let _ = writeln!(r, "\n## Convergence history\n");
    let _ = writeln!(r, "| stage | step | load factor | iterations | cutbacks | force residual | max ‖Ax−b‖/‖b‖ | sliding / in contact | yielding soil points | state changes | re-associations |");
    let _ = writeln!(r, "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for s in &summary.steps {
        let lin = s.linear_residuals.iter().cloned().fold(0.0f64, f64::max);
        let _ = writeln!(
            r,
            "| {} | {} | {:.4} | {} | {} | {:.1e} | {:.1e} | {} / {} | {} | {} | {} |",
            s.stage,
            s.step,
            s.load_factor,
            s.iterations,
            s.cutbacks,
            s.force_residual,
            lin,
            s.sliding_points,
            s.contact_points,
            s.yielding_points,
            s.state_changes.len(),
            s.reassociations.len()
        );
    }
    let st = &summary.solver_stats;
    let _ = writeln!(
        r,
        "\nLinear algebra: {} analyses ({:.3} s), {} factorisations of {} matrices ({:.3} s), {} solves ({:.3} s); largest relative residual {:.1e}.",
        st.solver.analyses,
        st.solver.analyse_seconds,
        st.solver.factorizations,
        if st.solver.symmetric { "symmetric" } else { "unsymmetric" },
        st.solver.factorize_seconds,
        st.solver.solves,
        st.solver.solve_seconds,
        st.solver.max_relative_residual
    );
    if let Some(kept) = st.solver.condensed_unknowns {
        let _ = writeln!(
            r,
            "The interface iteration condensed the soil onto {kept} kept unknowns: {} dense factorisations, {} low-rank updates and {} BiCGSTAB iterations preconditioned by the last factorisation ({:.3} s with its solves).",
            st.solver.dense_factorizations, st.solver.dense_updates, st.solver.dense_iterations, st.solver.dense_seconds
        );
    }

    let _ = writeln!(r, "\n## Re-associations\n");
    let total: usize = summary.steps.iter().map(|s| s.reassociations.len()).sum();
    let _ = writeln!(r, "{total} in all; the first ones:\n");
    for (s, ra) in summary.steps.iter().flat_map(|s| s.reassociations.iter().map(move |ra| (s, ra))).take(30) {
        let seg = |v: &Option<[u64; 2]>| v.map(|[a, b]| format!("{a}–{b}")).unwrap_or_else(|| "out of contact".into());
        let _ = writeln!(
            r,
            "- stage \"{}\" step {}: `{}` {} face, node {}: {} → {} (ξ = {:.3})",
            s.stage,
            s.step,
            ra.interface,
            ra.face,
            ra.slave_node,
            seg(&ra.from),
            seg(&ra.to),
            ra.xi
        );
    }
}
