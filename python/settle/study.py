"""One study directory of `settle study run` (docs/studies.md, "The study directory"): study.json
(the plan: each case's index, folder and inputs), case_NNNN/ (a run directory and its
status.json), and study.csv once `settle study collect` has run."""

import dataclasses
import json
import pathlib

import pandas as pd

from .run import load_run

STATUS_FIELDS = ("state", "exit_status", "wall_seconds", "attempts")


@dataclasses.dataclass
class Study:
    """`plan`: study.json as a dict. `cases`: one row per case, indexed by the case's index:
    `folder`, `state` (pending, running, done, failed, interrupted), `exit_status`,
    `wall_seconds`, `attempts`, then one column per varied input. `table`: study.csv (None until
    `settle study collect` has written it)."""

    path: pathlib.Path
    plan: dict
    cases: pd.DataFrame
    table: pd.DataFrame | None

    @property
    def name(self):
        return self.plan.get("study", self.path.name)

    def run(self, index):
        """The Run of case `index` (settle.load_run of its folder)."""
        return load_run(self.path / self.cases.loc[index, "folder"])

    def runs(self, state="done"):
        """The Runs of the cases in `state` (all cases when None), in case order."""
        chosen = self.cases if state is None else self.cases[self.cases["state"] == state]
        return [self.run(index) for index in chosen.index]


def case_status(case_dir):
    """A case's status.json, read as settle reads it (src/study/study_directory.cpp): pending
    without one, and a case marked done whose summary.json is missing counts as interrupted."""
    status = {"state": "pending", "exit_status": 0, "wall_seconds": 0.0, "attempts": 0}
    file = case_dir / "status.json"
    if file.is_file():
        recorded = json.loads(file.read_text(encoding="utf-8"))
        status.update({key: recorded[key] for key in STATUS_FIELDS if key in recorded})
    if status["state"] == "done" and not (case_dir / "summary.json").is_file():
        status["state"] = "interrupted"
    return status


def load_study(path):
    """The study directory `path` (the -o folder of `settle study run`) as a Study."""
    path = pathlib.Path(path)
    plan_file = path / "study.json"
    if not plan_file.is_file():
        raise FileNotFoundError(f"{plan_file}: missing (give the -o directory of `settle study run`)")
    plan = json.loads(plan_file.read_text(encoding="utf-8"))
    rows = []
    for case in plan["cases"]:
        row = {"index": case["index"], "folder": case["folder"]}
        row.update(case_status(path / case["folder"]))
        row.update(case.get("inputs", {}))
        rows.append(row)
    columns = ["index", "folder", *STATUS_FIELDS, *plan.get("inputs", [])]
    cases = pd.DataFrame(rows, columns=columns).set_index("index")
    table_file = path / "study.csv"
    table = pd.read_csv(table_file) if table_file.is_file() else None
    return Study(path=path, plan=plan, cases=cases, table=table)
