#!/usr/bin/env python3
"""Figures of one `settle run` output directory (called by `settle plot`; docs/plots.md).

Reads RUN_DIR/timeseries.csv (SI units), RUN_DIR/summary.json and RUN_DIR/case.resolved.toml and
writes PNG files to RUN_DIR/plots (or --output-dir):

    velocity.png       translational and angular velocity and the Reynolds number against time
    trajectory.png     side views x-z and y-z and the top view x-y, true aspect ratio
    trajectory_3d.png  the path in 3D
    orientation.png    tilt of the body z axis and both Euler sets against time, active set shaded
    forces.png         hydrodynamic force and torque (and the markers' no-slip error if present)
    reference.png      only with reference data: the published curves over the simulated ones

The paths written go to stdout, one a line; notes and measured agreement go to stderr.
Exit status: 0 done, 2 a problem the user can fix (bad RUN_DIR, unknown reference key), 1 other.
Only python3, numpy and matplotlib (Debian: python3-matplotlib) are needed.
"""

import argparse
import io
import json
import math
import os
import sys
import textwrap

try:
    import matplotlib

    matplotlib.use("Agg")  # files only, no display needed
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize
    from matplotlib.patches import Rectangle
    from matplotlib.ticker import MaxNLocator, MultipleLocator
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    MISSING_MODULE = None
except ImportError as import_error:  # reported by main() with the Debian package to install
    MISSING_MODULE = import_error

PROGRAM = "settle plot"

# Columns every timeseries.csv has (docs/architecture.md, "Contracts"); extra columns may follow.
REQUIRED_COLUMNS = (
    "t x y z ux uy uz wx wy wz wbx wby wbz psi theta gamma psi_r theta_r gamma_r euler_set "
    "Fx Fy Fz Tx Ty Tz Re"
).split()

# Names of the digitised series in validation/reference-data.json (see that file's "units").
VELOCITY_SERIES = "digitized_velocity_t_s__uz_m_per_s"  # [t (s), u_z (m/s), negative = down]
TRAJECTORY_SERIES = "digitized_trajectory_t_s__gap_over_d"  # [t (s), bottom gap / d]

FIGURE_DPI = 150


class UserError(Exception):
    """A problem the user can fix; reported as 'settle plot: error: ...' with exit status 2."""


def note(message):
    print(f"{PROGRAM}: {message}", file=sys.stderr)


# ----------------------------------------------------------------------------------------------
# Inputs


def read_timeseries(path):
    """The columns of timeseries.csv as a dict of 1-D float arrays."""
    if not os.path.isfile(path):
        raise UserError(f"RUN_DIR: no timeseries.csv at {path} (expected a directory written by `settle run`)")
    with open(path, encoding="utf-8") as file:
        text = file.read()
    lines = text.split("\n")
    header = lines[0].strip().split(",")
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise UserError(f"RUN_DIR: {path} lacks the columns {', '.join(missing)}")
    rows = lines[1:]
    # settle flushes whole rows: a last row without its newline was cut while being written (the
    # run stopped on a full disk, or was killed), so it is left out rather than failing the table.
    if not text.endswith("\n") and rows and rows[-1].strip():
        note(f"warning: {path}: its last row is incomplete (the run stopped while writing it); plotted without it")
        rows = rows[:-1]
    try:
        values = np.loadtxt(io.StringIO("\n".join(rows)), delimiter=",", ndmin=2)
    except ValueError as error:
        raise UserError(f"RUN_DIR: {path} is not a numeric CSV table: {error}") from error
    if values.shape[0] == 0:
        raise UserError(f"RUN_DIR: {path} has a header but no rows")
    return {name: values[:, i] for i, name in enumerate(header)}


def read_json(path):
    if not os.path.isfile(path):
        return {}
    try:
        with open(path, encoding="utf-8") as file:
            return json.load(file)
    except (OSError, ValueError) as error:
        note(f"warning: cannot read {path} ({error}); going on without it")
        return {}


def read_toml(path):
    if not os.path.isfile(path):
        return {}
    try:
        import tomllib  # python >= 3.11
    except ImportError:
        note(f"warning: python {sys.version.split()[0]} has no tomllib; {path} is not read")
        return {}
    try:
        with open(path, "rb") as file:
            return tomllib.load(file)
    except (OSError, ValueError) as error:
        note(f"warning: cannot read {path} ({error}); going on without it")
        return {}


