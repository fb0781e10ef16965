#!/usr/bin/env bash
# The test command of the README, and what CI runs (.ci/run): installs what is missing (Debian
# packages) and runs three stages, each of which fails the whole command:
#   release     check the layout of the C++ files (scripts/check_format.sh), build the release
#               preset, run the unit and case tests (labels unit|case)
#   sanitizers  build the debug preset with clang (AddressSanitizer + UndefinedBehaviorSanitizer on
#               the library and the front end; the fuzz targets in the same tree) and run the unit
#               and case tests but the heavy ones, by their recorded seconds there
#               (scripts/run_sanitizer_tests.sh, tests/sanitizer_test_seconds.txt)
#   fuzz        link the libFuzzer targets of that build and fuzz the case parser, --set, the
#               study file and the STL reader for 15 s each, one per core at a time (scripts/fuzz.sh;
#               docs/fuzzing.md)
# Both builds make compiler warnings errors (SETTLE_WERROR=ON; off by default for users).
# On the 2-core development machine, idle, from a clean clone: about 7.5, 13 and 0.5 minutes (1256 s in all)
# (docs/notes.md, "The test command's time").
# SETTLE_TEST_STAGES picks stages, e.g. SETTLE_TEST_STAGES=release for the quick local loop.
# Validation runs are separate (docs/validation.md).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
stages=${SETTLE_TEST_STAGES:-release sanitizers fuzz}

for stage in $stages; do
  case $stage in
    release | sanitizers | fuzz) ;;
    *) echo "run_tests: unknown stage '$stage' in SETTLE_TEST_STAGES (allowed: release sanitizers fuzz)" >&2; exit 2 ;;
  esac
done

for stage in $stages; do
  echo "run_tests: stage $stage ($(date -u +%T))"
  case $stage in
    release)
      bash scripts/install-deps.sh
      bash scripts/check_format.sh
      cmake --preset release -DSETTLE_WERROR=ON >/dev/null
      cmake --build --preset release
      ctest --preset release
      ;;
    sanitizers) bash scripts/run_sanitizer_tests.sh -DSETTLE_WERROR=ON ;;
    fuzz) bash scripts/fuzz.sh 15 ;;
  esac
done
echo "run_tests: all stages passed: $stages ($(date -u +%T))"
