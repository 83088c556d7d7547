//! The run's figures: the force against displacement of each prescribed target, and T(x), u(x),
//! τ(x) and σn(x) along each reinforcement at the steps worth showing.

use super::plots;
use crate::analysis::results::StepResults;
use crate::error::Error;
use crate::model::UnitLabels;

/// T(x), u(x), τ(x) and σn(x) along one reinforcement at one step.
#[derive(Debug, Clone)]
pub(super) struct ReinforcementProfile {
    tension: Vec<(f64, f64)>,
    displacement: Vec<(f64, f64)>,
    shear: Vec<(f64, f64)>,
    normal: Vec<(f64, f64)>,
    /// Which face τ and σn are of: `upper face`, or `each face` of an embedded reinforcement.
    face: &'static str,
}

impl ReinforcementProfile {
    /// The largest tension along the reinforcement and the x of the bar that carries it (none for
    /// a reinforcement without bars).
    pub(super) fn largest_tension(&self) -> Option<(f64, f64)> {
        self.tension.iter().map(|&(x, t)| (t, x)).max_by(|a, b| a.0.total_cmp(&b.0))
    }
}

#[derive(Debug, Clone)]
pub(super) struct StepProfile {
    pub label: String,
    pub reinforcements: Vec<ReinforcementProfile>,
}

/// A reinforcement interface's nodes: their ids, and their places in the mesh's node list (in
/// that list's order), which are those of `StepResults::displacements`.
pub(super) struct ReinforcementNodes {
    pub name: String,
    pub ids: std::collections::HashSet<u64>,
    pub indices: Vec<usize>,
}

pub(super) fn profile(nodes: &ReinforcementNodes, r: &StepResults) -> ReinforcementProfile {
    let name = nodes.name.as_str();
    let mut tension: Vec<(f64, f64)> = r
        .bar_forces
        .iter()
        .filter(|b| nodes.ids.contains(&b.nodes[0]) && nodes.ids.contains(&b.nodes[1]))
        .map(|b| (b.midpoint[0], b.axial_force))
        .collect();
    // (the reinforcement's own nodes, not every node of the mesh looked up in the set)
    let mut displacement: Vec<(f64, f64)> =
        nodes.indices.iter().filter_map(|&n| r.displacements.get(n)).map(|(_, x, u)| (x[0], u[0])).collect();
    let upper = |p: &&crate::analysis::results::InterfacePointResult| {
        p.interface == name && (p.face == "upper" || p.face == "embedded") && p.state != "outside"
    };
    let mut shear: Vec<(f64, f64)> = r.interface_points.iter().filter(upper).map(|p| (p.x[0], p.tau)).collect();
    let mut normal: Vec<(f64, f64)> =
        r.interface_points.iter().filter(upper).filter(|p| p.tributary > 0.0).map(|p| (p.x[0], p.sigma_n)).collect();
    for v in [&mut tension, &mut displacement, &mut shear, &mut normal] {
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let face = if r.interface_points.iter().any(|p| p.interface == name && p.face == "embedded") {
        "each face"
    } else {
        "upper face"
    };
    ReinforcementProfile { tension, displacement, shear, normal, face }
}

/// What the figures are drawn from.
pub(super) struct Figures<'a> {
    pub folder: &'a super::owned_folder::OwnedFolder,
    pub units: &'a UnitLabels,
    /// Each prescribed target: its label, its direction (`x` or `y`) and its (displacement,
    /// reaction) at each step.
    pub curves: Vec<(&'a str, &'static str, Vec<(f64, f64)>)>,
    /// The profiles along each reinforcement at each step.
    pub profiles: &'a [StepProfile],
    /// Steps worth drawing: where slip starts, where everything slides.
    pub marked_steps: &'a [usize],
    /// The reinforcements' names, in the order of each profile's.
    pub reinforcements: Vec<&'a str>,
}

