"""The package layout is the data flow: each sub-package imports only the ones above it, with no circles,
and the library never imports studies or test oracles (imports inside functions count too)."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "modalfe"
# top to bottom: a layer may import itself and the layers before it
LAYERS = ("errors", "caches", "geometry", "scene", "models", "results", "solve", "response", "contact", "design",
          "report", "plot", "cli")


def _imports(path: Path) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module)
            found.update(f"{node.module}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return found


def _layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[0] == "modalfe" and parts[1] in LAYERS else None


MODULES = sorted(p for p in PACKAGE.rglob("*.py") if p.parent != PACKAGE or p.name == "errors.py")


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_run_down_the_layers_only(path):
    own = path.relative_to(PACKAGE).parts[0].removesuffix(".py")
    rank = LAYERS.index(own)
    upward = [m for m in _imports(path) if _layer(m) is not None and LAYERS.index(_layer(m)) > rank]
    assert not upward, f"{own} imports a lower layer: {upward}"
    outside = [m for m in _imports(path) if m.split(".")[0] in ("studies", "tests", "geometries")]
    assert not outside, f"the library imports {outside}"


def test_every_sub_package_is_a_layer():
    packages = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    assert packages <= set(LAYERS), packages - set(LAYERS)
    assert len(MODULES) > 40  # the walk found the library


def test_no_module_over_600_lines():
    lines = {str(p.relative_to(PACKAGE)): len(p.read_text().splitlines()) for p in PACKAGE.rglob("*.py")}
    assert max(lines.values()) <= 600, {k: n for k, n in lines.items() if n > 600}
