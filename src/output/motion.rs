//! The histories of the dynamic stages: at every time step the base's acceleration, each recorded
//! node set's mean displacement and velocity (relative to a rigid base, absolute over a compliant
//! one, as the headers say) and its absolute acceleration,
//! each interface's mean slip and each reinforcement's largest tension; written as `motion.csv`,
//! drawn as `motion.png`/`.svg`, and summed up per stage in the report (the permanent slip, the
//! peak and end-of-shaking loads).

use super::folder::{csv_bytes, num};
use super::owned_folder::OwnedFolder;
use super::plots::{write_figure, Panel, Series};
use crate::analysis::results::StepResults;
use crate::analysis::StepRecord;
use crate::error::Error;
use crate::model::{Model, UnitLabels};
use std::fmt::Write;

/// One time step's row.
#[derive(Debug, Clone)]
struct Row {
    stage_index: usize,
    step: usize,
    time: f64,
    ground: [f64; 2],
    /// Per recorded set: ux, uy, vx, vy (in the history's `Frame`), ax, ay (absolute).
    sets: Vec<[f64; 6]>,
    /// Per interface: its mean slip.
    slips: Vec<f64>,
    /// Per reinforcement: its largest tension.
    tensions: Vec<f64>,
}

/// What a dynamic stage started from: its interfaces' slip and its reinforcements' largest
/// tension at the step before it.
#[derive(Debug, Clone)]
struct StageStart {
    stage_index: usize,
    name: String,
    slips: Vec<f64>,
    tensions: Vec<f64>,
}

/// The dynamic stages' histories.
pub(super) struct MotionHistory {
    /// The node sets recorded in any dynamic stage: (name, nodes).
    sets: Vec<(String, Vec<usize>)>,
    interfaces: Vec<String>,
    reinforcements: Vec<String>,
    rows: Vec<Row>,
    starts: Vec<StageStart>,
    /// The last step's interface slips and reinforcement tensions (a dynamic stage starts from
    /// them).
    last: (Vec<f64>, Vec<f64>),
    /// What the displacements and velocities are measured from (`Frame`).
    frame: Frame,
}

/// What the recorded displacements and velocities are measured from: the base where it is rigid
/// (the stage shakes the model in the base's frame), a fixed point over a compliant base.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Frame {
    Relative,
    Absolute,
    /// Some dynamic stages on a rigid base, some on a compliant one.
    Mixed,
}

impl Frame {
    /// The word the headers and captions use.
    fn word(self) -> &'static str {
        match self {
            Frame::Relative => "relative",
            Frame::Absolute => "absolute",
            Frame::Mixed => "relative-or-absolute",
        }
    }
}

impl MotionHistory {
    /// The histories of `model`'s dynamic stages (`reinforcements`: the reinforcement interfaces'
    /// names, in the order their tensions come); `None` when it has none.
    pub fn new(model: &Model, reinforcements: Vec<String>) -> Option<MotionHistory> {
        let dynamic: Vec<_> = model.stages.iter().filter_map(|s| s.dynamic.as_ref()).collect();
        if dynamic.is_empty() {
            return None;
        }
        let mut sets: Vec<(String, Vec<usize>)> = Vec::new();
        for name in dynamic.iter().flat_map(|d| &d.record) {
            if !sets.iter().any(|(n, _)| n == name) {
                sets.push((name.clone(), model.node_sets.get(name).cloned().unwrap_or_default()));
            }
        }
        let interfaces: Vec<String> = model.interfaces.iter().map(|i| i.name.clone()).collect();
        let last = (vec![0.0; interfaces.len()], vec![0.0; reinforcements.len()]);
        let frame = match (dynamic.iter().all(|d| !d.compliant_base), dynamic.iter().all(|d| d.compliant_base)) {
            (true, _) => Frame::Relative,
            (_, true) => Frame::Absolute,
            _ => Frame::Mixed,
        };
        Some(MotionHistory { sets, interfaces, reinforcements, rows: Vec::new(), starts: Vec::new(), last, frame })
    }

    /// Take a converged step (`tensions`: each reinforcement's largest tension in it).
    pub fn push(&mut self, record: &StepRecord, results: &StepResults, tensions: Vec<f64>) {
        let slips: Vec<f64> = self.interfaces.iter().map(|name| mean_slip(results, name)).collect();
        if let Some(motion) = &results.motion {
            if self.starts.last().is_none_or(|s| s.stage_index != record.stage_index) {
                self.starts.push(StageStart {
                    stage_index: record.stage_index,
                    name: record.stage.clone(),
                    slips: self.last.0.clone(),
                    tensions: self.last.1.clone(),
                });
            }
            let sets = self
                .sets
                .iter()
                .map(|(_, nodes)| {
                    let mean = |v: &[f64], d: usize| {
                        nodes.iter().map(|&n| v[2 * n + d]).sum::<f64>() / nodes.len().max(1) as f64
                    };
                    let u = &results.displacement_vector;
                    let (v, a) = (&motion.velocity, &motion.acceleration);
                    // over a rigid base, the absolute acceleration is the relative one plus the base's
                    let base = if motion.relative { motion.ground } else { [0.0; 2] };
                    [mean(u, 0), mean(u, 1), mean(v, 0), mean(v, 1), mean(a, 0) + base[0], mean(a, 1) + base[1]]
                })
                .collect();
            self.rows.push(Row {
                stage_index: record.stage_index,
                step: record.step,
                time: motion.time,
                ground: motion.ground,
                sets,
                slips: slips.clone(),
                tensions: tensions.clone(),
            });
        }
        self.last = (slips, tensions);
    }

