#!/usr/bin/env bash
# Float against double storage of the populations (`numerics.precision`): runs each case twice, the
# same in everything else, and compares the figures a user reads from the runs: the terminal (or
# last) settling speed, the drag coefficient, the largest settling speed and the path angle. A
# figure differing by more than 0.3% (0.1 degree for the angle) fails the comparison
# (docs/performance.md, "Storage precision", says why 0.3%). Also printed, not judged: the settling
# speed over the whole run (the largest difference at the times both runs wrote, over the larger
# run's largest speed). Through a landing or a rocking transient it measures how the motion
# amplifies any small difference: a cylinder moved by 1e-8 cells at the start, in double storage,
# differs from the unmoved run by 0.29% there against float storage's 0.34% (docs/notes.md, "Float
# storage against double"). NOT run in CI: the default set takes about an hour on one core.
#
#   scripts/validate_precision.sh [extra `settle run` arguments...]
#   e.g. scripts/validate_precision.sh --set 'numerics.coupling="momentum_exchange"'
#
# Environment: SETTLE (default: build the `native` preset and use its binary), THREADS (default:
# all cores), RUNS_DIR (default runs/precision), CASES (default: the built-in default case, written
# `default`, and the shipped non-spherical cases and ten Cate E3 and E4). A run whose folder already
# holds a summary.json is kept, not run again (delete the folder to rerun it). Exit status 1 when a
# run fails or a figure differs by more than its bound.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/validation_lib.sh
settle_binary

cases="${CASES:-default prolate_spheroid oblate_spheroid cylinder disk cube tencate_E3 tencate_E4}"
runs="${RUNS_DIR:-runs/precision}"
pairs=()
for name in $cases; do
  case_file=()
  if [[ $name != default ]]; then case_file=("cases/${name}.toml"); fi
  for precision in double float; do
    dir="${runs}/${name}_${precision}"
    if [[ -f ${dir}/summary.json ]]; then
      echo "== ${name}, ${precision} storage: kept ${dir}" >&2
      continue
    fi
    echo "== ${name}, ${precision} storage -> ${dir}" >&2
    start=$(date +%s)
    "${SETTLE}" run "${case_file[@]}" -o "${dir}" --threads "${THREADS:-0}" \
      --set "numerics.precision=\"${precision}\"" --set run.vtk_interval=0 "$@" >&2
    echo "$(($(date +%s) - start))" >"${dir}/wall_seconds.txt"
  done
  pairs+=("${name}:${runs}/${name}_double:${runs}/${name}_float")
done

python3 - "${pairs[@]}" <<'PY'
import csv, json, math, sys

RELATIVE_BOUND = 0.003
ANGLE_BOUND_DEG = 0.1

def settling_speeds(run):
    with open(f"{run}/timeseries.csv") as f:
        return {round(float(r["t"]), 9): -float(r["uz"]) for r in csv.DictReader(f)}

def relative(a, b):
    return abs(b - a) / abs(a) if a else math.inf

ok = True
print("| case | figure | double | float | difference | wall double / float (s) |")
print("| --- | --- | --- | --- | --- | --- |")
for item in sys.argv[1:]:
    name, run_d, run_f = item.split(":")
    sd, sf = (json.load(open(f"{r}/summary.json")) for r in (run_d, run_f))
    ud, uf = settling_speeds(run_d), settling_speeds(run_f)
    common = sorted(set(ud) & set(uf))
    largest = max(max(ud.values()), max(uf.values()))
    walls = " / ".join(open(f"{r}/wall_seconds.txt").read().strip() for r in (run_d, run_f))
    rows = [
        ("late mean speed (terminal when reached), m/s", sd["late_mean_velocity"], sf["late_mean_velocity"]),
        ("drag coefficient", sd["drag_coefficient"], sf["drag_coefficient"]),
        ("largest settling speed, m/s", max(ud.values()), max(uf.values())),
    ]
    for label, a, b in rows:
        d = relative(a, b)
        ok = ok and d <= RELATIVE_BOUND
        print(f"| {name} | {label} | {a:.6g} | {b:.6g} | {100 * d:.3f}% | {walls} |")
    d = max(abs(ud[t] - uf[t]) for t in common) / largest
    print(f"| {name} | settling speed over {len(common)} common rows (not judged) | | | {100 * d:.3f}% of the largest "
          f"| {walls} |")
    if "lateral" not in sd:  # a towed or fixed body: its path is prescribed
        continue
    ad, af = sd["lateral"]["path_angle_deg"], sf["lateral"]["path_angle_deg"]
    ok = ok and abs(af - ad) <= ANGLE_BOUND_DEG
    print(f"| {name} | path angle, deg | {ad:.3f} | {af:.3f} | {af - ad:+.3f} deg | {walls} |")
print("all within the bounds" if ok else "OUTSIDE the bounds")
sys.exit(0 if ok else 1)
PY
