//! Distributed runs on MUMPS's MPI build (Debian `libmumps-dev`, OpenMPI), under `mpirun -np N`.
//!
//! Rank 0 (the host, PAR = 1) does everything geoslip does: it reads the model, assembles, iterates
//! and writes the results, and it holds the whole matrix and right-hand side (centralised input,
//! ICNTL(18) = 0 and ICNTL(20) = 0). MUMPS distributes the analysis, the factorisation and the solve
//! over every rank, but each MUMPS call is collective: every rank must make it, with the same JOB.
//! So before each call rank 0 broadcasts a command (the instance, JOB, SYM and its ICNTL and CNTL),
//! and the other ranks, in [`Cluster::serve`], make the same call on their own copy of that instance.
//! When rank 0 is done, [`Cluster::release`] tells them to stop.

use geoslip_sys::mumps as ffi;
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::Root;
use std::collections::HashMap;

/// See `mumps.rs`: the Fortran communicator value that means MPI_COMM_WORLD.
const USE_COMM_WORLD: i32 = -987654;
const ICNTL: usize = 60;
const CNTL: usize = 15;
/// kind, instance, job, sym, ICNTL(1..60), CNTL(1..15) as bits.
const COMMAND: usize = 4 + ICNTL + CNTL;
const QUIT: i64 = 0;
const CALL: i64 = 1;

/// MPI, started once for the whole run and finalised when this is dropped.
pub struct Cluster {
    _universe: mpi::environment::Universe,
    rank: i32,
    size: i32,
}

impl Cluster {
    /// Start MPI (a run without mpirun is a one-rank job). `None` when MPI was already started.
    pub fn start() -> Option<Cluster> {
        let universe = mpi::initialize()?;
        let world = universe.world();
        let (rank, size) = (world.rank(), world.size());
        Some(Cluster { _universe: universe, rank, size })
    }

    pub fn is_host(&self) -> bool {
        self.rank == 0
    }

    pub fn size(&self) -> i32 {
        self.size
    }

    /// On ranks other than 0: make every MUMPS call rank 0 announces, until it says stop.
    pub fn serve(&self) {
        let world = SimpleCommunicator::world();
        let root = world.process_at_rank(0);
        let mut instances: HashMap<i64, Box<ffi::DMUMPS_STRUC_C>> = HashMap::new();
        loop {
            let mut command = [0i64; COMMAND];
            root.broadcast_into(&mut command[..]);
            if command[0] == QUIT {
                break;
            }
            let (instance, job, sym) = (command[1], command[2] as i32, command[3] as i32);
            let id = instances.entry(instance).or_insert_with(|| {
                // SAFETY: all-zero is a valid DMUMPS_STRUC_C; JOB = −1 below initialises it.
                let mut id: Box<ffi::DMUMPS_STRUC_C> = Box::new(unsafe { std::mem::zeroed() });
                id.comm_fortran = USE_COMM_WORLD;
                id.par = 1;
                id.sym = sym;
                id
            });
            if job != -1 {
                // JOB = −1 sets MUMPS's defaults; later calls use the host's controls.
                for (k, v) in id.icntl.iter_mut().enumerate().take(ICNTL) {
                    *v = command[4 + k] as i32;
                }
                for (k, v) in id.cntl.iter_mut().enumerate().take(CNTL) {
                    *v = f64::from_bits(command[4 + ICNTL + k] as u64);
                }
            }
            id.job = job;
            // SAFETY: a worker's instance holds no user pointers (the matrix and right-hand side
            // live on the host only: centralised input), and JOB = −1 came first for it.
            unsafe { ffi::dmumps_c(&mut **id) };
            if job == -2 {
                instances.remove(&instance);
            }
        }
    }

    /// On rank 0 when it is done: let the other ranks stop.
    pub fn release(&self) {
        let mut command = [0i64; COMMAND];
        command[0] = QUIT;
        SimpleCommunicator::world().process_at_rank(0).broadcast_into(&mut command[..]);
    }
}

/// On rank 0, just before it calls MUMPS: tell the other ranks to make the same call.
pub(super) fn announce(instance: u64, id: &ffi::DMUMPS_STRUC_C) {
    let mut command = [0i64; COMMAND];
    command[0] = CALL;
    command[1] = instance as i64;
    command[2] = i64::from(id.job);
    command[3] = i64::from(id.sym);
    for (k, v) in id.icntl.iter().enumerate().take(ICNTL) {
        command[4 + k] = i64::from(*v);
    }
    for (k, v) in id.cntl.iter().enumerate().take(CNTL) {
        command[4 + ICNTL + k] = v.to_bits() as i64;
    }
    SimpleCommunicator::world().process_at_rank(0).broadcast_into(&mut command[..]);
}