    /// `motion.csv`: a header with the units, then a row per time step.
    pub fn csv(&self, units: &UnitLabels) -> Vec<u8> {
        let (l, f) = (units.length, units.force_per_width.as_str());
        let mut header: Vec<String> = vec![
            "stage".into(),
            "step".into(),
            "time [s]".into(),
            format!("ground ax [{l}/s2]"),
            format!("ground ay [{l}/s2]"),
        ];
        let frame = self.frame.word();
        for (name, _) in &self.sets {
            for (what, unit) in [
                (format!("ux {frame}"), l.to_string()),
                (format!("uy {frame}"), l.to_string()),
                (format!("vx {frame}"), format!("{l}/s")),
                (format!("vy {frame}"), format!("{l}/s")),
                ("ax absolute".to_string(), format!("{l}/s2")),
                ("ay absolute".to_string(), format!("{l}/s2")),
            ] {
                header.push(format!("{name} {what} [{unit}]"));
            }
        }
        header.extend(self.interfaces.iter().map(|name| format!("{name} mean slip [{l}]")));
        header.extend(self.reinforcements.iter().map(|name| format!("{name} T_max [{f}]")));
        let stage_name = |k: usize| self.starts.iter().find(|s| s.stage_index == k).map_or("", |s| s.name.as_str());
        let rows = self.rows.iter().map(|r| {
            let mut cells = vec![stage_name(r.stage_index).to_string(), r.step.to_string(), num(r.time)];
            cells.extend(r.ground.iter().map(|&a| num(a)));
            cells.extend(r.sets.iter().flatten().map(|&v| num(v)));
            cells.extend(r.slips.iter().chain(&r.tensions).map(|&v| num(v)));
            cells
        });
        csv_bytes(&header, rows)
    }

    /// `motion.png` and `.svg`: the base's and the recorded sets' accelerations, the interfaces'
    /// slip and the reinforcements' largest tension against time; its stem and caption.
    pub fn figure(&self, folder: &OwnedFolder, units: &UnitLabels) -> Result<Option<(String, String)>, Error> {
        if self.rows.is_empty() {
            return Ok(None);
        }
        let (l, f) = (units.length, units.force_per_width.as_str());
        // time runs on across the dynamic stages
        let times = self.run_times();
        let series = |label: String, value: &dyn Fn(&Row) -> f64| -> Series {
            (label, self.rows.iter().zip(&times).map(|(r, &t)| (t, value(r))).collect())
        };
        let mut accelerations = vec![series("base, x".into(), &|r| r.ground[0])];
        if self.rows.iter().any(|r| r.ground[1] != 0.0) {
            accelerations.push(series("base, y".into(), &|r| r.ground[1]));
        }
        for (k, (name, _)) in self.sets.iter().enumerate() {
            accelerations.push(series(format!("{name}, x"), &|r| r.sets[k][4]));
        }
        let mut panels = vec![Panel {
            title: "Absolute acceleration".into(),
            x_label: "time [s]".into(),
            y_label: format!("a [{l}/s²]"),
            series: accelerations,
            markers_only: Vec::new(),
        }];
        if !self.interfaces.is_empty() {
            panels.push(Panel {
                title: "Interfaces' mean slip".into(),
                x_label: "time [s]".into(),
                y_label: format!("slip [{l}]"),
                series: (0..self.interfaces.len())
                    .map(|k| series(self.interfaces[k].clone(), &|r| r.slips[k]))
                    .collect(),
                markers_only: Vec::new(),
            });
        }
        if !self.reinforcements.is_empty() {
            panels.push(Panel {
                title: "Reinforcements' largest tension".into(),
                x_label: "time [s]".into(),
                y_label: format!("T_max [{f}]"),
                series: (0..self.reinforcements.len())
                    .map(|k| series(self.reinforcements[k].clone(), &|r| r.tensions[k]))
                    .collect(),
                markers_only: Vec::new(),
            });
        }
        if !self.sets.is_empty() {
            panels.push(Panel {
                title: match self.frame {
                    Frame::Relative => "Displacement relative to the base",
                    Frame::Absolute => "Displacement (absolute: a compliant base)",
                    Frame::Mixed => "Displacement (relative to a rigid base, absolute over a compliant one)",
                }
                .into(),
                x_label: "time [s]".into(),
                y_label: format!("ux [{l}]"),
                series: (0..self.sets.len()).map(|k| series(self.sets[k].0.clone(), &|r| r.sets[k][0])).collect(),
                markers_only: Vec::new(),
            });
        }
        write_figure(folder, "motion", &panels, 2)?;
        let caption = "The shaking: accelerations, the interfaces' slip, the reinforcements' tension and the \
                       recorded sets' displacement against time";
        Ok(Some(("motion".into(), caption.into())))
    }

