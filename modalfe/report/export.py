"""VTU export for ParaView: every computed mode as point data, parts as cell data."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from modalfe.models.symmetry import whole_device_mesh


def export_vtu(modes, path: str | Path) -> Path:
    """Write the whole device (symmetric models unfolded) with one point-data vector per mode,
    named ``mode_<index>_<label>_<frequency>Hz``, and the cell data ``part`` (index; names in the
    field data ``part_names``). Returns the path."""
    import meshio

    model = modes.model
    fields = {f"mode_{m.index}_{m.label.replace(' ', '_')}_{m.frequency:.1f}Hz": model.nodal_displacement(m.shape)
              for m in modes}
    points, cells, kind, unfolded_fields, part_id, names = whole_device_mesh(model, fields)
    mesh = meshio.Mesh(points, [("hexahedron" if kind == 12 else "tetra", cells)],
                       point_data=unfolded_fields, cell_data={"part": [part_id]},
                       field_data={name: np.array([i, 3]) for i, name in enumerate(names)})
    path = Path(path)
    mesh.write(path)
    return path
