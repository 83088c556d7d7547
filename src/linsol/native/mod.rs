//! The native backends, and the only unsafe code in geoslip.
//!
//! Each backend has one struct that owns its native handle: created (and null-checked) in `new`,
//! freed in `Drop`. No raw pointer leaves this module. MUMPS calls hold `geoslip_sys::MUMPS_LOCK`.

#[cfg(all(geoslip_mumps, feature = "mpi"))]
pub mod cluster;
#[cfg(geoslip_mumps)]
pub mod mumps;
#[cfg(geoslip_umfpack)]
pub mod umfpack;

/// MUMPS's INFO(1)/INFOG(1) codes and what they mean (MUMPS 5.5 user guide, §8 "Error
/// diagnostics"). Kept outside the cfg so that the mapping is tested on every build.
pub fn mumps_message(code: i32, info2: i64) -> String {
    let text = match code {
        0 => "success",
        -1 => "an error occurred on a processor (INFO(2) names it)",
        -2 => "the number of entries NNZ is out of range",
        -3 => "MUMPS was called with an invalid JOB, or phases in the wrong order",
        -4 => "error in the user-provided permutation",
        -5 => "not enough memory for real workspace during the analysis",
        -6 => "the matrix is singular in structure (INFO(2) is its structural rank)",
        -7 => "not enough memory for integer workspace during the analysis",
        -8 => "the integer working array is too small for the factorisation (ICNTL(14) too small)",
        -9 => "the real working array is too small for the factorisation (ICNTL(14) too small)",
        -10 => "the matrix is numerically singular",
        -11 => "the real working array is too small for the solution phase",
        -12 => "the real working array is too small for iterative refinement",
        -13 => "a memory allocation failed (INFO(2) is the size asked for)",
        -14 => "the integer working array is too small for the solution phase",
        -15 => "the integer working array is too small for iterative refinement or error analysis",
        -16 => "N is out of range",
        -17 => "the internal send buffer is too small",
        -19 => "the memory limit ICNTL(23) is too small for the factorisation",
        -20 => "the internal reception buffer is too small",
        -21 => "PAR = 0 is not allowed with only one process",
        -22 => "a pointer array is missing or has the wrong size (INFO(2) says which)",
        -23 => "MPI was not initialised before JOB = -1",
        -24 => "NELT is out of range",
        -26 => "LRHS is out of range",
        -38 => "parallel analysis was requested but PT-SCOTCH and ParMETIS are not available",
        -40 => "a negative or null pivot was met although the matrix was declared positive definite",
        -44 => "the solve phase cannot run: the factors are not available",
        -45 => "NRHS is not positive",
        -50 => "the fill-reducing ordering failed during the analysis",
        -51 => "the ordering library's 32-bit integers cannot index a graph this large",
        -53 => "inconsistent input between two consecutive calls",
        -69 => "the Fortran INTEGER size does not match MUMPS_INT",
        -90 => "error in the out-of-core management",
        c if c > 0 => return format!("MUMPS warning {c} (1: index out of range ignored; 2: solution norm near zero; 8: iterative refinement did not converge; sums combine them)"),
        _ => return format!("MUMPS error {code} (INFO(2) = {info2}); see the MUMPS user guide, section 8"),
    };
    format!("{text} (INFOG(1) = {code}, INFOG(2) = {info2})")
}

/// UMFPACK status codes (UMFPACK user guide, "umfpack_*_symbolic/numeric/solve: Returns").
pub fn umfpack_message(status: i64) -> String {
    let text = match status {
        0 => "ok",
        1 => "the matrix is singular (UMFPACK_WARNING_singular_matrix)",
        2 => "the determinant underflowed (UMFPACK_WARNING_determinant_underflow)",
        3 => "the determinant overflowed (UMFPACK_WARNING_determinant_overflow)",
        -1 => "out of memory (UMFPACK_ERROR_out_of_memory)",
        -3 => "invalid numeric factorisation object (UMFPACK_ERROR_invalid_Numeric_object)",
        -4 => "invalid symbolic analysis object (UMFPACK_ERROR_invalid_Symbolic_object)",
        -5 => "a required argument is missing (UMFPACK_ERROR_argument_missing)",
        -6 => "the matrix dimension is not positive (UMFPACK_ERROR_n_nonpositive)",
        -8 => "the matrix is invalid: column pointers or row indices are wrong (UMFPACK_ERROR_invalid_matrix)",
        -11 => "the pattern differs from the one analysed (UMFPACK_ERROR_different_pattern)",
        -13 => "invalid system to solve (UMFPACK_ERROR_invalid_system)",
        -15 => "invalid permutation (UMFPACK_ERROR_invalid_permutation)",
        -17 => "file input/output error (UMFPACK_ERROR_file_IO)",
        -18 => "the ordering method failed (UMFPACK_ERROR_ordering_failed)",
        -911 => "internal error (UMFPACK_ERROR_internal_error)",
        _ => return format!("UMFPACK status {status} (see the UMFPACK user guide)"),
    };
    format!("{text}, status {status}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mumps_code_maps_to_a_message() {
        for code in [0, -1, -2, -3, -5, -6, -7, -8, -9, -10, -13, -16, -22, -40, -50, 1, 8, -777] {
            let m = mumps_message(code, 3);
            assert!(!m.is_empty());
            assert!(m.contains(&code.to_string()), "{m}");
        }
        assert!(mumps_message(-9, 0).contains("ICNTL(14)"));
        assert!(mumps_message(-10, 0).contains("singular"));
    }

    #[test]
    fn every_umfpack_status_maps_to_a_message() {
        for s in [0, 1, 2, 3, -1, -3, -4, -5, -6, -8, -11, -13, -15, -17, -18, -911, -99] {
            assert!(umfpack_message(s).contains(&s.to_string()));
        }
        assert!(umfpack_message(1).contains("singular"));
    }
}
