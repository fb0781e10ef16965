#!/usr/bin/env python3
"""How fast a free body's lateral swing grows or decays, from a run's timeseries.csv.

    python3 scripts/swing_decay.py RUN_DIR --from T0 [--to T1] [--scale U] [--diameter D] [--smooth N]
        [--threshold H]

The horizontal speed |u_h| = sqrt(ux^2 + uy^2), smoothed by a running mean of N rows, has
extrema after T0 (each confirmed once |u_h| has moved H U away from it); the half-swing is half the difference of neighbouring extrema. Printed: each
half-swing with its time, the ratio per period (from the least-squares slope of ln(half-swing)
against time, over all but the last, possibly cut-off, half-swing), that growth rate in 1/s,
the swing's frequency f from the mean spacing of the extrema (and f D / U), and the means of
the vertical and horizontal speeds and of the body's spin |omega| D / U over the last
quarter of [T0, T1]. Speeds are printed divided by U (--scale; Uhlmann and Dusek's u_g for
their cases). docs/validation.md quotes this script's figures for Uhlmann and Dusek's case C.
"""
import argparse
import csv
import math
import sys


def read_rows(run_dir):
    with open(f"{run_dir}/timeseries.csv", newline="") as handle:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(handle)]


def running_mean(values, width):
    half = width // 2
    out = []
    for i in range(len(values)):
        window = values[max(0, i - half): i + half + 1]
        out.append(sum(window) / len(window))
    return out


def extrema(times, values, threshold):
    """Alternating extrema, each confirmed once the series has moved `threshold` away from it,
    so that wiggles smaller than that do not count as swings."""
    found = []
    best_i, rising = 0, None
    for i in range(1, len(values)):
        if rising is None:
            if abs(values[i] - values[0]) >= threshold:
                rising = values[i] > values[0]
                best_i = i
            continue
        if (values[i] > values[best_i]) == rising:
            best_i = i
        elif abs(values[i] - values[best_i]) >= threshold:
            found.append((times[best_i], values[best_i]))
            best_i, rising = i, not rising
    return found


def least_squares_slope(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--from", dest="t0", type=float, required=True, help="start of the judged window (s)")
    parser.add_argument("--to", dest="t1", type=float, default=math.inf, help="end of the judged window (s)")
    parser.add_argument("--scale", type=float, default=0.07004, help="velocity scale U (m/s); default: case C's u_g")
    parser.add_argument("--diameter", type=float, default=1.0e-3, help="body diameter D (m)")
    parser.add_argument("--smooth", type=int, default=5, help="rows in the running mean")
    parser.add_argument("--threshold", type=float, default=0.002, help="smallest swing counted, in units of U")
    args = parser.parse_args()

    rows = [r for r in read_rows(args.run_dir) if args.t0 <= r["t"] <= args.t1]
    if len(rows) < 10:
        sys.exit(f"swing_decay: fewer than 10 rows in [{args.t0}, {args.t1}] s")
    times = [r["t"] for r in rows]
    horizontal = running_mean([math.hypot(r["ux"], r["uy"]) / args.scale for r in rows], args.smooth)
    peaks = extrema(times, horizontal, args.threshold)
    halves = [(0.5 * (a[0] + b[0]), 0.5 * abs(a[1] - b[1])) for a, b in zip(peaks, peaks[1:])]
    print("half-swings of u_h / U (time s: value):")
    for t, h in halves:
        print(f"  {t:.3f}: {h:.5f}")
    if len(halves) >= 3:
        judged = [(t, h) for t, h in halves[:-1] if h > 0.0]
        rate = least_squares_slope([t for t, _ in judged], [math.log(h) for _, h in judged])
        period = 2.0 * (peaks[-1][0] - peaks[0][0]) / (len(peaks) - 1)
        print(f"growth rate {rate:+.2f} 1/s; frequency {1.0 / period:.2f} Hz, f D / U {args.diameter / (period * args.scale):.4f}; "
              f"ratio per period {math.exp(rate * period):.2f}")
    else:
        print("fewer than three half-swings: no rate")
    tail = [r for r in rows if r["t"] >= times[-1] - 0.25 * (times[-1] - times[0])]
    mean = lambda f: sum(f(r) for r in tail) / len(tail)
    u_v = mean(lambda r: -r["uz"]) / args.scale
    u_h = mean(lambda r: math.hypot(r["ux"], r["uy"])) / args.scale
    spin = mean(lambda r: math.sqrt(r["wx"] ** 2 + r["wy"] ** 2 + r["wz"] ** 2)) * args.diameter / args.scale
    print(f"last quarter ({tail[0]['t']:.3f}-{tail[-1]['t']:.3f} s): u_v / U {u_v:.4f}, u_h / U {u_h:.4f}, "
          f"path angle {math.degrees(math.atan2(u_h, u_v)):.2f} degrees, |omega| D / U {spin:.4f}")


if __name__ == "__main__":
    main()
