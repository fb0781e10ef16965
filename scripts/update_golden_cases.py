#!/usr/bin/env python3
"""Writes the expected values of tests/data/golden_cases.json from a settle binary.

The golden test (tests/app/test_golden_cases.cpp) runs every case of cases/ for five steps on a
coarse grid and compares dt, tau, the body's displacement, velocity and angular velocity and the
hydrodynamic force with this file. Regenerate it only when a change is meant to move results (a
new model, a corrected bug), from a release build of that change, and let the review read the diff:

    python3 scripts/update_golden_cases.py build/release/src/app/settle

A case new to cases/ gets the settings of DEFAULT_SET; a case whose coarse grid the preflight
refuses needs its own entry in CASE_SET. A case that holds its body (particle.release_time)
brings it to speed over hundreds of steps (particle.hold_ramp_time), which five steps cannot do
gently: it starts free from rest instead (FREE_FROM_REST), as in tests/app/test_shipped_cases.cpp.
The runs use one thread; the test runs with two, so it also checks that the thread count does not
change the numbers.
"""
import json
import pathlib
import subprocess
import sys
import tempfile
import tomllib

ROOT = pathlib.Path(__file__).resolve().parent.parent
GOLDEN = ROOT / "tests" / "data" / "golden_cases.json"
STEPS = 5

# Every case: no files beside the time series and the summary, a row every step.
COMMON_SET = ["run.output_interval=0", "run.vtk_interval=0", "run.checkpoint_interval=0",
              "run.stop_at_terminal=false"]
# A case that holds its body (particle.release_time) runs free from rest.
FREE_FROM_REST = ["particle.release_time=0", "particle.hold_ramp_time=0", "particle.velocity=[0, 0, 0]"]
# The coarse grid that keeps each case near a tenth of a second.
DEFAULT_SET = ["numerics.cells_per_diameter=6"]
# The fixed sphere towed obliquely through its stream: in five steps it then moves its walls, uncovers
# and refills cells, which a sphere held fixed would not exercise.
CASE_SET = {"fixed_sphere_stream": ["numerics.cells_per_diameter=6", 'particle.motion="towed"',
                                    "particle.towing_velocity=[0.002,0.001,-0.03]"]}

ABOUT = ("Expected values of tests/app/test_golden_cases.cpp: each case of cases/ with common_set and its own set, "
         "run to end_time (4.5 of its dt: five steps). Displacement (m) is the last row's position minus the first's; "
         "velocity (m/s), angular_velocity (rad/s, inertial) and force (hydrodynamic, N) are the last row's. Written by "
         "scripts/update_golden_cases.py; regenerate only for a change meant to move results, and review the diff.")


def run(binary, case, out_dir, settings):
    command = [binary, "run", str(case), "-o", str(out_dir), "--threads", "1", "--quiet"]
    for setting in settings:
        command += ["--set", setting]
    finished = subprocess.run(command, capture_output=True, text=True)
    if finished.returncode != 0:
        sys.exit(f"{' '.join(command)}\nexited with {finished.returncode}:\n{finished.stderr}")
    return json.loads((out_dir / "summary.json").read_text())


def rows_of(csv_path):
    lines = csv_path.read_text().splitlines()
    header = lines[0].split(",")
    return [dict(zip(header, map(float, line.split(",")))) for line in lines[1:]]


def triple(row, names):
    return [row[name] for name in names]


def golden_entry(binary, case, scratch):
    held = tomllib.loads(case.read_text()).get("particle", {}).get("release_time", 0.0) > 0.0
    case_set = CASE_SET.get(case.stem, DEFAULT_SET) + (FREE_FROM_REST if held else [])
    settings = COMMON_SET + case_set
    probe = run(binary, case, scratch / "probe", settings + ["run.end_time=1e-12"])
    end_time = (STEPS - 0.5) * probe["dt"]
    summary = run(binary, case, scratch / "run", settings + [f"run.end_time={end_time!r}"])
    rows = rows_of(scratch / "run" / "timeseries.csv")
    first, last = rows[0], rows[-1]
    return {
        "set": case_set,
        "end_time": end_time,
        "steps": summary["steps"],
        "dt": summary["dt"],
        "tau": summary["tau"],
        "displacement": [b - a for a, b in zip(triple(first, "xyz"), triple(last, "xyz"))],
        "velocity": triple(last, ["ux", "uy", "uz"]),
        "angular_velocity": triple(last, ["wx", "wy", "wz"]),
        "force": triple(last, ["Fx", "Fy", "Fz"]),
    }


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    binary = sys.argv[1]
    cases = {}
    for case in sorted((ROOT / "cases").glob("*.toml")):
        with tempfile.TemporaryDirectory() as scratch:
            cases[case.stem] = golden_entry(binary, case, pathlib.Path(scratch))
        print(f"{case.stem}: {cases[case.stem]['steps']} steps, dt = {cases[case.stem]['dt']:.6g} s")
    document = {"about": ABOUT, "common_set": COMMON_SET, "cases": cases}
    GOLDEN.write_text(json.dumps(document, indent=2) + "\n")
    print(f"wrote {GOLDEN}")


if __name__ == "__main__":
    main()
