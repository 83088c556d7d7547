//! Result files: the fields of the kept steps (`results.h5` + `results.xdmf` in a build with the
//! `hdf5` feature, ParaView `.vtu` files without it or on request, per-step CSV files on request), a
//! history of the prescribed targets, a JSON run summary, a report and plots.
//!
//! Every file but `results.h5` is written to a temporary file in the same folder and renamed into
//! place, so a crash never leaves a truncated file under a final name; `results.h5` is written in
//! place, flushed after every step, and only `results.xdmf`, rewritten atomically after the flush,
//! says which of its steps are complete (see `results_h5.rs`). Each step's files are handed to
//! the writer thread as soon as the step converges (a step held back by `--keep` as soon as it
//! proves to be kept), and the thread writes every file, in every build, in the order it was
//! handed them (`writer_thread.rs`): a file that lists steps is written after the steps it lists,
//! and completed steps are never lost. The files written whole that grow with the run (the index, the
//! history and the summary) are rewritten at every step while that is cheap, less often once it
//! is not (`pace.rs`), and always at the end.

pub mod checkpoints;
#[cfg(feature = "hdf5")]
mod chunk_deflate;
mod design_checks;
mod events;
mod figures;
mod folder;
pub mod grids;
#[cfg(feature = "hdf5")]
mod h5_arrays;
pub mod history;
pub mod kept_steps;
mod motion;
pub mod options;
pub mod owned_folder;
mod pace;
pub mod plots;
mod record;
mod record_removal;
pub mod report;
#[cfg(feature = "hdf5")]
pub mod results_h5;
mod run;
mod run_timings;
pub mod series;
mod step_tables;
mod summary;
mod targets;
pub mod vtk;
mod writer;
mod writer_thread;
pub mod xdmf;

pub use folder::path_component;
pub use kept_steps::KeptSteps;
pub use options::OutputOptions;
pub use owned_folder::OwnedFolder;
pub use run::{run_and_write, write_run};
pub use summary::{FieldFiles, RunSummary, TargetPeak, Unknowns};
pub use writer::ResultWriter;