def named_reference(summary, case):
    """The reference key a run names: summary.json "reference", or a `reference` string at the top
    of case.resolved.toml or in any of its tables (e.g. [run] reference = "tenCate2002_E1")."""
    if isinstance(summary.get("reference"), str):
        return summary["reference"]
    if isinstance(case.get("reference"), str):
        return case["reference"]
    for table in case.values():
        if isinstance(table, dict) and isinstance(table.get("reference"), str):
            return table["reference"]
    return None


def default_reference_file():
    """validation/reference-data.json of the source tree this script lives in."""
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.join(os.path.dirname(here), "validation", "reference-data.json")


def curve_keys(data):
    return sorted(k for k, v in data.items() if isinstance(v, dict) and has_curves(v))


def has_curves(entry):
    fields = entry.get("fields", {})
    return isinstance(fields, dict) and (VELOCITY_SERIES in fields or TRAJECTORY_SERIES in fields)


def load_reference(key, path, explicit):
    """The entry `key` of the reference file, with the citation of its *_setup sibling.

    An explicit --reference that cannot be honoured is an error; one named by the run itself only
    warns, so the other figures are still made."""
    def refuse(message):
        if explicit:
            raise UserError(message)
        note(f"warning: {message}; reference.png is not made")
        return None

    if not os.path.isfile(path):
        return refuse(f"--reference-file: {path} does not exist")
    try:
        with open(path, encoding="utf-8") as file:
            data = json.load(file)
    except (OSError, ValueError) as error:
        return refuse(f"--reference-file: cannot read {path}: {error}")
    if key not in data or not has_curves(data[key]):
        return refuse(f"--reference: '{key}' has no curves in {path}; keys with curves: {', '.join(curve_keys(data))}")
    entry = dict(data[key])
    setup = data.get(key.rsplit("_", 1)[0] + "_setup", {}) if "_" in key else {}
    entry["citation"] = entry.get("reference") or setup.get("reference", "")
    entry["setup_fields"] = setup.get("fields", {})
    entry["key"] = key
    return entry


# ----------------------------------------------------------------------------------------------
# Attitude (conventions of docs/architecture.md, "Frames and attitude", and src/attitude/euler.hpp)


def set1_body_to_inertial(psi, theta, gamma):
    """C_b^n of set 1 (S5): Rz(psi) Ry(theta) Rx(gamma), shape (N, 3, 3); v_n = C_b^n v_b.

    Cheng, Cao, Li & Borthwick 2023, Phys. Fluids 35, doi:10.1063/5.0165555, supplementary Eq. S5."""
    cps, sps = np.cos(psi), np.sin(psi)
    cth, sth = np.cos(theta), np.sin(theta)
    cga, sga = np.cos(gamma), np.sin(gamma)
    rows = [
        [cps * cth, cps * sth * sga - sps * cga, cps * sth * cga + sps * sga],
        [sps * cth, sps * sth * sga + cps * cga, sps * sth * cga - cps * sga],
        [-sth, cth * sga, cth * cga],
    ]
    return np.moveaxis(np.array(rows), -1, 0)


def set2_body_to_inertial(psi_r, theta_r, gamma_r):
    """(C_b^n)_r of set 2 (S8): Rz(psi_r) Rx(gamma_r) Ry(theta_r), shape (N, 3, 3)."""
    cps, sps = np.cos(psi_r), np.sin(psi_r)
    cth, sth = np.cos(theta_r), np.sin(theta_r)
    cga, sga = np.cos(gamma_r), np.sin(gamma_r)
    rows = [
        [cth * cps - sth * sga * sps, -cga * sps, sth * cps + cth * sga * sps],
        [cth * sps + sth * sga * cps, cga * cps, sth * sps - cth * sga * cps],
        [-sth * cga, sga, cth * cga],
    ]
    return np.moveaxis(np.array(rows), -1, 0)


def tilt_from_vertical(matrices):
    """Angle (rad, in [0, pi/2]) between the body z axis (a spheroid's or cylinder's symmetry axis)
    and the vertical e_z: acos(|C_b^n[:, 2] . e_z|). The absolute value treats the axis as a line,
    which suits shapes symmetric under body z -> -z; a body with a distinct 'up' needs the signed
    version."""
    return np.arccos(np.clip(np.abs(matrices[:, 2, 2]), 0.0, 1.0))


# ----------------------------------------------------------------------------------------------
# Plot helpers

