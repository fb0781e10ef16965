#!/usr/bin/env python3
"""Figures of a settle study (docs/studies.md), from DIR/study_results.json written by
`settle study collect DIR`, into DIR/plots:

- coefficients_vs_incidence.png: C_D, C_L and C_T against the incidence angle, one curve per
  combination of the other inputs (for example the Reynolds number), with the fitted forms and,
  for C_D, Hoelzer and Sommerfeld's law at each case's Reynolds number and attitude (dashed);
- grid_convergence.png: each converging figure against the cell size 1/(cells per diameter), with
  Richardson's extrapolate at zero and Roache's grid convergence index as the band around it;
- ensemble.png: histograms of the ensemble figures with their mean and standard deviation, and
  the regime counts.

Only the figures the study's inputs call for are drawn. Prints the paths written, one a line.
Exit status 2 for a problem the user can fix (a missing file).
"""
import argparse
import json
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as import_error:
    MISSING_MODULE = import_error
else:
    MISSING_MODULE = None

LABELS = {
    "drag_coefficient": "$C_D$",
    "lift_coefficient": "$C_L$",
    "torque_coefficient": "$C_T$",
    "terminal_velocity_m_s": "terminal speed (m/s)",
    "terminal_vertical_velocity_m_s": "settling velocity (m/s)",
    "late_mean_velocity_m_s": "late mean speed, not terminal (m/s)",
    "late_mean_vertical_velocity_m_s": "late mean settling velocity (m/s)",
    "path_angle_deg": "path angle (deg)",
    "tilt_mean_deg": "mean tilt (deg)",
}


def group_label(inputs):
    return ", ".join(f"{k} = {v:g}" if isinstance(v, (int, float)) else f"{k} = {v}" for k, v in inputs.items()) or "all"


def fitted(fit, phi_deg):
    c = fit["coefficients"]
    s = np.sin(np.radians(phi_deg))
    if fit["figure"] == "drag_coefficient":
        return c["C_D0"] + (c["C_D90"] - c["C_D0"]) * s ** c["a"]
    co = np.clip(np.cos(np.radians(phi_deg)), 0.0, None)
    return c["A"] * s ** c["b1"] * co ** c["b2"]


def plot_coefficients(results, out_dir):
    fits = results["analyses"]["coefficient_fits"]
    if not fits:
        return None
    figures = [f for f in ("drag_coefficient", "lift_coefficient", "torque_coefficient")
               if any(fit["figure"] == f for fit in fits)]
    fig, axes = plt.subplots(1, len(figures), figsize=(4.5 * len(figures), 3.8), squeeze=False)
    phi = np.linspace(0.0, 90.0, 181)
    for ax, figure in zip(axes[0], figures):
        for k, fit in enumerate(f for f in fits if f["figure"] == figure):
            colour = f"C{k % 10}"
            ax.plot(fit["incidence_deg"], fit["values"], "o", color=colour, label=group_label(fit["inputs"]))
            ax.plot(phi, fitted(fit, phi), "-", color=colour, lw=1)
            if figure == "drag_coefficient":
                law = sorted((row["incidence_deg"], row["drag_coefficient_holzer_sommerfeld"])
                             for row in results["rows"]
                             if row.get("drag_coefficient_holzer_sommerfeld") is not None
                             and all(row.get(key) == value for key, value in fit["inputs"].items()))
                if law:
                    ax.plot(*zip(*law), "--", color=colour, lw=1,
                            label="Hoelzer and Sommerfeld 2008" if k == 0 else None)
        ax.set_xlabel("incidence (deg)")
        ax.set_ylabel(LABELS[figure])
        ax.set_xticks(range(0, 91, 15))
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.suptitle(f"{results['study']}: settle (points), fitted forms (lines), drag law (dashed)", fontsize=9)
    fig.tight_layout()
    path = os.path.join(out_dir, "coefficients_vs_incidence.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def plot_grid_convergence(results, out_dir):
    entries = [e for e in results["analyses"]["grid_convergence"] if e["extrapolated"] is not None]
    if not entries:
        return None
    columns = min(3, len(entries))
    rows = math.ceil(len(entries) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.4 * rows), squeeze=False)
    for ax, e in zip(axes.flat, entries):
        h = [1.0 / n for n in e["cells_per_diameter"]]
        ax.plot(h, e["values"], "o-", label="settle")
        band = abs(e["values"][0]) * e["gci_fine"] if e["gci_fine"] is not None else 0.0
        ax.errorbar([0.0], [e["extrapolated"]], yerr=[band], fmt="s", capsize=4,
                    label=f"extrapolated, p = {e['observed_order']:.2f}, GCI {100 * (e['gci_fine'] or 0):.2g}%")
        ax.set_xlabel("cell size / d  (1 / cells per diameter)")
        ax.set_ylabel(LABELS.get(e["figure"], e["figure"]))
        ax.set_title(group_label(e["inputs"]), fontsize=8)
        ax.set_xlim(left=-0.01)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(entries):]:
        ax.set_visible(False)
    fig.tight_layout()
    path = os.path.join(out_dir, "grid_convergence.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def plot_ensembles(results, out_dir):
    ensembles = results["analyses"]["ensembles"]
    if not ensembles:
        return None
    names = [n for n in ("terminal_velocity_m_s", "tilt_mean_deg", "path_angle_deg")
             if any(n in e["figures"] for e in ensembles)]
    fig, axes = plt.subplots(len(ensembles), len(names) + 1, figsize=(4.0 * (len(names) + 1), 3.3 * len(ensembles)),
                             squeeze=False)
    rows = results["rows"]
    for r, e in enumerate(ensembles):
        members = [row for row in rows if row["status"] == "done"
                   and all(row.get(k) == v for k, v in e["inputs"].items())]
        for ax, name in zip(axes[r], names):
            values = [row[name] for row in members if isinstance(row.get(name), (int, float))]
            if values:
                ax.hist(values, bins=max(5, int(math.sqrt(len(values)))), color="C0", alpha=0.8)
                s = e["figures"][name]
                ax.axvline(s["mean"], color="k")
                ax.axvspan(s["mean"] - s["standard_deviation"], s["mean"] + s["standard_deviation"], color="k",
                           alpha=0.1)
                ax.set_title(f"{s['mean']:.4g} +- {s['standard_deviation']:.2g} ({s['count']} runs)", fontsize=8)
            ax.set_xlabel(LABELS.get(name, name))
        regimes = e["regimes"]
        axes[r][-1].bar(list(regimes.keys()), list(regimes.values()), color="C1")
        axes[r][-1].tick_params(axis="x", labelrotation=30, labelsize=7)
        axes[r][-1].set_title("regimes " + group_label(e["inputs"]), fontsize=8)
    fig.tight_layout()
    path = os.path.join(out_dir, "ensemble.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("study_dir")
    args = parser.parse_args()
    if MISSING_MODULE is not None:
        print(f"settle study collect: {MISSING_MODULE}; install Debian's python3-matplotlib", file=sys.stderr)
        return 2
    results_file = os.path.join(args.study_dir, "study_results.json")
    if not os.path.isfile(results_file):
        print(f"settle study collect: {results_file}: missing", file=sys.stderr)
        return 2
    with open(results_file) as f:
        results = json.load(f)
    out_dir = os.path.join(args.study_dir, "plots")
    os.makedirs(out_dir, exist_ok=True)
    for plot in (plot_coefficients, plot_grid_convergence, plot_ensembles):
        path = plot(results, out_dir)
        if path:
            print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
