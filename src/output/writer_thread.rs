//! Every file of a run written on a thread of its own, in every build, in the order the run hands
//! them over, while the run goes on with the next step: the encoding is done by the run's thread,
//! the writing, syncing and (for `results.h5`) compression overlap the next step's iterations.
//!
//! A step hands over its field files (its `.vtu` grids, its CSV tables as one folder, its fields
//! in `results.h5`), its saved step (encoded here: it is the largest), its history entry in `results.h5` and a commit, and at the
//! steps where the files written whole are due (`pace.rs`) a commit with the index and the new
//! `results.pvd`, `history.csv` and `summary.json`. The thread does them in that order (see
//! `results_h5.rs`: the index `results.xdmf` is rewritten only after the HDF5 file is flushed, so
//! it lists complete steps only, whatever the moment the run is killed; the files written whole
//! follow it, and each lists only what was written before it). At most two steps wait at once: a
//! run never holds more than a few steps' files in memory. An error on the writer thread stops it;
//! the run's thread gets the error at its next hand-over, or when it finishes.

use super::checkpoints;
#[cfg(feature = "hdf5")]
use super::grids::{GridLayout, StepGrids};
use super::owned_folder::OwnedFolder;
#[cfg(feature = "hdf5")]
use super::results_h5::Hdf5Results;
use crate::analysis::Checkpoint;
#[cfg(feature = "hdf5")]
use crate::analysis::StepRecord;
use crate::error::Error;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Steps that may wait for the writer thread.
const WAITING: usize = 2;
/// The jobs a step hands over: its three `.vtu` grids, its CSV tables, its saved step, its fields,
/// history entry and commit in `results.h5`, and `results.pvd`, `history.csv` and `summary.json`.
/// The channel holds `WAITING` steps of them: were it to hold fewer, the run's thread would wait
/// at every step for the writer to be done with the step's fields (with two jobs, 15 ms a step at
/// 10⁵ unknowns).
const JOBS_PER_STEP: usize = 11;

/// One piece of work for the writer thread.
enum Job {
    /// A file of one step (a `.vtu` grid, a saved step), by its name in the output folder.
    File { name: String, bytes: Vec<u8> },
    /// A saved step a run can continue from, encoded here (`checkpoints.rs`).
    Checkpoint(Box<Checkpoint>),
    /// A step's CSV tables: written into a folder beside `dir`, which is then moved into place, so
    /// that the step's folder appears whole or not at all.
    StepFolder { dir: String, files: Vec<(String, Vec<u8>)> },
    /// A file written whole that grows with the run (`results.pvd`, `history.csv`,
    /// `summary.json`), replaced; its time counts to the rewrites' pace.
    Rewrite { name: String, bytes: Vec<u8> },
    #[cfg(feature = "hdf5")]
    Fields { time: usize, record: StepRecord, grids: StepGrids },
    #[cfg(feature = "hdf5")]
    History { time: usize, record: StepRecord, targets: Vec<(f64, f64)> },
    /// `results.h5` made durable; with `index`, its steps listed in `results.xdmf` too.
    #[cfg(feature = "hdf5")]
    Commit { index: bool },
}

/// `results.h5`, created, and the grids' fixed parts its steps are written with.
#[cfg(feature = "hdf5")]
pub struct Hdf5Files {
    pub results: Hdf5Results,
    pub layout: Arc<GridLayout>,
}

/// The writer thread of a run's output folder.
pub struct WriterThread {
    jobs: Option<SyncSender<Job>>,
    thread: Option<JoinHandle<Result<Option<f64>, Error>>>,
    path: PathBuf,
    /// The thread's CPU time when it ended [s], where the system tells it.
    cpu_seconds: Option<f64>,
    /// The time the thread spent on the files written whole (`results.xdmf` and the rewrites)
    /// since it was last taken [ns].
    rewrites: Arc<AtomicU64>,
    /// Whether the thread writes `results.h5`.
    #[cfg(feature = "hdf5")]
    has_hdf5: bool,
}