SI_PREFIXES = ((-15, "f"), (-12, "p"), (-9, "n"), (-6, "µ"), (-3, "m"), (0, ""), (3, "k"))


def si_scale(values, unit):
    """A factor and a unit label (e.g. 1e6, 'µN') that put the largest |value| in [1, 1000), so the
    axes read without a separate power-of-ten offset."""
    finite = np.abs(np.asarray(values, dtype=float))
    finite = finite[np.isfinite(finite)]
    largest = float(finite.max()) if finite.size else 0.0
    if largest == 0.0:
        return 1.0, unit
    exponent = 3 * math.floor(math.log10(largest) / 3)
    for power, prefix in SI_PREFIXES:
        if power == max(min(exponent, SI_PREFIXES[-1][0]), SI_PREFIXES[0][0]):
            return 10.0 ** (-power), prefix + unit
    return 1.0, unit


def break_at_wraps(angle_deg):
    """The angle with NaN put where it wraps around +-180 deg, so no vertical line joins the two
    ends. Replaces the sample after a jump larger than 180 deg (output samples are far closer)."""
    broken = np.array(angle_deg, dtype=float)
    jumps = np.nonzero(np.abs(np.diff(broken)) > 180.0)[0]
    broken[jumps + 1] = np.nan
    return broken


def active_spans(t, euler_set, which):
    """(start, end) time intervals during which `which` is the active Euler set; a switch between
    two samples is drawn half-way between them."""
    active = euler_set == which
    edges = np.concatenate(([t[0]], 0.5 * (t[1:] + t[:-1]), [t[-1]]))
    spans, start = [], None
    for i, is_active in enumerate(active):
        if is_active and start is None:
            start = edges[i]
        if not is_active and start is not None:
            spans.append((start, edges[i]))
            start = None
    if start is not None:
        spans.append((start, edges[-1]))
    return spans


def finish(fig, path, written):
    fig.savefig(path, dpi=FIGURE_DPI, bbox_inches="tight")
    plt.close(fig)
    written.append(path)


def run_title(summary, case, what):
    name = summary.get("case") or "run"
    shape = case.get("particle", {}).get("shape")
    motion = summary.get("motion") or case.get("particle", {}).get("motion")
    details = ", ".join(x for x in (shape, motion) if x)
    return f"{name}{f' ({details})' if details else ''}: {what}"


def time_axis(ax):
    ax.set_xlabel("t (s)")
    ax.grid(True, alpha=0.3)


def legend_right(ax, top=False):
    """The legend outside the axes on the right, so it never hides data."""
    ax.legend(loc="upper left" if top else "center left", bbox_to_anchor=(1.01, 1.0 if top else 0.5),
              fontsize="small", frameon=False)


# ----------------------------------------------------------------------------------------------
# Figures


def gravity_unit(case):
    g = np.array(case.get("fluid", {}).get("gravity", [0.0, 0.0, -9.81]), dtype=float)
    norm = np.linalg.norm(g)
    return g / norm if norm > 0 else np.array([0.0, 0.0, -1.0])


def plot_velocity(ts, summary, case, path, written):
    t = ts["t"]
    fig, (ax_u, ax_w, ax_re) = plt.subplots(3, 1, sharex=True, figsize=(8.5, 8.0), layout="constrained")
    factor, unit = si_scale(np.concatenate([ts["ux"], ts["uy"], ts["uz"]]), "m/s")
    for name, colour in (("ux", "C0"), ("uy", "C1"), ("uz", "C2")):
        ax_u.plot(t, ts[name] * factor, color=colour, label=f"$u_{name[1]}$")
    speed = np.sqrt(ts["ux"] ** 2 + ts["uy"] ** 2 + ts["uz"] ** 2)
    ax_u.plot(t, speed * factor, color="k", lw=0.8, ls="--", label="$|u|$")
    terminal = summary.get("terminal_vertical_velocity")
    if summary.get("motion") == "free" and isinstance(terminal, (int, float)):
        # summary.json counts it along gravity (> 0 sinking); its z component is what u_z tends to.
        ax_u.axhline(terminal * gravity_unit(case)[2] * factor, color="C2", lw=0.8, ls=":",
                     label="terminal $u_z$\n(summary.json)")
    ax_u.set_ylabel(f"velocity ({unit})")
    ax_u.set_title(run_title(summary, case, "velocity (inertial frame)"))
    legend_right(ax_u)

    factor, unit = si_scale(np.concatenate([ts["wx"], ts["wy"], ts["wz"]]), "rad/s")
    for name, colour in (("wx", "C0"), ("wy", "C1"), ("wz", "C2")):
        ax_w.plot(t, ts[name] * factor, color=colour, label=rf"$\omega_{name[1]}$")
    ax_w.set_ylabel(f"angular velocity ({unit})")
    legend_right(ax_w)

    ax_re.plot(t, ts["Re"], color="C3")
    ax_re.set_ylabel("Reynolds number (–)\nof the relative flow")
    for ax in (ax_u, ax_w, ax_re):
        ax.grid(True, alpha=0.3)
    time_axis(ax_re)
    finish(fig, path, written)


