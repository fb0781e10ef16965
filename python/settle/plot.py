"""A figure of several runs over each other: one panel per column, one line per run.

Drawn on a matplotlib Figure with the Agg canvas, not through pyplot: no window and no global
figure state, so it works on a machine without a display and inside other programs' figures."""

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure


def axis_label(run, column):
    unit = run.timeseries.attrs.get("units", {}).get(column)
    return f"{column} ({unit})" if unit and unit != "1" else column


def overlay(runs, columns=("uz",), x="t", labels=None, path=None):
    """A Figure with one panel per name in `columns` (any column of the runs' time series,
    derived ones included), each run a line against column `x`. `labels` defaults to each run's
    name; `path`, when given, is where the figure is saved (the format from its extension).
    Returns the Figure."""
    runs = list(runs)
    if not runs:
        raise ValueError("runs: give at least one Run (settle.load_run)")
    labels = list(labels) if labels is not None else [run.name for run in runs]
    if len(labels) != len(runs):
        raise ValueError(f"labels: {len(labels)} labels for {len(runs)} runs")
    columns = [columns] if isinstance(columns, str) else list(columns)
    figure = Figure(figsize=(8.0, 2.6 * len(columns) + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    panels = figure.subplots(len(columns), 1, sharex=True, squeeze=False)[:, 0]
    for panel, column in zip(panels, columns):
        for run, label in zip(runs, labels):
            series = run.timeseries
            if column not in series.columns:
                raise KeyError(f"{column}: not a column of {run.path}/timeseries.csv (or a derived one)")
            panel.plot(series[x], series[column], label=label)
        panel.set_ylabel(axis_label(runs[0], column))
        panel.grid(True, alpha=0.3)
    panels[-1].set_xlabel(axis_label(runs[0], x))
    panels[0].legend(loc="best", fontsize="small")
    if path is not None:
        figure.savefig(path, dpi=120)
    return figure
