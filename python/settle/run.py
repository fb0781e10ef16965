"""One run directory of `settle run` (docs/user-guide.md, "Outputs and their units")."""

import dataclasses
import json
import pathlib
import warnings
from io import StringIO

import pandas as pd

from .attitude import add_body_axes


@dataclasses.dataclass
class Run:
    """A run's outputs: `timeseries` (timeseries.csv with the derived columns; its
    attrs["units"] and attrs["frames"] map each column to its unit and frame), `summary`
    (summary.json as a dict; None while the run has not finished: settle writes it last), and
    `case_text` (case.resolved.toml, the case as run; "" when missing)."""

    path: pathlib.Path
    timeseries: pd.DataFrame
    summary: dict | None
    case_text: str

    @property
    def name(self):
        """The case name of the summary, else the folder's name."""
        return (self.summary or {}).get("case") or self.path.name


def read_columns(path):
    """timeseries.json, the sidecar settle writes beside timeseries.csv: {name: {"unit", "frame",
    "meaning"}}. Empty for a run of a settle that did not write one."""
    sidecar = path / "timeseries.json"
    if not sidecar.is_file():
        warnings.warn(f"{sidecar}: missing (a run of an older settle): no units for its columns", stacklevel=3)
        return {}
    with open(sidecar, encoding="utf-8") as file:
        return {column["name"]: column for column in json.load(file)["columns"]}


def read_timeseries(path):
    """timeseries.csv as a DataFrame, its rows as settle wrote them. A last row without its
    newline (a run stopped while writing it) is left out, as `settle plot` leaves it out."""
    csv = path / "timeseries.csv"
    if not csv.is_file():
        raise FileNotFoundError(f"{csv}: missing (give the -o directory of `settle run`)")
    text = csv.read_text(encoding="utf-8")
    if text and not text.endswith("\n"):
        warnings.warn(f"{csv}: its last row is incomplete; read without it", stacklevel=3)
        text = text[: text.rfind("\n") + 1]
    return pd.read_csv(StringIO(text))


def add_derived(df, units, frames):
    """The body-axis columns (from the quaternion), with their units and frames."""
    if "q_w" not in df.columns:
        warnings.warn("timeseries.csv has no quaternion columns (a run of an older settle): no body axes", stacklevel=3)
        return
    for name in add_body_axes(df):
        units[name] = "1"
        frames[name] = "inertial"


def load_run(path):
    """The outputs of the run directory `path` as a Run (timeseries, summary, case_text).

    run.timeseries.attrs["units"]["uz"] == "m/s"; the columns bx_x .. bz_z are the body axes in
    inertial components (settle.body_axis, settle.tilt_deg)."""
    path = pathlib.Path(path)
    df = read_timeseries(path)
    columns = read_columns(path)
    units = {name: columns[name]["unit"] for name in df.columns if name in columns}
    frames = {name: columns[name]["frame"] for name in df.columns if name in columns}
    add_derived(df, units, frames)
    df.attrs["units"] = units
    df.attrs["frames"] = frames
    summary_file = path / "summary.json"
    summary = json.loads(summary_file.read_text(encoding="utf-8")) if summary_file.is_file() else None
    case_file = path / "case.resolved.toml"
    case_text = case_file.read_text(encoding="utf-8") if case_file.is_file() else ""
    return Run(path=path, timeseries=df, summary=summary, case_text=case_text)


__all__ = ["Run", "load_run"]