def domain_box(case, ts):
    """The domain's extent (m) when the particle stays inside a fixed domain; None when the window
    follows the particle (the fluid box then moves) or the size is unknown."""
    domain = case.get("domain", {})
    size = domain.get("size")
    if domain.get("follow_particle") or not isinstance(size, list) or len(size) != 3:
        return None
    size = np.array(size, dtype=float)
    inside = all((ts[c] >= 0.0).all() and (ts[c] <= size[i]).all() for i, c in enumerate("xyz"))
    return size if inside else None


def time_coloured_path(ax, u, v, t, norm):
    points = np.column_stack([u, v]).reshape(-1, 1, 2)
    segments = np.concatenate([points[:-1], points[1:]], axis=1)
    lines = LineCollection(segments, cmap="viridis", norm=norm, linewidth=2.0)
    lines.set_array(0.5 * (t[1:] + t[:-1]))
    ax.add_collection(lines)
    return lines


def plot_trajectory(ts, summary, case, path, written):
    t = ts["t"]
    box = domain_box(case, ts)
    extent = np.concatenate([ts["x"], ts["y"], ts["z"]] + ([box] if box is not None else []))
    factor, unit = si_scale(extent, "m")
    xyz = {c: ts[c] * factor for c in "xyz"}
    norm = Normalize(vmin=t[0], vmax=t[-1] if t[-1] > t[0] else t[0] + 1.0)

    fig, axes = plt.subplots(1, 3, figsize=(11.0, 6.0), layout="constrained")
    views = (("x", "z", "side view x-z"), ("y", "z", "side view y-z"), ("x", "y", "top view x-y"))
    lines = None
    for ax, (h, v, title) in zip(axes, views):
        if box is not None:
            i, j = "xyz".index(h), "xyz".index(v)
            ax.add_patch(Rectangle((0.0, 0.0), box[i] * factor, box[j] * factor, fill=False, color="0.5",
                                   lw=1.0, ls="--", label="domain"))
        if len(t) > 1:
            lines = time_coloured_path(ax, xyz[h], xyz[v], t, norm)
        ax.plot(xyz[h][0], xyz[v][0], "o", color="C2", ms=7, label="start")
        ax.plot(xyz[h][-1], xyz[v][-1], "s", color="C3", ms=7, label="end")
        ax.set_xlabel(f"{h} ({unit})")
        ax.set_ylabel(f"{v} ({unit})")
        ax.set_title(title)
        # True aspect ratio: a settling path is tall and thin, and a stretched axis would make
        # round-off-sized drift look like a zigzag.
        # Inside a drawn domain the box fits the domain; a bare path gets the limits widened.
        ax.set_aspect("equal", adjustable="box" if box is not None else "datalim")
        ax.autoscale_view()
        # The panels are narrow: few horizontal ticks, so long labels (tiny drift far from the
        # origin) cannot run into each other.
        ax.xaxis.set_major_locator(MaxNLocator(nbins=3))
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="best", fontsize="small")
    if lines is not None:
        fig.colorbar(lines, ax=axes, label="t (s)", shrink=0.8)
    drift = np.hypot(ts["x"] - ts["x"][0], ts["y"] - ts["y"][0]).max()
    drift_factor, drift_unit = si_scale([drift], "m")
    window = " (moving window: domain not drawn)" if case.get("domain", {}).get("follow_particle") else ""
    fig.suptitle(run_title(summary, case, f"trajectory of the centre of mass{window}\n"
                           f"largest horizontal distance from the start: {drift * drift_factor:.3g} {drift_unit}"))
    finish(fig, path, written)


