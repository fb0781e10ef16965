#!/usr/bin/env python3
"""How the force on a fixed or towed body develops, window by window, from a finished run.

    python3 scripts/lift_history.py RUN_DIR [--window W] [--from T0] [--to T1]

Times are in d / U (d the body's volume-equivalent diameter, U the mean relative flow speed, both
from RUN_DIR/summary.json; the fluid density from RUN_DIR/case.resolved.toml). Coefficients use the
summary's convention, force / (rho U^2 / 2 pi d^2 / 4), with the lift the force normal to the mean
flow. Printed: for each window of W d / U, the range of C_L, the mean C_D and the lift's azimuth
about the flow at the window's end; then, over [T0, T1], the mean C_L, the rms of C_L about its
least-squares line (for each half of the interval too, to tell a growing oscillation from a
decaying one) and the Strouhal number f d / U of the largest discrete Fourier component of that
remainder between St 0.02 and 0.30. summary.json's own lift_strouhal spans the second half of the
run, where a slow drift of the lift can outweigh the shedding. docs/validation.md quotes this
script's figures for the fixed sphere at Re = 280.
"""
import argparse
import csv
import json
import math
import tomllib


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def perpendicular_basis(flow):
    """Two unit vectors normal to the flow, for the lift's azimuth."""
    helper = [1.0, 0.0, 0.0] if abs(flow[0]) < 0.9 else [0.0, 1.0, 0.0]
    e1 = unit([h - dot(helper, flow) * f for h, f in zip(helper, flow)])
    e2 = [flow[1] * e1[2] - flow[2] * e1[1], flow[2] * e1[0] - flow[0] * e1[2], flow[0] * e1[1] - flow[1] * e1[0]]
    return e1, e2


def read_history(run_dir):
    summary = json.load(open(f"{run_dir}/summary.json"))
    with open(f"{run_dir}/case.resolved.toml", "rb") as handle:
        rho = tomllib.load(handle)["fluid"]["density"]
    relative_flow = summary["mean_relative_flow"]
    speed = math.sqrt(dot(relative_flow, relative_flow))
    flow = unit(relative_flow)
    d = summary["equivalent_diameter"]
    pressure_area = 0.5 * rho * speed * speed * math.pi * d * d / 4.0
    e1, e2 = perpendicular_basis(flow)
    rows = []
    with open(f"{run_dir}/timeseries.csv", newline="") as handle:
        for r in csv.DictReader(handle):
            force = [float(r["Fx"]), float(r["Fy"]), float(r["Fz"])]
            drag = dot(force, flow)
            lift = [f - drag * u for f, u in zip(force, flow)]
            rows.append((float(r["t"]) * speed / d, math.sqrt(dot(lift, lift)) / pressure_area, drag / pressure_area,
                         math.degrees(math.atan2(dot(lift, e2), dot(lift, e1)))))
    return rows


def print_windows(rows, width):
    windows = {}
    for row in rows:
        windows.setdefault(int(row[0] // width), []).append(row)
    print("window (d/U): C_L range, mean C_D, lift azimuth (degrees)")
    for k in sorted(windows):
        w = windows[k]
        lifts = [r[1] for r in w]
        print(f"  {k * width:6.1f}-{(k + 1) * width:6.1f}: {min(lifts):.4f}-{max(lifts):.4f}, "
              f"{sum(r[2] for r in w) / len(w):.4f}, {w[-1][3]:7.1f}")


def rms(values):
    return math.sqrt(sum(v * v for v in values) / len(values))


def print_oscillation(rows, t0, t1):
    judged = [(t, c) for t, c, _, _ in rows if t0 <= t <= t1]
    if len(judged) < 10:
        print(f"fewer than 10 rows in [{t0}, {t1}] d/U: no oscillation figures")
        return
    times, lifts = [t for t, _ in judged], [c for _, c in judged]
    mean_t, mean_c = sum(times) / len(times), sum(lifts) / len(lifts)
    slope = (sum((t - mean_t) * (c - mean_c) for t, c in judged) / sum((t - mean_t) ** 2 for t in times))
    remainder = [c - mean_c - slope * (t - mean_t) for t, c in judged]

    def amplitude(st):
        w = 2.0 * math.pi * st
        return math.hypot(sum(v * math.cos(w * t) for t, v in zip(times, remainder)),
                          sum(v * math.sin(w * t) for t, v in zip(times, remainder)))

    strouhal = max((0.02 + 0.001 * i for i in range(281)), key=amplitude)
    half = len(remainder) // 2
    print(f"{times[0]:.1f}-{times[-1]:.1f} d/U: mean C_L {mean_c:.4f} (trend {slope:+.2e} per d/U), "
          f"C_L about the trend {rms(remainder):.5f} rms (halves {rms(remainder[:half]):.5f}, "
          f"{rms(remainder[half:]):.5f}), its largest Fourier component at St {strouhal:.3f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--window", type=float, default=5.0, help="window width (d/U)")
    parser.add_argument("--from", dest="t0", type=float, default=None, help="start of the judged interval (d/U; default: half the run)")
    parser.add_argument("--to", dest="t1", type=float, default=math.inf, help="end of the judged interval (d/U)")
    args = parser.parse_args()
    rows = read_history(args.run_dir)
    print_windows(rows, args.window)
    print_oscillation(rows, 0.5 * rows[-1][0] if args.t0 is None else args.t0, args.t1)


if __name__ == "__main__":
    main()
