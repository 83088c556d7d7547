//! The C heap that geoslip shares with the native solvers and their threads.
//!
//! glibc gives each thread that allocates under contention an arena of its own, up to eight per
//! core. Memory freed into a worker thread's arena is reused only by threads that land on that
//! arena, so in a run whose worker threads (faer's, OpenBLAS's) allocate large temporaries the
//! resident set grows by what each arena keeps. At one arena per core the 10⁵-unknown pull-out
//! run's peak is 35–45 MiB lower at the same wall time (docs/performance.md, "The C heap").

/// Allow glibc one heap arena per core, unless the user chose a number (`MALLOC_ARENA_MAX`, which
/// glibc reads itself). Call before any thread is started; elsewhere than glibc, nothing is done.
pub fn one_arena_per_core() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        if std::env::var_os("MALLOC_ARENA_MAX").is_some() {
            return;
        }
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let arenas = std::ffi::c_int::try_from(cores).unwrap_or(std::ffi::c_int::MAX);
        // glibc's malloc.h: #define M_ARENA_MAX -8
        const M_ARENA_MAX: std::ffi::c_int = -8;
        extern "C" {
            fn mallopt(param: std::ffi::c_int, value: std::ffi::c_int) -> std::ffi::c_int;
        }
        // SAFETY: mallopt only sets a parameter of glibc's allocator; M_ARENA_MAX takes any
        // positive count. Its status (0 on failure) leaves glibc's default, which is harmless.
        unsafe { mallopt(M_ARENA_MAX, arenas) };
    }
}