impl Figures<'_> {
    /// The pull-out curves and the profiles along each reinforcement; returns the figure stems.
    pub fn write(&self) -> Result<Vec<(String, String)>, Error> {
        let u = self.units;
        let mut figures = Vec::new();
        // pull-out curves: one panel per prescribed target
        let mut panels = Vec::new();
        for (label, dir, signed) in &self.curves {
            let signed = signed.clone();
            // a monotonic pull is drawn as magnitudes; a displacement that changes sign (cyclic
            // loading) is drawn with its signs, so that the loops show
            let largest = signed.iter().fold(0.0f64, |a, p| a.max(p.0.abs()));
            // (1 % of the largest either way: the small opposite movement of a head under the
            // confining stage is not a reversal)
            let both_ways = signed.iter().any(|p| p.0 > 0.01 * largest) && signed.iter().any(|p| p.0 < -0.01 * largest);
            let (points, bars) = if both_ways {
                (signed, ("", ""))
            } else {
                (signed.into_iter().map(|(x, y)| (x.abs(), y.abs())).collect(), ("|", "|"))
            };
            panels.push(plots::Panel {
                title: format!("{label} ({dir}): force against displacement"),
                x_label: format!("{}displacement{} [{}]", bars.0, bars.1, u.length),
                y_label: format!("{}reaction{} [{}]", bars.0, bars.1, u.force_per_width),
                series: vec![(String::new(), points)],
                markers_only: Vec::new(),
            });
        }
        if !panels.is_empty() {
            plots::write_figure(self.folder, "pullout", &panels, panels.len().min(2))?;
            figures.push(("pullout".to_string(), "Force against displacement of each prescribed target".to_string()));
        }
        // profiles at the marked steps and the last one
        // (a marked step has its profile unless the run stopped while writing it)
        let mut chosen: Vec<usize> = self.marked_steps.iter().copied().filter(|&s| s < self.profiles.len()).collect();
        if let Some(last) = self.profiles.len().checked_sub(1) {
            chosen.push(last);
        }
        chosen.sort_unstable();
        chosen.dedup();
        for (k, name) in self.reinforcements.iter().enumerate() {
            let series = |pick: &dyn Fn(&ReinforcementProfile) -> Vec<(f64, f64)>| -> Vec<plots::Series> {
                chosen
                    .iter()
                    .map(|&s| (self.profiles[s].label.clone(), pick(&self.profiles[s].reinforcements[k])))
                    .collect()
            };
            let x = format!("x at the reference position [{}]", u.length);
            let face = chosen.last().map_or("upper face", |&s| self.profiles[s].reinforcements[k].face);
            let panels = vec![
                plots::Panel {
                    title: format!("{name}: tension T(x)"),
                    x_label: x.clone(),
                    y_label: format!("T [{}]", u.force_per_width),
                    series: series(&|p| p.tension.clone()),
                    markers_only: Vec::new(),
                },
                plots::Panel {
                    title: format!("{name}: displacement u(x)"),
                    x_label: x.clone(),
                    y_label: format!("ux [{}]", u.length),
                    series: series(&|p| p.displacement.clone()),
                    markers_only: Vec::new(),
                },
                plots::Panel {
                    title: format!("{name}: shear stress τ(x), {face}"),
                    x_label: x.clone(),
                    y_label: format!("τ [{}]", u.stress),
                    series: series(&|p| p.shear.clone()),
                    markers_only: Vec::new(),
                },
                plots::Panel {
                    title: format!("{name}: normal stress σn(x), {face}"),
                    x_label: x,
                    y_label: format!("σn [{}]", u.stress),
                    series: series(&|p| p.normal.clone()),
                    markers_only: Vec::new(),
                },
            ];
            let stem = format!("profiles-{}", name.replace(|c: char| !c.is_ascii_alphanumeric() && c != '-', "-"));
            plots::write_figure(self.folder, &stem, &panels, 2)?;
            figures.push((stem, format!("T(x), u(x), τ(x) and σn(x) along {name}")));
        }
        Ok(figures)
    }
}
