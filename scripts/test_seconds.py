#!/usr/bin/env python3
"""Which tests are too slow for the sanitizer stage, by their measured seconds (docs/fuzzing.md).

tests/sanitizer_test_seconds.txt records, for each test, how long it took in the sanitizer build
(the debug preset). A test recorded at HEAVY seconds or more (SETTLE_HEAVY_SECONDS, default 20) is
heavy: the sanitizer stage leaves it out; the release stage runs every test. No hand list: a test
becomes heavy when a run measures it so.

  test_seconds.py heavy-regex             the ctest -E pattern of the heavy tests
  test_seconds.py verify BUILD            fail if the record names a test BUILD does not have
  test_seconds.py check JUNIT             after a run: the slowest tests; fail if a test it ran took
                                          twice HEAVY or more (it must be recorded: `record`)
  test_seconds.py record JUNIT            write the run's seconds into the record

JUNIT is the file of `ctest --output-junit`. A run on a machine busy with other work takes longer
throughout: `check` and `record` divide the run's seconds by its load factor, the median ratio of
measured to recorded seconds over the tests recorded at 1 s or more (1 when fewer than 20 such
tests ran), so that the record and the limit keep the scale of an idle machine.
"""
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

RECORD = Path(__file__).resolve().parent.parent / "tests" / "sanitizer_test_seconds.txt"
HEADER = """\
# Seconds each test takes in the sanitizer build (debug preset, two tests at a time on the 2-core
# development machine), written by `python3 scripts/test_seconds.py record JUNIT`. A test at
# SETTLE_HEAVY_SECONDS (default 20) or more is left out of the sanitizer stage (docs/fuzzing.md).
# `measured`: from a sanitizer run; `estimated`: never run under the sanitizers, its release
# seconds times 12 (the median ratio of the two builds over the tests run in both).
"""
LINE = re.compile(r"^\s*([0-9.]+)\s+(measured|estimated)\s+(\S+)\s*$")


def heavy_seconds():
    return float(os.environ.get("SETTLE_HEAVY_SECONDS", "20"))


def read_record():
    record = {}
    for line in RECORD.read_text().splitlines():
        match = LINE.match(line)
        if match:
            record[match.group(3)] = (float(match.group(1)), match.group(2))
        elif line.strip() and not line.lstrip().startswith("#"):
            sys.exit(f"test_seconds: {RECORD}: unreadable line '{line}' (want: SECONDS measured|estimated NAME)")
    return record


def write_record(record):
    rows = sorted(record.items(), key=lambda item: (-item[1][0], item[0]))
    body = "".join(f"{seconds:8.2f} {kind:9s} {name}\n" for name, (seconds, kind) in rows)
    RECORD.write_text(HEADER + body)


def heavy_names(record):
    return sorted(name for name, (seconds, _) in record.items() if seconds >= heavy_seconds())


def junit_seconds(path):
    """Test name -> seconds of one ctest run; skipped tests are left out."""
    seconds = {}
    for case in ET.parse(path).getroot().iter("testcase"):
        if case.find("skipped") is None:
            seconds[case.get("name")] = float(case.get("time", "0"))
    return seconds


def load_factor(seconds, record):
    """Median of measured over recorded seconds, over the tests recorded at 1 s or more."""
    ratios = sorted(seconds[name] / record[name][0] for name in seconds if name in record and record[name][0] >= 1.0)
    if len(ratios) < 20:
        return 1.0
    middle = len(ratios) // 2
    return ratios[middle] if len(ratios) % 2 else 0.5 * (ratios[middle - 1] + ratios[middle])


def normalised_seconds(path):
    """The run's seconds on the record's scale, and the load factor they were divided by."""
    seconds = junit_seconds(path)
    factor = load_factor(seconds, read_record())
    return {name: value / factor for name, value in seconds.items()}, factor


def cmd_heavy_regex(_args):
    names = heavy_names(read_record())
    # ctest matches -E anywhere in the name: anchor each name, escape its dots and slashes.
    print("^(" + "|".join(re.escape(name) for name in names) + ")$" if names else "^$")


def cmd_verify(args):
    listing = subprocess.run(["ctest", "--test-dir", args[0], "-N"], check=True, capture_output=True, text=True).stdout
    present = set(re.findall(r"Test\s+#\d+: (\S+)", listing))
    stale = sorted(set(read_record()) - present)
    if stale:
        print("test_seconds: tests/sanitizer_test_seconds.txt names tests this build does not have "
              "(renamed or removed? a renamed heavy test would come back into the sanitizer stage):", file=sys.stderr)
        for name in stale:
            print(f"  {name}", file=sys.stderr)
        sys.exit(1)


def cmd_check(args):
    seconds, factor = normalised_seconds(args[0])
    print(f"test_seconds: this run's load factor {factor:.2f} (seconds below are divided by it)")
    print("test_seconds: the slowest tests of this run:")
    for name, value in sorted(seconds.items(), key=lambda item: -item[1])[:15]:
        print(f"  {value:7.1f} s  {name}")
    limit = heavy_seconds()
    slow = [(name, value) for name, value in seconds.items() if value >= limit]
    for name, value in slow:
        print(f"test_seconds: {name} took {value:.1f} s (heavy from {limit:g} s)", file=sys.stderr)
    too_slow = [name for name, value in slow if value >= 2 * limit]
    if too_slow:
        print(f"test_seconds: {len(too_slow)} test(s) took {2 * limit:g} s or more; record this run so that they "
              f"leave the stage: python3 scripts/test_seconds.py record {args[0]}", file=sys.stderr)
        sys.exit(1)


def cmd_record(args):
    record = read_record()
    seconds, factor = normalised_seconds(args[0])
    for name, value in seconds.items():
        record[name] = (value, "measured")
    write_record(record)
    print(f"test_seconds: {RECORD}: load factor {factor:.2f}; {len(heavy_names(record))} heavy test(s)")


COMMANDS = {"heavy-regex": (cmd_heavy_regex, 0), "verify": (cmd_verify, 1), "check": (cmd_check, 1),
            "record": (cmd_record, 1)}

if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in COMMANDS or len(sys.argv) - 2 != COMMANDS[sys.argv[1]][1]:
        sys.exit(__doc__)
    COMMANDS[sys.argv[1]][0](sys.argv[2:])