def plot_trajectory_3d(ts, summary, case, path, written):
    t = ts["t"]
    box = domain_box(case, ts)
    extent = np.concatenate([ts["x"], ts["y"], ts["z"]] + ([box] if box is not None else []))
    factor, unit = si_scale(extent, "m")
    x, y, z = (ts[c] * factor for c in "xyz")

    fig = plt.figure(figsize=(7.5, 7.5), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    if len(t) > 1:
        points = np.column_stack([x, y, z]).reshape(-1, 1, 3)
        lines = Line3DCollection(np.concatenate([points[:-1], points[1:]], axis=1), cmap="viridis",
                                 norm=Normalize(vmin=t[0], vmax=t[-1]), linewidth=2.0)
        lines.set_array(0.5 * (t[1:] + t[:-1]))
        ax.add_collection3d(lines)
        fig.colorbar(lines, ax=ax, label="t (s)", shrink=0.6, pad=0.02)
    ax.plot([x[0]], [y[0]], [z[0]], "o", color="C2", label="start")
    ax.plot([x[-1]], [y[-1]], [z[-1]], "s", color="C3", label="end")
    if box is not None:
        draw_box_edges(ax, box * factor)
        limits = [(0.0, box[i] * factor) for i in range(3)]
    else:
        limits = cube_limits(x, y, z)
    # The path's shadow on the floor of the view gives the depth a single 3D line lacks.
    ax.plot(x, y, np.full_like(z, limits[2][0]), color="0.55", lw=1.0, label="projection on the floor")
    ax.set_xlim(*limits[0])
    ax.set_ylim(*limits[1])
    ax.set_zlim(*limits[2])
    ax.set_box_aspect([hi - lo for lo, hi in limits])  # true proportions
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.set_zlabel(f"z ({unit})")
    ax.legend(loc="upper left", fontsize="small")
    ax.set_title(run_title(summary, case, "trajectory in 3D"))
    finish(fig, path, written)


def cube_limits(x, y, z):
    """Axis limits of equal length around the path, so the 3D view keeps true proportions."""
    centres = [0.5 * (c.min() + c.max()) for c in (x, y, z)]
    half = 0.5 * max(max(c.max() - c.min() for c in (x, y, z)), 1e-12) * 1.05
    return [(m - half, m + half) for m in centres]


def draw_box_edges(ax, size):
    for a in (0.0, size[0]):
        for b in (0.0, size[1]):
            ax.plot([a, a], [b, b], [0.0, size[2]], color="0.6", lw=0.8, ls="--")
    for a in (0.0, size[0]):
        for c in (0.0, size[2]):
            ax.plot([a, a], [0.0, size[1]], [c, c], color="0.6", lw=0.8, ls="--")
    for b in (0.0, size[1]):
        for c in (0.0, size[2]):
            ax.plot([0.0, size[0]], [b, b], [c, c], color="0.6", lw=0.8, ls="--")


def angle_limits(angles):
    """Axis limits (deg) on multiples of 45 deg around the angles, always showing +-45 deg (the
    switching threshold) and never beyond +-180 deg."""
    degrees = np.degrees(np.concatenate(angles))
    degrees = degrees[np.isfinite(degrees)]
    low = min(-45.0, 45.0 * math.floor(degrees.min() / 45.0)) if degrees.size else -45.0
    high = max(45.0, 45.0 * math.ceil(degrees.max() / 45.0)) if degrees.size else 45.0
    return max(low, -180.0) - 5.0, min(high, 180.0) + 5.0


def plot_euler_set(ax, t, angles, labels, euler_set, which):
    """One Euler set's angles (deg): solid where the set is active, dotted where it is derived."""
    for span in active_spans(t, euler_set, which):
        ax.axvspan(*span, color="C0", alpha=0.12, lw=0)
    active = euler_set == which
    # Decreasing widths, so a curve lying on top of another (say psi = gamma = 0) stays visible.
    for angle, label, colour, width in zip(angles, labels, ("C0", "C1", "C2"), (3.4, 2.3, 1.2)):
        degrees = break_at_wraps(np.degrees(angle))
        ax.plot(t, degrees, color=colour, lw=0.6 * width, ls=":")
        ax.plot(t, np.where(active, degrees, np.nan), color=colour, lw=width, label=label)
    ax.set_ylim(*angle_limits(angles))
    ax.yaxis.set_major_locator(MultipleLocator(45.0))
    ax.set_ylabel(f"set {which} (deg)")
    ax.plot([], [], color="0.4", lw=1.6, label="active (shaded)")
    ax.plot([], [], color="0.4", lw=0.9, ls=":", label="derived")


def plot_orientation(ts, summary, case, path, written):
    t, euler_set = ts["t"], np.rint(ts["euler_set"]).astype(int)
    tilt = tilt_from_vertical(set1_body_to_inertial(ts["psi"], ts["theta"], ts["gamma"]))
    fig, (ax_tilt, ax_1, ax_2) = plt.subplots(3, 1, sharex=True, figsize=(8.5, 8.5), layout="constrained")
    ax_tilt.plot(t, np.degrees(tilt), color="k", label="tilt of body z\nfrom vertical")
    ax_tilt.set_ylabel("tilt (deg)")
    ax_tilt.set_title(run_title(summary, case, "orientation"))
    legend_right(ax_tilt)

    plot_euler_set(ax_1, t, (ts["psi"], ts["theta"], ts["gamma"]), (r"$\psi$", r"$\theta$", r"$\gamma$"),
                   euler_set, 1)
    # Set 1 is integrated while |theta| <= 45 deg (or > 135 deg); docs/architecture.md, "Frames and attitude".
    for level in (-45.0, 45.0):
        ax_1.axhline(level, color="0.5", lw=0.7, ls="--")
    ax_1.plot([], [], color="0.5", lw=0.7, ls="--", label=r"switch at $|\theta|$ = 45°")
    legend_right(ax_1)
    plot_euler_set(ax_2, t, (ts["psi_r"], ts["theta_r"], ts["gamma_r"]),
                   (r"$\psi_r$", r"$\theta_r$", r"$\gamma_r$"), euler_set, 2)
    legend_right(ax_2)
    for ax in (ax_tilt, ax_1, ax_2):
        ax.grid(True, alpha=0.3)
    time_axis(ax_2)
    finish(fig, path, written)
    return tilt


def net_weight_balance(summary, case):
    """-(rho_p - rho_f) V g (N): the hydrodynamic force that holds a free body at its terminal
    velocity. V = pi d_eq^3 / 6 is exact, d_eq being the volume-equivalent diameter."""
    if summary.get("motion") != "free":
        return None
    d_eq = summary.get("equivalent_diameter")
    rho_p = case.get("particle", {}).get("density")
    rho_f = case.get("fluid", {}).get("density")
    gravity = case.get("fluid", {}).get("gravity")
    if not all(isinstance(v, (int, float)) for v in (d_eq, rho_p, rho_f)) or not isinstance(gravity, list):
        return None
    volume = math.pi * d_eq**3 / 6.0
    return -(rho_p - rho_f) * volume * np.array(gravity, dtype=float)


def plot_forces(ts, summary, case, path, written):
    t = ts["t"]
    has_slip = "slip_max" in ts and "slip_rms" in ts
    rows = 3 if has_slip else 2
    fig, axes = plt.subplots(rows, 1, sharex=True, figsize=(8.5, 2.7 * rows + 0.5), layout="constrained")
    balance = net_weight_balance(summary, case)
    forces = [ts["Fx"], ts["Fy"], ts["Fz"]] + ([balance] if balance is not None else [])
    factor, unit = si_scale(np.concatenate(forces), "N")
    for i, (name, colour) in enumerate((("Fx", "C0"), ("Fy", "C1"), ("Fz", "C2"))):
        axes[0].plot(t, ts[name] * factor, color=colour, label=f"$F_{name[1]}$")
        if balance is not None and balance[i] != 0.0:
            axes[0].axhline(balance[i] * factor, color=colour, lw=0.8, ls=":",
                            label=rf"$-(\rho_p-\rho_f)\,V g_{name[1]}$" + "\n(terminal balance)")
    axes[0].set_ylabel(f"force ({unit})")
    axes[0].set_title(run_title(summary, case, "hydrodynamic force and torque (inertial frame)"))
    legend_right(axes[0])

    factor, unit = si_scale(np.concatenate([ts["Tx"], ts["Ty"], ts["Tz"]]), "N m")
    for name, colour in (("Tx", "C0"), ("Ty", "C1"), ("Tz", "C2")):
        axes[1].plot(t, ts[name] * factor, color=colour, label=f"$T_{name[1]}$")
    axes[1].set_ylabel(f"torque about the\ncentre of mass ({unit})")
    legend_right(axes[1])

    if has_slip:
        factor, unit = si_scale(np.concatenate([ts["slip_max"], ts["slip_rms"]]), "m/s")
        axes[2].plot(t, ts["slip_max"] * factor, color="C3", label="largest")
        axes[2].plot(t, ts["slip_rms"] * factor, color="C4", label="rms")
        axes[2].set_ylabel(f"marker no-slip\nerror ({unit})")
        legend_right(axes[2])
    for ax in axes:
        ax.grid(True, alpha=0.3)
    time_axis(axes[-1])
    finish(fig, path, written)


def mismatches(reference, summary, case):
    """Differences (> 1 %) between the case and the experiment the reference describes."""
    fields, setup = reference.get("fields", {}), reference.get("setup_fields", {})
    pairs = (
        ("fluid density", case.get("fluid", {}).get("density"), fields.get("fluid_density"), "kg/m^3"),
        ("dynamic viscosity", case.get("fluid", {}).get("dynamic_viscosity"), fields.get("dynamic_viscosity"), "Pa s"),
        ("particle density", case.get("particle", {}).get("density"), setup.get("sphere_density"), "kg/m^3"),
        ("diameter", summary.get("equivalent_diameter"), setup.get("sphere_diameter"), "m"),
    )
    found = []
    for name, ours, theirs, unit in pairs:
        if isinstance(ours, (int, float)) and isinstance(theirs, (int, float)) and theirs != 0:
            if abs(ours / theirs - 1.0) > 0.01:
                found.append(f"{name} {ours:.4g} vs {theirs:.4g} {unit}")
    return found


def agreement(t_sim, y_sim, t_ref, y_ref):
    """RMS and largest difference of the simulated curve, interpolated linearly at the reference
    times inside the simulated interval, from the reference values; None if no overlap."""
    inside = (t_ref >= t_sim[0]) & (t_ref <= t_sim[-1])
    if not inside.any() or len(t_sim) < 2:
        return None
    difference = np.interp(t_ref[inside], t_sim, y_sim) - y_ref[inside]
    return float(np.sqrt(np.mean(difference**2))), float(np.abs(difference).max()), int(inside.sum())


def plot_reference(ts, summary, case, reference, path, written):
    fields = reference["fields"]
    panels = [s for s in (VELOCITY_SERIES, TRAJECTORY_SERIES) if s in fields]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(8.5, 3.6 * len(panels) + 0.8),
                             layout="constrained", squeeze=False)
    axes = axes[:, 0]
    for ax, series in zip(axes, panels):
        draw_reference_panel(ax, ts, summary, reference, series)
    key = reference["key"]
    title = run_title(summary, case, f"against {key}")
    if reference.get("citation"):
        title += "\n" + shorten_citation(reference["citation"])
    differences = mismatches(reference, summary, case)
    if differences:
        title += "\n" + "\n".join(textwrap.wrap("case differs from the experiment: " + "; ".join(differences), 95))
        note(f"warning: the case differs from {key}: " + "; ".join(differences))
    axes[0].set_title(title, fontsize="medium")
    time_axis(axes[-1])
    finish(fig, path, written)


