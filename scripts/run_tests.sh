#!/usr/bin/env bash
# The test command of the README: installs what is missing (Debian packages), builds the release
# preset and runs the unit and case tests (labels unit|case). Validation runs are separate:
# scripts/run_validation.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release
