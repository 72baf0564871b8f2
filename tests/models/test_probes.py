"""Point probes on hexahedra with a sliver element (modalfe/models/solid.py ``_probing``): skfem's inverse map
stalls at round-off there; the probes must still locate every point and read a linear field exactly."""

import numpy as np
import pytest
from skfem import Basis, ElementHex1, MeshHex1

from modalfe.models.solid import _probing


def test_probes_in_a_sliver_element_read_a_linear_field_exactly():
    """An 11.7 um wide last column of elements at x = 61.6 mm, as a tuned Cu-Be plate's mesh had (a part's edge
    11.7 um from the plate's end): skfem's probes raise ("Newton iteration didn't converge up to TOL=1e-12": the
    reference coordinates stall at eps x / h ~ 1e-12); ours give a trilinear element's exact values of a linear
    field, to round-off (1e-12 of the field's range)."""
    x = np.r_[np.linspace(0, 0.0616117, 40), 0.06162348]
    mesh = MeshHex1.init_tensor(x, np.linspace(0, 0.019, 8), np.array([0, 1e-3, 1.6944e-3]))
    basis = Basis(mesh, ElementHex1(), intorder=1)
    rng = np.random.default_rng(1)
    points = np.vstack([rng.uniform(0.06161174, 0.06162348, 600), rng.uniform(0, 0.019, 600),
                        rng.uniform(0, 1.69e-3, 600)])
    with pytest.raises(Exception, match="Newton iteration didn't converge"):
        basis.probes(points)  # skfem's own tolerance (if this passes, skfem changed and _probing may go)
    field = 1.0 + 20 * mesh.p[0] - 30 * mesh.p[1] + 400 * mesh.p[2]
    read = _probing(basis).probes(points) @ field
    assert read == pytest.approx(1.0 + 20 * points[0] - 30 * points[1] + 400 * points[2], abs=1e-12)