def draw_reference_panel(ax, ts, summary, reference, series):
    """One digitised series over the simulated one, with their measured difference."""
    fields, key, t = reference["fields"], reference["key"], ts["t"]
    data = np.array(fields[series], dtype=float)
    if series == VELOCITY_SERIES:
        simulated, ylabel, what, unit = ts["uz"], "$u_z$ (m/s)", "u_z", " m/s"
        for name, style, label in (("u_inf", "--", r"$-u_\infty$ (u_inf of the reference)"),
                                   ("u_max_exp", ":", r"$-u_{max}$ (largest measured speed)")):
            if isinstance(fields.get(name), (int, float)):
                ax.axhline(-fields[name], color="0.4", lw=0.9, ls=style, label=label)
    else:
        # The gap is measured from z = 0, the bottom of the domain (docs/architecture.md, "Frames and
        # attitude"), which is
        # where a ten Cate case puts the tank bottom; d is the volume-equivalent diameter.
        d_eq = summary.get("equivalent_diameter") or reference["setup_fields"].get("sphere_diameter")
        simulated, what, unit = (ts["z"] - 0.5 * d_eq) / d_eq, "gap/d", ""
        ylabel = "gap between sphere and\nbottom / d (–)"
    ax.plot(t, simulated, color="C0", lw=1.6, label="settle")
    ax.plot(data[:, 0], data[:, 1], "o", color="C3", ms=4.5, mfc="none", label=f"{key} (digitised)")
    score = agreement(t, simulated, data[:, 0], data[:, 1])
    if score is not None:
        rms, largest, count = score
        points = f"{count} reference point{'s' if count != 1 else ''}"
        note(f"reference {key}: {what}: rms difference {rms:.3g}{unit}, largest {largest:.3g}{unit} ({points})")
        # Under the legend, outside the data, so it never hides a curve.
        ax.text(1.02, 0.02, f"settle - reference ({what}):\nrms {rms:.3g}{unit}\nlargest {largest:.3g}{unit}\n"
                f"over {points}", transform=ax.transAxes, fontsize="small", va="bottom")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    legend_right(ax, top=True)