    /// Each row's time counted from the first dynamic stage's start, stage after stage.
    fn run_times(&self) -> Vec<f64> {
        let mut times = Vec::with_capacity(self.rows.len());
        let (mut offset, mut stage, mut last) = (0.0, None, 0.0);
        for r in &self.rows {
            if stage != Some(r.stage_index) {
                offset += last;
                stage = Some(r.stage_index);
            }
            last = r.time;
            times.push(offset + r.time);
        }
        times
    }

    /// The report's section: per dynamic stage, its shaking, each interface's permanent slip, each
    /// reinforcement's tension before, at its peak and at the end, each recorded set's peak
    /// acceleration and final displacement.
    pub fn report_section(&self, r: &mut String, units: &UnitLabels) {
        if self.starts.is_empty() {
            return;
        }
        let (l, f) = (units.length, units.force_per_width.as_str());
        let _ = writeln!(r, "\n## Shaking\n");
        for start in &self.starts {
            let rows: Vec<&Row> = self.rows.iter().filter(|row| row.stage_index == start.stage_index).collect();
            let Some(end) = rows.last() else { continue };
            let peak = |value: &dyn Fn(&Row) -> f64| rows.iter().map(|row| value(row).abs()).fold(0.0, f64::max);
            let _ = writeln!(
                r,
                "Stage \"{}\": {} steps to t = {:.3} s; the base's peak acceleration {:.4} {l}/s² in x, {:.4} in y.\n",
                start.name,
                rows.len(),
                end.time,
                peak(&|row| row.ground[0]),
                peak(&|row| row.ground[1]),
            );
            if !self.interfaces.is_empty() {
                let _ =
                    writeln!(r, "| interface | mean slip before [{l}] | permanent slip [{l}] | largest during [{l}] |");
                let _ = writeln!(r, "|---|---:|---:|---:|");
                for (k, name) in self.interfaces.iter().enumerate() {
                    let before = start.slips[k];
                    let largest = rows.iter().map(|row| row.slips[k] - before).fold(0.0f64, |m, v| {
                        if v.abs() > m.abs() {
                            v
                        } else {
                            m
                        }
                    });
                    let _ = writeln!(r, "| {name} | {before:.5} | {:.5} | {largest:.5} |", end.slips[k] - before);
                }
                let _ = writeln!(r);
            }
            if !self.reinforcements.is_empty() {
                let _ = writeln!(r, "| reinforcement | T_max before [{f}] | peak during [{f}] | at the end [{f}] |");
                let _ = writeln!(r, "|---|---:|---:|---:|");
                for (k, name) in self.reinforcements.iter().enumerate() {
                    let peak = rows.iter().map(|row| row.tensions[k]).fold(f64::NEG_INFINITY, f64::max);
                    let _ = writeln!(r, "| {name} | {:.3} | {peak:.3} | {:.3} |", start.tensions[k], end.tensions[k]);
                }
                let _ = writeln!(r);
            }
            if !self.sets.is_empty() {
                let _ = writeln!(
                    r,
                    "| node set | peak absolute ax [{l}/s²] | peak absolute ay [{l}/s²] | ux at the end [{l}] | uy at the end [{l}] |"
                );
                let _ = writeln!(r, "|---|---:|---:|---:|---:|");
                for (k, (name, _)) in self.sets.iter().enumerate() {
                    let _ = writeln!(
                        r,
                        "| {name} | {:.4} | {:.4} | {:.5} | {:.5} |",
                        peak(&|row| row.sets[k][4]),
                        peak(&|row| row.sets[k][5]),
                        end.sets[k][0],
                        end.sets[k][1]
                    );
                }
                let _ = writeln!(r);
            }
        }
        let _ = writeln!(
            r,
            "{} and count from the model's first stage; an interface's slip is positive towards the first \
             node of its slave line, and its permanent slip is the change of its mean slip over the stage. Every \
             time step is in `motion.csv`.",
            match self.frame {
                Frame::Relative => "Slip and displacements are relative to the base",
                Frame::Absolute =>
                    "Slip is relative, displacements absolute (the base is compliant: it moves with them)",
                Frame::Mixed =>
                    "Slip is relative; displacements are relative to the base in a stage on a rigid base \
                                 and absolute in a stage on a compliant one",
            }
        );
    }
}

/// The mean slip of an interface's points in contact (zero when none is).
fn mean_slip(results: &StepResults, interface: &str) -> f64 {
    let (sum, count) = results
        .interface_points
        .iter()
        .filter(|p| p.interface == interface && p.state != "outside")
        .fold((0.0, 0usize), |(s, c), p| (s + p.slip, c + 1));
    if count == 0 {
        0.0
    } else {
        sum / count as f64
    }
}
