//! The run's fields in one compressed HDF5 file, `results.h5`, indexed by `results.xdmf` for
//! ParaView (see `xdmf.rs`); in a build with the `hdf5` feature (hdf5-metno over the system's
//! libhdf5).
//!
//! Layout of `results.h5` (every dataset of 512 values or more chunked and deflate-compressed,
//! level 1, when the library has deflate, uncompressed otherwise; smaller ones stored whole; each
//! field dataset carries its `unit`; the step fields in single precision unless the run asks for
//! double, [`FieldPrecision`], each column of a table a chunk of its own behind the shuffle filter):
//!
//! ```text
//! /mesh/soil/geometry            nodes × 3, reference x, y, 0 of every mesh node, written once
//! /mesh/soil/topology-<k>, element_id-<k>, material-<k>
//!                                the cells of the soil present, their ids and materials; new ones
//!                                only when the soil present changes
//! /mesh/reinforcement/geometry, topology      the bars' nodes and the bars (two-node lines), once
//! /mesh/interface/geometry-<k>, topology-<k>  the interface points (one vertex each)
//! /steps/<nnnn>/                 a kept step (its number over the run; attributes stage,
//!                                stage_step, load_factor)
//!     soil/displacement (node), stress, strain (symmetric tensors xx, yy, zz, xy, yz, xz, as VTK
//!          orders them), pore_pressure, plastic_fraction,
//!          plastic_strain (cell); geometry, topology, element_id and material: links into /mesh
//!     reinforcement/displacement (node), axial_force, state, bar_id (cell)
//!     interface/displacement, lambda, sigma_n, tau, bearing, dilation, slip, state, face (node), face (cell);
//!          attribute faces: each face's name, `<interface>:<face>`, by its number
//! /history/time, stage, stage_step, load_factor     one entry per step of the run, kept or not
//! /history/<target> (<x|y>)/displacement, reaction  what history.csv holds, per target
//! ```
//!
//! Crash safety: the file is written in place, so it is not the file that says which steps are
//! complete but `results.xdmf`. After every step the HDF5 file is flushed (H5Fflush: every object
//! of the step and the file's metadata on disk, consistent) and synced, and only then is
//! `results.xdmf` rewritten, atomically, to list the steps written so far. Between two flushes
//! nothing of the flushed metadata changes on disk: the metadata cache evicts nothing (metadata
//! reaches the file only when it is flushed) and space freed in the file is never reused (a step's
//! data never lands on a block that the flushed metadata still points to). Without the two, a run
//! killed while it wrote a step once left a file whose listed steps could not be opened ("wrong
//! fractal heap header signature": the flushed metadata of the `steps` group overwritten before the
//! next flush; tests/killed_runs.rs, one kill in a few hundred). A run killed in the middle of a
//! step leaves an `.xdmf` that lists only steps whose data were flushed before it was rewritten,
//! whatever state the step being written is in (a kill during the flush itself, which rewrites
//! metadata in place, remains a short window); the run's `summary.json` still says
//! `running`. The next run into the folder removes both files (`clear_earlier_run`). A run writes
//! this file on the writer thread (`writer_thread.rs`), in the same order.

use super::chunk_deflate::ChunkDeflater;
use super::grids::{GridLayout, StepGrids};
use super::h5_arrays::{new_group, number_attr, text_attr, ArrayWriter, DEFLATE_LEVEL, OWN_CHUNK_FILTER};
use super::options::FieldPrecision;
use super::owned_folder::OwnedFolder;
use super::xdmf::{self, Center, DataRef, Field, GridStep, KeptStep, Topology, TopologyType};
use crate::analysis::StepRecord;
use crate::error::Error;
use crate::model::file::SolidKind;
use crate::model::UnitLabels;
use hdf5::file::{
    CacheDecreaseMode, CacheIncreaseMode, FileAccessBuilder, FileSpaceStrategy, FlashIncreaseMode, MetadataCacheConfig,
};
use hdf5::types::VarLenUnicode;
use hdf5::Group;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// The HDF5 file's name in the output folder, and its index's.
pub const H5_NAME: &str = "results.h5";
pub const XDMF_NAME: &str = "results.xdmf";

