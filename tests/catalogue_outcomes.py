"""The outcome of each row of the catalogue (tests/test_catalogue.py) on the polhode installed:
ok, minor or unacceptable, with the totals; for a note that compares versions of polhode.

    python tests/catalogue_outcomes.py [--from-probe] [--list]

- ok: the row passes (its typed error naming the argument, or its right value);
- minor: a typed error, but of another class or naming another argument (or none), or a plain
  ValueError; also a value row refused with a typed error;
- unacceptable: an exception from inside (AttributeError, IndexError, OverflowError, a panic,
  a warning raised as an error...), bad input accepted without a word, a wrong or non-finite
  value, or a row still running after a minute.

Each row runs in this process with warnings as errors (as pytest runs the suite) and a 60 s
alarm. ``--from-probe`` counts the rows from ``PROBE_FIRST_ROW`` on (the faults an adversarial
probe found and a wider probe of the public API); ``--list`` prints every row that is not ok.
"""

from __future__ import annotations

import argparse
import collections
import os
import signal
import sys
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import polhode as ph  # noqa: E402

#: Exceptions a user's mistake may be answered with: the typed ones (minor at worst).
TYPED = (ph.PolhodeError, TypeError, ValueError, FileNotFoundError)


class Hang(BaseException):
    pass


def _alarm(signum, frame):
    raise Hang


def outcome(row) -> tuple[str, str]:
    """(ok | minor | unacceptable, what happened)."""
    import test_catalogue as cat

    expect = row.expect
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(60)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            try:
                result = row.call()
            except Hang:
                return "unacceptable", "still running after 60 s"
            except BaseException as error:  # what it raised is the outcome
                return _raised(cat, expect, error)
            if isinstance(expect, cat.Raises):
                return "unacceptable", f"accepted, returned {type(result).__name__}"
            if isinstance(expect, cat.Exit):
                return _exit(expect, result)
            try:
                cat.finite_everywhere(result)
                expect.check(result)
            except Hang:
                return "unacceptable", "the check still running after 60 s"
            except AssertionError as error:
                return "unacceptable", f"wrong value: {str(error).splitlines()[0][:100]}"
            except BaseException as error:
                return "unacceptable", f"{type(error).__name__} checking the value: {error}"
            return "ok", ""
    finally:
        signal.alarm(0)


def _raised(cat, expect, error) -> tuple[str, str]:
    what = f"{type(error).__name__}: {str(error).splitlines()[0][:100] if str(error) else ''}"
    if not isinstance(expect, cat.Raises):
        return ("minor" if isinstance(error, TYPED) else "unacceptable"), "refused: " + what

    if type(error) is not expect.error and not isinstance(error, TYPED):
        return "unacceptable", what
    if type(error) is not expect.error:
        if not isinstance(error, ph.PolhodeError | FileNotFoundError) and "`" not in str(error):
            # A TypeError or ValueError of Python or numpy from inside, naming nothing of ours.
            return "unacceptable", what
        return "minor", f"expected {expect.error.__name__}, got " + what
    message = str(error)
    if isinstance(error, ph.PolhodeError):
        if error.argument != expect.argument or error.body != expect.body:
            return "minor", f"names {error.argument!r} (body {error.body}), not " \
                            f"{expect.argument!r}: " + what
    elif expect.argument is not None and f"`{expect.argument}`" not in message:
        return "minor", f"does not name `{expect.argument}`: " + what
    if expect.fragment is not None and expect.fragment not in message:
        return "minor", f"without {expect.fragment!r}: " + what
    if "Traceback" in message or len(message) >= 600:
        return "minor", "message too long or with a traceback"
    return "ok", ""


def _exit(expect, result) -> tuple[str, str]:
    code, out, errors = result
    if code != expect.code:
        return "unacceptable", f"exit {code}, expected {expect.code}"
    try:
        if expect.check is not None:
            expect.check(out, errors)
    except AssertionError as error:
        return "unacceptable", f"wrong output: {error}"
    return "ok", ""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--from-probe", action="store_true")
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    import test_catalogue as cat

    rows = cat.CATALOGUE[cat.PROBE_FIRST_ROW:] if args.from_probe else cat.CATALOGUE
    totals: collections.Counter = collections.Counter()
    by_area: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    listed = []
    for row in rows:
        kind, what = outcome(row)
        totals[kind] += 1
        by_area[row.area][kind] += 1
        if kind != "ok":
            listed.append((kind, row.id, what))
    print(f"polhode from {os.path.dirname(ph.__file__)}: {len(rows)} rows")
    print(f"{'area':24s} {'ok':>5s} {'minor':>6s} {'unacc.':>7s}")
    for area, count in by_area.items():
        print(f"{area:24s} {count['ok']:5d} {count['minor']:6d} {count['unacceptable']:7d}")
    print(f"{'total':24s} {totals['ok']:5d} {totals['minor']:6d} {totals['unacceptable']:7d}")
    if args.list:
        for kind, id_, what in sorted(listed):
            print(f"{kind:13s} {id_}: {what}")


if __name__ == "__main__":
    main()
