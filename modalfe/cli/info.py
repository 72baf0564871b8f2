"""`modalfe info SCENE`: what a scene is made of and what solving it will cost, without meshing."""

from __future__ import annotations

import json
import math
from typing import Any

ROLE_OF = {"drive": "driven electrode", "ground": "grounded electrode"}


def register(subparsers) -> None:
    p = subparsers.add_parser("info", help="parts, materials, face groups and their roles, supports, symmetry, "
                                           "the analysis and the estimated size of the default mesh (no meshing)")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true", help="one JSON document on stdout")
    p.set_defaults(func=_info)


def scene_info(scene) -> dict[str, Any]:
    """Everything ``info`` prints, as plain data (lengths [m], frequencies [Hz], memory [bytes])."""
    from modalfe.models.estimate import estimate_size, machine_memory
    from modalfe.models.symmetry import mirror_planes

    assembly = scene.full_assembly()
    parts = [{"name": p.name, "region": p.region, "material": p.material, "origin_m": list(p.lo),
              "size_m": list(p.size), "poling": _poling(p.poling)} for p in assembly.parts]
    materials = {}
    for name in dict.fromkeys(p.material for p in assembly.parts):
        mat = scene.material(name)
        piezo = getattr(mat, "e", None) is not None
        materials[name] = {"kind": "piezoelectric" if piezo else "elastic", "rho_kg_m3": float(mat.rho),
                           "C11_Pa": float(mat.C[0, 0]),
                           "source": "scene file" if name in scene.materials else mat.source}
    faces = {}
    for group, members in assembly.faces.items():
        role = _role(scene, group)
        faces[group] = {"faces": [f"{f.part}.{f.side}" + (_window(f.window) if f.window else "") for f in members],
                        "role": role}
    supports = {"clamps": {g: c for g, c in scene.clamps.items()},
                "edges": {name: {"faces": list(e["faces"]), "fix": e["fix"]} for name, e in scene.edges.items()},
                "guides": dict(scene.guides),
                "springs_N_m": {g: list(k) for g, k in scene.springs.items()},
                "masses_kg": dict(scene.masses)}
    if not any(supports.values()):
        supports["note"] = "free: no clamp, spring or mass (rigid-body modes at 0 Hz)"
    symmetry = [{"axis": "xyz"[axis], "plane_m": twice / 2,
                 "parity": "antisymmetric" if "xyz"[axis] in scene.antisymmetry else "symmetric"}
                for axis, twice in mirror_planes(scene)]
    a = scene.analysis
    analysis = {"near_hz": a.near, "count": a.count, "band_hz": list(a.band) if a.band else None,
                "circuit": a.circuit, "mesh_resolves_hz": scene.max_frequency,
                "elements_per_wavelength": scene.mesh.elements_per_wavelength,
                "element": scene.mesh.element, "order": scene.mesh.order,
                "working_modes": [{"selector": w.selector, "near_hz": w.near} for w in scene.working_modes]}
    estimates = {}
    for fidelity in dict.fromkeys(("solid", scene.kind)):
        e = estimate_size(scene, fidelity)
        estimates[fidelity] = {"elements": e.elements, "dofs": e.dofs, "memory_bytes": e.memory,
                               "text": e.describe()}
    limit = machine_memory()
    return {"scene": scene.name, "device": scene.device, "kind": scene.kind, "parts": parts,
            "materials": materials, "face_groups": faces, "supports": supports,
            "symmetry": {"planes": symmetry, "model": _model_name(len(symmetry)),
                         "note": f"only the modes {scene.mirror_family} are found" if symmetry else ""},
            "analysis": analysis, "estimate": estimates,
            "machine_memory_bytes": limit if math.isfinite(limit) else None}


def _role(scene, group: str) -> str:
    if group in scene.electrodes:
        return ROLE_OF.get(scene.electrodes[group], f"electrode ({scene.electrodes[group]})")
    if group in scene.clamps:
        return f"clamp ({scene.clamps[group]} fixed)"
    if group in scene.guides:
        return f"guided ({scene.guides[group]} uniform)"
    edges = [f"{name} ({e['fix']} fixed)" for name, e in scene.edges.items() if group in e["faces"]]
    if edges:
        return "meets on edge " + ", ".join(edges)
    if group in scene.springs:
        return "spring (kx, ky, kz) = (" + ", ".join(f"{k:.4g}" for k in scene.springs[group]) + ") N/m"
    if group in scene.masses:
        return f"mass {scene.masses[group]:.4g} kg"
    if group.startswith("foot"):
        return "foot contact face (free)"
    return "none"


