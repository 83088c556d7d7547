//! `geoslip-mpi`: geoslip built against Debian's MPI build of MUMPS (`cargo build --release
//! --features mpi`). Run it under `mpirun -np N`: rank 0 reads the model, assembles and writes the
//! results; MUMPS distributes the analysis, the factorisation and the solves over all N ranks.

fn main() -> std::process::ExitCode {
    geoslip::cli::main()
}
