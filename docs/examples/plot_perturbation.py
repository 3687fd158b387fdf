"""
The perturbation expansion
==========================

Near a principal axis, :func:`polhode.perturbation` expands the motion in the size eps of the
perturbation. Its error against the exact solution falls like eps^(n+1) at order n.
"""

import matplotlib.pyplot as plt

import polhode as ph

moments = [1.0, 2.0, 3.0]
fig, (smallest, largest) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
ph.plot.perturbation_error(moments, axis=0, ax=smallest)
ph.plot.perturbation_error(moments, axis=2, ax=largest)