def _window(window) -> str:
    (u0, v0), (u1, v1) = window
    return f" window ({1e3 * u0:.4g}, {1e3 * v0:.4g})-({1e3 * u1:.4g}, {1e3 * v1:.4g}) mm"


def _model_name(planes: int) -> str:
    return {0: "whole device", 1: "half model", 2: "quarter model"}.get(planes, f"1/{2 ** planes} model")


def _mm(values) -> str:
    return " x ".join(f"{1e3 * v:g}" for v in values)


def format_info(info: dict[str, Any]) -> str:
    """The text ``info`` prints."""
    lines = [f"{info['scene']}: device '{info['device']}', {info['kind']} labels"]
    lines.append("parts (origin and size in mm):")
    for p in info["parts"]:
        lines.append(f"  {p['name']:<14} {p['material']:<20} at ({_mm(p['origin_m']).replace(' x ', ', ')})"
                     f"  size {_mm(p['size_m'])}  poling {p['poling']}")
    lines.append("materials:")
    for name, m in info["materials"].items():
        lines.append(f"  {name:<20} {m['kind']:<14} rho {m['rho_kg_m3']:g} kg/m^3, C11 {m['C11_Pa']:.4g} Pa;"
                     f" source: {m['source']}")
    lines.append("face groups:")
    for group, f in info["face_groups"].items():
        lines.append(f"  {group:<16} {f['role']:<32} {', '.join(f['faces'])}")
    s = info["supports"]
    lines.append("supports: " + ("; ".join(
        [f"clamp {g} ({c})" for g, c in s["clamps"].items()]
        + [f"edge {n} ({e['fix']} on {' x '.join(e['faces'])})" for n, e in s["edges"].items()]
        + [f"guide {g} ({c} uniform)" for g, c in s["guides"].items()]
        + [f"spring {g}" for g in s["springs_N_m"]] + [f"mass {g} {m:g} kg" for g, m in s["masses_kg"].items()])
        or s.get("note", "")))
    sym = info["symmetry"]
    lines.append("symmetry: " + ("none (whole device solved)" if not sym["planes"] else
                                 f"{sym['model']} about " + " and ".join(f"{p['axis']} = {1e3 * p['plane_m']:g} mm"
                                                                           for p in sym["planes"])
                                 + f" ({sym['note']})"))
    a = info["analysis"]
    asked = f"band {a['band_hz'][0]:g}-{a['band_hz'][1]:g} Hz" if a["band_hz"] else \
        f"{a['count']} modes near {a['near_hz']:g} Hz" if a["near_hz"] else f"{a['count']} modes"
    lines.append(f"analysis: {asked}, {a['circuit']} circuit; mesh resolves {a['mesh_resolves_hz']:.4g} Hz at "
                 f"{a['elements_per_wavelength']:g} elements per wavelength ({a['element']}, order {a['order']})")
    for w in a["working_modes"]:
        lines.append(f"  working mode {w['selector']} near {w['near_hz']:g} Hz")
    lines.append("estimated size of the default mesh (before meshing):")
    for fidelity, e in info["estimate"].items():
        lines.append(f"  {fidelity:<6} {e['text']}")
    if info["machine_memory_bytes"]:
        lines.append(f"  machine memory {info['machine_memory_bytes'] / 1e9:.3g} GB")
    return "\n".join(lines)


def _info(args) -> int:
    from modalfe.cli.options import parse_overrides
    from modalfe.scene import load_scene

    scene = load_scene(args.scene, **parse_overrides(args.set))
    info = scene_info(scene)
    print(json.dumps(info, indent=2) if args.json else format_info(info))
    return 0


def _poling(poling) -> str:
    """A part's poling as written in scene files: "+z" for 1, "-z" for -1, an axis or "radial" as is."""
    if isinstance(poling, str):
        return poling
    return {1: "+z", -1: "-z"}.get(poling, "none")
