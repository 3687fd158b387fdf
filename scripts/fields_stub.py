"""Writes python/polhode/_fields.pyi, the trajectories' typed fields, from the core's table of
quantities (polhode._core.QUANTITIES) of the polhode that Python imports: run it after adding
or changing a quantity in rust/polhode/src/simulation/quantity.rs, with the core built
(tests/test_quantities.py fails while the two differ).

    python scripts/fields_stub.py
"""

from pathlib import Path

from polhode._quantities import stub

path = Path(__file__).resolve().parent.parent / "python" / "polhode" / "_fields.pyi"
path.write_text(stub(), encoding="utf-8")
print(f"written: {path}")
