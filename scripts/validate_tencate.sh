#!/usr/bin/env bash
# Validation against ten Cate et al. 2002 (Phys. Fluids 14, 4012, doi:10.1063/1.1512918): runs the
# four shipped cases cases/tencate_E1..E4.toml at one resolution into runs/, then `settle analyze`
# and `settle plot --reference tenCate2002_EN` on each, and prints a table of the largest settling
# speed against the measured u_max. NOT run in CI: at the default 16 cells per diameter each case
# takes about 10-15 minutes on two cores (docs/cases.md), at 20 about 2.4 times that.
#
#   scripts/validate_tencate.sh [CELLS_PER_DIAMETER] [extra `settle run` arguments...]
#   e.g. scripts/validate_tencate.sh 10
#        scripts/validate_tencate.sh 20 --set 'particle.position=[0.05,0.05,0.13125]'
#
# Environment: SETTLE (the settle binary; default: build the `native` preset and use its binary),
# THREADS (default: all cores), RUNS_DIR (default runs), SETTLE_PYTHON (python3 for the table;
# the figures need matplotlib, see docs/plots.md).
# Results: RUNS_DIR/tencate_EN_nCELLS/ with timeseries.csv, summary.json, analysis.txt and plots/
# (reference.png overlays the digitised u_z(t) and gap(t) of the experiment).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

cells="${1:-16}"
if [[ $# -gt 0 ]]; then shift; fi
runs_dir="${RUNS_DIR:-runs}"
threads="${THREADS:-0}"  # 0: OpenMP's default (all cores)
python="${SETTLE_PYTHON:-python3}"

if [[ -z "${SETTLE:-}" ]]; then
  cmake --preset native >/dev/null
  cmake --build --preset native --target settle_cli
  SETTLE=./build/native/src/app/settle
fi

failed=()
for case in E1 E2 E3 E4; do
  dir="${runs_dir}/tencate_${case}_n${cells}"
  echo "== ten Cate ${case}, ${cells} cells per diameter -> ${dir}"
  if ! "${SETTLE}" run "cases/tencate_${case}.toml" -o "${dir}" --set "numerics.cells_per_diameter=${cells}" \
      --threads "${threads}" "$@"; then
    echo "validate_tencate: the run of ${case} failed (see above); going on with the others" >&2
    failed+=("${case}")
    continue
  fi
  "${SETTLE}" analyze "${dir}" | tee "${dir}/analysis.txt"
  "${SETTLE}" plot "${dir}" --reference "tenCate2002_${case}" 2>&1 | tee "${dir}/plot.txt"
done

# The table: the largest settling speed of each run (timeseries.csv) against ten Cate's u_max
# (validation/reference-data.json), and the plot's rms differences from the digitised curves.
"${python}" - "${runs_dir}" "${cells}" <<'EOF'
import csv, json, os, re, sys
runs_dir, cells = sys.argv[1], sys.argv[2]
reference = json.load(open("validation/reference-data.json"))
print(f"\n{'case':5} {'u_max settle':>13} {'u_max exp':>10} {'error':>8}  {'stop':>16} {'wall (s)':>9}  rms u_z, rms gap/d")
for case in ("E1", "E2", "E3", "E4"):
    run = os.path.join(runs_dir, f"tencate_{case}_n{cells}")
    u_exp = reference[f"tenCate2002_{case}"]["fields"]["u_max_exp"]
    if not os.path.exists(os.path.join(run, "summary.json")):
        print(f"{case:5} {'(no summary.json: the run failed or did not finish)':>40}")
        continue
    summary = json.load(open(os.path.join(run, "summary.json")))
    with open(os.path.join(run, "timeseries.csv")) as f:
        u_max = max(-float(row["uz"]) for row in csv.DictReader(f))
    rms = ""
    plot_log = os.path.join(run, "plot.txt")
    if os.path.exists(plot_log):
        rms = ", ".join(re.findall(r"rms difference ([0-9.eE+-]+(?: m/s)?)", open(plot_log).read()))
    print(f"{case:5} {u_max:13.5f} {u_exp:10.5f} {100 * (u_max / u_exp - 1):+7.2f}%  "
          f"{summary.get('stop_reason', '?'):>16} {summary.get('wall_seconds', 0):9.0f}  {rms}")
EOF

if [[ ${#failed[@]} -gt 0 ]]; then
  echo "validate_tencate: failed runs: ${failed[*]}" >&2
  exit 1
fi
