#!/usr/bin/env bash
# Validation against ten Cate et al. 2002 (Phys. Fluids 14, 4012, doi:10.1063/1.1512918): runs the
# four shipped cases cases/tencate_E1..E4.toml at one resolution into runs/, then `settle analyze`
# and `settle plot --reference tenCate2002_EN` on each, and prints a table of the largest settling
# speed against the measured u_max, and a table of the 5% bands of the acceptance (the largest difference of
# u_z from the digitised curve over the measured u_max, and of the gap over the initial gap, while
# the experiment's gap is above 1 d and above 2 d), and the first digitised velocities beside the
# Basset-Boussinesq-Oseen solution for a release from rest. NOT run in CI: at the default 16 cells per diameter the
# four take about 4.5 minutes on two cores (docs/cases.md), at 20 cells several times that.
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
def interpolate(ts, ys, t):
    if t < ts[0]:
        return None
    for k in range(1, len(ts)):
        if ts[k] >= t:
            f = (t - ts[k - 1]) / (ts[k] - ts[k - 1])
            return ys[k - 1] + f * (ys[k] - ys[k - 1])
    return None

def band_deviations(run, fields, reference, least_gap=1.0):
    setup = reference["tenCate2002_setup"]["fields"]
    d = setup["sphere_diameter"]
    path = os.path.join(run, "timeseries.csv")
    if not os.path.exists(path):
        return (None, None, 0, 0)
    with open(path) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["t"]) for r in rows]
    uz = [float(r["uz"]) for r in rows]
    gap = [(float(r["z"]) - d / 2) / d for r in rows]
    traj = fields["digitized_trajectory_t_s__gap_over_d"]
    gap_t, gap_v = [p[0] for p in traj], [p[1] for p in traj]
    gap0 = setup["initial_gap_bottom_of_sphere_to_tank_bottom"] / d
    du, n_u = 0.0, 0
    for te, ue in fields["digitized_velocity_t_s__uz_m_per_s"]:
        g = interpolate(gap_t, gap_v, te)
        u = interpolate(t, uz, te)
        if g is None or g <= least_gap or u is None:
            continue
        du, n_u = max(du, abs(u - ue) / fields["u_max_exp"]), n_u + 1
    dg, n_g = 0.0, 0
    for te, ge in traj:
        g = interpolate(t, gap, te)
        if ge <= least_gap or g is None:
            continue
        dg, n_g = max(dg, abs(g - ge) / gap0), n_g + 1
    return (du, dg, n_u, n_g)

bands = []
print(f"\n{'case':5} {'u_max settle':>13} {'u_max exp':>10} {'error':>8}  {'stop':>16} {'wall (s)':>9}  rms u_z, rms gap/d")
for case in ("E1", "E2", "E3", "E4"):
    run = os.path.join(runs_dir, f"tencate_{case}_n{cells}")
    u_exp = reference[f"tenCate2002_{case}"]["fields"]["u_max_exp"]
    fields = reference[f"tenCate2002_{case}"]["fields"]
    bands.append((case, band_deviations(run, fields, reference), band_deviations(run, fields, reference, 2.0)))
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

# The 5% bands of the acceptance: until the sphere nears the bottom (the experiment's gap above 1 d),
# the simulated u_z(t) within 5% of the measured u_max of the digitised velocity, and the simulated
# gap(t) within 5% of the initial gap (8 d) of the digitised trajectory. Linear interpolation of the
# simulated series at the digitised times.
print(f"\n{'case':5} {'gap > 1 d: |du_z|/u_max':>24} {'|dgap|/gap_0':>13} {'gap > 2 d: |du_z|/u_max':>24} {'|dgap|/gap_0':>13}  (band 5%)")
for case, (du, dgap, n_u, n_gap), (du2, dgap2, n_u2, n_gap2) in bands:
    if du is None:
        continue
    verdict = "inside" if du <= 0.05 and dgap <= 0.05 else "OUTSIDE"
    verdict2 = "inside" if du2 <= 0.05 and dgap2 <= 0.05 else "OUTSIDE"
    print(f"{case:5} {100 * du:23.2f}% {100 * dgap:12.2f}% {100 * du2:23.2f}% {100 * dgap2:12.2f}%  "
          f"{verdict} ({n_u}, {n_gap} points) / {verdict2} ({n_u2}, {n_gap2} points)")

# The start: the sphere released from rest at t = 0 in an unbounded fluid, by the
# Basset-Boussinesq-Oseen equation at low Reynolds number (Maxey and Riley 1983, doi:10.1063/1.864230):
# Stokes drag, added mass and Basset's history force, solved by scripts/sphere_release_transient.py.
# Before the walls (3.3 d away) and the wake matter, the resolved sphere should follow it; the table
# shows whether the first digitised points of the experiment are consistent with a release at t = 0.
sys.path.insert(0, "scripts")
from sphere_release_transient import settling_speeds


def bbo_release(rho_p, rho_f, mu, d, g, t_end, n=2000):
    dt = t_end / n
    speeds = settling_speeds(d, rho_p, rho_f, mu, g, t_end, dt, kernel="basset", drag="stokes")
    return [(k * dt, u) for k, u in enumerate(speeds)]

print("\nThe start (m/s, downward): measured / settle / the BBO equation for a release from rest at t = 0")
setup = reference["tenCate2002_setup"]["fields"]
for case in ("E1", "E2", "E3", "E4"):
    fields = reference[f"tenCate2002_{case}"]["fields"]
    run = os.path.join(runs_dir, f"tencate_{case}_n{cells}")
    if not os.path.exists(os.path.join(run, "timeseries.csv")):
        continue
    with open(os.path.join(run, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    ts, us = [float(r["t"]) for r in rows], [-float(r["uz"]) for r in rows]
    early = [(t, -u) for t, u in fields["digitized_velocity_t_s__uz_m_per_s"] if t < 0.25][:4]
    if not early:
        continue
    curve = bbo_release(setup["sphere_density"], fields["fluid_density"], fields["dynamic_viscosity"],
                        setup["sphere_diameter"], setup["gravity"], early[-1][0] * 1.01)
    bt, bu = [p[0] for p in curve], [p[1] for p in curve]
    print(f"{case:5} " + "  ".join(f"t = {t:.3f} s: {u:.4f} / {interpolate(ts, us, t):.4f} / {interpolate(bt, bu, t):.4f}"
                                   for t, u in early))
EOF

if [[ ${#failed[@]} -gt 0 ]]; then
  echo "validate_tencate: failed runs: ${failed[*]}" >&2
  exit 1
fi
