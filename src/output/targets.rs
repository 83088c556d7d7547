//! The prescribed targets a run follows: each one's mean displacement and total reaction at every
//! step, its largest reaction so far, and a fall from that peak.

use super::history::HistoryRow;
use super::summary::TargetPeak;
use crate::analysis::results::StepResults;
use crate::analysis::StepRecord;
use crate::dofs::dof;
use crate::model::file::Direction;
use crate::model::Model;

/// A fall of the reaction below this fraction of its peak is reported (once per peak).
const FALL_FROM_PEAK: f64 = 0.98;

/// A prescribed target followed through the run: its mean displacement and total reaction.
struct Target {
    label: String,
    nodes: Vec<usize>,
    direction: Direction,
}

impl Target {
    fn direction_label(&self) -> &'static str {
        if self.direction == Direction::X {
            "x"
        } else {
            "y"
        }
    }
}

/// Every prescribed target of a model, with the peak of its reaction so far.
pub struct Targets {
    targets: Vec<Target>,
    /// Largest |reaction| so far per target, and whether a drop from it was reported.
    peak_reaction: Vec<(f64, bool)>,
    /// The target's displacement where its reaction peaked.
    peak_displacement: Vec<f64>,
}

/// What one step did to the targets.
pub struct TargetStep {
    /// One history row per target.
    pub rows: Vec<HistoryRow>,
    /// Each target's (mean displacement, total reaction).
    pub values: Vec<(f64, f64)>,
    /// The targets whose reaction reached a new peak at this step.
    pub peaked: Vec<usize>,
    /// The targets whose reaction fell from its peak at this step, each with the event's text.
    pub fell: Vec<(usize, String)>,
}

impl Targets {
    /// The nodes every stage prescribes a displacement on, grouped by the node set that holds
    /// them (or by node) and direction.
    pub fn of_model(model: &Model) -> Targets {
        let mut targets: Vec<Target> = Vec::new();
        for stage in &model.stages {
            for &(n, d, _) in &stage.prescribed {
                let set = model.node_sets.iter().find(|(_, nodes)| nodes.contains(&n)).map(|(name, _)| name.clone());
                let label = set.unwrap_or_else(|| format!("node {}", model.mesh.node_id(n)));
                match targets.iter_mut().find(|t| t.label == label && t.direction == d) {
                    Some(t) => {
                        if !t.nodes.contains(&n) {
                            t.nodes.push(n)
                        }
                    }
                    None => targets.push(Target { label, nodes: vec![n], direction: d }),
                }
            }
        }
        let count = targets.len();
        Targets { targets, peak_reaction: vec![(0.0, false); count], peak_displacement: vec![0.0; count] }
    }

    /// How many targets there are.
    pub fn count(&self) -> usize {
        self.targets.len()
    }

    /// Each target as (label, `x` or `y`, nodes).
    pub fn list(&self) -> Vec<(String, &'static str, Vec<usize>)> {
        self.targets.iter().map(|t| (t.label.clone(), t.direction_label(), t.nodes.clone())).collect()
    }

    /// Each target as (label, `x` or `y`), for `results.h5`'s history.
    #[cfg(feature = "hdf5")]
    pub fn labels(&self) -> Vec<(&str, &'static str)> {
        self.targets.iter().map(|t| (t.label.as_str(), t.direction_label())).collect()
    }

    /// Each target's largest |reaction| so far, and the displacement where it occurred.
    pub fn peaks(&self) -> Vec<TargetPeak> {
        self.targets
            .iter()
            .enumerate()
            .map(|(i, t)| TargetPeak {
                label: t.label.clone(),
                direction: t.direction,
                reaction: self.peak_reaction[i].0,
                displacement: self.peak_displacement[i],
            })
            .collect()
    }

    /// Each target's displacement and reaction at a converged step (`when` names the step in an
    /// event's text): a new peak, or a fall below 98 % of the last one.
    pub fn observe(&mut self, record: &StepRecord, results: &StepResults, when: &str) -> TargetStep {
        let mut step = TargetStep { rows: Vec::new(), values: Vec::new(), peaked: Vec::new(), fell: Vec::new() };
        for (ti, t) in self.targets.iter().enumerate() {
            let d = |n: usize| dof(n, t.direction);
            let mean_u = t.nodes.iter().map(|&n| results.displacement_vector[d(n)]).sum::<f64>() / t.nodes.len() as f64;
            let reaction: f64 = t.nodes.iter().map(|&n| results.reaction_vector[d(n)]).sum();
            let (peak, reported) = self.peak_reaction[ti];
            if peak > 0.0 && !reported && reaction.abs() < FALL_FROM_PEAK * peak {
                let text = format!(
                    "{when}: the reaction on {} ({}) fell to {:.4} at displacement {:.5}, from its peak {:.4} at displacement {:.5}",
                    t.label,
                    t.direction_label(),
                    reaction.abs(),
                    mean_u,
                    peak,
                    self.peak_displacement[ti]
                );
                self.peak_reaction[ti].1 = true; // once per peak
                step.fell.push((ti, text));
            } else if reaction.abs() > peak {
                self.peak_reaction[ti] = (reaction.abs(), false);
                self.peak_displacement[ti] = mean_u;
                step.peaked.push(ti);
            }
            step.rows.push(HistoryRow {
                stage: record.stage.clone(),
                step: record.step,
                load_factor: record.load_factor,
                target: t.label.clone(),
                direction: t.direction_label(),
                displacement: mean_u,
                reaction,
            });
            step.values.push((mean_u, reaction));
        }
        step
    }

    /// Each target's (label, `x` or `y`, its (displacement, reaction) points) from the history.
    pub fn curves<'a>(&'a self, history: &[HistoryRow]) -> Vec<(&'a str, &'static str, Vec<(f64, f64)>)> {
        self.targets
            .iter()
            .map(|t| {
                let dir = t.direction_label();
                let points = history
                    .iter()
                    .filter(|h| h.target == t.label && h.direction == dir)
                    .map(|h| (h.displacement, h.reaction))
                    .collect();
                (t.label.as_str(), dir, points)
            })
            .collect()
    }
}
