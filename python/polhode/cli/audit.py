"""``polhode audit``: the audit table of a URDF or MJCF file (polhode.io.audit)."""

from __future__ import annotations

import argparse
import sys

import polhode as ph


def run(args: argparse.Namespace) -> int:
    """The audit table of a URDF or MJCF file; 1 if any link has an error, 2 for a bad file."""
    from polhode.io import audit

    try:
        findings = audit(args.file, rtol=args.rtol, geometry=args.geometry, density=args.density)
    except (ph.PolhodeError, OSError, ImportError) as error:
        print(f"polhode audit: error: {error}", file=sys.stderr)
        return 2
    width = max([4] + [len(f.link) for f in findings])
    print(f"{'link':{width}s}  {'severity':8s}  {'check':19s}  message")
    for f in findings:
        print(f"{f.link:{width}s}  {f.severity:8s}  {f.check:19s}  {f.message}")
    corrected = [f for f in findings if f.corrected and f.severity in ("error", "warning")]
    shown: set[str] = set()
    for f in corrected:
        if f.link in shown:
            continue
        shown.add(f.link)
        print(f"\ncorrected inertial of {f.link} (from its geometry, at its declared mass):")
        print("\n".join("  " + line for line in (f.corrected or "").splitlines()))
    counts = {s: sum(1 for f in findings if f.severity == s) for s in ("error", "warning")}
    links = len({f.link for f in findings})
    print(f"\n{links} links: {counts['error']} errors, {counts['warning']} warnings")
    return 1 if counts["error"] else 0
