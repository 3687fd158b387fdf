"""polhode: the rotation of rigid bodies, with a Rust core.

Mass properties and principal axes (:class:`Body`, :func:`principal`); see the README.
"""

from polhode._core import InertiaError, PolhodeError
from polhode.bodies import Body
from polhode.principal_axes import Principal, principal

__all__ = ["Body", "InertiaError", "PolhodeError", "Principal", "principal"]
__version__ = "0.1.0"
