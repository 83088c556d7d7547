//! Design checks of a reinforced soil wall by the code methods, set beside the finite-element answer.
//!
//! A model with a `[design]` table builds a wall whose reinforcement layers are its reinforcement
//! interfaces. After the run, each layer's largest tension from the analysis is set beside:
//! - the AASHTO LRFD / FHWA Simplified Method's T_max ([`simplified`]);
//! - the pull-out resistance of the length beyond the failure surface ([`pullout`]),
//!
//! and the ratios of resistance to load. [`wall`] finds the wall's height, face, layers and surcharge
//! in what the model holds; `docs/design-checks.md` gives the equations and their sources. The
//! module knows nothing of the model: `model/validate/design.rs` hands it the fill's nodes, the
//! reinforcements' nodes and the edge tractions.

pub mod parameters;
pub mod pullout;
pub mod simplified;
pub mod wall;

pub use parameters::{DesignParameters, ReinforcementKind, WallFace};
pub use wall::{LayerCheck, Wall, WallInputs};
