#!/usr/bin/env bash
# Validation against Uhlmann and Dusek 2014 (Int. J. Multiphase Flow 59, 221,
# doi:10.1016/j.ijmultiphaseflow.2013.10.010): runs cases/uhlmann_dusek_A.toml (Ga = 144, steady
# vertical) and/or _B.toml (Ga = 178.46, steady oblique) at one resolution, then `settle analyze`,
# and compares the settling velocity u_v / u_g (tolerance 3%) and the path angle from the vertical
# (tolerance 1 degree) with validation/reference-data.json (UhlmannDusek2014_sphere_benchmark, large
# domain). NOT run in CI: case A takes about half an hour on two cores at 16 cells per diameter,
# case B more than an hour.
#
#   scripts/validate_uhlmann_dusek.sh [CELLS_PER_DIAMETER] [CASES] [extra `settle run` arguments...]
#   e.g. scripts/validate_uhlmann_dusek.sh 16 A
#
# Environment: SETTLE (default: build the `native` preset and use its binary), THREADS (default:
# all cores), RUNS_DIR (default runs). Exit status 1 when a run fails or a figure is outside its
# tolerance.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

cells="${1:-16}"
cases="${2:-A B}"
if [[ $# -gt 0 ]]; then shift; fi
if [[ $# -gt 0 ]]; then shift; fi
source scripts/validation_lib.sh
settle_binary

dirs=()
for c in $cases; do
  if [[ $c != A && $c != B ]]; then
    echo "validate_uhlmann_dusek: unknown case '$c' (allowed: A B)" >&2
    exit 2
  fi
  dir=$(run_validation_case "uhlmann_dusek_${c}" "${cells}" "$@")
  dirs+=("${c}:${dir}")
done

python3 - "${dirs[@]}" <<'PY'
import json, math, sys
ref = {c["case"]: c for c in json.load(open("validation/reference-data.json"))
       ["UhlmannDusek2014_sphere_benchmark"]["fields"]["cases"]}
ok = True
print("| case | Ga | cells / d | u_v/u_g settle | published | deviation | u_h/u_g settle | published | angle settle | published | Re settle | wall |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for item in sys.argv[1:]:
    c, run = item.split(":", 1)
    r = ref[c]
    s = json.load(open(f"{run}/summary.json"))
    ga, re = s["galileo"], s["reynolds"]
    # Re / Ga = |U| / u_g, so u_g = |U| Ga / Re.
    ug = s["terminal_velocity"] * ga / re
    uv = s["terminal_vertical_velocity"] / ug
    uh = s["lateral"]["drift_velocity"] / ug
    angle = s["lateral"]["path_angle_deg"]
    uv_ref = r.get("u_v_over_ug_large_domain")
    uh_ref = r.get("u_h_over_ug_large_domain", 0.0)
    angle_ref = r.get("angle_deg_large_domain", 0.0)
    dev = uv / uv_ref - 1.0
    ok = ok and abs(dev) <= 0.03 and abs(angle - angle_ref) <= 1.0 and s["terminal_state"]["reached"]
    wall = open(f"{run}/wall_seconds.txt").read().strip()
    print(f"| {c} | {ga:.2f} | {run.rsplit('_n', 1)[-1]} | {uv:.4f} | {uv_ref} | {100 * dev:+.2f}% | {uh:.4f} | "
          f"{uh_ref} | {angle:.2f} deg | {angle_ref} deg | {re:.1f} ({r['Re']}) | {wall} s |")
print("within the tolerances (3% on u_v, 1 degree on the angle)" if ok
      else "OUTSIDE the tolerances (3% on u_v, 1 degree on the angle), or no terminal state")
sys.exit(0 if ok else 1)
PY
