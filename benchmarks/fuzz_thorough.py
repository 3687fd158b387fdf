"""The hypothesis properties at a thorough profile, outside CI: many more examples than the
suite's 100 (local) or 400 (CI), for the note of a release.

    python -m benchmarks.fuzz_thorough [--examples N] [--only PATTERN ...] [--all]

By default the four physical properties: the exact solution keeps T, |L| and L in space (and
the splitting |L| and L in space), principal() against numpy's eigh, the parallel-axis
relation, and composition in any order (tests/test_properties.py); ``--all`` adds every
property of tests/test_properties.py and the whole-API fuzz of tests/test_fuzz.py (any input: a
finite answer or a typed error). Each runs ``--examples`` examples (default 20000) through
pytest with the ``polhode-fuzz`` profile (tests/conftest.py). The script prints, per property,
the examples that passed, failed and were invalid (hypothesis' statistics), the CPU time it
took, and the outcome; the exit status is pytest's.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import time

#: The four properties (pytest -k expressions on tests/test_properties.py).
PROPERTIES = {
    "exact conservation": "test_the_exact_solution_keeps_the_invariants",
    "principal vs eigh": "test_principal_matches_numpy_eigh or "
    "test_principal_reconstructs_the_tensor",
    "parallel axis": "test_parallel_axis_relation or test_inertia_about_point_matches_exact",
    "composition order": "test_composition_associative_and_commutative or "
    "test_composition_matches_reference",
}

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(files: list[str], expression: str | None, examples: int) -> tuple[int, str, float]:
    env = dict(os.environ, HYPOTHESIS_PROFILE="polhode-fuzz", POLHODE_FUZZ_EXAMPLES=str(examples))
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:randomly",
               "--hypothesis-show-statistics", *files]
    if expression:
        command += ["-k", expression]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(command, cwd=os.path.join(ROOT, "tests"), env=env,
                          capture_output=True, text=True, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return done.returncode, done.stdout + done.stderr, cpu


def statistics(output: str) -> list[tuple[str, int, int, int]]:
    """(test, passing, failing, invalid) from hypothesis' statistics, summed over phases."""
    out = []
    for block in re.split(r"\n(?=\S+::\S+:\n)", output):
        name = re.match(r"(\S+::\S+):\n", block)
        if not name:
            continue
        counts = [0, 0, 0]
        pattern = r"(\d+) passing, (\d+) failing, and (\d+) invalid"
        for found in re.finditer(pattern, block):
            for k in range(3):
                counts[k] += int(found.group(k + 1))
        out.append((name.group(1).split("::")[-1], *counts))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=20000)
    parser.add_argument("--only", nargs="*", default=None, help="names of PROPERTIES")
    parser.add_argument("--all", action="store_true", help="every property and the API fuzz")
    args = parser.parse_args()
    jobs: list[tuple[str, list[str], str | None]] = []
    for name, expression in PROPERTIES.items():
        if args.only is None or name in args.only:
            jobs.append((name, ["test_properties.py"], expression))
    if args.all:
        chosen = " or ".join(PROPERTIES.values())
        jobs.append(("other properties", ["test_properties.py"], f"not ({chosen})"))
        jobs.append(("API fuzz", ["test_fuzz.py"], None))
    status = 0
    started = time.perf_counter()
    for name, files, expression in jobs:
        code, output, cpu = run(files, expression, args.examples)
        status = status or code
        summary = output.strip().splitlines()[-1] if output.strip() else ""
        print(f"## {name}: {summary} ({cpu:.0f} s CPU)", flush=True)
        for test, passing, failing, invalid in statistics(output):
            print(f"   {test}: {passing} passing, {failing} failing, {invalid} invalid")
        if code:
            print(output[-6000:])
    print(f"# {time.perf_counter() - started:.0f} s wall, {args.examples} examples per property")
    sys.exit(status)


if __name__ == "__main__":
    main()
