#!/usr/bin/env bash
# Long runs of the model fuzzer (tests/model_fuzzer.rs): mutated model files checked and run by the
# geoslip binary, counting panics, crashes, time-outs, check/run disagreements, non-finite results
# and files written outside --out. The test command runs it on a fixed seed for under a minute;
# this is for people (100 000 cases take about an hour on two cores), not for CI. With --parsers N
# it runs the in-process fuzzer of every reader (tests/parser_fuzz.rs) instead, N inputs a target.
#
#   scripts/fuzz.sh [--cases N] [--seed S] [--first K] [--release] [--log FILE]
#   scripts/fuzz.sh --parsers N [--seed S] [--release]
#
#   --cases N    how many mutated models (default 10000)
#   --seed S     the campaign's seed (default 1); the same seed and count give the same models
#   --first K    start at case K of the seed's sequence (default 0), to go on with a campaign
#   --release    fuzz the release build (default: the dev profile, which the tests use)
#   --log FILE   append one line per case: seed model, mutations, exit codes, geoslip's first message
#
# Failing models are saved under target/fuzz-failures/ with their mutations, output and reason.
# The exit status is that of the test: 0 when every count is zero.
set -euo pipefail
cd "$(dirname "$0")/.."

cases=10000
seed=1
first=0
profile=()
log=""
parsers=""
while [ $# -gt 0 ]; do
  case "$1" in
    --cases) cases="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --first) first="$2"; shift 2 ;;
    --release) profile=(--release); shift ;;
    --log) log="$2"; shift 2 ;;
    --parsers) parsers="$2"; shift 2 ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "scripts/fuzz.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
case "$cases$seed$first$parsers" in *[!0-9]*) echo "scripts/fuzz.sh: --cases, --seed and --first take whole numbers" >&2; exit 2 ;; esac

if [ -n "$parsers" ]; then
  echo "== fuzzing every reader in process: $parsers inputs a target, seed $seed"
  export GEOSLIP_PARSER_FUZZ_CASES="$parsers" GEOSLIP_FUZZ_SEED="$seed"
  exec cargo test --locked "${profile[@]}" --test parser_fuzz -- --nocapture
fi

echo "== building the fuzzer and geoslip (${profile[*]:-dev profile})"
cargo test --locked "${profile[@]}" --test model_fuzzer --no-run --quiet

echo "== fuzzing: $cases cases from case $first, seed $seed"
export GEOSLIP_FUZZ_CASES="$cases" GEOSLIP_FUZZ_SEED="$seed" GEOSLIP_FUZZ_FIRST="$first" GEOSLIP_FUZZ_PROGRESS=1
if [ -n "$log" ]; then
  export GEOSLIP_FUZZ_LOG="$log"
fi
cargo test --locked "${profile[@]}" --test model_fuzzer -- --nocapture mutated_models
