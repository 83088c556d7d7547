//! Gmsh meshes: read `.msh` files (format 4.1, ASCII or binary, in `msh41`; format 2.2 ASCII, in
//! `msh22`) with their `$PhysicalNames` (`read`), and run Debian's `gmsh` on a `.geo` file, confined
//! (`mesher`, `confinement`).
//!
//! The result is a flat [`GmshMesh`] (`types`): node tags with x–y coordinates, elements with their
//! Gmsh type and the physical groups they belong to, and the physical groups by dimension, tag and
//! name. Turning that into soil elements, node and edge sets and reinforcement paths is the model's
//! job (`model::import`).

mod confinement;
mod mesher;
mod msh22;
mod msh41;
mod read;
mod types;

pub use confinement::ConfineError;
pub use mesher::{mesh_geometry, refuse_script_actions, GeneratedMesh, MeshingOptions};
pub use read::{check_declared_size, declared_counts};
pub use types::{GmshElement, GmshError, GmshKind, GmshMesh, PhysicalGroup};