/// The metadata cache's size: a step's metadata (its groups, datasets and chunk indices) stays in
/// it until the step is flushed.
const METADATA_CACHE_BYTES: usize = 32 << 20;
/// Steps written between two openings of the file. Its metadata cache never evicts (crash
/// safety), so it holds every object written since the file was opened, and HDF5 1.10 goes over
/// all of the cache at every flush: without reopening, a run of 2000 steps spent most of its time
/// in the flushes (docs/performance.md).
const STEPS_PER_OPENING: usize = 32;
/// Half the entries of a chunk-index node (HDF5's default is 32, for datasets of many chunks).
const ISTORE_K: u32 = 4;

/// A prescribed target followed in the history: its label and direction (`x` or `y`).
pub struct HistoryTarget<'a> {
    pub label: &'a str,
    pub direction: &'a str,
}

/// `results.h5` being written, and the kept steps that `results.xdmf` lists.
pub struct Hdf5Results {
    /// `results.h5` as messages name it.
    path: PathBuf,
    /// The name HDF5 opens it by: through the output folder's handle.
    open_path: PathBuf,
    /// The output folder, which `results.xdmf` is written through.
    folder: OwnedFolder,
    /// The open file (`None` only when opening it again failed: `reopen`).
    file: Option<hdf5::File>,
    /// Steps written since the file was last opened.
    opened_steps: usize,
    /// Deflate is available in the library: datasets are chunked and compressed.
    compress: bool,
    precision: FieldPrecision,
    /// Shuffles and deflates the step fields' chunks (when `compress`).
    deflater: RefCell<ChunkDeflater>,
    units: UnitLabels,
    steps: Vec<KeptStep>,
    soil_geometry: DataRef,
    /// Each set of present soil elements written so far, and its cells.
    soil_topologies: Vec<(Vec<usize>, SoilCells)>,
    reinforcement: Option<(DataRef, Topology)>,
    /// Each list of interface point positions written so far, its geometry and topology.
    interface_meshes: Vec<(Vec<[f64; 2]>, DataRef, Topology)>,
    history: History,
}

/// The soil elements present in some steps: their topology, ids and materials, written once.
#[derive(Clone)]
struct SoilCells {
    topology: Topology,
    element_id: DataRef,
    material: DataRef,
}

/// The history datasets, one entry per step appended, by their paths in the file (no handle
/// stays open between steps: the file is closed and opened again, `STEPS_PER_OPENING`).
struct History {
    time: String,
    stage: String,
    stage_step: String,
    load_factor: String,
    /// Per target: displacement, reaction.
    targets: Vec<(String, String)>,
    len: usize,
}