def shorten_citation(citation):
    """Authors and journal of a citation, without the DOI tail, short enough for a title line."""
    text = citation.split(", doi:")[0]
    return text if len(text) <= 110 else text[:107] + "..."


# ----------------------------------------------------------------------------------------------
# Driver


def check_attitude_columns(ts):
    """Warns when the set-1 and set-2 angles of a row describe different attitudes: both are
    written from one matrix, so they must agree to round-off."""
    set1 = set1_body_to_inertial(ts["psi"], ts["theta"], ts["gamma"])
    set2 = set2_body_to_inertial(ts["psi_r"], ts["theta_r"], ts["gamma_r"])
    difference = float(np.abs(set1 - set2).max())
    # 17-digit output and the trigonometry of S5/S8 keep the two within ~1e-15; 1e-9 leaves room
    # for any reader while still catching a wrong angle or a swapped column.
    if difference > 1e-9:
        note(f"warning: set-1 and set-2 angles disagree (largest matrix difference {difference:.3g})")
    return difference


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog=PROGRAM, description="PNG figures of a `settle run` output directory.")
    parser.add_argument("run_dir", metavar="RUN_DIR", help="output directory of settle run")
    parser.add_argument("-o", "--output-dir", "--output", dest="output_dir",
                        help="where to write the PNG files (default RUN_DIR/plots)")
    parser.add_argument("--reference", metavar="KEY",
                        help="reference data set to overlay, a key of the reference file (e.g. tenCate2002_E1); "
                        "default: the `reference` the run names in summary.json or case.resolved.toml")
    parser.add_argument("--reference-file", metavar="FILE", default=default_reference_file(),
                        help="reference data (default: validation/reference-data.json of the settle sources)")
    return parser.parse_args(argv)


