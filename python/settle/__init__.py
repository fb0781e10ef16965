"""Read the outputs of settle runs and studies into pandas (docs/python.md).

    import settle
    run = settle.load_run("runs/prolate")       # run.timeseries (DataFrame), run.summary (dict)
    run.timeseries.attrs["units"]["uz"]          # 'm/s'
    settle.tilt_deg(run.timeseries, axis="z")    # tilt of the body z axis from vertical, deg
    study = settle.load_study("runs/prolate_map")
    settle.overlay([run, other], ["uz"]).savefig("uz.png")

Pure Python over a run's files (pandas, numpy; matplotlib for `overlay`); nothing here runs
settle. Usable from the source tree (PYTHONPATH=python) or from an install
(PYTHONPATH=<prefix>/share/settle/python).
"""

from .attitude import body_axis, tilt_deg
from .plot import overlay
from .run import Run, load_run
from .study import Study, load_study

__all__ = ["Run", "Study", "body_axis", "load_run", "load_study", "overlay", "tilt_deg"]