impl Hdf5Results {
    /// Create `results.h5` in `out` (replacing one there) with the mesh parts fixed for the run and
    /// empty history datasets.
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.h5`.
    pub fn create(
        folder: &OwnedFolder,
        title: &str,
        units: &UnitLabels,
        layout: &GridLayout,
        targets: &[HistoryTarget<'_>],
        precision: FieldPrecision,
    ) -> Result<Self, Error> {
        // made through the folder's handle (no link followed, no foreign file replaced), then
        // opened by HDF5 through the same handle's folder
        let open_path = folder.file_for_library(H5_NAME)?;
        let path = folder.path().join(H5_NAME);
        let fail = h5_error(&path);
        // the 1.8 file format: compact groups, and no file-consistency flags (the 1.10 format's
        // would make a file left by a killed run unreadable without h5clear)
        // small chunk-index nodes (most datasets have a chunk or a few), and no modification times
        // on the objects (two runs of a model write the same bytes but the root group's times)
        // crash safety (see the module's documentation): the metadata of what was flushed must stay
        // on disk as it was until the next flush. Metadata reaches the file only when it is flushed
        // (no evictions from the metadata cache between flushes), and space freed in the file is
        // never reused (a flushed object's old metadata blocks are never overwritten by a later
        // step's data)
        let file = hdf5::File::with_options()
            .with_fapl(file_access)
            .with_fcpl(|p| p.istore_k(ISTORE_K).obj_track_times(false).file_space_strategy(FileSpaceStrategy::None))
            .create(&open_path)
            .map_err(&fail)?;
        let compress = hdf5::filters::deflate_available();
        let deflater = RefCell::new(ChunkDeflater::new(DEFLATE_LEVEL).map_err(|e| fail(e.into()))?);
        text_attr(&file, "geoslip_version", env!("CARGO_PKG_VERSION")).map_err(&fail)?;
        text_attr(&file, "title", title).map_err(&fail)?;
        text_attr(&file, "xdmf", XDMF_NAME).map_err(&fail)?;
        let writer = ArrayWriter { compress, precision, deflater: &deflater, own_filter: OWN_CHUNK_FILTER };
        let mesh = new_group(&file, "mesh").map_err(&fail)?;
        new_group(&file, "steps").map_err(&fail)?;

        let soil = new_group(&mesh, "soil").map_err(&fail)?;
        let x: Vec<f64> = layout.node_x.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
        let soil_geometry = writer.table(&soil, "geometry", &x, 3, Some(units.length)).map_err(&fail)?;

        let reinforcement = if layout.bar_cells.is_empty() {
            None
        } else {
            let group = new_group(&mesh, "reinforcement").map_err(&fail)?;
            let x: Vec<f64> =
                layout.bar_nodes.iter().flat_map(|&n| [layout.node_x[n][0], layout.node_x[n][1], 0.0]).collect();
            let geometry = writer.table(&group, "geometry", &x, 3, Some(units.length)).map_err(&fail)?;
            let cells: Vec<i64> = layout.bar_cells.iter().flat_map(|c| [c[0] as i64, c[1] as i64]).collect();
            let data = writer.table(&group, "topology", &cells, 2, None).map_err(&fail)?;
            Some((geometry, Topology { kind: TopologyType::Polyline, cells: layout.bar_cells.len(), data }))
        };

        let group = new_group(&file, "history").map_err(&fail)?;
        let series = |name: &str, unit: Option<&str>| -> hdf5::Result<String> {
            let d = writer.growing::<f64>(&group, name)?;
            if let Some(u) = unit {
                text_attr(&d, "unit", u)?;
            }
            Ok(d.name())
        };
        let counter = |name: &str| writer.growing::<u64>(&group, name).map(|d| d.name());
        let history = (|| -> hdf5::Result<History> {
            let mut h = History {
                time: counter("time")?,
                stage: counter("stage")?,
                stage_step: counter("stage_step")?,
                load_factor: series("load_factor", Some("-"))?,
                targets: Vec::new(),
                len: 0,
            };
            let mut names: Vec<String> = Vec::new();
            for t in targets {
                // one group per target, named for it (a `/` in a set name cannot be part of a name)
                let base = format!("{} ({})", t.label.replace('/', "-"), t.direction);
                let mut name = base.clone();
                let mut k = 1;
                while names.contains(&name) {
                    k += 1;
                    name = format!("{base} {k}");
                }
                let g = new_group(&group, &name)?;
                text_attr(&g, "target", t.label)?;
                text_attr(&g, "direction", t.direction)?;
                let d = writer.growing::<f64>(&g, "displacement")?;
                text_attr(&d, "unit", units.length)?;
                let r = writer.growing::<f64>(&g, "reaction")?;
                text_attr(&r, "unit", &units.force_per_width)?;
                h.targets.push((d.name(), r.name()));
                names.push(name);
            }
            Ok(h)
        })()
        .map_err(&fail)?;
        drop(group);
        let mut results = Hdf5Results {
            open_path,
            folder: folder.clone(),
            file: Some(file),
            opened_steps: 0,
            compress,
            precision,
            deflater,
            units: units.clone(),
            steps: Vec::new(),
            soil_geometry,
            soil_topologies: Vec::new(),
            reinforcement,
            interface_meshes: Vec::new(),
            history,
            path,
        };
        results.commit()?;
        Ok(results)
    }

    /// A writer of datasets in this file's precision and compression.
    fn writer(&self) -> ArrayWriter<'_> {
        ArrayWriter {
            compress: self.compress,
            precision: self.precision,
            deflater: &self.deflater,
            own_filter: OWN_CHUNK_FILTER,
        }
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Append one step of the run to the history: its number, stage (1, 2, …), step in the stage,
    /// load factor, and each target's mean displacement and total reaction (in `create`'s order).
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.h5`.
    pub fn append_history(&mut self, time: usize, record: &StepRecord, targets: &[(f64, f64)]) -> Result<(), Error> {
        let fail = h5_error(&self.path);
        let file = self.file().map_err(&fail)?;
        let h = &self.history;
        let n = h.len;
        (|| -> hdf5::Result<()> {
            append_entry(file, &h.time, n, time as u64)?;
            append_entry(file, &h.stage, n, record.stage_index as u64 + 1)?;
            append_entry(file, &h.stage_step, n, record.step as u64)?;
            append_entry(file, &h.load_factor, n, record.load_factor)?;
            for ((d, r), (u, f)) in h.targets.iter().zip(targets) {
                append_entry(file, d, n, *u)?;
                append_entry(file, r, n, *f)?;
            }
            Ok(())
        })()
        .map_err(&fail)?;
        self.history.len = n + 1;
        Ok(())
    }

