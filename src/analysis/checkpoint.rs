//! What a run needs to continue from a completed step: the state, what the stages so far added to
//! the run (held DOFs, gravity, the weight in the applied force), the stage's progress, and prints
//! of the model it was made with, so that a continuation on a model changed where it matters is
//! refused with the reason.
//!
//! A checkpoint is taken after every converged step of a loading stage (not inside a
//! strength-reduction search, which starts again from the stage before it). Continuing from it
//! ([`super::resume`]) gives the same later steps as the run that wrote it: the same state enters
//! the same iterations.

use super::stage::progress::StageProgress;
use super::state::State;
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::hash::{Hash, Hasher};

/// Everything a run carries past one converged step.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    /// The geoslip version that wrote it (prints are compared only within one version).
    pub geoslip_version: String,
    pub model: ModelPrint,
    /// The stage (index in the model) and its converged step number (as in the outputs).
    pub stage_index: usize,
    pub stage: String,
    pub step: usize,
    pub state: State,
    /// DOFs held by the supports and the prescribed displacements of the stages so far.
    pub held: Vec<bool>,
    /// The sum of the gravity factors of the stages so far.
    pub gravity: f64,
    /// The soil's weight and the boundary water pressure in the applied force.
    pub applied_weight: Vec<f64>,
    pub progress: StageProgress,
}

/// Prints of the parts of a model a saved state depends on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelPrint {
    pub mesh: u64,
    pub materials: u64,
    pub interfaces: u64,
    pub supports: u64,
    /// One per stage.
    pub stages: Vec<u64>,
    /// One per setting of `[analysis]`, by name, and the model's units: each changes the answers.
    pub settings: Vec<(String, u64)>,
}

fn print_of(value: &impl std::fmt::Debug) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!("{value:?}").hash(&mut h);
    h.finish()
}

/// A print of each `[analysis]` setting, named as the model file names it, and of the units.
fn settings_of(model: &Model) -> Vec<(String, u64)> {
    let mut settings = vec![("units".to_string(), print_of(&model.units))];
    if let Ok(serde_json::Value::Object(fields)) = serde_json::to_value(&model.analysis) {
        settings.extend(fields.iter().map(|(name, value)| (format!("analysis.{name}"), print_of(&value.to_string()))));
    }
    settings
}

impl ModelPrint {
    pub fn of(model: &Model) -> ModelPrint {
        let mesh = &model.mesh;
        ModelPrint {
            mesh: print_of(&(&mesh.nodes, &mesh.solids, &mesh.bars, mesh.geometry)),
            materials: print_of(&(&model.soils, &model.reinforcements)),
            interfaces: print_of(&model.interfaces),
            supports: print_of(&model.supports),
            stages: model.stages.iter().map(print_of).collect(),
            settings: settings_of(model),
        }
    }
}

/// Why a saved state cannot be continued on a model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResumeRefusal {
    #[error("it was written by geoslip {written}, and this is geoslip {running}: continue it with the version that wrote it")]
    Version { written: String, running: String },
    #[error(
        "the {what} changed since the run that saved it ({detail}): the saved state belongs to the model as it was; run the model from the start"
    )]
    Changed { what: &'static str, detail: &'static str },
    #[error("its stage index {index} is past the model's {stages} stages")]
    NoStage { index: usize, stages: usize },
    #[error(
        "`{setting}` changed since the run that saved it: the saved state was reached with the setting as it was, and \
         continuing with another would mix two analyses; set it back, or run the model from the start"
    )]
    Setting { setting: String },
    #[error(
        "stage {index} (\"{name}\") changed or is gone: a continuation from stage \"{saved}\" keeps every stage up to that one; change only the stages after it (or continue from the end of the stage before the one you changed)"
    )]
    StageChanged { index: usize, name: String, saved: String },
}

impl Checkpoint {
    /// Whether this state can be continued on `model`: same version, same mesh, materials,
    /// interfaces and supports, and the same stages up to and including its own (the later ones
    /// may be changed, added or removed).
    ///
    /// # Errors
    /// The first [`ResumeRefusal`] found.
    pub fn fits(&self, model: &Model) -> Result<(), ResumeRefusal> {
        let running = env!("CARGO_PKG_VERSION");
        if self.geoslip_version != running {
            return Err(ResumeRefusal::Version { written: self.geoslip_version.clone(), running: running.into() });
        }
        if self.stage_index >= model.stages.len() || self.model.stages.len() <= self.stage_index {
            return Err(ResumeRefusal::NoStage { index: self.stage_index, stages: model.stages.len() });
        }
        let now = ModelPrint::of(model);
        let parts = [
            ("mesh", "its nodes, elements, bars or geometry", self.model.mesh, now.mesh),
            ("materials", "of the soil or the reinforcement", self.model.materials, now.materials),
            ("interfaces", "their lines, faces or laws", self.model.interfaces, now.interfaces),
            ("supports", "the nodes and directions held", self.model.supports, now.supports),
        ];
        if let Some(&(what, detail, _, _)) = parts.iter().find(|(_, _, a, b)| a != b) {
            return Err(ResumeRefusal::Changed { what, detail });
        }
        if self.model.settings != now.settings {
            let setting = now
                .settings
                .iter()
                .find(|s| !self.model.settings.contains(s))
                .or_else(|| self.model.settings.iter().find(|s| !now.settings.contains(s)))
                .map_or_else(|| "analysis".to_string(), |(name, _)| name.clone());
            return Err(ResumeRefusal::Setting { setting });
        }
        for index in 0..=self.stage_index {
            if self.model.stages.get(index) != now.stages.get(index) {
                let name = model.stages.get(index).map_or_else(|| "none".to_string(), |s| s.name.clone());
                return Err(ResumeRefusal::StageChanged { index: index + 1, name, saved: self.stage.clone() });
            }
        }
        Ok(())
    }
}
