"""Fixtures of the settle package's tests: small real runs and a two-case study made by the built
binary ($SETTLE_BINARY, which CTest sets) in pytest's temporary folder, never in the source tree."""

import os
import pathlib
import subprocess

import pytest

# The attitude the tilted run is released at (set 1, rad): theta within pi/4, so set 1 is active.
PSI, THETA, GAMMA = 0.3, 0.4, 0.5


def settle_binary():
    binary = os.environ.get("SETTLE_BINARY")
    if not binary:
        pytest.skip("SETTLE_BINARY is not set (CTest sets it to the built binary)")
    return binary


def source_dir():
    return pathlib.Path(os.environ.get("SETTLE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def run_settle(*arguments):
    result = subprocess.run([settle_binary(), *arguments], capture_output=True, text=True,
                            env={**os.environ, "OMP_NUM_THREADS": "1"}, check=False)
    assert result.returncode == 0, f"settle {' '.join(arguments)}: status {result.returncode}\n{result.stderr}"
    return result


@pytest.fixture(scope="session")
def tilted_run(tmp_path_factory):
    """The default case released at (PSI, THETA, GAMMA), 10 steps (2.5 ms), a row per step."""
    out = tmp_path_factory.mktemp("runs") / "tilted"
    run_settle("run", "-o", str(out), "--set", f"particle.euler=[{PSI},{THETA},{GAMMA}]",
               "--set", "run.end_time=0.0025", "--set", "run.output_interval=0", "--threads", "1", "--quiet")
    return out


@pytest.fixture(scope="session")
def study_dir(tmp_path_factory):
    """A two-case study (cells per diameter 5 and 6, 2 ms of the prolate spheroid), collected."""
    root = tmp_path_factory.mktemp("study")
    study_file = root / "tiny.toml"
    base = source_dir() / "cases" / "prolate_spheroid.toml"
    study_file.write_text(f'[study]\nname = "tiny"\nbase = "{base}"\n\n[vary]\n'
                          "numerics.cells_per_diameter = [5, 6]\nrun.end_time = [0.002]\n", encoding="utf-8")
    out = root / "out"
    run_settle("study", "run", str(study_file), "-o", str(out), "--jobs", "1", "--threads", "1")
    run_settle("study", "collect", str(out), "--no-plots")
    return out
