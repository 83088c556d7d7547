//! The native solvers' status codes as types: MUMPS's INFOG(1) and UMFPACK's status, each mapped
//! code a variant of its own with what it means and what to do.
//!
//! Kept outside the backends' `cfg` so that the mapping is built and tested on every build, with or
//! without the native libraries.

use std::fmt;

/// The phase of a native solver in which a code was returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// MUMPS JOB = −1.
    Initialisation,
    /// MUMPS JOB = 1, `umfpack_dl_symbolic`.
    Analysis,
    /// MUMPS JOB = 2, `umfpack_dl_numeric`.
    Factorisation,
    /// MUMPS JOB = 3, `umfpack_dl_solve`.
    Solution,
}

impl fmt::Display for Phase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Phase::Initialisation => "initialisation",
            Phase::Analysis => "analysis",
            Phase::Factorisation => "factorisation",
            Phase::Solution => "solution",
        })
    }
}

/// Declares a code enum with its numeric value and its text, and the two-way mapping.
macro_rules! status_codes {
    ($(#[$meta:meta])* $name:ident: $int:ty { $($variant:ident = $code:literal => $text:literal,)* }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[non_exhaustive]
        pub enum $name {
            $(#[doc = $text] $variant,)*
            /// A code this mapping does not know.
            Unknown($int),
        }

        impl $name {
            /// Every code the mapping knows.
            pub const KNOWN: &'static [$int] = &[$($code),*];

            /// The variant of a code.
            pub fn from_code(code: $int) -> Self {
                match code {
                    $($code => $name::$variant,)*
                    other => $name::Unknown(other),
                }
            }

            /// The code of a variant.
            pub fn code(self) -> $int {
                match self {
                    $($name::$variant => $code,)*
                    $name::Unknown(c) => c,
                }
            }

            /// What the code means.
            pub fn meaning(self) -> &'static str {
                match self {
                    $($name::$variant => $text,)*
                    $name::Unknown(_) => "a code geoslip does not know; see the library's user guide",
                }
            }
        }
    };
}

status_codes! {
    /// MUMPS's INFOG(1) error codes (MUMPS 5.5 user guide, §8 "Error diagnostics").
    MumpsCode: i32 {
        ProcessError = -1 => "an error occurred on another process (INFOG(2) names it)",
        EntryCountOutOfRange = -2 => "the number of entries NNZ is out of range",
        InvalidJob = -3 => "MUMPS was called with an invalid JOB, or its phases in the wrong order",
        InvalidPermutation = -4 => "error in the user-provided permutation",
        AnalysisRealMemory = -5 => "not enough memory for the real workspace of the analysis",
        StructurallySingular = -6 => "the matrix is singular in structure (INFOG(2) is its structural rank)",
        AnalysisIntegerMemory = -7 => "not enough memory for the integer workspace of the analysis",
        IntegerWorkspaceTooSmall = -8 => "the integer working array is too small for the factorisation (ICNTL(14) too small)",
        RealWorkspaceTooSmall = -9 => "the real working array is too small for the factorisation (ICNTL(14) too small)",
        NumericallySingular = -10 => "the matrix is numerically singular",
        SolutionRealWorkspace = -11 => "the real working array is too small for the solution phase",
        RefinementRealWorkspace = -12 => "the real working array is too small for iterative refinement",
        AllocationFailed = -13 => "a memory allocation failed (INFOG(2) is the size asked for)",
        SolutionIntegerWorkspace = -14 => "the integer working array is too small for the solution phase",
        RefinementIntegerWorkspace = -15 => "the integer working array is too small for iterative refinement or error analysis",
        OrderOutOfRange = -16 => "the order N of the matrix is out of range",
        SendBufferTooSmall = -17 => "the internal send buffer is too small",
        MemoryLimitTooSmall = -19 => "the memory limit ICNTL(23) is too small for the factorisation",
        ReceiveBufferTooSmall = -20 => "the internal reception buffer is too small",
        HostWithoutWork = -21 => "PAR = 0 is not allowed with only one process",
        PointerArrayMissing = -22 => "a pointer array is missing or has the wrong size (INFOG(2) says which)",
        MpiNotInitialised = -23 => "MPI was not initialised before JOB = -1",
        ElementCountOutOfRange = -24 => "NELT is out of range",
        RhsLeadingDimension = -26 => "LRHS is out of range",
        NoParallelOrdering = -38 => "parallel analysis was requested but PT-SCOTCH and ParMETIS are not available",
        NotPositiveDefinite = -40 => "a negative or null pivot was met although the matrix was declared positive definite",
        FactorsUnavailable = -44 => "the solution phase cannot run: the factors are not available",
        RhsCountNotPositive = -45 => "NRHS is not positive",
        OrderingFailed = -50 => "the fill-reducing ordering failed during the analysis",
        OrderingIndexOverflow = -51 => "the ordering library's 32-bit integers cannot index a graph this large",
        InconsistentCalls = -53 => "inconsistent input between two consecutive calls",
        IntegerSizeMismatch = -69 => "the Fortran INTEGER size does not match MUMPS_INT",
        OutOfCoreError = -90 => "error in the out-of-core management",
    }
}

status_codes! {
    /// UMFPACK's status codes (UMFPACK user guide, "umfpack_*_symbolic/numeric/solve: Returns").
    UmfpackStatus: i64 {
        SingularMatrix = 1 => "the matrix is singular (UMFPACK_WARNING_singular_matrix)",
        DeterminantUnderflow = 2 => "the determinant underflowed (UMFPACK_WARNING_determinant_underflow)",
        DeterminantOverflow = 3 => "the determinant overflowed (UMFPACK_WARNING_determinant_overflow)",
        OutOfMemory = -1 => "out of memory (UMFPACK_ERROR_out_of_memory)",
        InvalidNumericObject = -3 => "invalid numeric factorisation object (UMFPACK_ERROR_invalid_Numeric_object)",
        InvalidSymbolicObject = -4 => "invalid symbolic analysis object (UMFPACK_ERROR_invalid_Symbolic_object)",
        ArgumentMissing = -5 => "a required argument is missing (UMFPACK_ERROR_argument_missing)",
        OrderNotPositive = -6 => "the matrix dimension is not positive (UMFPACK_ERROR_n_nonpositive)",
        InvalidMatrix = -8 => "the matrix is invalid: column pointers or row indices are wrong (UMFPACK_ERROR_invalid_matrix)",
        DifferentPattern = -11 => "the pattern differs from the one analysed (UMFPACK_ERROR_different_pattern)",
        InvalidSystem = -13 => "invalid system to solve (UMFPACK_ERROR_invalid_system)",
        InvalidPermutation = -15 => "invalid permutation (UMFPACK_ERROR_invalid_permutation)",
        FileIo = -17 => "file input/output error (UMFPACK_ERROR_file_IO)",
        OrderingFailed = -18 => "the ordering method failed (UMFPACK_ERROR_ordering_failed)",
        InternalError = -911 => "internal error (UMFPACK_ERROR_internal_error)",
    }
}

impl MumpsCode {
    /// What a user can do about it, where there is something.
    pub fn hint(self) -> Option<&'static str> {
        match self {
            MumpsCode::AnalysisRealMemory
            | MumpsCode::AnalysisIntegerMemory
            | MumpsCode::AllocationFailed
            | MumpsCode::MemoryLimitTooSmall => {
                Some("the machine ran out of memory: try --out-of-core, a coarser mesh or a machine with more memory")
            }
            MumpsCode::IntegerWorkspaceTooSmall | MumpsCode::RealWorkspaceTooSmall => {
                Some("geoslip already doubled ICNTL(14) several times; the pivots of this matrix are far from the analysis's plan: check the model for nearly singular parts")
            }
            MumpsCode::StructurallySingular | MumpsCode::NumericallySingular => {
                Some("some unknown is not held: check the supports and that every body and bar is connected")
            }
            MumpsCode::OrderingFailed | MumpsCode::OrderingIndexOverflow => {
                Some("try another ordering (--ordering pord or --ordering amd)")
            }
            MumpsCode::OutOfCoreError => Some("check that MUMPS_OOC_TMPDIR (or /tmp) exists, is writable and has room"),
            _ => None,
        }
    }
}

