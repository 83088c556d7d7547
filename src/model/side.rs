//! A side of a soil element, as a load or a boundary names it.

/// A soil element side (that carries a traction, or lets waves out): element index and local side
/// index.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadedSide {
    pub solid: usize,
    pub side: usize,
}
