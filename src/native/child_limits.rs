//! Resource limits of a program geoslip starts (Gmsh): set in the child, after the fork and before
//! the program is executed, so that they bind it from its first instruction and bind nothing of
//! geoslip's own.

use std::os::unix::process::CommandExt;
use std::process::Command;

/// Set, for the program `command` starts: its address space to `memory_bytes`, each file it writes
/// to `file_bytes`, its CPU time to twice `wall_seconds` on every core of the machine (the wall
/// time itself is the caller's to watch), no core file; and it is killed when the thread that
/// started it ends (PR_SET_PDEATHSIG), so that it cannot outlive geoslip.
pub fn set(command: &mut Command, memory_bytes: u64, file_bytes: u64, wall_seconds: f64) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as f64;
    let cpu_seconds = (2.0 * wall_seconds * cores).ceil().min(u32::MAX as f64) as u64 + 1;
    let limits = [
        (libc::RLIMIT_AS, memory_bytes),
        (libc::RLIMIT_FSIZE, file_bytes),
        (libc::RLIMIT_CPU, cpu_seconds),
        (libc::RLIMIT_CORE, 0),
    ];
    // SAFETY: the closure runs in the forked child before exec and calls only setrlimit and prctl,
    // which are async-signal-safe; it allocates nothing and touches no lock.
    unsafe {
        command.pre_exec(move || {
            for (resource, value) in limits {
                let limit = libc::rlimit { rlim_cur: value as libc::rlim_t, rlim_max: value as libc::rlim_t };
                if libc::setrlimit(resource, &limit) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
            }
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL as libc::c_ulong, 0, 0, 0) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
}
