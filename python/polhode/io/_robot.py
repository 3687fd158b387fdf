"""What a robot reader returns: the bodies by name, and what it did not return as a body."""

from __future__ import annotations

from typing import Any

from polhode.bodies import Body

__all__ = ["RobotBodies"]


class RobotBodies(dict[str, Body]):
    """The bodies of a robot description by name, each in its own frame: a ``dict``
    ``{name: Body}`` in the file's order, with what is not in it as a body.

    Attributes
    ----------
    path : str
        The file.
    frames : list of str
        The bodies of no mass, in the file's order: frames (a static body MuJoCo compiles
        with mass 0, a moving body whose mass is in a body fixed to it). A :class:`Body` has
        a mass, so these are named here, not returned.
    left_out : dict of str to str
        The bodies left out because the simulator refuses them, each with the reason (the
        reader's :class:`polhode.RobotFileWarning` names them too).
    merged : dict of str to str
        With ``merge_fixed``: each body merged into another, and the body it went into
        (``"world"`` when its mass went to the ground, as MuJoCo drops it).
    notes : dict of str to list of str
        What the simulator does to a body that a reader of the file should know (a geom's
        mass dropped, a negative mass raised to 0, a mesh that is not closed).

    Examples
    --------
    >>> from polhode.io import RobotBodies
    >>> bodies = RobotBodies(path="robot.xml", frames=["world_mount"])
    >>> dict(bodies), bodies.frames
    ({}, ['world_mount'])
    """

    def __init__(
        self,
        bodies: Any = (),
        *,
        path: str = "",
        frames: Any = (),
        left_out: Any = None,
        merged: Any = None,
        notes: Any = None,
    ):
        super().__init__(bodies)
        self.path = path
        self.frames: list[str] = list(frames)
        self.left_out: dict[str, str] = dict(left_out or {})
        self.merged: dict[str, str] = dict(merged or {})
        self.notes: dict[str, list[str]] = {k: list(v) for k, v in (notes or {}).items()}

    def __repr__(self) -> str:
        extra = ""
        if self.frames:
            extra += f", frames={self.frames!r}"
        if self.left_out:
            extra += f", left_out={self.left_out!r}"
        if self.merged:
            extra += f", merged={self.merged!r}"
        return f"RobotBodies({dict.__repr__(self)}{extra})"
