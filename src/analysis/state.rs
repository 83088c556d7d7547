//! The state carried from step to step: what a cutback restores and a converged increment commits.

use super::options::RunOptions;
use super::soil;
use crate::element::bar::BarStates;
use crate::element::soil_state::SoilField;
use crate::interface::{multipliers, reserve_windows, Interface};
use crate::model::{Model, ReassociationRule};

/// The state carried from step to step.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct State {
    /// Displacements of every node, `2·node + d`.
    pub u: Vec<f64>,
    /// Multipliers in `dofs::multipliers` order.
    pub lambda: Vec<f64>,
    pub interfaces: Vec<Interface>,
    /// Total external force applied so far.
    pub f_ext: Vec<f64>,
    /// Displacements at the end of the last converged increment (slip increments start there).
    pub u_committed: Vec<f64>,
    /// σn per spring frozen at the start of the stage (when asked for).
    pub frozen_sigma_n: Option<Vec<f64>>,
    /// The displacements whose soil stress gives an embedded reinforcement's σn in this pass of
    /// the increment (`None`: the last converged increment's; see `equilibrium/settle.rs`).
    pub soil_sigma_from: Option<Vec<f64>>,
    /// Bars (in mesh order): ruptured, not yet placed, stretch at placement.
    pub bars: BarStates,
    /// The soil: present elements, Gauss-point stresses, pore pressures.
    pub soil: SoilField,
    /// Nodes of soil or reinforcement in place now: a face whose master segment is not (cover soil
    /// still to come over a liner) has no contact there. Empty: every node.
    pub placed: Vec<bool>,
    /// While a dynamic stage runs: time, velocities, accelerations (a dynamic stage keeps no
    /// saved steps, so a saved step never holds one).
    #[serde(skip)]
    pub motion: Option<super::time_scheme::Motion>,
}

impl State {
    /// Before the first stage: nothing displaced, no force, every interface point as the model
    /// built it, the soil and bars present that no stage places later.
    pub fn initial(model: &Model, options: &RunOptions) -> State {
        let dof_count = 2 * model.mesh.nodes.len();
        let mut state = State {
            u: vec![0.0; dof_count],
            lambda: vec![0.0; multipliers(&model.interfaces).len()],
            interfaces: model.interfaces.clone(),
            f_ext: vec![0.0; dof_count],
            u_committed: vec![0.0; dof_count],
            frozen_sigma_n: None,
            soil_sigma_from: None,
            bars: BarStates { absent: model.initially_absent_bars(), ..BarStates::new(model.mesh.bars.len()) },
            soil: soil::initial_field(&model.initially_absent()),
            placed: Vec::new(),
            motion: None,
        };
        state.reserve_segments(options);
        state
    }

    /// Reserve master segments around every interface point (see
    /// `AnalysisSettings::reserved_segments`).
    pub fn reserve_segments(&mut self, options: &RunOptions) {
        if options.analysis.reassociation != ReassociationRule::None && options.analysis.reserved_segments > 0 {
            reserve_windows(&mut self.interfaces, options.analysis.reserved_segments);
        }
    }
}
