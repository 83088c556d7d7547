//! Generate declarations for the native solvers that are installed, and nothing for those that are
//! not: a machine without them still builds (geoslip then runs on faer and the dense reference).
//!
//! Debian 12 locations (shared/DESIGN.md §2):
//! - MUMPS, sequential (`libmumps-seq-dev`): `dmumps_c.h` in the default include path; its MPI stub
//!   `mpi.h` in `/usr/include/mumps_seq`, which must come first; link `dmumps_seq`,
//!   `mumps_common_seq`, `mpiseq_seq`, `pord_seq`.
//! - UMFPACK (`libsuitesparse-dev`): `umfpack.h` in `/usr/include/suitesparse`; link `umfpack`.
//! - bindgen needs libclang (`libclang-dev`).
//!
//! - MUMPS, MPI build (`libmumps-dev`, OpenMPI), with the `mpi` feature instead of the sequential
//!   one: the same header and struct (`comm_fortran` is a Fortran integer in both); link `dmumps`,
//!   `mumps_common`, `pord`. The two libraries export the same symbols, so a binary has one or the
//!   other.
//!
//! `GEOSLIP_NO_NATIVE=1` builds without them even where they are installed (to test that build).
//! Tells the crates that depend on this one, through `DEP_GEOSLIP_NATIVE_MUMPS` and
//! `DEP_GEOSLIP_NATIVE_UMFPACK`, what was found.

use std::env;
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-env-changed=GEOSLIP_NO_NATIVE");
    println!("cargo:rerun-if-env-changed=GEOSLIP_MUMPS_INCLUDE");
    println!("cargo:rerun-if-env-changed=GEOSLIP_UMFPACK_INCLUDE");
    println!("cargo::rustc-check-cfg=cfg(has_mumps)");
    println!("cargo::rustc-check-cfg=cfg(has_umfpack)");
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let disabled = env::var("GEOSLIP_NO_NATIVE").is_ok_and(|v| !v.is_empty() && v != "0");

    let mumps_include = env::var("GEOSLIP_MUMPS_INCLUDE").unwrap_or_else(|_| "/usr/include".into());
    let mumps_header = Path::new(&mumps_include).join("dmumps_c.h");
    let mpi_stub = Path::new("/usr/include/mumps_seq");
    let umfpack_include = env::var("GEOSLIP_UMFPACK_INCLUDE").unwrap_or_else(|_| "/usr/include/suitesparse".into());
    let umfpack_header = Path::new(&umfpack_include).join("umfpack.h");
    println!("cargo:rerun-if-changed={}", mumps_header.display());
    println!("cargo:rerun-if-changed={}", umfpack_header.display());

    let mumps = !disabled
        && mumps_header.exists()
        && mpi_stub.join("mpi.h").exists()
        && generate(
            &mumps_header,
            &[mpi_stub, Path::new(&mumps_include)],
            &["dmumps_c"],
            &["DMUMPS_STRUC_C"],
            &["MUMPS_VERSION", "MUMPS_VERSION_MAX_LEN"],
            &out.join("mumps.rs"),
        );
    let umfpack = !disabled
        && umfpack_header.exists()
        && generate(
            &umfpack_header,
            &[Path::new(&umfpack_include)],
            &["umfpack_dl_.*"],
            &[],
            &["UMFPACK_.*"],
            &out.join("umfpack.rs"),
        );
    let mpi = env::var_os("CARGO_FEATURE_MPI").is_some();
    if mpi && !mumps {
        panic!(
            "the `mpi` feature needs MUMPS's header and bindgen: install Debian's libmumps-dev, libopenmpi-dev and \
             libclang-dev (and do not set GEOSLIP_NO_NATIVE)"
        );
    }
    if mpi {
        let found = ["/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib", "/usr/local/lib"]
            .iter()
            .any(|d| Path::new(d).join("libdmumps.so").exists());
        if !found {
            panic!("the `mpi` feature links MUMPS's MPI build (libdmumps.so): install Debian's libmumps-dev");
        }
    }
    if mumps {
        println!("cargo:rustc-cfg=has_mumps");
        let libs: &[&str] = if mpi {
            &["dmumps", "mumps_common", "pord"]
        } else {
            &["dmumps_seq", "mumps_common_seq", "mpiseq_seq", "pord_seq"]
        };
        for lib in libs {
            println!("cargo:rustc-link-lib={lib}");
        }
        println!("cargo:mumps=1");
        println!("cargo:mumps_mpi={}", u8::from(mpi));
    } else {
        println!("cargo:mumps=0");
    }
    if umfpack {
        println!("cargo:rustc-cfg=has_umfpack");
        println!("cargo:rustc-link-lib=umfpack");
        println!("cargo:umfpack=1");
    } else {
        println!("cargo:umfpack=0");
    }
}

/// Run bindgen over one header; false (with a build warning) when it cannot, for example when
/// libclang is missing.
fn generate(header: &Path, includes: &[&Path], functions: &[&str], types: &[&str], vars: &[&str], out: &Path) -> bool {
    let mut builder = bindgen::Builder::default()
        .header(header.display().to_string())
        .layout_tests(true)
        .derive_default(false)
        .generate_comments(false);
    for dir in includes {
        builder = builder.clang_arg(format!("-I{}", dir.display()));
    }
    for f in functions {
        builder = builder.allowlist_function(f);
    }
    for t in types {
        builder = builder.allowlist_type(t);
    }
    for v in vars {
        builder = builder.allowlist_var(v);
    }
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| builder.generate()));
    match result {
        Ok(Ok(bindings)) => match bindings.write_to_file(out) {
            Ok(()) => true,
            Err(e) => {
                println!("cargo:warning=geoslip-sys: cannot write {}: {e}", out.display());
                false
            }
        },
        Ok(Err(e)) => {
            println!("cargo:warning=geoslip-sys: bindgen failed on {}: {e}; building without it", header.display());
            false
        }
        Err(_) => {
            println!(
                "cargo:warning=geoslip-sys: bindgen could not run on {} (is libclang-dev installed?); building without it",
                header.display()
            );
            false
        }
    }
}