impl WriterThread {
    /// Start the thread that writes into `folder` (and `results.h5`, when given).
    ///
    /// # Errors
    /// [`Error::Write`] naming the output folder when no thread can be started.
    pub fn start(folder: OwnedFolder, #[cfg(feature = "hdf5")] hdf5: Option<Hdf5Files>) -> Result<Self, Error> {
        let path = folder.path().to_path_buf();
        let (jobs, inbox) = sync_channel::<Job>(WAITING * JOBS_PER_STEP);
        let rewrites = Arc::new(AtomicU64::new(0));
        let rewriting = Arc::clone(&rewrites);
        #[cfg(feature = "hdf5")]
        let has_hdf5 = hdf5.is_some();
        #[cfg(feature = "hdf5")]
        let mut hdf5 = hdf5;
        let thread = std::thread::Builder::new()
            .name("results".into())
            .spawn(move || {
                let timed = |started: Instant| rewriting.fetch_add(nanoseconds(started), Ordering::Relaxed);
                for job in inbox {
                    match job {
                        Job::File { name, bytes } => folder.write(&name, &bytes)?,
                        Job::Checkpoint(checkpoint) => checkpoints::write(&folder, &checkpoint)?,
                        Job::StepFolder { dir, files } => write_folder_whole(&folder, &dir, files)?,
                        Job::Rewrite { name, bytes } => {
                            let started = Instant::now();
                            folder.write(&name, &bytes)?;
                            timed(started);
                        }
                        #[cfg(feature = "hdf5")]
                        Job::Fields { time, record, grids } => {
                            if let Some(h5) = hdf5.as_mut() {
                                h5.results.write_step(time, &record, &h5.layout, &grids)?;
                            }
                        }
                        #[cfg(feature = "hdf5")]
                        Job::History { time, record, targets } => {
                            if let Some(h5) = hdf5.as_mut() {
                                h5.results.append_history(time, &record, &targets)?;
                            }
                        }
                        #[cfg(feature = "hdf5")]
                        Job::Commit { index } => {
                            if let Some(h5) = hdf5.as_mut() {
                                h5.results.flush()?;
                                if index {
                                    let started = Instant::now();
                                    h5.results.write_index()?;
                                    timed(started);
                                }
                            }
                        }
                    }
                }
                #[cfg(feature = "hdf5")]
                if let Some(mut h5) = hdf5 {
                    h5.results.commit()?;
                    h5.results.close()?;
                }
                Ok(thread_cpu_seconds())
            })
            .map_err(|source| Error::Write { path: path.clone(), source })?;
        Ok(WriterThread {
            jobs: Some(jobs),
            thread: Some(thread),
            path,
            cpu_seconds: None,
            rewrites,
            #[cfg(feature = "hdf5")]
            has_hdf5,
        })
    }

    /// Whether the thread writes `results.h5`.
    #[cfg(feature = "hdf5")]
    pub fn has_hdf5(&self) -> bool {
        self.has_hdf5
    }

    /// Hand over a file of one step, by its name in the output folder (written atomically and
    /// synced, as `OwnedFolder::write` does), after everything handed over before it.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn write_file(&mut self, name: String, bytes: Vec<u8>) -> Result<(), Error> {
        self.send(Job::File { name, bytes })
    }

    /// Hand over a saved step, to encode and write into `restart/`.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn write_checkpoint(&mut self, checkpoint: Checkpoint) -> Result<(), Error> {
        self.send(Job::Checkpoint(Box::new(checkpoint)))
    }

    /// Hand over a step's folder `dir` of `files`, which appears whole or not at all.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn write_step_folder(&mut self, dir: String, files: Vec<(String, Vec<u8>)>) -> Result<(), Error> {
        self.send(Job::StepFolder { dir, files })
    }

    /// Hand over a file written whole that grows with the run, to replace, after everything
    /// handed over before it.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn replace_file(&mut self, name: String, bytes: Vec<u8>) -> Result<(), Error> {
        self.send(Job::Rewrite { name, bytes })
    }

    /// Hand step `time`'s grids over for `results.h5`.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    #[cfg(feature = "hdf5")]
    pub fn write_step(&mut self, time: usize, record: &StepRecord, grids: StepGrids) -> Result<(), Error> {
        self.send(Job::Fields { time, record: record.clone(), grids })
    }

    /// Hand step `time`'s history entry over for `results.h5`: each target's displacement and
    /// reaction.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    #[cfg(feature = "hdf5")]
    pub fn append_history(&mut self, time: usize, record: &StepRecord, targets: &[(f64, f64)]) -> Result<(), Error> {
        self.send(Job::History { time, record: record.clone(), targets: targets.to_vec() })
    }

    /// Ask for the `results.h5` part of what was handed over so far to be made durable and, with `index`, listed in
    /// `results.xdmf`.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    #[cfg(feature = "hdf5")]
    pub fn commit(&mut self, index: bool) -> Result<(), Error> {
        self.send(Job::Commit { index })
    }

    /// The time the writer thread spent writing `results.xdmf` and the files handed over since
    /// the last call (the rewrites it has done so far; `pace.rs`).
    pub fn take_rewrite_time(&self) -> Duration {
        Duration::from_nanos(self.rewrites.swap(0, Ordering::Relaxed))
    }

    /// Whether the thread takes work: started, and not finished.
    pub fn running(&self) -> bool {
        self.jobs.is_some()
    }

    /// The CPU time the writer thread took [s], once it has finished (`None` before, or where
    /// /proc/thread-self/schedstat is not there to tell it).
    pub fn cpu_seconds(&self) -> Option<f64> {
        self.cpu_seconds
    }

    /// Wait for the writer thread to finish what it was handed (and commit it).
    ///
    /// # Errors
    /// The writer thread's error.
    pub fn finish(&mut self) -> Result<(), Error> {
        self.jobs = None;
        self.join()
    }

    fn send(&mut self, job: Job) -> Result<(), Error> {
        let sent = self.jobs.as_ref().is_some_and(|jobs| jobs.send(job).is_ok());
        if sent {
            return Ok(());
        }
        // the thread has stopped: its error
        self.jobs = None;
        self.join()?;
        Err(self.stopped())
    }

    fn join(&mut self) -> Result<(), Error> {
        match self.thread.take().map(JoinHandle::join) {
            None => Ok(()),
            Some(Ok(Ok(cpu_seconds))) => {
                self.cpu_seconds = cpu_seconds;
                Ok(())
            }
            Some(Ok(Err(e))) => Err(e),
            Some(Err(_)) => Err(self.stopped()),
        }
    }

    fn stopped(&self) -> Error {
        Error::Write {
            path: self.path.clone(),
            source: std::io::Error::other("the thread writing the results stopped"),
        }
    }
}

