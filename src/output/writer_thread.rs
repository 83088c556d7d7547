//! `results.h5` written on a thread of its own, while the run goes on with the next step: the
//! compression and the writing of a step's fields overlap the next step's equilibrium iterations
//! instead of adding to them.
//!
//! The run's thread hands each step's grids, its history entry and a commit to the writer thread,
//! and at the steps where the files written whole are due (`pace.rs`) a commit with the index and
//! the new `history.csv` and `summary.json`; the thread does them in order (see `results_h5.rs`:
//! the index `results.xdmf` is rewritten only after the HDF5 file is flushed, so it lists complete
//! steps only, whatever the moment the run is killed; the two files follow it). The index is
//! written at the end whatever the pace.
//! At most two steps wait at once: a run never holds more than a few steps' grids in memory. An
//! error on the writer thread stops it; the run's thread gets the error at its next hand-over, or
//! when it finishes.

use super::grids::{GridLayout, StepGrids};
use super::owned_folder::OwnedFolder;
use super::results_h5::Hdf5Results;
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
/// The jobs a step hands over: its fields, its history entry, the commit, `history.csv` and
/// `summary.json`. The channel holds `WAITING` steps of them: were it to hold fewer, the run's
/// thread would wait at every step for the writer to be done with the step's fields (with
/// two jobs, 15 ms a step at 10⁵ unknowns).
const JOBS_PER_STEP: usize = 5;

/// One piece of work for the writer thread.
enum Job {
    Fields {
        time: usize,
        record: StepRecord,
        grids: StepGrids,
    },
    History {
        time: usize,
        record: StepRecord,
        targets: Vec<(f64, f64)>,
    },
    /// The file made durable; with `index`, its steps listed in `results.xdmf` too.
    Commit {
        index: bool,
    },
    /// A whole file of the output folder replaced (`OwnedFolder::write`), by its name there.
    File {
        name: String,
        bytes: Vec<u8>,
    },
}

/// The writer thread of `results.h5`.
pub struct Hdf5Thread {
    jobs: Option<SyncSender<Job>>,
    thread: Option<JoinHandle<Result<Option<f64>, Error>>>,
    path: PathBuf,
    /// The thread's CPU time when it ended [s], where the system tells it.
    cpu_seconds: Option<f64>,
    /// The time the thread spent on the files written whole (`results.xdmf` and the files handed
    /// over) since it was last taken [ns].
    rewrites: Arc<AtomicU64>,
}

impl Hdf5Thread {
    /// Start the thread that writes `results` (already created), with the grids' fixed parts.
    ///
    /// # Errors
    /// [`Error::Write`] naming `results.h5` when no thread can be started.
    pub fn start(mut results: Hdf5Results, layout: Arc<GridLayout>, folder: OwnedFolder) -> Result<Self, Error> {
        let path = results.path().to_path_buf();
        let (jobs, inbox) = sync_channel::<Job>(WAITING * JOBS_PER_STEP);
        let rewrites = Arc::new(AtomicU64::new(0));
        let rewriting = Arc::clone(&rewrites);
        let thread = std::thread::Builder::new()
            .name("results.h5".into())
            .spawn(move || {
                for job in inbox {
                    match job {
                        Job::Fields { time, record, grids } => results.write_step(time, &record, &layout, &grids)?,
                        Job::History { time, record, targets } => results.append_history(time, &record, &targets)?,
                        Job::Commit { index: false } => results.flush()?,
                        Job::Commit { index: true } => {
                            results.flush()?;
                            let started = Instant::now();
                            results.write_index()?;
                            rewriting.fetch_add(nanoseconds(started), Ordering::Relaxed);
                        }
                        Job::File { name, bytes } => {
                            let started = Instant::now();
                            folder.write(&name, &bytes)?;
                            rewriting.fetch_add(nanoseconds(started), Ordering::Relaxed);
                        }
                    }
                }
                results.commit()?;
                results.close()?;
                Ok(thread_cpu_seconds())
            })
            .map_err(|source| Error::Write { path: path.clone(), source })?;
        Ok(Hdf5Thread { jobs: Some(jobs), thread: Some(thread), path, cpu_seconds: None, rewrites })
    }

    /// Hand step `time`'s grids over.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn write_step(&mut self, time: usize, record: &StepRecord, grids: StepGrids) -> Result<(), Error> {
        self.send(Job::Fields { time, record: record.clone(), grids })
    }

    /// Hand step `time`'s history entry over: each target's displacement and reaction.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn append_history(&mut self, time: usize, record: &StepRecord, targets: &[(f64, f64)]) -> Result<(), Error> {
        self.send(Job::History { time, record: record.clone(), targets: targets.to_vec() })
    }

    /// Ask for what was handed over so far to be made durable and, with `index`, listed in
    /// `results.xdmf`.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn commit(&mut self, index: bool) -> Result<(), Error> {
        self.send(Job::Commit { index })
    }

    /// The time the writer thread spent writing `results.xdmf` and the files handed over since
    /// the last call (the rewrites it has done so far; `pace.rs`).
    pub fn take_rewrite_time(&self) -> Duration {
        Duration::from_nanos(self.rewrites.swap(0, Ordering::Relaxed))
    }

    /// Hand over a whole file to replace at `path` (written atomically and synced, as
    /// `write_atomically` does), after everything handed over before it.
    ///
    /// # Errors
    /// The writer thread's error, if it has stopped.
    pub fn replace_file(&mut self, name: String, bytes: Vec<u8>) -> Result<(), Error> {
        self.send(Job::File { name, bytes })
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
        Error::Write { path: self.path.clone(), source: std::io::Error::other("the HDF5 writer thread stopped") }
    }
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

impl Drop for Hdf5Thread {
    fn drop(&mut self) {
        // what was handed over is written even when the run ends without `finish`
        let _ = self.finish();
    }
}