def make_plots(args):
    if not os.path.isdir(args.run_dir):
        raise UserError(f"RUN_DIR: '{args.run_dir}' is not a directory")
    ts = read_timeseries(os.path.join(args.run_dir, "timeseries.csv"))
    summary = read_json(os.path.join(args.run_dir, "summary.json"))
    case = read_toml(os.path.join(args.run_dir, "case.resolved.toml"))
    key = args.reference or named_reference(summary, case)
    reference = load_reference(key, args.reference_file, explicit=bool(args.reference)) if key else None

    out_dir = args.output_dir or os.path.join(args.run_dir, "plots")
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as error:
        raise UserError(f"--output-dir: cannot create {out_dir}: {error}") from error

    check_attitude_columns(ts)
    written = []
    plot_velocity(ts, summary, case, os.path.join(out_dir, "velocity.png"), written)
    plot_trajectory(ts, summary, case, os.path.join(out_dir, "trajectory.png"), written)
    plot_trajectory_3d(ts, summary, case, os.path.join(out_dir, "trajectory_3d.png"), written)
    tilt = plot_orientation(ts, summary, case, os.path.join(out_dir, "orientation.png"), written)
    plot_forces(ts, summary, case, os.path.join(out_dir, "forces.png"), written)
    if reference is not None:
        plot_reference(ts, summary, case, reference, os.path.join(out_dir, "reference.png"), written)
    note(f"tilt of body z from vertical: {math.degrees(tilt[0]):.6f} deg at t = {ts['t'][0]:.6g} s, "
         f"{math.degrees(tilt[-1]):.6f} deg at t = {ts['t'][-1]:.6g} s")
    for path in written:
        print(path)


def main(argv=None):
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    if MISSING_MODULE is not None:
        note(f"error: {MISSING_MODULE.name} is not importable by {sys.executable}: install Debian's "
             "python3-matplotlib (apt-get install python3-matplotlib python3-numpy)")
        return 2
    try:
        make_plots(args)
    except UserError as error:
        note(f"error: {error}")
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
