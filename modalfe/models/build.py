"""One entry that builds a scene's assembled model at a fidelity: the 3-D solid (mesh + assembly), the 2-D
axisymmetric model (harmonics 0..``mesh.harmonics``), the 2-D plate or the 1-D beam. Models are kept while the
scene's physics and mesh are unchanged (a second window, the other circuit, a forced response reuse them);
``modalfe.caches.clear`` drops them."""

from __future__ import annotations

import time
from collections import OrderedDict
from dataclasses import dataclass, replace

import numpy as np

import modalfe.caches as caches
from modalfe.errors import SceneError

MODEL_FIDELITIES = ("beam", "plate", "axisymmetric", "solid")
_KEPT = 3  # per kind of model: a fine and a coarse model of the scene in use, plus one
_MODELS: OrderedDict = OrderedDict()  # solid models
_LAYERED: OrderedDict = OrderedDict()  # plate, beam and axisymmetric models


@dataclass(frozen=True)
class Level:
    """One discretization of a scene, all ``build_model`` needs besides the scene: the model ``fidelity``, the mesh
    settings (``MeshSettings``: element order and family, thickness layers), element sizes x ``size_factor`` and
    the solid's thickness layers when they override the settings' (``min_layers``, estimate levels)."""

    fidelity: str
    mesh: object
    size_factor: float = 1.0
    min_layers: int | None = None

    def scene_of(self, scene):
        """``scene`` meshed at this level's settings."""
        return scene if scene.mesh == self.mesh else replace(scene, mesh=self.mesh)


def forget_models() -> None:
    """Drop the assembled models kept (registered with ``modalfe.caches``)."""
    _MODELS.clear()
    _LAYERED.clear()


caches.register("assembled models", forget_models)


def build_model(scene, fidelity: str = "solid", *, size_factor: float = 1.0, frame=None,
                min_layers: int | None = None) -> tuple[object, dict[str, float]]:
    """(assembled model, seconds spent on {"mesh", "assembly"}, zero for reused work) of ``scene`` at
    ``fidelity``, element sizes scaled by ``size_factor``; ``frame`` (3, 3) rotates a solid device,
    ``min_layers`` overrides the solid's element layers through the thinnest part."""
    if fidelity not in MODEL_FIDELITIES:
        raise SceneError(f"fidelity: must be one of {MODEL_FIDELITIES}, got '{fidelity}'")
    from modalfe.models.estimate import check_size

    if fidelity != "axisymmetric":  # a meridian mesh: a 2-D model of a few thousand unknowns per harmonic
        check_size(scene, fidelity, size_factor=size_factor, min_layers=min_layers)  # refuse before meshing
    if fidelity == "solid":
        return _solid(scene, size_factor=size_factor, frame=frame, min_layers=min_layers)
    key = repr((fidelity, scene, size_factor))
    if key in _LAYERED:
        _LAYERED.move_to_end(key)
        return _LAYERED[key], {"mesh": 0.0, "assembly": 0.0}
    if fidelity == "beam":
        from modalfe.models.beam import assemble_beam as assemble
    elif fidelity == "plate":
        from modalfe.models.plate import assemble_plate as assemble
    else:
        from modalfe.models.axisymmetric import assemble_axisymmetric as assemble
    model = assemble(scene, size_factor=size_factor)
    _keep(_LAYERED, key, model)
    return model, dict(model.timings)


def solid_mesh(scene, *, size_factor: float = 1.0, min_layers: int | None = None):
    """The 3-D solid's ``DeviceMesh`` of ``scene`` (element sizes x ``size_factor``, ``min_layers`` thickness layers
    where given), meshed (or read back from the mesh cache) without assembling: what ``build_model`` solves on."""
    from modalfe.models.mesh import build_mesh, element_sizes, mass_patches

    sizes = {k: v * size_factor for k, v in element_sizes(scene).items()}
    layers = scene.mesh.min_layers if min_layers is None else min_layers
    fully_clamped = tuple(sorted(g for g, components in scene.clamps.items() if set(components) == set("xyz")))
    return build_mesh(scene.assembly(), size=sizes, element=scene.mesh.element, min_layers=layers,
                      graded_faces=fully_clamped, grading_layers=scene.mesh.clamp_grading,
                      patches=mass_patches(scene, size_factor))


def _solid(scene, *, size_factor: float, frame, min_layers: int | None) -> tuple[object, dict[str, float]]:
    from modalfe.models.solid import assemble

    t0 = time.perf_counter()
    dm = solid_mesh(scene, size_factor=size_factor, min_layers=min_layers)
    t_mesh = (time.perf_counter() - t0) if dm.seconds else 0.0
    key = repr((dm.key, scene.params, scene.materials, scene.springs, scene.masses, scene.electrodes,
                scene.clamps, scene.edges, scene.guides, scene.symmetry_clamps, scene.mesh.order, scene.mesh.family,
                None if frame is None else np.asarray(frame).tobytes()))
    if key in _MODELS:
        _MODELS.move_to_end(key)
        return _MODELS[key], {"mesh": t_mesh, "assembly": 0.0}
    model = assemble(scene, dm, frame=frame)
    _keep(_MODELS, key, model)
    return model, {"mesh": t_mesh, "assembly": model.timings["assembly"]}


def _keep(cache: OrderedDict, key: str, model) -> None:
    cache[key] = model
    while len(cache) > _KEPT:
        cache.popitem(last=False)