/// Write the folder `dir` of `folder` whole or not at all: its `files` (by their names in it) into
/// a folder beside it, which is then renamed into place (over the same step of an earlier run into
/// this folder).
///
/// # Errors
/// As [`OwnedFolder::write`].
pub(super) fn write_folder_whole(folder: &OwnedFolder, dir: &str, files: Vec<(String, Vec<u8>)>) -> Result<(), Error> {
    let partial = folder.temporary_folder(dir)?;
    for (name, bytes) in files {
        folder.write(&format!("{partial}/{name}"), &bytes)?;
    }
    folder.move_folder(&partial, dir)
}

/// The time since `started` [ns].
fn nanoseconds(started: Instant) -> u64 {
    u64::try_from(started.elapsed().as_nanos()).unwrap_or(u64::MAX)
}

/// The calling thread's CPU time so far [s]: the first field of /proc/thread-self/schedstat, in
/// nanoseconds.
fn thread_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let nanoseconds: f64 = stat.split_whitespace().next()?.parse().ok()?;
    Some(nanoseconds * 1e-9)
}

impl Drop for WriterThread {
    fn drop(&mut self) {
        // what was handed over is written even when the run ends without `finish`
        let _ = self.finish();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start(folder: &OwnedFolder) -> WriterThread {
        #[cfg(feature = "hdf5")]
        let thread = WriterThread::start(folder.clone(), None);
        #[cfg(not(feature = "hdf5"))]
        let thread = WriterThread::start(folder.clone());
        thread.expect("a writer thread")
    }

    #[test]
    fn files_are_written_in_the_order_handed_over() {
        let scratch = tempfile::tempdir().unwrap();
        let folder = OwnedFolder::open(scratch.path(), &[]).unwrap();
        let mut thread = start(&folder);
        thread.write_file("vtk/step-0001-soil.vtu".into(), b"first".to_vec()).unwrap();
        thread.write_step_folder("stage-1-a/step-001".into(), vec![("t.csv".into(), b"1,2".to_vec())]).unwrap();
        thread.replace_file("summary.json".into(), b"{\"steps\": 1}".to_vec()).unwrap();
        // the same file handed over again: the later bytes win only if the order is kept
        thread.write_file("vtk/step-0001-soil.vtu".into(), b"second".to_vec()).unwrap();
        thread.replace_file("summary.json".into(), b"{\"steps\": 2}".to_vec()).unwrap();
        thread.finish().unwrap();
        let read = |rel: &str| std::fs::read_to_string(scratch.path().join(rel)).unwrap();
        assert_eq!(read("vtk/step-0001-soil.vtu"), "second");
        assert_eq!(read("summary.json"), "{\"steps\": 2}");
        assert_eq!(read("stage-1-a/step-001/t.csv"), "1,2");
        assert!(thread.cpu_seconds().is_none_or(|s| s >= 0.0));
    }

    #[test]
    fn nothing_handed_over_after_a_failed_file_is_written_and_the_failure_is_named() {
        let scratch = tempfile::tempdir().unwrap();
        let folder = OwnedFolder::open(scratch.path(), &[]).unwrap();
        let mut thread = start(&folder);
        thread.write_file("../outside.txt".into(), b"refused".to_vec()).unwrap();
        // the thread may have stopped already: a hand-over then returns its error
        let later = thread.replace_file("summary.json".into(), b"{}".to_vec());
        let finished = thread.finish();
        let error = later.err().or(finished.err()).expect("the refused file's error");
        assert!(error.to_string().contains("not a plain path inside the output folder"), "{error}");
        assert!(!scratch.path().join("summary.json").exists());
        assert!(!scratch.path().parent().unwrap().join("outside.txt").exists());
    }
}
