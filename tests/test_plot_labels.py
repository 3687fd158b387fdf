"""What a person reads on polhode.plot's figures (units, numbering, nothing clipped).

- One numbering: the principal axes are 1, 2, 3 with I1 <= I2 <= I3 in every legend, label
  and title; axes that are not principal are x, y, z. Which body axis is which is computed
  here from closed-form moments (a cuboid's, given moments), never read back from polhode.
- Units: every axis label says its unit (SI by default, another set through ``units``) or is
  a ratio, listed here as such.
- Nothing clipped: every drawn artist inside the figure after its default layout (the
  figure's tight bounding box within its area).
- A readable dissipation polhode: coloured by time, its ends marked.
- A body wherever ``simulate`` takes one.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.text import Text  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

import polhode as ph  # noqa: E402
from polhode import plot  # noqa: E402
from reference import cuboid  # noqa: E402

MOMENTS = [1.0, 2.0, 3.0]
OMEGA0 = [0.1, 1.0, 0.2]
TIMES = np.linspace(0.0, 20.0, 801)
SIZE = (0.1, 0.3, 0.02)  # a cuboid whose x axis is its intermediate one, y its smallest


@pytest.fixture(scope="module")
def sol():
    return ph.simulate(MOMENTS, OMEGA0, TIMES)


@pytest.fixture(scope="module")
def damped():
    damper = ph.rotors.SphericalDamper(0.2, 0.1)
    return ph.simulate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], np.linspace(0.0, 400.0, 4001),
                       rotors=[damper])


@pytest.fixture(scope="module")
def brick():
    return ph.Body.cuboid(1.0, SIZE)


@pytest.fixture(scope="module")
def brick_sol(brick):
    return ph.simulate(brick, [5.0, 0.05, 0.05], np.linspace(0.0, 4.0, 81))


def texts(figure):
    """Every non-empty text of the figure (labels, titles, legends, colour bars), drawn."""
    FigureCanvasAgg(figure).draw()
    return [t.get_text() for t in figure.findobj(Text) if t.get_visible() and t.get_text()]


def every_plot(sol, damped, brick, brick_sol):
    """(name, figure) of every plot, with default options."""
    anim = plot.animate(brick_sol, brick, frames=3)
    anim.to_jshtml()
    return [
        ("omega", plot.omega(sol).figure),
        ("drift", plot.drift(sol).figure),
        ("dissipation", plot.dissipation(damped).figure),
        ("herpolhode", plot.herpolhode(sol).figure),
        ("polhode", plot.polhode(traj=sol).figure),
        ("polhode damped", plot.polhode(traj=damped).figure),
        ("work_precision", plot.work_precision({"rk4": ([1e-3, 1e-2], [1e-6, 1e-9])}).figure),
        ("perturbation_error", plot.perturbation_error(MOMENTS, axis=0).figure),
        ("animate", anim._fig),
    ]


# ---------------------------------------------------------------------------------------------
# One numbering
# ---------------------------------------------------------------------------------------------


def legend(ax):
    return {line.get_gid(): line.get_label() for line in ax.get_lines()}


def test_omega_is_labelled_by_principal_axis_where_the_body_axes_are_principal(brick, brick_sol):
    # Moments given in ascending order: columns 0, 1, 2 are axes 1, 2, 3.
    ax = plot.omega(ph.simulate(MOMENTS, OMEGA0, TIMES))
    assert legend(ax) == {f"omega[{k}]": f"$\\omega_{{{k + 1}}}$" for k in range(3)}
    # Moments in another order: each column is the axis of its moment's rank.
    moments = [3.0, 1.0, 2.0]
    ax = plot.omega(ph.simulate(moments, OMEGA0, TIMES))
    ranks = np.argsort(np.argsort(moments)) + 1
    assert legend(ax) == {f"omega[{k}]": f"$\\omega_{{{ranks[k]}}}$" for k in range(3)}
    # The legend reads omega_1, omega_2, omega_3 in that order.
    assert [line.get_label() for line in ax.get_lines()] == [
        f"$\\omega_{{{n}}}$" for n in (1, 2, 3)
    ]
    # A Body whose own axes are principal but not ascending (the closed-form cuboid's).
    reference = np.diag(cuboid(1.0, SIZE).inertia)
    ranks = np.argsort(np.argsort(reference)) + 1
    assert list(ranks) == [2, 1, 3]
    assert legend(plot.omega(brick_sol)) == {
        f"omega[{k}]": f"$\\omega_{{{ranks[k]}}}$" for k in range(3)
    }
    assert "principal axes" in plot.omega(brick_sol).get_title()


def test_omega_in_body_axes_that_are_not_principal_is_x_y_z():
    turn = Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix()
    tensor = turn @ np.diag(MOMENTS) @ turn.T
    ax = plot.omega(ph.simulate(tensor, OMEGA0, TIMES))
    assert legend(ax) == {f"omega[{k}]": f"$\\omega_{{{c}}}$" for k, c in enumerate("xyz")}
    assert "not principal" in ax.get_title()
    # With rotors (a damper in a body given by principal moments): still principal.
    damper = ph.rotors.SphericalDamper(0.2, 0.1)
    ax = plot.omega(ph.simulate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], np.linspace(0, 50, 201),
                                rotors=[damper]))
    assert legend(ax) == {f"omega[{k}]": f"$\\omega_{{{k + 1}}}$" for k in range(3)}


def test_the_polhode_animation_and_perturbation_plots_number_axes_1_2_3(sol, brick, brick_sol):
    ax = plot.polhode(traj=sol)
    assert [ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()] == [
        f"$L_{{{k}}}$ (kg m$^2$/s)" for k in (1, 2, 3)
    ]
    anim = plot.animate(brick_sol, brick, frames=2)
    drawn = {line.get_gid(): line.get_label() for line in anim._fig.axes[0].get_lines()}
    assert [drawn[f"axis{k}"] for k in (1, 2, 3)] == [
        "$I_{1}$ axis (smallest moment)",
        "$I_{2}$ axis (intermediate moment)",
        "$I_{3}$ axis (largest moment)",
    ]
    anim.to_jshtml()
    for axis in range(3):
        title = plot.perturbation_error(MOMENTS, axis=axis, eps=[1e-3, 1e-2]).get_title()
        assert f"near axis {axis + 1} ({('smallest', 'intermediate', 'largest')[axis]}" in title
    names = [t.name or "" for t in plot.scene(brick_sol, brick, frames=2).data]
    assert {"I1 axis", "I2 axis", "I3 axis"} <= {n[:7] for n in names}


def test_no_text_numbers_an_axis_0_1_2(sol, damped, brick, brick_sol):
    """Scanned: no "(0)", "axis 0", subscript 0 or "omega0"-style number anywhere a person
    reads; every axis number read is 1, 2 or 3."""
    for name, figure in every_plot(sol, damped, brick, brick_sol):
        for text in texts(figure):
            assert not re.search(r"\(\s*[0-2]\s*\)", text), (name, text)
            for number in re.findall(r"(?:axis|axes) (\d)|[IL]_\{(\d)\}|\\omega_\{(\d)\}", text):
                assert "".join(number) in ("1", "2", "3"), (name, text)


# ---------------------------------------------------------------------------------------------
# Units
# ---------------------------------------------------------------------------------------------

#: The labels that are ratios (no unit): relative errors and ratios to a value at t0, eps.
RATIOS = ("relative drift", "relative to its value", "relative error", "$\\epsilon$")


def unit_of(label):
    found = re.search(r"\(([^()]*)\)$", label)
    return None if found is None else found.group(1)


def check_units(figure, name, expected):
    for ax in figure.axes:
        labels = [ax.get_xlabel(), ax.get_ylabel()]
        if hasattr(ax, "get_zlabel"):
            labels.append(ax.get_zlabel())
        for label in labels:
            if not label or any(label.startswith(r) for r in RATIOS):
                continue
            assert unit_of(label) in expected, (name, label)


@pytest.mark.parametrize("units", [None, {"time": "min", "length": "mm", "mass": "g"}])
def test_every_axis_label_says_its_unit(sol, damped, brick, brick_sol, units):
    time, length, mass = ("s", "m", "kg") if units is None else ("min", "mm", "g")
    expected = {time, f"rad/{time}", f"{mass} {length}$^2$/{time}"}
    figures = {
        "omega": plot.omega(sol, units=units),
        "drift": plot.drift(sol, units=units),
        "dissipation": plot.dissipation(damped, units=units),
        "herpolhode": plot.herpolhode(sol, units=units),
        "polhode": plot.polhode(traj=sol, units=units),
        "polhode damped": plot.polhode(traj=damped, units=units),
        "work_precision": plot.work_precision({"a": ([1e-3], [1e-6])}, units=units),
        "perturbation_error": plot.perturbation_error(MOMENTS, eps=[1e-3], units=units),
    }
    for name, ax in figures.items():
        check_units(ax.figure, name, expected)
        assert ax.get_xlabel(), name
    assert figures["omega"].get_xlabel() == f"$t$ ({time})"
    assert figures["omega"].get_ylabel() == f"$\\omega$ (rad/{time})"
    assert figures["polhode"].get_xlabel() == f"$L_{{1}}$ ({mass} {length}$^2$/{time})"
    colorbar = figures["polhode damped"].figure.axes[-1]
    assert colorbar.get_ylabel() == f"$t$ ({time})"
    assert figures["herpolhode"].get_xlabel().endswith(f"(rad/{time})")
    anim = plot.animate(brick_sol, brick, frames=2, units=units)
    anim.to_jshtml()
    assert anim._fig.axes[0].get_title().endswith(f" {time}")
    if units is not None:
        names = " | ".join(t.name or "" for t in plot.scene(brick_sol, brick, frames=2,
                                                                units=units).data)
        assert "g mm^2/min" in names and "rad/min" in names


def test_the_units_of_the_old_labels_were_missing():
    """The labels this replaces: "t", "omega (body axes)", "L, smallest axis (0)"."""
    ax = plot.omega(ph.simulate(MOMENTS, OMEGA0, [0.0, 1.0]))
    assert ax.get_xlabel() != "t" and unit_of(ax.get_xlabel()) == "s"


# ---------------------------------------------------------------------------------------------
# Nothing clipped
# ---------------------------------------------------------------------------------------------


def test_nothing_is_clipped(sol, damped, brick, brick_sol):
    for name, figure in every_plot(sol, damped, brick, brick_sol):
        canvas = FigureCanvasAgg(figure)
        canvas.draw()
        tight = figure.get_tightbbox(canvas.get_renderer())  # inches
        width, height = figure.get_size_inches()
        slack = 0.5 / figure.dpi  # half a pixel
        assert tight.x0 >= -slack and tight.y0 >= -slack, (name, tight.extents)
        assert tight.x1 <= width + slack and tight.y1 <= height + slack, (name, tight.extents)


# ---------------------------------------------------------------------------------------------
# The dissipation polhode
# ---------------------------------------------------------------------------------------------


def test_the_dissipation_polhode_is_coloured_by_time_with_its_ends_marked(damped):
    ax = plot.polhode(traj=damped)
    (segments,) = [c for c in ax.collections if c.get_gid() == "trajectory:time"]
    t = damped.t
    np.testing.assert_array_equal(segments.get_array(), (t[:-1] + t[1:]) / 2)
    assert segments.norm.vmin == t[0] and segments.norm.vmax == t[-1]
    # principal moments given ascending: L in the principal axes is the body's own
    momentum = damped.angular_momentum_body
    start = [line for line in ax.get_lines() if line.get_gid() == "start"][0]
    end = [line for line in ax.get_lines() if line.get_gid() == "end"][0]
    np.testing.assert_array_equal(np.ravel(start.get_data_3d()), momentum[0])
    np.testing.assert_array_equal(np.ravel(end.get_data_3d()), momentum[-1])
    # from axis 1 (the spin) to axis 3 (the damper's end state)
    ell = np.linalg.norm(momentum[0])
    assert abs(momentum[0][0]) > 0.99 * ell and abs(momentum[-1][2]) > 0.99 * ell
    # no energy levels to cross: the separatrix alone, and the colour bar says the time
    assert not [line for line in ax.get_lines() if str(line.get_gid()).startswith("polhode:")]
    assert ax.figure.axes[-1].get_ylabel() == "$t$ (s)"
    # A motion that keeps its energy is one red line over the levels, as before.
    free = plot.polhode(traj=ph.simulate(MOMENTS, OMEGA0, TIMES))
    assert not [c for c in free.collections if c.get_gid() == "trajectory:time"]
    assert len([x for x in free.get_lines() if str(x.get_gid()).startswith("polhode:")]) == 16
    # and either can be asked for
    assert plot.polhode(traj=damped, color_by_time=False).collections is not None
    assert not [c for c in plot.polhode(traj=damped, color_by_time=False).collections
                if c.get_gid() == "trajectory:time"]


# ---------------------------------------------------------------------------------------------
# A body wherever simulate takes one
# ---------------------------------------------------------------------------------------------


def test_polhode_takes_the_body_the_trajectory_was_simulated_with(brick, brick_sol):
    reference = cuboid(1.0, SIZE).inertia  # closed form, diagonal
    moments = np.sort(np.diag(reference))
    order = np.argsort(np.diag(reference))
    for body in (brick, reference, np.diag(reference)):
        ax = plot.polhode(body, traj=brick_sol)
        (line,) = [x for x in ax.get_lines() if x.get_gid() == "trajectory"]
        drawn = np.column_stack(line.get_data_3d())
        # the body's L, its columns in the order of the ascending moments (signs aside)
        np.testing.assert_allclose(np.abs(drawn), np.abs(brick_sol.angular_momentum_body[:, order]),
                                   rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(np.sum(drawn**2 / moments, axis=1), 2 * brick_sol.energy,
                                   rtol=1e-12)
    # another body's moments, or the same moments in other axes: refused, naming `body`
    for other in (ph.Body.cuboid(1.0, (0.1, 0.3, 0.03)), ph.Body.cuboid(1.0, (0.3, 0.1, 0.02))):
        with pytest.raises(ph.ArgumentError) as error:
            plot.polhode(other, traj=brick_sol)
        assert error.value.argument == "body"


def test_perturbation_error_takes_a_body(brick):
    moments = np.sort(np.diag(cuboid(1.0, SIZE).inertia))
    from_body = plot.perturbation_errors(brick, 0, [1e-3, 1e-2])
    from_moments = plot.perturbation_errors(moments, 0, [1e-3, 1e-2])
    for order in (1, 2):
        # the closed-form moments and the Body's differ in their last bits: the errors (of
        # omega, about 1 rad/s) then by a few eps of omega
        np.testing.assert_allclose(from_body[order], from_moments[order], rtol=1e-9, atol=1e-15)
    ax = plot.perturbation_error(brick, axis=0, eps=[1e-3, 1e-2])
    assert [x.get_gid() for x in ax.get_lines()][:1] == ["perturbation_error:1"]


@pytest.mark.parametrize("given", ["moments", "tensor", "none"])
def test_animate_takes_moments_a_tensor_or_nothing(brick_sol, given):
    """Drawn as the uniform box of those moments: for a cuboid, a box of the cuboid's own
    proportions (its sides a_k^2 ~ I_i + I_j - I_k = m a_k^2 / 6), along its own axes."""
    reference = cuboid(1.0, SIZE).inertia  # closed form
    body = {"moments": np.diag(reference), "tensor": reference, "none": None}[given]
    anim = plot.animate(brick_sol, body, frames=1)
    surface = next(c for c in anim._fig.axes[0].collections if c.get_gid() == "body")
    anim.to_jshtml()
    # the drawn vertices of frame 0 (matplotlib keeps the 3-D polygons in _faces)
    faces = np.ma.asarray(surface._faces)
    corners = np.asarray(faces.reshape(-1, 3)[~np.ma.getmaskarray(faces).reshape(-1, 3)
                                              .any(axis=1)])
    r0 = Rotation.from_quat(brick_sol.quaternion[0]).as_matrix()
    extents = np.ptp(corners @ r0, axis=0)  # back in body axes
    np.testing.assert_allclose(extents / extents[1], np.array(SIZE) / SIZE[1], rtol=1e-9)
