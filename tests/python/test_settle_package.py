"""The settle package (python/settle/) on real runs of the built binary (conftest.py)."""

import math
import shutil

import numpy as np
import pytest
from conftest import GAMMA, PSI, THETA

import settle


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def body_axes_matrix(row):
    """C_b^n from the package's body-axis columns: column a is body axis a."""
    return np.array([[row[f"b{a}_{i}"] for a in "xyz"] for i in "xyz"])


def test_units_and_frames_come_from_the_sidecar(tilted_run):
    df = settle.load_run(tilted_run).timeseries
    units, frames = df.attrs["units"], df.attrs["frames"]
    assert set(units) == set(df.columns)  # every column, settle's and the derived ones
    assert (units["t"], units["z"], units["uz"], units["wbx"], units["Tz"]) == ("s", "m", "m/s", "rad/s", "N m")
    assert (units["q_w"], units["bz_z"]) == ("1", "1")
    assert (frames["wbx"], frames["ux"], frames["psi"], frames["bz_x"]) == ("body", "inertial", "body to inertial",
                                                                          "inertial")


def test_the_quaternion_is_unit_with_a_non_negative_scalar_part(tilted_run):
    df = settle.load_run(tilted_run).timeseries
    q = df[["q_w", "q_x", "q_y", "q_z"]].to_numpy()
    assert len(q) >= 10
    # Written with 17 significant digits from a composed (not integrated) quaternion: unit to
    # round-off of a few products, 1e-14.
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, rtol=0, atol=1e-14)
    assert (q[:, 0] >= 0).all()


def test_the_body_axes_agree_with_both_euler_sets(tilted_run):
    # docs/attitude.md, "Conventions": set 1 is C_b^n = Rz(psi) Ry(theta) Rx(gamma), set 2 is
    # Rz(psi_r) Rx(gamma_r) Ry(theta_r). The body axes come from the quaternion columns; both
    # sides are a few products of the same doubles, so 1e-13 is round-off, while a transposed
    # matrix or a swapped order misses by the angles' size (0.1 and more here).
    df = settle.load_run(tilted_run).timeseries
    for _, row in df.iterrows():
        axes = body_axes_matrix(row)
        set1 = rz(row["psi"]) @ ry(row["theta"]) @ rx(row["gamma"])
        set2 = rz(row["psi_r"]) @ rx(row["gamma_r"]) @ ry(row["theta_r"])
        np.testing.assert_allclose(axes, set1, rtol=0, atol=1e-13)
        np.testing.assert_allclose(axes, set2, rtol=0, atol=1e-13)
        np.testing.assert_allclose(axes.T @ axes, np.eye(3), rtol=0, atol=1e-13)


def test_tilt_of_a_body_released_at_known_angles(tilted_run):
    df = settle.load_run(tilted_run).timeseries
    assert df["t"].iloc[0] == 0.0
    # At t = 0 the attitude is the case's exactly. Body z = C_b^n e_z has vertical component
    # cos(theta) cos(gamma); body x has -sin(theta). 1e-9 deg: acos of a number known to 1e-15
    # away from +-1 (where acos's slope stays below 2 here).
    tilt_z = settle.tilt_deg(df, axis="z")
    assert tilt_z.iloc[0] == pytest.approx(math.degrees(math.acos(math.cos(THETA) * math.cos(GAMMA))), abs=1e-9)
    assert tilt_z.iloc[0] == pytest.approx(36.069144, abs=1e-6)  # the figure docs/plots.md prints
    tilt_x = settle.tilt_deg(df, axis="x", line=False)
    assert tilt_x.iloc[0] == pytest.approx(90.0 + math.degrees(THETA), abs=1e-9)
    assert settle.tilt_deg(df, axis="x").iloc[0] == pytest.approx(90.0 - math.degrees(THETA), abs=1e-9)
    np.testing.assert_allclose(settle.body_axis(df, "z")[0], rz(PSI) @ ry(THETA) @ rx(GAMMA) @ [0, 0, 1], atol=1e-14)
    with pytest.raises(ValueError):
        settle.tilt_deg(df, axis="w")


def test_the_summary_and_the_case_come_with_the_run(tilted_run):
    run = settle.load_run(tilted_run)
    assert run.summary["steps"] == 10
    assert run.summary["case"] == run.name
    assert "[particle]" in run.case_text
    assert len(run.timeseries) == 11  # t = 0 and each of the 10 steps


def test_a_cut_last_row_is_left_out_and_an_unfinished_run_has_no_summary(tilted_run, tmp_path):
    copy = tmp_path / "cut"
    shutil.copytree(tilted_run, copy)
    csv = copy / "timeseries.csv"
    text = csv.read_text(encoding="utf-8")
    csv.write_text(text[:-10], encoding="utf-8")  # the last row without its end
    (copy / "summary.json").unlink()
    with pytest.warns(UserWarning, match="incomplete"):
        run = settle.load_run(copy)
    assert len(run.timeseries) == 10
    assert run.summary is None


def test_a_run_without_the_sidecar_loads_without_units(tilted_run, tmp_path):
    copy = tmp_path / "old"
    shutil.copytree(tilted_run, copy)
    (copy / "timeseries.json").unlink()
    with pytest.warns(UserWarning, match="timeseries.json"):
        df = settle.load_run(copy).timeseries
    # Units only for the derived body axes (the package's own); none for settle's columns.
    assert set(df.attrs["units"]) == {f"b{a}_{i}" for a in "xyz" for i in "xyz"}


def test_overlay_draws_a_line_per_run_in_a_panel_per_column(tilted_run, tmp_path):
    run = settle.load_run(tilted_run)
    path = tmp_path / "overlay.png"
    figure = settle.overlay([run, run], ["uz", "bz_z"], labels=["a", "b"], path=path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    panels = figure.get_axes()
    assert len(panels) == 2
    assert [len(panel.get_lines()) for panel in panels] == [2, 2]
    np.testing.assert_array_equal(panels[0].get_lines()[0].get_ydata(), run.timeseries["uz"])
    assert panels[0].get_ylabel() == "uz (m/s)"
    with pytest.raises(KeyError):
        settle.overlay([run], ["no_such_column"])


def test_load_study_reads_the_plan_the_states_and_the_table(study_dir):
    study = settle.load_study(study_dir)
    assert study.name == "tiny"
    assert list(study.cases.index) == [0, 1]
    assert list(study.cases["numerics.cells_per_diameter"]) == [5, 6]
    assert (study.cases["state"] == "done").all()
    assert list(study.cases["folder"]) == [f"case_{i:04d}" for i in study.cases.index]
    runs = study.runs()
    assert len(runs) == 2
    assert all(run.summary is not None and len(run.timeseries) >= 2 for run in runs)
    assert study.table is not None and len(study.table) == 2
    # A case whose summary went missing counts as interrupted, as settle counts it.
    first = study.cases.index[0]
    (study_dir / study.cases.loc[first, "folder"] / "summary.json").rename(study_dir / "kept_summary.json")
    try:
        assert settle.load_study(study_dir).cases.loc[first, "state"] == "interrupted"
    finally:
        (study_dir / "kept_summary.json").rename(study_dir / study.cases.loc[first, "folder"] / "summary.json")


def test_load_run_names_a_folder_without_a_time_series(tmp_path):
    with pytest.raises(FileNotFoundError, match="timeseries.csv"):
        settle.load_run(tmp_path)
    with pytest.raises(FileNotFoundError, match="study.json"):
        settle.load_study(tmp_path)
