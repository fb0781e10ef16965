#!/usr/bin/env bash
# The main-job command of the README: installs what is missing (Debian packages), builds settle
# tuned for this CPU (the `native` preset) and runs the built-in default case into runs/default/:
# a prolate spheroid (aspect ratio 2, density ratio 1.1) released tilted in water, which turns
# while it settles (the case text is in src/io/case.cpp; runs/default/case.resolved.toml shows
# every value used), then draws its figures into runs/default/plots/ (settle plot, matplotlib).
# Extra arguments go to `settle run`, e.g. --threads 2 or --set run.end_time=0.2.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh
cmake --preset native >/dev/null
cmake --build --preset native --target settle_cli
./build/native/src/app/settle run -o runs/default "$@"
./build/native/src/app/settle plot runs/default
echo "results in runs/default/: timeseries.csv, summary.json, case.resolved.toml, plots/*.png"
