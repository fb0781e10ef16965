"""The attitude columns a run's time series gains on loading: the body axes in the inertial frame,
from the unit quaternion (q_w, q_x, q_y, q_z) of the rotation body -> inertial that settle writes
(docs/attitude.md, "Conventions": q v_b q* = v_n, scalar part non-negative). Column `b{a}_{i}` is
the inertial component i of the body axis a: C_b^n's column for a, so `bz_z` is the cosine of
the body z axis's angle to the vertical."""

import numpy as np
import pandas as pd

AXES = ("x", "y", "z")


def axis_column(axis, component):
    """The column name of inertial `component` of body `axis` ("bz_x": body z, inertial x)."""
    return f"b{axis}_{component}"


def body_to_inertial(q_w, q_x, q_y, q_z):
    """C_b^n of unit quaternions (arrays of N), shape (N, 3, 3): the standard rotation matrix of
    q = (w, x, y, z), v_n = C_b^n v_b."""
    w, x, y, z = (np.asarray(c, dtype=float) for c in (q_w, q_x, q_y, q_z))
    rows = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    return np.moveaxis(np.array(rows), -1, 0)


def add_body_axes(df):
    """Appends the nine body-axis columns (dimensionless, inertial frame) computed from the
    quaternion columns; returns their names."""
    matrices = body_to_inertial(df["q_w"], df["q_x"], df["q_y"], df["q_z"])
    names = []
    for j, axis in enumerate(AXES):
        for i, component in enumerate(AXES):
            name = axis_column(axis, component)
            df[name] = matrices[:, i, j]
            names.append(name)
    return names


def body_axis(df, axis="z"):
    """The body `axis` ("x", "y" or "z") in inertial components, an (N, 3) array."""
    if axis not in AXES:
        raise ValueError(f"axis: {axis!r} is not one of x, y, z")
    return df[[axis_column(axis, c) for c in AXES]].to_numpy()


def tilt_deg(df, axis="z", line=True):
    """The angle in degrees between body `axis` and the vertical (inertial z, up), one per row
    (a Series on the rows of `df`).

    line=True treats the axis as a line (a spheroid's or cylinder's symmetry axis, which has no
    "up"): acos(|b . e_z|), in [0, 90], as `settle plot`'s orientation figure (docs/plots.md).
    line=False gives the angle of the directed axis, acos(b . e_z), in [0, 180]."""
    vertical = body_axis(df, axis)[:, 2]
    if line:
        vertical = np.abs(vertical)
    # Rows of a unit quaternion give |b_z| <= 1 only to round-off; clip before acos.
    tilt = np.degrees(np.arccos(np.clip(vertical, -1.0, 1.0)))
    return pd.Series(tilt, index=df.index, name=f"tilt_{axis}_deg")
