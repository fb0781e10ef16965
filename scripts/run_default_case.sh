#!/usr/bin/env bash
# The main-job command of the README: installs what is missing, builds settle tuned for this CPU
# and runs the built-in default case into runs/default/.
#
# Until the coupled fluid-particle run lands (issue "settle run"), the default job is the attitude
# demonstration: a torque-free asymmetric body (principal moments 1, 2, 3 kg m^2) spun about its
# unstable intermediate axis, which flips over and over (the Dzhanibekov effect). The dual-Euler
# solver switches Euler sets at each flip; the CSV holds both angle sets, the active one and the
# attitude matrix.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh
cmake --preset native >/dev/null
cmake --build --preset native --target settle_cli
mkdir -p runs/default
./build/native/src/app/settle attitude --inertia 1,2,3 --omega 0.01,1,0.01 --dt 1e-3 --t-end 40 \
  -o runs/default/attitude.csv "$@"
echo "wrote runs/default/attitude.csv"
