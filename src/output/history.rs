//! The history of the prescribed targets: one typed row per step and target, written as
//! `history.csv` and read by the report and the plots as numbers.

use super::folder::{csv_bytes, num};
use crate::model::UnitLabels;

/// A prescribed target's mean displacement and total reaction at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryRow {
    pub stage: String,
    pub step: usize,
    pub load_factor: f64,
    /// The target's node set (or node).
    pub target: String,
    /// `x` or `y`.
    pub direction: &'static str,
    pub displacement: f64,
    pub reaction: f64,
}

impl HistoryRow {
    /// The row as `history.csv` writes it.
    fn cells(&self) -> Vec<String> {
        vec![
            self.stage.clone(),
            self.step.to_string(),
            num(self.load_factor),
            self.target.clone(),
            self.direction.to_string(),
            num(self.displacement),
            num(self.reaction),
        ]
    }
}

/// `history.csv`: a header with the units, then the rows.
pub(super) fn csv(rows: &[HistoryRow], units: &UnitLabels) -> Vec<u8> {
    let header = vec![
        "stage".to_string(),
        "step".into(),
        "load_factor [-]".into(),
        "target".into(),
        "direction".into(),
        format!("displacement [{}]", units.length),
        format!("reaction [{}]", units.force_per_width),
    ];
    csv_bytes(&header, rows.iter().map(HistoryRow::cells))
}
