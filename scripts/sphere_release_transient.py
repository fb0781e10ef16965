#!/usr/bin/env python3
"""Settling speed of a sphere released from rest, from the equation of motion with added mass,
quasi-steady drag and a history force: a reference for the first milliseconds of a release run.

    m_p du/dt = (m_p - m_f) g - (m_f / 2) du/dt - F_qs(u) - F_h(t)
    F_qs = 3 pi mu d u (1 + 0.15 Re^0.687)          (Schiller and Naumann 1933; or Stokes: 3 pi mu d u)
    F_h  = 3 pi mu d  int_0^t K(t - s) du/ds ds

Kernels: "basset", K = (4 pi nu t / d^2)^(-1/2) (Basset 1888; the unsteady Stokes limit, exact
while the sphere has moved a small fraction of its diameter), and "mei", the finite-Reynolds-number
kernel of Mei and Adrian 1992 (J. Fluid Mech. 237, 323-341, doi:10.1017/S0022112092003434),
K = [ (4 pi nu t / d^2)^(1/4) + (pi t^2 u^3 / (nu d f_H^3))^(1/2) ]^(-2), f_H = 0.75 + 0.105 Re,
which lets the memory fade once the wake forms. Approximations: the quasi-steady drag and the
history force are added as if independent (Maxey and Riley 1983 for the Stokes limit); the kernel
uses the current speed. Past the first few percent of a diameter of travel this is a model, not a
closed form.

Usage:
    scripts/sphere_release_transient.py --diameter 1.5e-3 --density 2560 --fluid-density 1000 \
        --viscosity 8.9e-4 --end 0.01 --every 0.002 [--kernel basset|mei] [--compare RUN/timeseries.csv]

With --compare, each printed time also gives the run's settling speed (|uz|, linear between its
rows) and its relative deviation from the model.
"""
import argparse
import csv
import math


def settling_speeds(d, rho_p, rho_f, mu, g, end, dt, kernel="basset", drag="schiller_naumann"):
    """Speeds u(n dt), n = 0..end/dt, by an implicit step in the newest history interval.
    drag: "schiller_naumann", or "stokes" for the low-Reynolds-number form (scripts/validate_tencate.sh)."""
    nu = mu / rho_f
    volume = math.pi * d**3 / 6.0
    m_p, m_f = rho_p * volume, rho_f * volume
    stokes = 3.0 * math.pi * mu * d

    def k(lag, u):
        diffusive = (4.0 * math.pi * nu * lag / d**2) ** 0.25
        if kernel == "basset":
            return diffusive**-2
        re = abs(u) * d / nu
        f_h = 0.75 + 0.105 * re
        fading = math.sqrt(math.pi * lag**2 * abs(u) ** 3 / (nu * d * f_h**3))
        return (diffusive + fading) ** -2

    def interval_weight(lag_near, lag_far, u):
        # int K over [lag_near, lag_far]; lag = r^2 removes the 1/sqrt(lag) singularity.
        r0, r1, parts = math.sqrt(lag_near), math.sqrt(lag_far), 4
        h = (r1 - r0) / parts
        return sum(k((r0 + (j + 0.5) * h) ** 2, u) * 2.0 * (r0 + (j + 0.5) * h) * h for j in range(parts))

    steps = int(round(end / dt))
    speeds, accelerations = [0.0], []
    for n in range(steps):
        t, u = (n + 1) * dt, speeds[-1]
        re = u * d / nu
        quasi_steady = stokes * u * (1.0 + 0.15 * re**0.687 if drag == "schiller_naumann" else 1.0)
        memory = sum(a * interval_weight(t - (j + 1) * dt, t - j * dt, u) for j, a in enumerate(accelerations))
        newest = stokes * interval_weight(0.0, dt, u)
        a = ((m_p - m_f) * g - quasi_steady - stokes * memory) / (m_p + 0.5 * m_f + newest)
        accelerations.append(a)
        speeds.append(u + a * dt)
    return speeds


def run_speeds(path):
    with open(path, newline="") as f:
        return [(float(r["t"]), abs(float(r["uz"]))) for r in csv.DictReader(f)]


def interpolated(rows, t):
    """The run's speed at t, linear between its rows (rows fall on time steps, not on round times)."""
    for (t0, u0), (t1, u1) in zip(rows, rows[1:]):
        if t0 <= t <= t1:
            return u0 + (u1 - u0) * (t - t0) / (t1 - t0)
    raise SystemExit(f"the run has no rows around t = {t} s")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--diameter", type=float, required=True, help="m")
    p.add_argument("--density", type=float, required=True, help="particle, kg/m^3")
    p.add_argument("--fluid-density", type=float, required=True, help="kg/m^3")
    p.add_argument("--viscosity", type=float, required=True, help="dynamic, Pa s")
    p.add_argument("--gravity", type=float, default=9.81, help="m/s^2")
    p.add_argument("--end", type=float, required=True, help="s")
    p.add_argument("--every", type=float, required=True, help="s between printed rows")
    p.add_argument("--dt", type=float, default=2.5e-5, help="s, the model's step")
    p.add_argument("--kernel", choices=["basset", "mei"], default="basset")
    p.add_argument("--drag", choices=["schiller_naumann", "stokes"], default="schiller_naumann")
    p.add_argument("--compare", help="a run's timeseries.csv")
    args = p.parse_args()

    speeds = settling_speeds(args.diameter, args.density, args.fluid_density, args.viscosity, args.gravity,
                             args.end, args.dt, args.kernel, args.drag)
    run = run_speeds(args.compare) if args.compare else None
    stride = int(round(args.every / args.dt))
    print("t_s,model_m_s" + (",run_m_s,deviation" if run else ""))
    for n in range(stride, len(speeds), stride):
        t = n * args.dt
        row = f"{t:.6g},{speeds[n]:.6g}"
        if run:
            measured = interpolated(run, t)
            row += f",{measured:.6g},{measured / speeds[n] - 1.0:+.4f}"
        print(row)


if __name__ == "__main__":
    main()