impl UmfpackStatus {
    /// What a user can do about it, where there is something.
    pub fn hint(self) -> Option<&'static str> {
        match self {
            UmfpackStatus::OutOfMemory => {
                Some("the machine ran out of memory: try --solver mumps --out-of-core, or a coarser mesh")
            }
            UmfpackStatus::SingularMatrix => {
                Some("some unknown is not held: check the supports and that every body and bar is connected")
            }
            UmfpackStatus::OrderingFailed => Some("try --solver mumps or --solver faer"),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    //! Every code maps to its own variant and back, with a meaning of its own.
    use super::*;

    #[test]
    fn every_mumps_code_is_a_variant_of_its_own() {
        let mut meanings = std::collections::HashSet::new();
        for &code in MumpsCode::KNOWN {
            let variant = MumpsCode::from_code(code);
            assert!(!matches!(variant, MumpsCode::Unknown(_)), "INFOG(1) = {code} is not mapped");
            assert_eq!(variant.code(), code);
            assert!(meanings.insert(variant.meaning()), "INFOG(1) = {code} shares its meaning");
        }
        assert_eq!(MumpsCode::KNOWN.len(), 33);
        assert_eq!(MumpsCode::from_code(-777), MumpsCode::Unknown(-777));
        assert_eq!(MumpsCode::from_code(-777).code(), -777);
        assert_eq!(MumpsCode::from_code(-9), MumpsCode::RealWorkspaceTooSmall);
        assert_eq!(MumpsCode::from_code(-10), MumpsCode::NumericallySingular);
        assert!(MumpsCode::from_code(-13).hint().unwrap().contains("out-of-core"));
    }

    #[test]
    fn every_umfpack_status_is_a_variant_of_its_own() {
        let mut meanings = std::collections::HashSet::new();
        for &status in UmfpackStatus::KNOWN {
            let variant = UmfpackStatus::from_code(status);
            assert!(!matches!(variant, UmfpackStatus::Unknown(_)), "status {status} is not mapped");
            assert_eq!(variant.code(), status);
            assert!(meanings.insert(variant.meaning()), "status {status} shares its meaning");
        }
        assert_eq!(UmfpackStatus::KNOWN.len(), 15);
        assert_eq!(UmfpackStatus::from_code(-99), UmfpackStatus::Unknown(-99));
        assert_eq!(UmfpackStatus::from_code(-6), UmfpackStatus::OrderNotPositive);
        assert!(UmfpackStatus::from_code(1).meaning().contains("singular"));
    }
}
