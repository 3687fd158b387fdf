"""
Work-precision
==============

Wall time against error for every method, on five tennis-racket flips of I = (1, 2, 3), against
a 30-digit reference (:data:`polhode.bench.REFERENCE`), with scipy's ``solve_ivp`` in the same
run. A quick version of the benchmark of ``docs/benchmarks.md``: fewer settings and repeats, on
whatever machine builds these pages.
"""

import matplotlib.pyplot as plt

import polhode as ph
from polhode.bench import work_precision

result = work_precision("flip", quick=True, repeats=3, budget=0.5)
series = {
    s.name: ([p.median for p in s.points], [p.error("omega") for p in s.points])
    for s in result.series
    if not s.name.startswith("MuJoCo")
}
fig, ax = plt.subplots(figsize=(8, 5.5), layout="constrained")
ph.plot.work_precision(series, ax=ax)
ax.set_xlabel("wall time of the call (s)")
ax.set_ylabel("relative error of omega at t = 100")
ax.legend(loc="lower right", fontsize="small")

# %%
# The exact solution costs the same at any accuracy, and the fastest way to a given error is
# always one of polhode's: see :doc:`/guide/motion` for which method to pick.
print(result.table())
