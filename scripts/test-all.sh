#!/usr/bin/env bash
# The whole test suite, with every solver backend.
#
# On Debian 12 as root it first installs what the native backends need (MUMPS sequential, UMFPACK,
# libclang for bindgen, OpenBLAS as the BLAS alternative), libhdf5 for the HDF5 results, MUMPS's MPI
# build with OpenMPI, and what the tests run beside geoslip: Gmsh (meshes the examples' .geo
# files), VTK's Python module (reads the .vtu output back), h5py and meshio (read results.h5 and
# results.xdmf back). It then tests
#   1. the full build (with the hdf5 feature), which must have MUMPS and UMFPACK when the packages
#      are installed,
#   2. the MPI build (--features mpi): mpirun -np 2 against the sequential run, and
#   3. a build with no native libraries (GEOSLIP_NO_NATIVE=1) and without the hdf5 feature, which
#      runs on faer and dense and writes .vtu files (its unit tests and the integration tests of
#      what differs in it: the commands, the .vtu output, killed runs, the paper's examples);
# and the Python package (python/, PyO3 + maturin) with its pytest tests against the CLI and the
# parameter-study example (maturin, pytest, NumPy and matplotlib from PyPI into target/python-env).
# The tests run under cargo-nextest where it is installed (tests of different binaries side by
# side), else under cargo test. It first checks the code's layout (scripts/check-imports.py) and
# that docs/architecture.md names every source file (scripts/check-architecture.py).
# This is the command the README gives and the one CI runs (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(libmumps-seq-dev libsuitesparse-dev libclang-dev libopenblas0-pthread libmumps-dev libopenmpi-dev openmpi-bin libhdf5-dev)
tools=(gmsh python3-vtk9 python3-h5py python3-meshio python3-venv)
native_expected=0
if [ -r /etc/debian_version ] && command -v apt-get >/dev/null 2>&1; then
  missing=()
  for p in "${packages[@]}" "${tools[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" -eq 0 ]; then
      echo "== installing ${missing[*]}"
      export DEBIAN_FRONTEND=noninteractive
      apt-get install -y -q "${missing[@]}" >/dev/null 2>&1 || { apt-get update -q >/dev/null && apt-get install -y -q "${missing[@]}" >/dev/null; }
    else
      echo "== not root: cannot install ${missing[*]}; testing the backends this machine can build"
    fi
  fi
  native_expected=1
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || native_expected=0
  done
fi

# the HDF5 results need libhdf5: with it the full build has the hdf5 feature (and its tests run);
# without it (not root, or not Debian) the full build is tested without the feature
features=()
if { [ -r /etc/debian_version ] && dpkg-query -W -f='${Status}' libhdf5-dev 2>/dev/null | grep -q "install ok installed"; } \
   || pkg-config --exists hdf5 2>/dev/null; then
  features=(--features hdf5)
else
  echo "== libhdf5 is not installed: the full build is tested without the hdf5 feature"
fi

echo "== layout: no import circle, no core module on the file format, every source file in docs/architecture.md"
python3 scripts/check-imports.py
python3 scripts/check-architecture.py

echo "== full build: backends"
# every build below names the whole workspace (--workspace), the Python module with it, so that
# cargo gives the dependencies the same features each time and compiles each of them once: the
# test build here, the Python module, the MPI build and the build without native libraries differ
# only in what they change (tests/, python/, the mpi feature, geoslip-sys)
cargo test --workspace --locked --quiet --no-run "${features[@]}"
backends=$(target/debug/geoslip backends | tr '\n' ' ')
echo "   $backends"
if [ "$native_expected" = 1 ]; then
  for b in mumps umfpack; do
    case " $backends " in *" $b "*) ;; *) echo "error: $b was not built although its packages are installed"; exit 1 ;; esac
  done
fi
# cargo-nextest, where it is installed, runs tests of different binaries side by side on the
# machine's cores (.config/nextest.toml names the tests that run alone); cargo test runs the
# binaries one after another. Either runs every test.
nextest=0
cargo nextest --version >/dev/null 2>&1 && nextest=1
run_tests() {
  if [ "$nextest" = 1 ]; then
    cargo nextest run --locked --no-tests=warn "$@"
  else
    cargo test --locked "$@"
  fi
}

echo "== full build: tests${features[*]:+ (${features[*]})}"
# each test that a document quotes records its numbers here (tests/common/mod.rs, doc_number)
rm -rf target/doc-numbers
GEOSLIP_DOC_NUMBERS="$PWD/target/doc-numbers" run_tests --workspace "${features[@]}"
if [ "$nextest" = 1 ]; then
  # (nextest does not run documentation examples)
  cargo test --workspace --locked "${features[@]}" --doc
fi

echo "== the numbers the README and docs quote from runs, against the runs"
python3 scripts/doc-numbers.py --geoslip target/debug/geoslip --measured target/doc-numbers

echo "== Python package: built by maturin into target/python-env, its tests (pytest) and the parameter study"
# maturin, pytest, NumPy and matplotlib come from the package registry (PyPI); the module shares
# target/ and the features with the build above (HDF5 results as well), so only PyO3 and the
# module are compiled
python3 -m venv target/python-env
# without pip's cache (its temporary copies of the wheels need room beside target/), retried once
# after a failed download
pip_install() {
  target/python-env/bin/pip install --quiet --disable-pip-version-check --no-cache-dir --retries 5 --timeout 60 \
    "maturin>=1.5,<2" pytest numpy matplotlib
}
pip_install || { echo "== the Python packages' download failed; trying once more"; sleep 10; pip_install; }
(cd python && VIRTUAL_ENV="$PWD/../target/python-env" CARGO_TARGET_DIR="$PWD/../target" \
  ../target/python-env/bin/maturin develop --locked --quiet "${features[@]}")
GEOSLIP_CLI="$PWD/target/debug/geoslip" target/python-env/bin/python -m pytest -q python/tests
target/python-env/bin/python examples/python/parameter_study.py target/parameter-study.png

if command -v mpirun >/dev/null 2>&1 && [ -e /usr/lib/x86_64-linux-gnu/libdmumps.so ]; then
  echo "== MPI build: mpirun -np 2 against the sequential run"
  # built in the same target folder, so that only the crates the mpi feature changes are compiled
  # again; the sequential binary it is compared with is kept aside first, because the MPI build
  # replaces target/debug/geoslip
  cp target/debug/geoslip target/geoslip-sequential
  GEOSLIP_SEQUENTIAL="$PWD/target/geoslip-sequential" \
    cargo test --workspace --locked --features mpi --test mpi_agreement
elif [ "$native_expected" = 1 ]; then
  echo "error: the MPI packages are installed but mpirun or libdmumps.so is missing"; exit 1
else
  echo "== MPI build: skipped (needs libmumps-dev, libopenmpi-dev and openmpi-bin)"
fi

echo "== build without native libraries and without HDF5: unit tests and the tests of what differs"
# every integration test ran above on faer and dense as well; here the build itself, the commands,
# the .vtu output read back, killed runs without HDF5, and the paper's examples on this build
GEOSLIP_NO_NATIVE=1 run_tests --workspace --lib --bins --test cli --test vtk_readback \
  --test killed_runs --test paper_examples --test kept_steps --test untrusted_model_files
echo "== all tests passed ($backends, and faer/dense alone)"
