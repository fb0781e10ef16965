#!/usr/bin/env bash
# Fuzzes the case parser, the --set overrides, the study file and the STL reader (docs/fuzzing.md):
# builds the four targets of tests/fuzz in the sanitizer build (the debug preset: clang, ASan +
# UBSan, libFuzzer's coverage on the modules they drive; shared with scripts/run_sanitizer_tests.sh,
# so after that stage only the targets are left to link), then runs each target for SECONDS
# (default 60) in one process, SETTLE_FUZZ_PARALLEL of them side by side (default: one per core).
# Crash, timeout and out-of-memory inputs go to build/debug/findings/; the script exits with status
# 1 when any target found something.
#
#   scripts/fuzz.sh [SECONDS]
#
# Environment: SETTLE_FUZZ_JOBS (build jobs, default: all cores), SETTLE_FUZZ_PARALLEL (targets at
# a time, default: all cores). The corpus each target grows is kept in build/debug/corpus/<target>
# and reused by the next run; the seeds are tests/fuzz/corpus_<input>.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

seconds=${1:-60}
if ! [[ $seconds =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: scripts/fuzz.sh [SECONDS]  (a positive whole number of seconds per target, got '$seconds')" >&2
  exit 2
fi
build=build/debug
jobs=${SETTLE_FUZZ_JOBS:-$(nproc)}
lanes=${SETTLE_FUZZ_PARALLEL:-$(nproc)}
if ! [[ $lanes =~ ^[1-9][0-9]*$ ]]; then
  echo "fuzz: SETTLE_FUZZ_PARALLEL must be a positive whole number, got '$lanes'" >&2
  exit 2
fi

bash scripts/install-deps.sh --clang
cmake --preset debug >/dev/null
cmake --build --preset debug -j "$jobs" --target fuzz_case fuzz_set fuzz_study fuzz_stl

findings="$build/findings"
mkdir -p "$findings" "$build/logs"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export OMP_NUM_THREADS=1

status_dir=$(mktemp -d)
trap 'rm -rf "$status_dir"' EXIT
# Runs in the background: its verdict goes to $status_dir/<target> (0: no finding).
run_target() {
  local target=$1 seeds=$2
  shift 2
  local corpus="$build/corpus/$target" log="$build/logs/$target.log" status=0
  mkdir -p "$corpus"
  echo "fuzz: $target for ${seconds} s (log: $log)"
  # New inputs go to the first corpus directory (the build's); the seeds are only read.
  "$build/tests/fuzz/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$findings/$target-" -print_final_stats=1 "$@" "$corpus" "$seeds" >"$log" 2>&1 || status=$?
  if ((status == 0)); then
    grep -E "^(Done|stat::number_of_executed_units|stat::peak_rss_mb)" "$log" | sed "s/^/fuzz: $target: /" || true
  else
    echo "fuzz: $target: FINDING (status $status); last lines of $log:" >&2
    tail -n 40 "$log" >&2
  fi
  echo "$status" >"$status_dir/$target"
}
# At most $lanes targets at a time, one core each (the targets are single-threaded).
start_target() {
  while (($(jobs -rp | wc -l) >= lanes)); do wait -n || true; done
  run_target "$@" &
}
start_target fuzz_case tests/fuzz/corpus_case -dict=tests/fuzz/case.dict
start_target fuzz_set tests/fuzz/corpus_set -dict=tests/fuzz/case.dict
start_target fuzz_study tests/fuzz/corpus_study -dict=tests/fuzz/study.dict
start_target fuzz_stl tests/fuzz/corpus_stl
wait

failed=()
for target in fuzz_case fuzz_set fuzz_study fuzz_stl; do
  [[ $(cat "$status_dir/$target" 2>/dev/null) == 0 ]] || failed+=("$target")
done
if ((${#failed[@]} > 0)); then
  echo "fuzz: findings in ${failed[*]}: inputs in $findings/; reproduce with $build/tests/fuzz/<target> FILE" >&2
  exit 1
fi
echo "fuzz: no findings"