    /// Write the grids of kept step `time` under `/steps/<time>`; it is listed in `results.xdmf`
    /// from the next [`commit`](Self::commit).
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.h5`.
    pub fn write_step(
        &mut self,
        time: usize,
        record: &StepRecord,
        layout: &GridLayout,
        grids: &StepGrids,
    ) -> Result<(), Error> {
        let fail = h5_error(&self.path);
        let steps = self.file().and_then(|f| f.group("steps")).map_err(&fail)?;
        let group = new_group(&steps, &format!("{time:04}")).map_err(&fail)?;
        text_attr(&group, "stage", &record.stage).map_err(&fail)?;
        number_attr(&group, "stage_step", record.step as u64).map_err(&fail)?;
        number_attr(&group, "load_factor", record.load_factor).map_err(&fail)?;
        let mut kept = KeptStep { time, label: format!("{} step {}", record.stage, record.step), grids: Vec::new() };
        let soil = self.soil_step(&group, layout, grids).map_err(&fail)?;
        kept.grids.push(("soil", soil));
        if let Some(reinforcement) = self.reinforcement_step(&group, grids).map_err(&fail)? {
            kept.grids.push(("reinforcement", reinforcement));
        }
        if let Some(interface) = self.interface_step(&group, grids).map_err(&fail)? {
            kept.grids.push(("interface", interface));
        }
        let at = self.steps.partition_point(|s| s.time < time);
        self.steps.insert(at, kept);
        self.opened_steps += 1;
        Ok(())
    }

    /// Make what was written so far durable, then list its kept steps in `results.xdmf`: the HDF5
    /// file is flushed and synced first, the index rewritten atomically after.
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.h5` or `results.xdmf`.
    /// Close the file, and note its size and time in the output folder's record (so that the next
    /// run removes it only while nobody changed it).
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.h5`.
    pub fn close(mut self) -> Result<(), Error> {
        if let Some(file) = self.file.take() {
            file.close().map_err(h5_error(&self.path))?;
        }
        self.folder.record(H5_NAME)
    }

    pub fn commit(&mut self) -> Result<(), Error> {
        self.flush()?;
        self.write_index()
    }

    /// Make what was written so far durable without listing it in `results.xdmf` yet (the index
    /// is rewritten at a later commit: `pace.rs`). Every `STEPS_PER_OPENING` steps the file is
    /// then closed and opened again.
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.h5`.
    pub fn flush(&mut self) -> Result<(), Error> {
        self.file().and_then(|f| f.flush()).map_err(h5_error(&self.path))?;
        std::fs::File::open(&self.open_path)
            .and_then(|f| f.sync_data())
            .map_err(|source| Error::Write { path: self.path.clone(), source })?;
        if self.opened_steps >= STEPS_PER_OPENING {
            self.reopen()?;
        }
        Ok(())
    }

    /// Close the file (flushed) and open it again: its metadata cache, which never evicts, starts
    /// empty.
    fn reopen(&mut self) -> Result<(), Error> {
        let fail = h5_error(&self.path);
        if let Some(file) = self.file.take() {
            // no other handle is open between steps (the history is held by its paths), so this
            // closes the file
            file.close().map_err(&fail)?;
        }
        let file = hdf5::File::with_options().with_fapl(file_access).open_rw(&self.open_path).map_err(&fail)?;
        self.file = Some(file);
        self.opened_steps = 0;
        Ok(())
    }

    /// The open file.
    fn file(&self) -> hdf5::Result<&hdf5::File> {
        self.file.as_ref().ok_or_else(|| "results.h5 could not be opened again after a step".into())
    }

