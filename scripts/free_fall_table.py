#!/usr/bin/env python3
"""A study of free falls against the standard drag curve, one row per case.

    scripts/free_fall_table.py STUDY_DIR [--from T_S] [--settle PATH] [--csv OUT.csv]

For every case of a `settle study run` directory: whether the run completed (or the time at which
it stopped, and why), the mean vertical speed over t >= T_S (default: the second half of the
run), the terminal speed of the standard drag curve (Clift, Grace and Weber 1978, as
`settle predict` solves it for the case's sphere and fluid), their difference in percent, the
steps, the wall time and MLUPS. Markdown on stdout, grouped by the study's inputs.
"""
import argparse
import csv
import json
import math
import subprocess
import sys
from pathlib import Path


def mean_fall_speed(timeseries, t_from):
    """Mean of -uz over rows with t >= t_from (m/s), the rows' time span, and the last time."""
    t_values, uz_values = [], []
    if not Path(timeseries).exists():
        return None, 0.0, 0.0
    with open(timeseries, newline="") as handle:
        for row in csv.DictReader(handle):
            try:
                t, uz = float(row["t"]), float(row["uz"])
            except (KeyError, ValueError):
                continue
            t_values.append(t)
            uz_values.append(uz)
    if not t_values:
        return None, 0.0, 0.0
    last = t_values[-1]
    start = t_from if t_from is not None else 0.5 * last
    picked = [-u for t, u in zip(t_values, uz_values) if t >= start]
    if not picked:
        return None, 0.0, last
    return sum(picked) / len(picked), last - start, last


def standard_curve_speed(settle, case_toml):
    out = subprocess.run([settle, "predict", str(case_toml), "--json"], capture_output=True, text=True, check=True)
    for law in json.loads(out.stdout):
        if law["law"] == "clift_grace_weber":
            return law["terminal_velocity"], law["reynolds"]
    raise RuntimeError(f"{case_toml}: settle predict gave no clift_grace_weber row")


def stop_reason(run_log):
    if not run_log.exists():
        return ""
    lines = [line for line in run_log.read_text(errors="replace").splitlines() if "run stopped" in line]
    return lines[-1].split("run stopped:", 1)[-1].strip()[:120] if lines else ""


def row_of(study_dir, case, settle, t_from):
    folder = study_dir / case["folder"]
    status = json.loads((folder / "status.json").read_text()) if (folder / "status.json").exists() else {}
    summary_path = folder / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    speed, span, last = mean_fall_speed(folder / "timeseries.csv", t_from)
    reference, reference_re = standard_curve_speed(settle, folder / "case.toml")
    done = status.get("state") == "done"
    return {
        **{k: v for k, v in case["inputs"].items()},
        "state": status.get("state", "absent"),
        "stopped_at_s": "" if done else f"{last:.3f}",
        "reason": "" if done else stop_reason(folder / "run.log"),
        "mean_fall_speed_m_s": f"{speed:.5g}" if speed is not None and done else "",
        "averaged_over_s": f"{span:.3f}" if done else "",
        "standard_curve_m_s": f"{reference:.5g}",
        "standard_curve_re": f"{reference_re:.4g}",
        "deviation_percent": f"{100.0 * (speed / reference - 1.0):+.1f}" if speed is not None and done else "",
        "tau": f"{summary['tau']:.5f}" if "tau" in summary else "",
        "steps": summary.get("steps", ""),
        "wall_s": f"{status.get('wall_seconds', math.nan):.0f}" if done else "",
        "mlups": f"{summary['mlups']:.0f}" if "mlups" in summary else "",
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("study_dir", type=Path)
    parser.add_argument("--from", dest="t_from", type=float, default=None,
                        help="average the fall speed over t >= this (s); default: the run's second half")
    parser.add_argument("--settle", default="settle", help="the settle binary (for settle predict)")
    parser.add_argument("--csv", type=Path, help="also write the rows as CSV")
    args = parser.parse_args()
    plan = json.loads((args.study_dir / "study.json").read_text())
    rows = [row_of(args.study_dir, case, args.settle, args.t_from) for case in plan["cases"]]
    columns = list(rows[0].keys())
    print("| " + " | ".join(columns) + " |")
    print("|" + " --- |" * len(columns))
    for row in rows:
        print("| " + " | ".join(str(row[c]) for c in columns) + " |")
    if args.csv:
        with open(args.csv, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=columns)
            writer.writeheader()
            writer.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
