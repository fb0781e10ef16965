#!/usr/bin/env bash
# Sanitizer stage of CI (docs/fuzzing.md): installs what is missing (Debian packages, clang),
# builds the debug preset (build/debug, clang: the library and the front end instrumented with
# AddressSanitizer + UndefinedBehaviorSanitizer at -O1 -g1; the tests' own code is not, but links
# the runtimes; the fuzz targets of the next stage are built in the same tree) and runs its unit
# and case tests but the heavy ones: those recorded at 20 s or more in this build
# (tests/sanitizer_test_seconds.txt, scripts/test_seconds.py; the release stage runs them). The stage
# fails when a test it ran took twice that: record the run so that the test leaves the stage. A
# sanitizer report fails the test that triggered it (halt_on_error, abort_on_error in the preset).
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

# A heavy test renamed or removed would come back into this stage or leave a stale record.
python3 scripts/test_seconds.py verify build/debug
junit=build/debug/sanitizer_tests.xml
status=0
ctest --preset debug -E "$(python3 scripts/test_seconds.py heavy-regex)" --output-junit "$PWD/$junit" || status=$?
python3 scripts/test_seconds.py check "$junit" || status=1
exit $status
