//! Detect which native solver backends this build has.
//!
//! `geoslip-sys` runs bindgen over the headers that are installed and reports what it found through
//! its `links` metadata (`DEP_GEOSLIP_NATIVE_MUMPS`, `DEP_GEOSLIP_NATIVE_UMFPACK`). This script turns
//! that into `cfg(geoslip_mumps)` and `cfg(geoslip_umfpack)`, and records the backend list that
//! `geoslip --version` and `geoslip backends` print. Without the native libraries the build still
//! succeeds and runs on faer and the dense reference.

fn main() {
    // (what it reads is geoslip-sys's metadata, which cargo tracks: without this line every change
    // of any file of the package, a test or a document, would run it again and rebuild the library)
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo::rustc-check-cfg=cfg(geoslip_mumps)");
    println!("cargo::rustc-check-cfg=cfg(geoslip_umfpack)");
    let found = |name: &str| std::env::var(format!("DEP_GEOSLIP_NATIVE_{name}")).is_ok_and(|v| v == "1");
    let mut backends = Vec::new();
    if found("MUMPS") {
        println!("cargo:rustc-cfg=geoslip_mumps");
        backends.push(if found("MUMPS_MPI") { "mumps (MPI build)" } else { "mumps" });
    }
    if found("UMFPACK") {
        println!("cargo:rustc-cfg=geoslip_umfpack");
        backends.push("umfpack");
    }
    backends.extend(["faer", "dense"]);
    println!("cargo:rustc-env=GEOSLIP_BACKENDS={}", backends.join(", "));
}
