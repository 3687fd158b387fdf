"""What the robot readers return: the links (URDF) or bodies (MJCF) read as bodies, and what
was not read as a body."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from polhode.bodies import Body

__all__ = ["Links"]


class Links(dict[str, Body]):
    """What :func:`polhode.io.read_urdf` and :func:`polhode.io.read_mjcf` return:
    ``{name: Body}``, each in its link's (body's) own frame, a dict in the file's order, with
    what was not read as a body.

    Attributes
    ----------
    path : str
        The file.
    frames : dict[str, str]
        The links of no mass that a simulator takes as frames, ``{name: why}``: a static
        body MuJoCo compiles with mass 0, a moving one whose mass is on the bodies fixed to
        it. A :class:`polhode.Body` has a mass, so these are named here, not returned.
    left_out : dict[str, str]
        The links left out because the simulator refuses them, and why (the field and the
        check that failed). The :class:`polhode.errors.RobotFileWarning` of the call names the
        same links.
    merged : dict[str, str]
        With ``merge_fixed``: ``{name: the body it was fused into}`` (``"world"`` for an MJCF
        body whose mass MuJoCo drops with the world's).
    notes : dict[str, list[str]]
        What the simulator does to a link that a reader of the file should know: a geom's
        mass dropped, a negative mass raised to 0, a mesh that is not closed.

    Examples
    --------
    >>> from polhode.io import Links
    >>> links = Links(path="robot.xml", frames={"mount": "mass 0: a static body"})
    >>> dict(links), links.frames, links.left_out
    ({}, {'mount': 'mass 0: a static body'}, {})
    """

    path: str
    frames: dict[str, str]
    left_out: dict[str, str]
    merged: dict[str, str]
    notes: dict[str, list[str]]

    def __init__(
        self,
        bodies: Mapping[str, Body] | Iterable[tuple[str, Body]] = (),
        *,
        path: str = "",
        frames: Mapping[str, str] | None = None,
        left_out: Mapping[str, str] | None = None,
        merged: Mapping[str, str] | None = None,
        notes: Mapping[str, Iterable[str]] | None = None,
    ):
        super().__init__(bodies)
        self.path = path
        self.frames = dict(frames or {})
        self.left_out = dict(left_out or {})
        self.merged = dict(merged or {})
        self.notes = {k: list(v) for k, v in (notes or {}).items()}
