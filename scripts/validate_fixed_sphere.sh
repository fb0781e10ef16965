#!/usr/bin/env bash
# Validation against Johnson and Patel 1999 (J. Fluid Mech. 378, 19, doi:10.1017/S0022112098003206):
# a sphere fixed in a uniform stream, cases/fixed_sphere_stream.toml, at Re = 250 (a steady oblique
# wake: C_D within 3%, C_L within 15%) and Re = 300 (periodic shedding: C_D within 3%, Strouhal
# number of the lift within 5%), with the references of validation/reference-data.json
# (JohnsonPatel1999_fixed_sphere; the Re = 250 figures are unconfirmed there). summary.json averages
# over the second half of the 90 d / U run. NOT run in CI: each run takes about an hour on two cores
# at 16 cells per diameter (docs/validation.md, A sphere fixed in a uniform stream).
#
#   scripts/validate_fixed_sphere.sh [CELLS] [RE...] [-- extra `settle run` arguments...]
#   e.g. scripts/validate_fixed_sphere.sh 16 300 -- --set 'numerics.coupling="immersed_boundary"'
#
# Environment: SETTLE (default: build the `native` preset and use its binary), THREADS (default: all
# cores), RUNS_DIR (default runs), TAG (appended to each run's folder name). Exit status 1 when a run
# fails or a figure is outside its tolerance.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

cells="${1:-16}"
if [[ $# -gt 0 ]]; then shift; fi
reynolds=()
while [[ $# -gt 0 && $1 != -- ]]; do reynolds+=("$1"); shift; done
if [[ $# -gt 0 ]]; then shift; fi
((${#reynolds[@]})) || reynolds=(250 300)
source scripts/validation_lib.sh
settle_binary

status=0
for re in "${reynolds[@]}"; do
  # d = 10 mm, nu = 1e-6 m^2/s: U = Re nu / d.
  speed=$(python3 -c "print(${re} * 1e-6 / 0.01)")
  dir="${RUNS_DIR:-runs}/fixed_sphere_re${re}_n${cells}${TAG:-}"
  echo "== Re = ${re}, ${cells} cells per diameter -> ${dir}" >&2
  start=$(date +%s)
  "${SETTLE}" run cases/fixed_sphere_stream.toml -o "${dir}" --threads "${THREADS:-0}" \
    --set "numerics.cells_per_diameter=${cells}" --set "domain.inflow_velocity=[0,0,${speed}]" "$@" >&2
  echo "$(($(date +%s) - start))" >"${dir}/wall_seconds.txt"
  python3 - "${dir}" "${re}" <<'PY' || status=1
import json, sys
run, re = sys.argv[1], sys.argv[2]
s = json.load(open(f"{run}/summary.json"))
ref = json.load(open("validation/reference-data.json"))["JohnsonPatel1999_fixed_sphere"]["fields"]
checks = {"300": [("C_D", s["drag_coefficient"], ref["Re300"]["JohnsonPatel1999"]["C_D"], 0.03),
                  ("St", s["lift_strouhal"], ref["Re300"]["JohnsonPatel1999"]["St"], 0.05)],
          "250": [("C_D", s["drag_coefficient"], ref["Re250"]["JohnsonPatel1999_U"]["C_D"], 0.03),
                  ("C_L", s["lift_coefficient"], ref["Re250"]["JohnsonPatel1999_U"]["C_L"], 0.15)]}[re]
print(f"{run}: C_D {s['drag_coefficient']:.4f}, C_L {s['lift_coefficient']:.4f}, lift fluctuation "
      f"{s['lift_fluctuation_coefficient']:.4f}, St {s['lift_strouhal']}")
ok = True
for name, got, want, tolerance in checks:
    if got is None:
        print(f"  {name}: none (no oscillation found)"); ok = False; continue
    deviation = got / want - 1.0
    print(f"  {name}: {got:.4f} against {want} ({100 * deviation:+.1f}%, tolerance {100 * tolerance:.0f}%)")
    ok = ok and abs(deviation) <= tolerance
sys.exit(0 if ok else 1)
PY
done
exit ${status}
