"""The axisymmetric model's body revolved round its axis (``Revolved``, a part of ``AxisymmetricModel``): the
meridian mesh's points at ``REVOLVED_ANGLES`` angles for the disc labeller, and its elements cut finer and swept
into hexahedra with their displacement, potential, strain, stress and field for ``show`` and ``export``."""

from __future__ import annotations

import functools

import numpy as np
import scipy.sparse as sp

from modalfe.models.meridian_forms import COS_ROWS, SIN_ROWS, coupled_tensor, strain_maps, tensor_of, turned, voigt_of

REVOLVED_ANGLES = 64  # angles the meridian is revolved at for the disc labeller (harmonics up to 10 resolved)
# each meridian element cut in DISPLAY_SPLIT x DISPLAY_SPLIT cells for the revolved body drawn and exported: an
# element (order 2-4) varies through its span, which one cell would average away (a disc one element thick bends
# through it: a flexural mode's cell-mean stress through the whole thickness is zero)
DISPLAY_SPLIT = 3


class Revolved:
    """Methods of ``AxisymmetricModel`` on its revolved body (they read its mesh, basis, section, harmonics,
    regions and its ``_revolved`` / ``_potential_revolved`` probes)."""

    @functools.cached_property
    def _label_probes(self) -> tuple[np.ndarray, sp.csr_matrix]:
        return self._revolved_vertices(np.arange(self.mesh.p.shape[1]), axis_once=False)

    def _revolved_vertices(self, vertices: np.ndarray, *, axis_once: bool) -> tuple[np.ndarray, sp.csr_matrix]:
        """(points (3, m) [m], (3 m, ndofs) displacement probes) of the meridian mesh's ``vertices`` revolved
        (``_revolved_points``; a Lagrange vertex's value is its DOF)."""
        P = sp.csr_matrix((np.ones(len(vertices)), (np.arange(len(vertices)), self.basis.nodal_dofs[0][vertices])),
                          shape=(len(vertices), self.basis.N))
        points, which, angle = self._revolved_points(self.mesh.p[:, vertices], axis_once=axis_once)
        return points, self._revolved(P[which], angle)

    def _revolved_points(self, rz: np.ndarray, *, axis_once: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(points (3, m) [m], meridian point of each (m,), its angle (m,) [rad]) of the meridian points ``rz``
        (2, n) [m] revolved at ``REVOLVED_ANGLES`` angles (those of one meridian point consecutive); those on the axis
        (one point per z, not a ring) once, after the others, where ``axis_once``, else left out."""
        r, z = rz
        on_axis = r <= 1e-12 * self.section.element_size
        theta = np.linspace(0, 2 * np.pi, REVOLVED_ANGLES, endpoint=False)
        off = np.flatnonzero(~on_axis)
        which = np.concatenate([np.repeat(off, len(theta)), np.flatnonzero(on_axis) if axis_once else []]).astype(int)
        angle = np.concatenate([np.tile(theta, len(off)), np.zeros(len(which) - len(off) * len(theta))])
        e1, e3 = self.section.radial, self.section.axis
        e2 = np.cross(e3, e1)
        points = (self.section.origin[:, None] + np.outer(e1, r[which] * np.cos(angle))
                  + np.outer(e2, r[which] * np.sin(angle)) + np.outer(e3, z[which]))
        return points, which, angle

    @functools.cached_property
    def _display(self) -> tuple[np.ndarray, np.ndarray, sp.csr_matrix]:
        """(points (2, m) [m] of the meridian plane, cells (n_el DISPLAY_SPLIT^2, 4) into them, (m, basis.N) scalar
        probes at the points): each element cut in DISPLAY_SPLIT x DISPLAY_SPLIT, cell e DISPLAY_SPLIT^2 + s the
        sub-square s = i + DISPLAY_SPLIT j of element e (reference coordinates [i, i + 1] x [j, j + 1] /
        DISPLAY_SPLIT), corners in the element's own order; a point's probe the element's basis at its reference
        coordinates (no point search: a corner on the boundary is off the mesh by round-off)."""
        from skfem import Basis

        k = DISPLAY_SPLIT
        corners = np.array([[0.0, 1.0, 1.0, 0.0], [0.0, 0.0, 1.0, 1.0]])
        reference = np.hstack([(corners + np.array([[i], [j]])) / k for j in range(k) for i in range(k)])
        flat = self.basis.mapping.F(reference).reshape(2, -1)  # (2, nel k^2 4): element, then sub-square, corner
        scale = float(np.abs(flat).max())
        _, first, index = np.unique(np.round(flat / scale, 10), axis=1, return_index=True, return_inverse=True)
        at = Basis(self.mesh, self.basis.elem, quadrature=(reference, np.ones(reference.shape[1])))
        element, point = np.divmod(first, reference.shape[1])
        values = np.array([np.asarray(at.basis[i][0])[element, point] for i in range(at.Nbfun)])  # (Nbfun, m)
        P = sp.csr_matrix((values.T.ravel(), (np.repeat(np.arange(len(first)), at.Nbfun),
                                               self.basis.element_dofs[:, element].T.ravel())),
                          shape=(len(first), self.basis.N))
        return flat[:, first], index.reshape(-1, 4), P

    @functools.cached_property
    def revolved_mesh(self) -> tuple[np.ndarray, np.ndarray, sp.csr_matrix, sp.csr_matrix, np.ndarray]:
        """(points (m, 3) [m], hexahedra (k, 8) in VTK order, displacement probes (3 m, ndofs) component-major,
        potential probes (m, ndofs), region index of each hexahedron): the meridian mesh's elements, each cut in
        DISPLAY_SPLIT x DISPLAY_SPLIT (``_display``), swept round the axis in ``REVOLVED_ANGLES`` sectors, the revolved
        body drawn and exported (hexahedron a n_cells + c: sector a, meridian cell c); a cell with an edge on the
        axis sweeps to hexahedra whose axis edge is one line (degenerate, zero-area faces inside the body)."""
        rz, quads, P = self._display
        on_axis = rz[0] <= 1e-12 * self.section.element_size
        points, which, angle = self._revolved_points(rz, axis_once=True)
        off = np.flatnonzero(~on_axis)
        k = REVOLVED_ANGLES
        ids = np.zeros((rz.shape[1], k), dtype=int)  # point id of each meridian point at each angle
        ids[off] = np.arange(len(off) * k).reshape(len(off), k)
        ids[on_axis] = (len(off) * k + np.arange(on_axis.sum()))[:, None]
        # a cell in the element's corner order, then at the next angle: the positive volume VTK needs
        cells = np.concatenate([np.hstack([ids[quads, j], ids[quads, (j + 1) % k]]) for j in range(k)])
        return (points.T, cells, self._revolved(P[which], angle), self._potential_revolved(P[which], angle),
                np.tile(np.repeat(self.region, DISPLAY_SPLIT**2), k))

    def cell_fields(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(strain (k, 6) [-] with engineering shears, stress (k, 6) [Pa], electric field (k, 3) [V/m]) in the xyz
        frame, Voigt order xx, yy, zz, yz, xz, xy, of the full DOF vector ``x`` on each hexahedron of
        ``revolved_mesh``: the mean over its meridian cell (weight r dr dz, Gauss points of the model's order in the
        cell) of the strain table's [S; G] of each harmonic (module docstring), taken at the sector's middle angle
        (cos / sin n theta), the stress T = c^E S - e^T E = rows 0-5 of the region's coupled tensor times [S; G],
        E = -G (zero outside the poled parts); turned from the local (r, theta, z) frame to xyz."""
        from skfem import Basis
        from skfem.quadrature import get_quadrature

        x = np.asarray(x, dtype=float)
        split = DISPLAY_SPLIT
        X, W = get_quadrature(self.mesh.elem.refdom, 2 * self.basis.elem.maxdeg)
        subs = [Basis(self.mesh, self.basis.elem, quadrature=((X + np.array([[i], [j]])) / split, W / split**2))
                for j in range(split) for i in range(split)]
        n_cells = self.mesh.t.shape[1] * split**2
        k = REVOLVED_ANGLES
        theta = (np.arange(k) + 0.5) * 2 * np.pi / k
        local = np.zeros((k, n_cells, 9))
        for h, n in enumerate(self.harmonics):
            phi = np.zeros(self.basis.N)
            phi[self.phi_nodes] = x[self.phi_dof(h, np.arange(len(self.phi_nodes)))]
            fields = [x[self.u_dof(h, np.arange(self.basis.N), c)] for c in range(3)] + [phi]
            B0, Br, Bz = strain_maps(n)
            mean = np.zeros((9, n_cells))
            for at, sub in enumerate(subs):
                r = np.asarray(sub.global_coordinates())[0]  # at the quadrature points (nel, nq) [m]
                weight = sub.dx * r  # r dr dz
                q = [sub.interpolate(f) for f in fields]
                values = np.array([np.asarray(f) for f in q])  # (4, nel, nq)
                grads = np.array([f.grad for f in q])  # (4, 2, nel, nq)
                SG = (np.einsum("ij,jeq->ieq", B0, values / r) + np.einsum("ij,jeq->ieq", Br, grads[:, 0])
                      + np.einsum("ij,jeq->ieq", Bz, grads[:, 1]))
                mean[:, at::split**2] = np.sum(SG * weight, axis=-1) / np.sum(weight, axis=-1)
            angle = np.ones((k, 9))
            angle[:, COS_ROWS] = np.cos(n * theta)[:, None]
            angle[:, SIN_ROWS] = np.sin(n * theta)[:, None] if n else 1.0  # n = 0: the torsional set, no angle
            local += angle[:, None, :] * mean.T[None]
        region = np.repeat(self.region, split**2)
        stress = np.zeros((k, n_cells, 6))
        field = np.zeros((k, n_cells, 3))
        for i, reg in enumerate(self.section.regions):
            at = region == i
            stress[:, at] = local[:, at] @ coupled_tensor(reg.material)[:6].T
            if reg.poled:
                field[:, at] = -local[:, at, 6:]
        e1, e3 = self.section.radial, self.section.axis
        e2 = np.cross(e3, e1)
        R = np.stack([np.outer(np.cos(theta), e1) + np.outer(np.sin(theta), e2),
                      -np.outer(np.sin(theta), e1) + np.outer(np.cos(theta), e2),
                      np.tile(e3, (k, 1))], axis=-1)  # (k, 3, 3): columns e_r, e_theta, e_z in xyz
        strain = turned(tensor_of(local[..., :6], 0.5), R)
        return (voigt_of(strain, 2.0).reshape(-1, 6), voigt_of(turned(tensor_of(stress, 1.0), R), 1.0).reshape(-1, 6),
                np.einsum("kij,kej->kei", R, field).reshape(-1, 3))

    def label_field(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(points (3, m) [m], displacement (3, m) [m]) of the full DOF vector ``x`` on the mesh vertices revolved
        at ``REVOLVED_ANGLES`` angles: the whole body's field the disc labeller reads (``modalfe.results.labels``)."""
        points, probes = self._label_probes
        return points, (probes @ np.asarray(x)).reshape(3, -1)
