"""The errors modalfe raises: one base class, one subclass per stage.

Every message names the field, region or parameter at fault in one line.
"""


class ModalfeError(Exception):
    """Base of every error modalfe raises on purpose."""


class SceneError(ModalfeError, ValueError):
    """A scene parameter is missing, of the wrong type or out of range."""


class MeshError(ModalfeError):
    """Geometry could not be built or meshed."""


class SolverError(ModalfeError):
    """A solve failed: singular shift, no convergence, no modes in the band, NaN."""


class ContactError(ModalfeError, ValueError):
    """A contact or friction simulator parameter is out of range, or its solve failed."""
