#!/usr/bin/env bash
# Sanitizer stage of CI (docs/fuzzing.md): installs what is missing (Debian packages, clang),
# builds the debug preset (build/debug, clang: the library and the front end instrumented with
# AddressSanitizer + UndefinedBehaviorSanitizer at -O1 -g1; the tests' own code is not, but links
# the runtimes; the fuzz targets of the next stage are built in the same tree) and runs its unit
# and case tests. The debug test preset leaves out the tests labelled `heavy`
# (tests/heavy_tests.cmake: long numerical runs, still run by the release preset of
# scripts/run_tests.sh). A sanitizer report fails the test that triggered it (halt_on_error,
# abort_on_error in the preset).
#
#   scripts/run_sanitizer_tests.sh [CMAKE_ARGS...]   (given to the configure step, e.g. -DSETTLE_WERROR=ON)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh --clang
cmake --preset debug "$@" >/dev/null
cmake --build --preset debug

# The code under test must carry the instrumentation (a flag lost from a module's target would
# otherwise make this stage pass without checking that module): every module library calls both
# runtimes.
modules=(build/debug/src/libsettle_*.a)
if [[ ! -e ${modules[0]} ]]; then
  echo "run_sanitizer_tests: no module libraries build/debug/src/libsettle_*.a" >&2
  exit 1
fi
for library in "${modules[@]}"; do
  undefined_symbols=$(nm --undefined-only "$library" 2>/dev/null)
  for sym in __asan_report_load8 __ubsan_handle_; do
    if ! grep -q " U ${sym}" <<<"$undefined_symbols"; then
      echo "run_sanitizer_tests: $library has no calls to ${sym}*: not instrumented" >&2
      exit 1
    fi
  done
done

# A renamed heavy test would silently lose its label and make this stage too slow for CI.
listed=$(grep -cE '^\s+[A-Za-z0-9_/]+\.[A-Za-z0-9_/]+' tests/heavy_tests.cmake)
labelled=$(ctest --test-dir build/debug -N -L heavy | grep -cE '^\s*Test +#' || true)
if [[ $listed != "$labelled" ]]; then
  echo "run_sanitizer_tests: tests/heavy_tests.cmake names $listed tests but $labelled carry the label heavy;" \
    "update the names there" >&2
  exit 1
fi

ctest --preset debug
