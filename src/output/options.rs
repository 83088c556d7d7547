//! What a run writes besides its history, summary, report and plots (which it always writes): the
//! fields of the kept steps as `results.h5` + `results.xdmf` (a build with the `hdf5` feature) or
//! as ParaView `.vtu` files (a build without it, or on request), per-step CSV files on request, and
//! the saved steps a run can continue from (unless left out).

use super::kept_steps::KeptSteps;

/// The field files of a run (`geoslip run --csv --keep … --vtu`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OutputOptions {
    /// Each kept step's whole fields as CSV files too, in `stage-<k>-<name>/step-<nnn>/`.
    pub csv: bool,
    /// Which steps' fields are written.
    pub keep: KeptSteps,
    /// The ParaView `.vtu` files and `results.pvd` beside `results.h5`/`.xdmf`. A build without the
    /// `hdf5` feature writes them in any case: they are then its only field files.
    pub vtu: bool,
    /// Leave out the saved steps a run can continue from (`restart/`, written by default): their
    /// disk space for the ability to continue.
    pub no_restart: bool,
    /// The precision of the step fields in `results.h5` (single by default).
    pub precision: FieldPrecision,
}

/// The precision of the step fields in `results.h5`: every field of every kept step (displacements,
/// stresses, strains, the interface's and the bars' values). The mesh's coordinates and the history
/// are written in double precision either way; the saved steps a run continues from, history.csv
/// and the CSV files hold every digit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum FieldPrecision {
    /// 4-byte floats (about 7 significant digits, as ParaView shows them, and as Abaqus writes its
    /// field output): each value the computed one rounded to the nearest single-precision number;
    /// half the size of double.
    #[default]
    Single,
    /// 8-byte floats: every value exactly as computed.
    Double,
}

impl OutputOptions {
    /// Every step, with its CSV files: what a program that post-processes the step folders needs.
    pub fn with_csv() -> Self {
        OutputOptions { csv: true, ..OutputOptions::default() }
    }

    /// Whether the `.vtu` files are written: on request, or always without HDF5.
    pub fn writes_vtu(&self) -> bool {
        self.vtu || !cfg!(feature = "hdf5")
    }

    /// Whether `results.h5` and `results.xdmf` are written: in every build with the `hdf5` feature.
    pub fn writes_hdf5(&self) -> bool {
        cfg!(feature = "hdf5")
    }
}