    /// List the kept steps written so far in `results.xdmf` (rewritten atomically): after a
    /// [`flush`](Self::flush), so that it lists complete steps only.
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.xdmf`.
    pub fn write_index(&self) -> Result<(), Error> {
        self.folder.write(XDMF_NAME, xdmf::document(H5_NAME, &self.steps).as_bytes())
    }

    fn soil_step(&mut self, step: &Group, layout: &GridLayout, grids: &StepGrids) -> hdf5::Result<GridStep> {
        let g = &grids.soil;
        let cells = match self.soil_topologies.iter().find(|(present, _)| *present == g.present) {
            Some((_, cells)) => cells.clone(),
            None => {
                let cells = self.soil_cells(layout, grids)?;
                self.soil_topologies.push((g.present.clone(), cells.clone()));
                cells
            }
        };
        let group = new_group(&step, "soil")?;
        group.link_soft(&self.soil_geometry.path, "geometry")?;
        group.link_soft(&cells.topology.data.path, "topology")?;
        group.link_soft(&cells.element_id.path, "element_id")?;
        group.link_soft(&cells.material.path, "material")?;
        let w = self.writer();
        let u = &self.units;
        let (length, stress) = (Some(u.length), Some(u.stress.as_str()));
        let fields = vec![
            Field {
                name: "displacement",
                center: Center::Node,
                data: w.field(&group, "displacement", g.displacement.as_flattened(), 3, length)?,
            },
            Field {
                name: "stress",
                center: Center::Cell,
                data: w.field(&group, "stress", g.stress.as_flattened(), 6, stress)?,
            },
            Field {
                name: "strain",
                center: Center::Cell,
                data: w.field(&group, "strain", g.strain.as_flattened(), 6, Some("-"))?,
            },
            Field {
                name: "pore_pressure",
                center: Center::Cell,
                data: w.field(&group, "pore_pressure", &g.pore_pressure, 1, stress)?,
            },
            Field {
                name: "plastic_fraction",
                center: Center::Cell,
                data: w.field(&group, "plastic_fraction", &g.plastic_fraction, 1, Some("-"))?,
            },
            Field {
                name: "plastic_strain",
                center: Center::Cell,
                data: w.field(&group, "plastic_strain", &g.plastic_strain, 1, Some("-"))?,
            },
            Field { name: "material", center: Center::Cell, data: cells.material },
            Field { name: "element_id", center: Center::Cell, data: cells.element_id },
        ];
        Ok(GridStep { topology: cells.topology, geometry: self.soil_geometry.clone(), fields })
    }

    /// The cells of the soil elements present in `grids` (one kind as a cells × nodes table,
    /// several as XDMF's `Mixed` list), their ids and materials, as `/mesh/soil/*-<k>`.
    fn soil_cells(&self, layout: &GridLayout, grids: &StepGrids) -> hdf5::Result<SoilCells> {
        let group = self.file()?.group("mesh/soil")?;
        let k = self.soil_topologies.len() + 1;
        let present = &grids.soil.present;
        let w = self.writer();
        let element_id = w.table(&group, &format!("element_id-{k}"), &grids.soil.element_id, 1, None)?;
        let material = w.table(&group, &format!("material-{k}"), &grids.soil.material, 1, None)?;
        let name = format!("topology-{k}");
        let kinds: Vec<SolidKind> = present.iter().map(|&i| layout.soil_cells[i].0).collect();
        let single = kinds.first().filter(|k| kinds.iter().all(|other| other == *k));
        let (kind, data) = match single {
            Some(&kind) => {
                let per_cell = layout.soil_cells[present[0]].1.len();
                let cells: Vec<i64> =
                    present.iter().flat_map(|&i| layout.soil_cells[i].1.iter().map(|&n| n as i64)).collect();
                (TopologyType::of(kind), w.table(&group, &name, &cells, per_cell, None)?)
            }
            None => {
                let mut cells = Vec::new();
                for &i in present {
                    let (kind, nodes) = &layout.soil_cells[i];
                    cells.push(TopologyType::mixed_id(*kind));
                    cells.extend(nodes.iter().map(|&n| n as i64));
                }
                (TopologyType::Mixed, w.table(&group, &name, &cells, 1, None)?)
            }
        };
        Ok(SoilCells { topology: Topology { kind, cells: present.len(), data }, element_id, material })
    }

    fn reinforcement_step(&self, step: &Group, grids: &StepGrids) -> hdf5::Result<Option<GridStep>> {
        let Some((geometry, topology)) = &self.reinforcement else { return Ok(None) };
        let g = &grids.reinforcement;
        let group = new_group(&step, "reinforcement")?;
        group.link_soft(&geometry.path, "geometry")?;
        group.link_soft(&topology.data.path, "topology")?;
        let w = self.writer();
        let fields = vec![
            Field {
                name: "displacement",
                center: Center::Node,
                data: w.field(&group, "displacement", g.displacement.as_flattened(), 3, Some(self.units.length))?,
            },
            Field {
                name: "axial_force",
                center: Center::Cell,
                data: w.field(&group, "axial_force", &g.axial_force, 1, Some(&self.units.force_per_width))?,
            },
            Field { name: "state", center: Center::Cell, data: w.table(&group, "state", &g.state, 1, None)? },
            Field { name: "bar_id", center: Center::Cell, data: w.table(&group, "bar_id", &g.bar_id, 1, None)? },
        ];
        Ok(Some(GridStep { topology: topology.clone(), geometry: geometry.clone(), fields }))
    }

    fn interface_step(&mut self, step: &Group, grids: &StepGrids) -> hdf5::Result<Option<GridStep>> {
        let g = &grids.interface;
        if g.x.is_empty() {
            return Ok(None);
        }
        let (geometry, topology) = match self.interface_meshes.iter().find(|(x, _, _)| *x == g.x) {
            Some((_, geometry, topology)) => (geometry.clone(), topology.clone()),
            None => {
                let k = self.interface_meshes.len() + 1;
                let mesh = self.file()?.group("mesh")?;
                let group = match mesh.group("interface") {
                    Ok(group) => group,
                    Err(_) => new_group(&mesh, "interface")?,
                };
                let w = self.writer();
                let x: Vec<f64> = g.x.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
                let geometry = w.table(&group, &format!("geometry-{k}"), &x, 3, Some(self.units.length))?;
                let vertices: Vec<i64> = (0..g.x.len() as i64).collect();
                let data = w.table(&group, &format!("topology-{k}"), &vertices, 1, None)?;
                let topology = Topology { kind: TopologyType::Polyvertex, cells: g.x.len(), data };
                self.interface_meshes.push((g.x.clone(), geometry.clone(), topology.clone()));
                (geometry, topology)
            }
        };
        let group = new_group(&step, "interface")?;
        let faces: Vec<VarLenUnicode> = g.face_names.iter().filter_map(|f| f.replace('\0', "").parse().ok()).collect();
        group.new_attr_builder().with_data(faces.as_slice()).create("faces")?;
        group.link_soft(&geometry.path, "geometry")?;
        group.link_soft(&topology.data.path, "topology")?;
        let w = self.writer();
        let u = &self.units;
        let (length, stress) = (Some(u.length), Some(u.stress.as_str()));
        let node = |name: &'static str, data: DataRef| Field { name, center: Center::Node, data };
        let face = w.table(&group, "face", &g.face, 1, None)?;
        let fields = vec![
            node("displacement", w.field(&group, "displacement", g.displacement.as_flattened(), 3, length)?),
            node("lambda", w.field(&group, "lambda", &g.lambda, 1, Some(&u.force_per_width))?),
            node("sigma_n", w.field(&group, "sigma_n", &g.sigma_n, 1, stress)?),
            node("tau", w.field(&group, "tau", &g.tau, 1, stress)?),
            node("bearing", w.field(&group, "bearing", &g.bearing, 1, stress)?),
            node("dilation", w.field(&group, "dilation", &g.dilation, 1, length)?),
            node("slip", w.field(&group, "slip", &g.slip, 1, length)?),
            node("state", w.table(&group, "state", &g.state, 1, None)?),
            node("face", face.clone()),
            // one vertex cell per point: the cells' face is the points'
            Field { name: "face", center: Center::Cell, data: face },
        ];
        Ok(Some(GridStep { topology, geometry, fields }))
    }
}

/// How `results.h5` is opened, created or opened again: the 1.8 format, and a metadata cache that
/// never evicts (see `Hdf5Results::create`).
fn file_access(p: &mut FileAccessBuilder) -> &mut FileAccessBuilder {
    let cache = MetadataCacheConfig {
        evictions_enabled: false,
        incr_mode: CacheIncreaseMode::Off,
        flash_incr_mode: FlashIncreaseMode::Off,
        decr_mode: CacheDecreaseMode::Off,
        set_initial_size: true,
        initial_size: METADATA_CACHE_BYTES,
        max_size: METADATA_CACHE_BYTES,
        ..MetadataCacheConfig::default()
    };
    p.libver_v18().mdc_config(&cache)
}

/// Entry `at` (the dataset's length so far) appended to the growing dataset at `path`.
fn append_entry<T: hdf5::H5Type>(file: &hdf5::File, path: &str, at: usize, value: T) -> hdf5::Result<()> {
    let dataset = file.dataset(path)?;
    dataset.resize(at + 1)?;
    dataset.write_slice(&[value][..], at..at + 1)
}

/// The error of a failed HDF5 call on `path`.
fn h5_error(path: &Path) -> impl Fn(hdf5::Error) -> Error {
    let path = path.to_path_buf();
    move |e| Error::Write { path: path.clone(), source: std::io::Error::other(format!("HDF5: {e}")) }
}
