"""The hostile-input cases: bad scene files, flags, ``--set`` values, materials, supports, sizes, paths,
caches, sweeps and interrupts, over every command and the Python API. Each case is data: its input, the
verdict expected (one-line error naming a field, or a correct answer) and, for a failure that belongs to
another item of issue 16, its owner. ``studies/hostile_inputs.py`` prints the table."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

from tests.hostile.harness import Case, modalfe_subprocess

OTHERS = "items 1-4/7"
CONTACT = "contact"

# a clamped steel beam, 40 x 4 x 1 mm: 672 DOFs, a solve takes ~0.2 s
TINY = """name = "tiny"
units = "mm"
kind = "beam"
[analysis]
near = 2000.0
count = 3
[mesh]
elements_per_wavelength = 6
[materials.steel]
E = 200e9
nu = 0.3
rho = 7850.0
[[parts]]
name = "beam"
material = "steel"
origin = [0, 0, 0]
size = [40, 4, 1]
[faces]
clamp = ["beam.xmin"]
tip = ["beam.xmax"]
[clamps]
clamp = "xyz"
"""

# the user guide's bimorph: a clamped steel beam with a PZT-5A patch, driven; a working mode for `forced`
BIMORPH = TINY.replace('name = "tiny"', 'name = "bimorph"').replace(
    "[faces]\nclamp", '[faces]\nelectrode_top = ["patch.zmax"]\nelectrode_bottom = ["patch.zmin"]\nclamp') + """
[[parts]]
name = "patch"
region = "piezo"
material = "PZT-5A"
origin = [5, 0, 1]
size = [10, 4, 0.2]
poling = 1
[electrodes]
electrode_top = "drive"
electrode_bottom = "ground"
[[working_modes]]
selector = "bending-z 1"
near = 500.0
targets = [{name = "guess", value = 500.0}]
"""

SOLVE = ("--fidelity", "solid", "--no-error-estimate")


def _edit(base: str, old: str, new: str) -> str:
    assert old in base, old
    return base.replace(old, new, 1)


def _file(id: str, area: str, text: str | bytes, field: str, *, owner: str = "", expect: str = "error",
          check=None, name: str = "scene.toml", extra: tuple[str, ...] = ()) -> Case:
    """A scene file run through ``modalfe modes FILE`` (solid, no estimate: a few tenths of a second)."""
    return Case(id, area, expect, field, argv=("modes", "{file}", *SOLVE, *extra), files={name: text},
                owner=owner, check=check)


def _tiny(id: str, area: str, old: str, new: str, field: str, **kw) -> Case:
    return _file(id, area, _edit(TINY, old, new), field, **kw)


def _cli(id: str, area: str, argv: tuple[str, ...], field: str, *, expect: str = "error", files=None, **kw) -> Case:
    return Case(id, area, expect, field, argv=argv, files=files or {"scene.toml": TINY}, **kw)


def _api(id: str, area: str, call, field: str = "", *, expect: str = "error", **kw) -> Case:
    return Case(id, area, expect, field, call=call, **kw)


def _json(text: str):
    return json.loads(text)


def _modes_listed(out: str) -> bool:
    return "bending" in out or "torsion" in out


SCENE_FILES = [
    _file("toml-syntax", "scene file", "parts = [[[", "{tmp}/scene.toml"),
    _file("toml-duplicate-key", "scene file", "units = 'mm'\nunits = 'm'\n", "{tmp}/scene.toml"),
    _file("binary-file", "scene file", bytes(range(256)) * 4, "{tmp}/scene.toml"),
    _file("latin-1-file", "scene file", _edit(TINY, 'name = "tiny"', 'name = "poutre d\'acier \xe9"').encode("latin-1"),
          "{tmp}/scene.toml"),
    _file("empty-file", "scene file", "", "parts"),
    _file("bom-utf8", "scene file", "\ufeff" + TINY, "{tmp}/scene.toml"),
    Case("directory-named-toml", "scene file", "error", "scene", argv=("modes", "{tmp}/x.toml"),
         prepare=lambda tmp: (tmp / "x.toml").mkdir(exist_ok=True)),
    Case("missing-file", "scene file", "error", "scene", argv=("modes", "{tmp}/nothere.toml")),
    Case("not-toml-suffix", "scene file", "error", "scene", argv=("modes", "{tmp}/scene.txt"),
         files={"scene.txt": TINY}),
    _tiny("unknown-top-key", "scene file", 'units = "mm"', 'units = "mm"\ncolour = "red"', "colour"),
    _tiny("units-inch", "scene file", 'units = "mm"', 'units = "inch"', "units"),
    _tiny("units-number", "scene file", 'units = "mm"', "units = 1", "units"),
    _tiny("kind-unknown", "scene file", 'kind = "beam"', 'kind = "shell"', "kind"),
    _tiny("kind-number", "scene file", 'kind = "beam"', "kind = 3", "kind"),
    _tiny("name-number", "scene file", 'name = "tiny"', "name = 5", "name"),
    _tiny("symmetry-axis", "scene file", 'units = "mm"', 'units = "mm"\nsymmetry = ["w"]', "symmetry[0]"),
    _tiny("symmetry-string", "scene file", 'units = "mm"', 'units = "mm"\nsymmetry = "y"', "symmetry"),
    # parts
    _file("parts-as-table", "parts", TINY.replace("[[parts]]", "[parts]"), "parts"),
    _file("parts-missing", "parts", "units = 'mm'\n[analysis]\nnear = 100.0\n", "parts"),
    _file("parts-empty", "parts", "parts = []\n[analysis]\nnear = 100.0\n", "parts"),
    _tiny("part-missing-size", "parts", "size = [40, 4, 1]\n", "", "parts[0].size"),
    _tiny("part-unknown-key", "parts", "size = [40, 4, 1]", "size = [40, 4, 1]\nthickness = 1", "parts[0].thickness"),
    _tiny("size-inf", "sizes", "size = [40, 4, 1]", "size = [inf, 4, 1]", "parts[0].size[0]"),
    _tiny("size-nan", "sizes", "size = [40, 4, 1]", "size = [nan, 4, 1]", "parts[0].size[0]"),
    _tiny("size-negative", "sizes", "size = [40, 4, 1]", "size = [40, 4, -1]", "parts[0].size[2]"),
    _tiny("size-zero", "sizes", "size = [40, 4, 1]", "size = [40, 0, 1]", "parts[0].size[1]"),
    _tiny("size-two-numbers", "sizes", "size = [40, 4, 1]", "size = [40, 4]", "parts[0].size"),
    _tiny("size-string", "sizes", "size = [40, 4, 1]", 'size = "40, 4, 1"', "parts[0].size"),
    _tiny("size-with-unit", "sizes", "size = [40, 4, 1]", 'size = ["40 mm", 4, 1]', "parts[0].size[0]"),
    _tiny("size-bool", "sizes", "size = [40, 4, 1]", "size = [40, true, 1]", "parts[0].size[1]"),
    _tiny("origin-string", "parts", "origin = [0, 0, 0]", 'origin = [0, "a", 0]', "parts[0].origin[1]"),
    _tiny("origin-inf", "parts", "origin = [0, 0, 0]", "origin = [0, -inf, 0]", "parts[0].origin[1]"),
    _tiny("material-number", "parts", 'material = "steel"', "material = 5", "parts[0].material"),
    _tiny("material-unknown", "materials", 'material = "steel"', 'material = "unobtainium"', "part 'beam'"),
    _tiny("poling-two", "parts", 'size = [40, 4, 1]', "size = [40, 4, 1]\npoling = 2", "parts[0].poling"),
    _tiny("poling-string", "parts", 'size = [40, 4, 1]', 'size = [40, 4, 1]\npoling = "up"', "parts[0].poling"),
    _tiny("poling-steel", "parts", 'size = [40, 4, 1]', "size = [40, 4, 1]\npoling = 1", "part 'beam'"),
    _file("part-duplicate-name", "parts", TINY + '[[parts]]\nname = "beam"\nmaterial = "steel"\norigin = [40, 0, 0]\n'
          'size = [10, 4, 1]\n', "parts[1].name"),
    _file("parts-overlap", "parts", TINY + '[[parts]]\nname = "b"\nmaterial = "steel"\norigin = [20, 0, 0]\n'
          'size = [10, 4, 1]\n', "parts"),
    _file("part-not-table", "parts", "units = 'mm'\nparts = [5]\n[analysis]\nnear = 100.0\n", "parts[0]"),
    # analysis
    _tiny("near-string", "analysis", "near = 2000.0", 'near = "2000"', "analysis.near"),
    _tiny("near-negative", "analysis", "near = 2000.0", "near = -2000.0", "analysis.near"),
    _tiny("near-zero", "analysis", "near = 2000.0", "near = 0.0", "analysis.near"),
    _tiny("near-inf", "analysis", "near = 2000.0", "near = inf", "analysis.near"),
    _tiny("near-nan", "analysis", "near = 2000.0", "near = nan", "analysis.near"),
    _tiny("near-bool", "analysis", "near = 2000.0", "near = true", "analysis.near"),
    _tiny("count-zero", "analysis", "count = 3", "count = 0", "analysis.count"),
    _tiny("count-float", "analysis", "count = 3", "count = 2.5", "analysis.count"),
    _tiny("count-string", "analysis", "count = 3", 'count = "3"', "analysis.count"),
    _tiny("count-negative", "analysis", "count = 3", "count = -1", "analysis.count"),
    _tiny("band-reversed", "analysis", "near = 2000.0\ncount = 3", "band = [5000.0, 1000.0]", "analysis.band"),
    _tiny("band-one-number", "analysis", "near = 2000.0\ncount = 3", "band = [1000.0]", "analysis.band"),
    _tiny("band-string", "analysis", "near = 2000.0\ncount = 3", 'band = "1000-2000"', "analysis.band"),
    _tiny("band-negative", "analysis", "near = 2000.0\ncount = 3", "band = [-1.0, 100.0]", "analysis.band[0]"),
    _tiny("circuit-closed", "analysis", "count = 3", 'count = 3\ncircuit = "closed"', "analysis.circuit"),
    _tiny("analysis-typo", "analysis", "count = 3", "count = 3\nnearr = 5.0", "analysis.nearr"),
    _tiny("analysis-not-table", "analysis", "[analysis]\nnear = 2000.0\ncount = 3", "analysis = 5", "analysis"),
    _tiny("analysis-empty", "analysis", "near = 2000.0\ncount = 3", "", "analysis"),
    # mesh
    _tiny("min-layers-zero", "mesh", "elements_per_wavelength = 6", "min_layers = 0", "mesh.min_layers"),
    _tiny("min-layers-float", "mesh", "elements_per_wavelength = 6", "min_layers = 2.5", "mesh.min_layers"),
    _tiny("epw-zero", "mesh", "elements_per_wavelength = 6", "elements_per_wavelength = 0",
          "mesh.elements_per_wavelength"),
    _tiny("epw-negative", "mesh", "elements_per_wavelength = 6", "elements_per_wavelength = -3",
          "mesh.elements_per_wavelength"),
    _tiny("epw-string", "mesh", "elements_per_wavelength = 6", 'elements_per_wavelength = "six"',
          "mesh.elements_per_wavelength"),
    _tiny("element-prism", "mesh", "elements_per_wavelength = 6", 'element = "prism"', "mesh.element"),
    _tiny("order-five", "mesh", "elements_per_wavelength = 6", "order = 5", "mesh.order"),
    _tiny("order-three-tet", "mesh", "elements_per_wavelength = 6", "order = 3\nelement = \"tet\"", "mesh.order"),
    _tiny("family-unknown", "mesh", "elements_per_wavelength = 6", 'family = "hermite"', "mesh.family"),
    _tiny("family-serendipity-order-four", "mesh", "elements_per_wavelength = 6",
          'order = 4\nfamily = "serendipity"', "mesh.family"),
    _tiny("family-serendipity-tet", "mesh", "elements_per_wavelength = 6",
          'element = "tet"\nfamily = "serendipity"', "mesh.family"),
    _tiny("max-size-zero", "mesh", "elements_per_wavelength = 6", "max_size = 0.0", "mesh.max_size"),
    _tiny("max-size-negative", "mesh", "elements_per_wavelength = 6", "max_size = -1.0", "mesh.max_size"),
    _tiny("min-above-max-size", "mesh", "elements_per_wavelength = 6", "min_size = 0.01\nmax_size = 0.001",
          "mesh.min_size"),
    _tiny("mesh-key-typo", "mesh", "elements_per_wavelength = 6", "element_per_wavelength = 6",
          "mesh.element_per_wavelength"),
    _tiny("clamp-grading-20", "mesh", "elements_per_wavelength = 6", "clamp_grading = 20", "mesh.clamp_grading"),
    _tiny("clamp-grading-bool", "mesh", "elements_per_wavelength = 6", "clamp_grading = true", "mesh.clamp_grading"),
    _tiny("max-frequency-negative", "mesh", "elements_per_wavelength = 6", "max_frequency = -5.0",
          "mesh.max_frequency"),
    _tiny("max-frequency-unit", "mesh", "elements_per_wavelength = 6", 'max_frequency = "50kHz"', "mesh.max_frequency"),
    _tiny("epw-huge", "sizes", "elements_per_wavelength = 6", "elements_per_wavelength = 1e6", "mesh"),
    _tiny("near-1e12", "sizes", "near = 2000.0", "near = 1e12", "mesh"),
    _tiny("min-layers-1000", "sizes", "elements_per_wavelength = 6", "min_layers = 1000", "mesh"),
    # faces
    _tiny("faces-string", "faces", 'clamp = ["beam.xmin"]', 'clamp = "beam.xmin"', "faces.clamp"),
    _tiny("faces-bad-side", "faces", 'clamp = ["beam.xmin"]', 'clamp = ["beam.left"]', "faces.clamp"),
    _tiny("faces-unknown-part", "faces", 'clamp = ["beam.xmin"]', 'clamp = ["nope.xmin"]', "faces.clamp"),
    _tiny("faces-number", "faces", 'clamp = ["beam.xmin"]', "clamp = [5]", "faces.clamp[0]"),
    _file("faces-not-table", "faces", _edit(_edit(TINY, '[faces]\nclamp = ["beam.xmin"]\ntip = ["beam.xmax"]\n', ""),
                                          'units = "mm"', 'units = "mm"\nfaces = 3'), "faces"),
    # clamps
    _tiny("clamp-components", "supports", 'clamp = "xyz"', 'clamp = "xq"', "clamps.clamp"),
    _tiny("clamp-empty", "supports", 'clamp = "xyz"', 'clamp = ""', "clamps.clamp"),
    _tiny("clamp-number", "supports", 'clamp = "xyz"', "clamp = 5", "clamps.clamp"),
    _tiny("clamp-missing-group", "supports", 'clamp = "xyz"', 'nothere = "xyz"', "clamps.nothere"),
    _tiny("clamp-repeated", "supports", 'clamp = "xyz"', 'clamp = "xx"', "clamps.clamp"),
    _file("clamps-list-form", "supports", _edit(_edit(TINY, '[clamps]\nclamp = "xyz"', ''), 'units = "mm"',
                                                'units = "mm"\nclamps = ["clamp"]'), "",
          expect="ok", check=_modes_listed),
    # springs and masses
    _tiny("spring-scalar", "supports", "[clamps]", "[springs]\ntip = 1e4\n[clamps]", "springs.tip"),
    _tiny("spring-two", "supports", "[clamps]", "[springs]\ntip = [1e4, 1e4]\n[clamps]", "springs.tip"),
    _tiny("spring-negative", "supports", "[clamps]", "[springs]\ntip = [0, 0, -1e4]\n[clamps]", "springs.tip[2]"),
    _tiny("spring-string", "supports", "[clamps]", '[springs]\ntip = ["1e4", 0, 0]\n[clamps]', "springs.tip[0]"),
    _tiny("spring-missing-group", "supports", "[clamps]", "[springs]\nnowhere = [0, 0, 1]\n[clamps]",
          "springs.nowhere"),
    _tiny("spring-inf", "supports", "[clamps]", "[springs]\ntip = [0, 0, inf]\n[clamps]", "springs.tip[2]"),
    _tiny("mass-negative", "supports", "[clamps]", "[masses]\ntip = -0.1\n[clamps]", "masses.tip"),
    _tiny("mass-zero", "supports", "[clamps]", "[masses]\ntip = 0.0\n[clamps]", "masses.tip"),
    _tiny("mass-list", "supports", "[clamps]", "[masses]\ntip = [0.1]\n[clamps]", "masses.tip"),
    _tiny("mass-with-unit", "supports", "[clamps]", '[masses]\ntip = "2 g"\n[clamps]', "masses.tip"),
    _tiny("mass-missing-group", "supports", "[clamps]", "[masses]\nnowhere = 0.1\n[clamps]", "masses.nowhere"),
    _file("spring-and-mass-ok", "supports", _edit(TINY, "[clamps]", "[springs]\ntip = [0, 0, 1e3]\n[masses]\n"
                                                   "tip = 0.001\n[clamps]"), "", expect="ok", check=_modes_listed),
    # materials
    _tiny("E-with-unit", "materials", "E = 200e9", 'E = "200 GPa"', "materials.steel.E"),
    _tiny("E-in-GPa", "materials", "E = 200e9", "E = 200", "materials.steel.E"),
    _tiny("E-negative", "materials", "E = 200e9", "E = -200e9", "materials.steel.E"),
    _tiny("nu-half", "materials", "nu = 0.3", "nu = 0.5", "materials.steel.nu"),
    _tiny("nu-string", "materials", "nu = 0.3", 'nu = "0.3"', "materials.steel.nu"),
    _tiny("rho-missing", "materials", "rho = 7850.0\n", "", "materials.steel.rho"),
    _tiny("rho-g-per-cm3", "materials", "rho = 7850.0", "rho = 7.85", "materials.steel.rho"),
    _tiny("material-unknown-key", "materials", "rho = 7850.0", "rho = 7850.0\nyoung = 1", "materials.steel.young"),
    _tiny("material-not-table", "materials", "[materials.steel]\nE = 200e9\nnu = 0.3\nrho = 7850.0",
          "[materials]\nsteel = 5", "materials.steel"),
    _tiny("C-not-6x6", "materials", "E = 200e9\nnu = 0.3", "C = [[1e9, 0], [0, 1e9]]", "materials.steel.C"),
    _tiny("C-indefinite", "materials", "E = 200e9\nnu = 0.3",
          "C = " + str([[(-1e9 if i == j == 0 else 1e9) if i == j else 0.0 for j in range(6)] for i in range(6)]),
          "materials.steel.C"),
    _tiny("eps-relative-e-form", "materials", "E = 200e9\nnu = 0.3",
          "C = " + str([[1e11 if i == j else 0.0 for j in range(6)] for i in range(6)])
          + "\ne = " + str([[0.0] * 6, [0.0] * 6, [-5.0, -5.0, 15.0, 0.0, 0.0, 0.0]])
          + "\neps_S = [[900.0, 0, 0], [0, 900.0, 0], [0, 0, 800.0]]", "materials.steel.eps_S"),
    _tiny("e-form-missing-eps", "materials", "E = 200e9\nnu = 0.3",
          "C = " + str([[1e11 if i == j else 0.0 for j in range(6)] for i in range(6)])
          + "\ne = " + str([[0.0] * 6, [0.0] * 6, [-5.0, -5.0, 15.0, 0.0, 0.0, 0.0]]), "materials.steel"),
    _tiny("mixed-forms", "materials", "nu = 0.3", "nu = 0.3\nC = [[1.0]]", "materials.steel"),
]


def _pzt4_d_form(relative_eps: bool = False, s_scale: float = 1.0) -> dict:
    from modalfe.scene.materials import EPS0, MATERIALS, piezo_compliance_form

    m = MATERIALS["PZT-4"]
    s_E, d, eps_T = piezo_compliance_form(m.C, m.e, m.eps_S)
    return {"s_E": (s_E * s_scale).tolist(), "d": d.tolist(),
            "eps_T": (eps_T / EPS0 if relative_eps else eps_T).tolist(), "rho": 7500.0}


def _d_form_equals_e_form(_tmp: Path) -> bool:
    import numpy as np

    from modalfe.scene.materials import MATERIALS, material

    m, d = MATERIALS["PZT-4"], material({"name": "pzt4-datasheet", **_pzt4_d_form()})
    return bool(np.allclose(d.C, m.C, rtol=1e-9) and np.allclose(d.e, m.e, rtol=1e-9, atol=1e-9)
                and np.allclose(d.eps_S, m.eps_S, rtol=1e-9))


def _material(spec: dict):
    from modalfe.scene.materials import material

    return lambda _tmp: material(spec)


def _d_form_scene() -> str:
    spec = _pzt4_d_form()
    table = "\n".join(f"{k} = {json.dumps(v)}" for k, v in spec.items())
    return _edit(BIMORPH, "[[parts]]", f"[materials.pzt4-datasheet]\n{table}\n\n[[parts]]").replace(
        'material = "PZT-5A"', 'material = "pzt4-datasheet"')


MATERIALS = [
    _api("d-form-equals-e-form", "materials", lambda tmp: _d_form_equals_e_form(tmp), expect="ok", check=bool),
    _api("d-form-eps-relative", "materials", _material({"name": "p", **_pzt4_d_form(relative_eps=True)}),
         "materials.p.eps_T"),
    _api("d-form-s-in-wrong-unit", "materials", _material({"name": "p", **_pzt4_d_form(s_scale=1e12)}),
         "materials.p.s_E"),
    _api("d-form-d-shape", "materials", _material({"name": "p", **{**_pzt4_d_form(), "d": [[1e-10] * 6]}}),
         "materials.p.d"),
    _api("material-E-string-api", "materials", _material({"name": "q", "E": "200 GPa", "rho": 7850.0}),
         "materials.q.E"),
    _api("material-spec-not-table", "materials", _material(5), "material"),
    _file("d-form-scene-solves", "materials", _d_form_scene(), "", expect="ok", check=_modes_listed),
]

FLAGS = [
    _cli("near-negative", "flags", ("modes", "{file}", "--near", "-2000"), "--near"),
    _cli("near-nan", "flags", ("modes", "{file}", "--near", "nan"), "--near"),
    _cli("near-inf", "flags", ("modes", "{file}", "--near", "inf"), "--near"),
    _cli("near-word", "flags", ("modes", "{file}", "--near", "abc"), "--near"),
    _cli("near-zero-clamped", "flags", ("modes", "{file}", "--near", "0", *SOLVE), "", expect="ok",
         check=_modes_listed, owner=OTHERS),
    _cli("count-zero", "flags", ("modes", "{file}", "--count", "0"), "--count"),
    _cli("vary-unknown", "flags", ("sensitivity", "{file}", "--vary", "wingspan"), "wingspan"),
    _cli("vary-empty", "flags", ("sensitivity", "{file}", "--vary", ","), "--vary"),
    _cli("vary-material-not-in-file", "flags", ("sensitivity", "{file}", "--vary", "materials.PZT-5A.rho"),
         "materials.PZT-5A.rho"),
    _cli("vary-missing", "flags", ("sensitivity", "{file}"), "--vary"),
    _cli("tune-target-no-frequency", "flags", ("tune", "{file}", "--target", "bending-z 1", "--vary", "x"),
         "--target"),
    _cli("tune-target-word", "flags", ("tune", "{file}", "--target", "bending-z 1=fast", "--vary", "x"), "--target"),
    _cli("tune-bounds-reversed", "flags",
         ("tune", "{file}", "--target", "bending-z 1=900", "--vary", "x", "--bounds", "x=2:1"), "--bounds"),
    _cli("tune-tol-huge", "flags",
         ("tune", "{file}", "--target", "bending-z 1=900", "--vary", "materials.steel.E", "--tol", "3"), "tol"),
    _cli("count-negative", "flags", ("modes", "{file}", "--count", "-3"), "--count"),
    _cli("count-float", "flags", ("modes", "{file}", "--count", "2.5"), "--count"),
    _cli("count-10000", "flags", ("modes", "{file}", "--count", "10000", *SOLVE), "count", owner=OTHERS),
    _cli("near-and-band", "flags", ("modes", "{file}", "--near", "100", "--band", "1", "2"), "--near"),
    _cli("band-reversed", "flags", ("modes", "{file}", "--band", "5000", "1000"), "--band"),
    _cli("band-negative", "flags", ("modes", "{file}", "--band", "-1", "100"), "--band"),
    _cli("band-one-value", "flags", ("modes", "{file}", "--band", "1"), "--band"),
    _cli("band-nan", "flags", ("modes", "{file}", "--band", "nan", "100"), "--band"),
    _cli("count-with-band", "flags", ("modes", "{file}", "--band", "1", "5000", "--count", "3"), "--count"),
    _cli("circuit-closed", "flags", ("modes", "{file}", "--circuit", "closed"), "--circuit"),
    _cli("fidelity-magic", "flags", ("modes", "{file}", "--fidelity", "magic"), "--fidelity"),
    _cli("fidelity-plate-on-beam", "flags", ("modes", "{file}", "--fidelity", "plate"), "fidelity"),
    _cli("tol-zero", "flags", ("modes", "{file}", "--tol", "0"), "--tol"),
    _cli("tol-nan", "flags", ("modes", "{file}", "--tol", "nan"), "--tol"),
    _cli("unknown-flag", "flags", ("modes", "{file}", "--colour", "red"), "unrecognized arguments"),
    _cli("no-command", "flags", (), "command"),
    _cli("unknown-command", "flags", ("solve", "{file}"), "command"),
    _cli("report-unknown-scene", "flags", ("report", "--scene", "nope"), "scene"),
    _cli("report-jobs-zero", "flags", ("report", "--jobs", "0"), "--jobs"),
    _cli("show-near-negative", "flags", ("show", "{file}", "--near", "-1"), "--near"),
    _cli("export-count-zero", "flags", ("export", "{file}", "--vtu", "{tmp}/x.vtu", "--count", "0"), "--count"),
    _cli("forced-damping-word", "flags", ("forced", "{file}", "--damping", "Q=abc"), "damping"),
    _cli("forced-damping-negative", "flags", ("forced", "{file}", "--damping", "Q=-5"), "damping.Q"),
    _cli("forced-damping-empty", "flags", ("forced", "{file}", "--damping", "zeta="), "damping"),
    _cli("forced-damping-unknown", "flags", ("forced", "{file}", "--damping", "eta=0.1"), "damping"),
    _cli("forced-volts-zero", "flags", ("forced", "{file}", "--volts", "0"), "--volts"),
    _cli("forced-outputs-empty-item", "flags", ("forced", "{file}", "--outputs", "a,,b"), "--outputs"),
    _cli("forced-near-negative", "flags", ("forced", "{file}", "--near", "-500"), "--near"),
    _cli("forced-nothing-drives-it", "flags", ("forced", "{file}"), "drive.load"),
    _cli("forced-outputs-unknown", "flags", ("forced", "{file}", "--outputs", "nowhere"), "outputs",
         files={"bimorph.toml": BIMORPH}),
    _cli("show-mode-index-out-of-range", "flags", ("show", "{file}", "--mode", "99", "--near", "500",
                                                   "--out", "{tmp}/m.png"), "--mode", files={"bimorph.toml": BIMORPH}),
    _cli("friction-amplitude-negative", "flags", ("friction", "--amplitude=-1e-6"), "amplitude", owner=CONTACT),
    _cli("friction-preload-word", "flags", ("friction", "--amplitude", "1e-6", "--preload", "abc"), "--preload"),
    _cli("finger-frequency-zero", "flags", ("finger", "--frequency", "0"), "frequency"),
    _cli("texture-period-negative", "flags", ("texture", "--period=-1"), "period", owner=CONTACT),
]

FLAGS = [dataclasses.replace(c, id=f"flag-{c.id}") for c in FLAGS]

SETS = [
    _cli("set-bool-length", "--set", ("modes", "cube_plate", "--set", "ceramic_thickness=true"), "ceramic_thickness"),
    _cli("set-length-with-unit", "--set", ("modes", "cube_plate", "--set", "ceramic_thickness=0.65mm"),
         "ceramic_thickness"),
    _cli("set-length-string", "--set", ("modes", "cube_plate", "--set", 'ceramic_thickness="0.65"'),
         "ceramic_thickness"),
    _cli("set-length-negative", "--set", ("modes", "cube_plate", "--set", "ceramic_thickness=-1e-3"),
         "ceramic_thickness"),
    _cli("set-length-inf", "--set", ("modes", "cube_plate", "--set", "ceramic_thickness=inf"), "ceramic_thickness"),
    _cli("set-unknown-parameter", "--set", ("modes", "cube_plate", "--set", "ceramic_colour=1"), "ceramic_colour"),
    _cli("set-columns-float", "--set", ("modes", "cube_plate", "--set", "ceramic_columns=2.5"), "ceramic_columns"),
    _cli("set-poled-int", "--set", ("modes", "cube_plate", "--set", "poled=1"), "poled"),
    _cli("set-feet-off-plate", "--set", ("modes", "cube_plate", "--set", "feet=[[0.07, 0.006]]"), "feet[0]"),
    _cli("set-feet-scalar", "--set", ("modes", "cube_plate", "--set", "feet=3"), "feet"),
    _cli("set-material-unknown", "--set", ("modes", "cube_plate", "--set", "plate_material=unobtainium"), "part"),
    _cli("set-mesh-typo", "--set", ("modes", "{file}", "--set", "mesh.element_per_wavelength=8"),
         "mesh.element_per_wavelength"),
    _cli("set-mesh-table", "--set", ("modes", "{file}", "--set", "mesh=5"), "mesh"),
    _cli("set-mesh-min-layers-zero", "--set", ("modes", "{file}", "--set", "mesh.min_layers=0"), "mesh.min_layers"),
    _cli("set-mesh-max-size-tiny", "sizes", ("modes", "cube_plate", "--set", "mesh.max_size=1e-6"), "mesh"),
    _cli("set-near-string", "--set", ("modes", "{file}", "--set", 'analysis.near="2000"'), "analysis.near"),
    _cli("set-near-negative", "--set", ("modes", "{file}", "--set", "analysis.near=-5"), "analysis.near"),
    _cli("set-near-1e12", "sizes", ("modes", "cube_plate", "--set", "analysis.near=1e12"), "mesh"),
    _cli("band-1e9", "sizes", ("modes", "cube_plate", "--band", "1", "1e9"), "mesh"),
    # issue 35: a shift far above what the mesh resolves answered MHz modes with confident labels
    _cli("near-flag-1e12", "sizes", ("modes", "cube_plate", "--near", "1e12"), "near"),
    _cli("forced-near-1e9", "sizes", ("forced", "cube_plate", "--mode", "(0,6)", "--near", "1e9"), "near"),
    _cli("set-count-zero", "--set", ("modes", "{file}", "--set", "analysis.count=0"), "analysis.count"),
    _cli("set-band-one", "--set", ("modes", "{file}", "--set", "analysis.band=[1]"), "analysis.band"),
    _cli("set-band-scalar", "--set", ("modes", "{file}", "--set", "analysis.band=5"), "analysis.band"),
    _cli("set-band-words", "--set", ("modes", "{file}", "--set", 'analysis.band=["a", "b"]'), "analysis.band[0]"),
    _cli("set-spring-scalar", "--set", ("modes", "honeycomb_tile", "--set", "springs.mount_1=5"), "springs.mount_1"),
    _cli("set-mass-word", "--set", ("modes", "honeycomb_tile", "--set", 'masses.actuator="heavy"'), "masses.actuator"),
    _cli("set-mass-negative", "--set", ("modes", "honeycomb_tile", "--set", "masses.actuator=-1"), "masses.actuator"),
    _cli("set-electrode-role", "--set", ("modes", "cube_plate", "--set", 'electrodes.electrode_top="hot"'),
         "electrodes.electrode_top"),
    _cli("set-clamp-number", "--set", ("modes", "ciliary_beam", "--set", "clamps.clamp=5"), "clamps.clamp"),
    _cli("set-symmetry-number", "--set", ("modes", "cube_plate", "--set", "symmetry=5"), "symmetry"),
    _cli("set-symmetry-axis", "--set", ("modes", "cube_plate", "--set", 'symmetry=["q"]'), "symmetry[0]"),
    _cli("set-kind", "--set", ("modes", "{file}", "--set", 'kind="shell"'), "kind"),
    _cli("set-damping-word", "--set", ("forced", "cube_plate", "--set", 'drive.damping="Q=abc"'), "drive.damping"),
    _cli("set-damping-number", "--set", ("forced", "cube_plate", "--set", "drive.damping=5"), "drive.damping"),
    _cli("set-library-material-partial", "--set", ("modes", "cube_plate", "--set", "materials.CuBe.E=1.3e11"),
         "materials.CuBe"),
    _cli("set-material-E-string", "--set", ("modes", "{file}", "--set", 'materials.steel.E="200 GPa"'),
         "materials.steel.E"),
    _cli("set-no-key", "--set", ("modes", "{file}", "--set", "=5"), "--set"),
    _cli("set-no-equals", "--set", ("modes", "{file}", "--set", "novalue"), "--set"),
    _cli("set-empty-value", "--set", ("modes", "{file}", "--set", "analysis.near="), "analysis.near"),
    _cli("set-twice", "--set", ("modes", "{file}", "--set", "analysis.count=2", "--set", "analysis.count=3"),
         "analysis.count"),
    _cli("set-broken-list", "--set", ("modes", "{file}", "--set", "springs.tip=[1,2"), "springs.tip"),
    _cli("set-min-layers-huge", "--set", ("modes", "{file}", "--set", "mesh.min_layers=100000"), "mesh.min_layers"),
]

PATHS = [
    _cli("show-out-missing-folder", "paths", ("show", "{file}", "--out", "{tmp}/no/x.png"), "--out"),
    _cli("show-out-jpg", "paths", ("show", "{file}", "--out", "{tmp}/x.jpg"), "--out"),
    _cli("show-out-directory", "paths", ("show", "{file}", "--out", "{tmp}"), "--out"),
    _cli("export-vtu-missing-folder", "paths", ("export", "{file}", "--vtu", "{tmp}/no/x.vtu"), "--vtu"),
    _cli("export-vtu-suffix", "paths", ("export", "{file}", "--vtu", "{tmp}/x.txt"), "--vtu"),
    _cli("export-vtu-under-file", "paths", ("export", "{file}", "--vtu", "{file}/x.vtu"), "--vtu"),
    _cli("forced-plot-missing-folder", "paths", ("forced", "cube_plate", "--plot", "{tmp}/no/x.png"), "--plot"),
    _cli("forced-save-rom-missing-folder", "paths", ("forced", "cube_plate", "--save-rom", "{tmp}/no/r.json"),
         "--save-rom"),
    _cli("forced-save-rom-directory", "paths", ("forced", "cube_plate", "--save-rom", "{tmp}"), "--save-rom"),
    _cli("friction-plot-missing-folder", "paths", ("friction", "--amplitude", "1e-6", "--plot", "{tmp}/no/f.png"),
         "--plot"),
    _cli("sweep-out-directory", "paths", ("sweep", "{file}", "--param", "x=1:2:2", "--out", "{tmp}"), "--out"),
    _cli("sweep-out-under-file", "paths", ("sweep", "{file}", "--param", "x=1:2:2", "--out", "{file}/s.csv"),
         "--out"),
    _cli("export-vtu-ok", "paths", ("export", "{file}", "--vtu", "{tmp}/modes.vtu", "--near", "2000", "--count", "2"),
         "", expect="ok", check=lambda out: "modes ->" in out),
]

SWEEPS = [
    _cli("sweep-workers-zero", "sweeps", ("sweep", "{file}", "--param", "x=1:2:2", "--out", "{tmp}/s.csv",
                                          "--workers", "0"), "--workers"),
    _cli("sweep-param-no-equals", "sweeps", ("sweep", "{file}", "--param", "x", "--out", "{tmp}/s.csv"), "--param"),
    _cli("sweep-param-count-zero", "sweeps", ("sweep", "{file}", "--param", "x=1:2:0", "--out", "{tmp}/s.csv"),
         "--param x"),
    _cli("sweep-param-word", "sweeps", ("sweep", "{file}", "--param", "x=a:2:3", "--out", "{tmp}/s.csv"), "--param x"),
    _cli("sweep-param-two-colons", "sweeps", ("sweep", "{file}", "--param", "x=1:2", "--out", "{tmp}/s.csv"),
         "--param"),
    _cli("sweep-param-twice", "sweeps", ("sweep", "{file}", "--param", "x=1:2:2", "--param", "x=1:2:2", "--out",
                                         "{tmp}/s.csv"), "--param x"),
    _cli("sweep-param-huge", "sweeps", ("sweep", "{file}", "--param", "x=1:2:1000000000", "--out", "{tmp}/s.csv"),
         "--param x"),
    _cli("sweep-param-inf", "sweeps", ("sweep", "{file}", "--param", "x=1:inf:3", "--out", "{tmp}/s.csv"),
         "--param x"),
    _cli("sweep-unknown-parameter", "sweeps", ("sweep", "cube_plate", "--param", "nosuch=1:2:2", "--out",
                                               "{tmp}/s.csv"), "nosuch"),
    _cli("sweep-int-parameter-float-grid", "sweeps", ("sweep", "cube_plate", "--param", "ceramic_columns=3:5:4",
                                                      "--out", "{tmp}/s.csv"), "ceramic_columns"),
    _cli("sweep-no-working-mode", "sweeps", ("sweep", "{file}", "--param", "mesh.elements_per_wavelength=5:6:2",
                                             "--out", "{tmp}/s.csv"), "--mode/--near"),
    _cli("sweep-count-zero", "sweeps", ("sweep", "{file}", "--param", "x=1:2:2", "--out", "{tmp}/s.csv", "--count",
                                        "0"), "--count"),
]


def _api_scene(tmp: Path, text: str = TINY):
    import modalfe

    path = tmp / "api.toml"
    path.write_text(text)
    return modalfe.load_scene(path)


def _solve(tmp: Path, **kw):
    import modalfe

    return modalfe.solve_modes(_api_scene(tmp), **{"fidelity": "solid", "error_estimate": False, **kw})


def _fr_fa_beside_the_mode(out: str) -> bool:
    """The admittance's fr (|Y| maximum) within 1 % of its strongest mode's frequency (Q = 150: fr - f_r ~ 0.3 %
    at most from the residual), and fa (the minimum) above it: read off the model, not the coarse grid."""
    import re

    fr = re.search(r"maxima \(near fr\) \[Hz\]: ([0-9.]+)", out)
    fa = re.search(r"minima \(near fa\) \[Hz\]: ([0-9.]+)", out)
    mode = re.search(r"bending-z 1\s+([0-9.]+) Hz", out)
    if not (fr and fa and mode):
        return False
    f_r, f_a, f = (float(m.group(1)) for m in (fr, fa, mode))
    return abs(f_r / f - 1) < 0.01 and f_a > f_r


def _bimorph_mode(tmp: Path):
    import modalfe

    modes = modalfe.solve_modes(_api_scene(tmp, BIMORPH), near=500.0, count=3, fidelity="solid",
                                error_estimate=False)
    return modes[0]


def _reduce_unknown_output(tmp: Path):
    import modalfe

    return modalfe.reduce(_bimorph_mode(tmp), outputs=["nowhere"], damping=modalfe.Damping(Q=100))


def _forced(tmp: Path, **kw):
    import modalfe

    return modalfe.forced_response(_api_scene(tmp, BIMORPH), **kw)


def _sweep_unknown(tmp: Path):
    import modalfe

    return modalfe.sweep(str(tmp / "api.toml"), {"nosuch": [1.0]}, out=tmp / "s.csv", selector="bending-z 1",
                         near=500.0) if _api_scene(tmp, BIMORPH) else None


def _contact(**kw):
    import modalfe

    return lambda _tmp: modalfe.simulate_contact(**kw)


def _finger(*args, **kw):
    import modalfe

    return lambda _tmp: modalfe.simulate_finger(*args, **kw)


def _damping(**kw):
    import modalfe

    return lambda _tmp: modalfe.Damping(**kw)


def _load(*args, **kw):
    import modalfe

    return lambda _tmp: modalfe.load_scene(*args, **kw)


def _scene_from_dict(data):
    from modalfe.scene import scene_from_dict

    return lambda _tmp: scene_from_dict(data)


API = [
    _api("api-load-number", "python API", _load(5), "scene"),
    _api("api-load-none", "python API", _load(None), "scene"),
    _api("api-override-unit-string", "python API", _load("cube_plate", ceramic_thickness="1mm"), "ceramic_thickness"),
    _api("api-override-bool", "python API", _load("cube_plate", thickness=True), "thickness"),
    _api("api-override-numpy-ok", "python API", lambda _tmp: __import__("modalfe").load_scene(
        "cube_plate", ceramic_thickness=__import__("numpy").float64(0.8e-3)), expect="ok",
        check=lambda s: s.params["ceramic_thickness"] == 0.8e-3),
    _api("api-dict-not-mapping", "python API", _scene_from_dict([1, 2]), "scene file"),
    _api("api-solve-near-negative", "python API", lambda tmp: _solve(tmp, near=-5.0), "analysis.near"),
    _api("api-solve-near-string", "python API", lambda tmp: _solve(tmp, near="2000"), "analysis.near"),
    _api("api-solve-count-zero", "python API", lambda tmp: _solve(tmp, near=2000.0, count=0), "count",
         owner=OTHERS),
    _api("api-solve-count-float", "python API", lambda tmp: _solve(tmp, near=2000.0, count=2.5), "count"),
    _api("api-solve-band-reversed", "python API", lambda tmp: _solve(tmp, band=(5000.0, 1.0)), "analysis.band"),
    _api("api-solve-near-and-band", "python API", lambda tmp: _solve(tmp, near=2000.0, band=(1.0, 5000.0)), "near",
         owner=OTHERS),
    _api("api-solve-fidelity", "python API", lambda tmp: _solve(tmp, fidelity="magic"), "fidelity"),
    _api("api-solve-tol", "python API", lambda tmp: _solve(tmp, fidelity="auto", tol=-1.0), "tol"),
    _api("api-solve-circuit", "python API", lambda tmp: _solve(tmp, circuit="closed"), "analysis.circuit"),
    _api("api-solve-ok", "python API", lambda tmp: _solve(tmp, near=2000.0, count=2), expect="ok",
         check=lambda modes: len(modes) == 2 and 400 < modes[0].frequency < 4000),
    _api("api-reduce-unknown-output", "python API", _reduce_unknown_output, "outputs"),
    _api("api-forced-damping-string", "python API", lambda tmp: _forced(tmp, damping="Q=150"), "damping"),
    _api("api-forced-near-negative", "python API", lambda tmp: _forced(tmp, near=-1.0), "near"),
    _api("api-forced-selector-number", "python API", lambda tmp: _forced(tmp, selector=5), "mode"),
    _api("api-damping-negative-Q", "python API", _damping(Q=-1.0), "damping.Q"),
    _api("api-damping-two-kinds", "python API", _damping(Q=10.0, zeta=0.1), "damping"),
    _api("api-damping-nan", "python API", _damping(zeta=float("nan")), "damping.zeta"),
    _api("api-contact-negative-amplitude", "python API", _contact(amplitude=[-1e-6]), "amplitude", owner=CONTACT),
    _api("api-contact-preload-nan", "python API", _contact(amplitude=[1e-6], preload=float("nan")), "preload",
         owner=CONTACT),
    _api("api-finger-frequency-negative", "python API", _finger([1e-6], -66e3), "frequency", owner=CONTACT),
    _api("api-sweep-unknown-parameter", "python API", _sweep_unknown, "nosuch", owner=OTHERS),
]


def _two_boxes(gap: float, dz: float = 0.0) -> str:
    return _edit(TINY, "[faces]", f'[[parts]]\nname = "other"\nmaterial = "steel"\norigin = [{40 + gap}, 0, {dz}]\n'
                 f"size = [10, 4, 1]\n\n[faces]")


# a 40 x 40 x 1 mm steel plate built from two 20 mm boxes side by side, clamped along one edge
_SIDE_BY_SIDE = _edit(_edit(_edit(TINY, 'kind = "beam"', 'kind = "plate"'), "size = [40, 4, 1]", "size = [20, 40, 1]"),
                      "[faces]", '[[parts]]\nname = "other"\nmaterial = "steel"\norigin = [20, 0, 0]\n'
                      'size = [20, 40, 1]\n\n[faces]').replace('tip = ["beam.xmax"]', 'tip = ["other.xmax"]')

ELECTRODES_AND_MODELS = [
    _file("disconnected-parts", "parts", _two_boxes(5.0), "parts", owner=OTHERS),
    _file("parts-touch-along-edge", "parts", _two_boxes(0.0, dz=1.0), "parts", owner=OTHERS),
    _file("electrode-on-steel", "electrodes", _edit(TINY, "[clamps]", '[electrodes]\ntip = "drive"\n[clamps]'),
          "electrodes", owner=OTHERS),
    _file("electrode-drive-and-ground", "electrodes", _edit(_edit(
        BIMORPH, 'electrode_bottom = ["patch.zmin"]', 'electrode_bottom = ["patch.zmin"]\nalso = ["patch.zmax"]'),
        'electrode_bottom = "ground"', 'electrode_bottom = "ground"\nalso = "ground"'), "electrodes", owner=OTHERS),
    _file("electrode-role-hot", "electrodes", _edit(BIMORPH, 'electrode_top = "drive"', 'electrode_top = "hot"'),
          "electrodes.electrode_top"),
    _file("electrode-missing-group", "electrodes", _edit(BIMORPH, 'electrode_top = "drive"',
                                                         'electrode_top = "drive"\nnowhere = "ground"'),
          "electrodes.nowhere"),
    _file("plate-side-by-side-boxes", "parts", _SIDE_BY_SIDE, "", expect="ok", check=lambda out: "DOFs" in out,
          owner=OTHERS, extra=("--fidelity", "plate", "--no-error-estimate")),
]


def _json_ok(out: str) -> bool:
    json.loads(out)
    return True


def _damping_user(out: str) -> bool:
    data = json.loads(out)
    return data["damping_source"].startswith("set by the user") and "assumption" not in data["notes"][0]


def _twice_identical(tmp: Path) -> bool:
    from tests.hostile.harness import _run_cli

    path = tmp / "bimorph.toml"
    path.write_text(BIMORPH)
    first = _run_cli(["forced", str(path), "--outputs", "tip,clamp", "--json"])
    import modalfe.caches as caches

    caches.clear(disk=True)  # a fresh process's state: meshes, models and answers made anew
    second = _run_cli(["forced", str(path), "--outputs", "tip,clamp", "--json"])
    a, b = json.loads(first[1]), json.loads(second[1])
    return _same(a, b)


def _same(a, b) -> bool:
    """JSON documents equal, numbers to 1e-6 relative: the frequencies agree to the bit, but the mode shapes of two
    solves of one question agree only to ARPACK's residual tolerance (1e-8, on 2 PARDISO threads not bitwise
    repeatable), and what is linear in a shape (C0 of the one-mode circuit, the FRF, fa through a fresh or a reused
    factorization) carries that, divided by the mode's gap: measured up to 1.2e-7 apart (C0 3.5e-8, FRF 1.1e-7)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float):
        return abs(a - b) <= 1e-6 * max(abs(a), abs(b))
    return a == b


def _assumptions_follow(tmp: Path) -> bool:
    import modalfe

    lines = modalfe.load_scene("cube_plate", ceramic_thickness=0.65e-3, foot_height=5e-3).assumptions
    text = " ".join(lines)
    return "x 0.65 mm" in text and "x 1 mm" not in text and "x 5 mm" in text and "Abaqus 42.7 kHz: see" not in text


TEXT = [
    Case("forced-damping-flag-source", "text", "ok", argv=("forced", "{file}", "--damping", "Q=80", "--outputs", "tip",
                                                             "--json"),
         files={"bimorph.toml": BIMORPH}, check=_damping_user),
    Case("forced-set-damping-source", "text", "ok", argv=("forced", "{file}", "--set", 'drive.damping="Q=80"',
                                                          "--outputs", "tip", "--json"),
         files={"bimorph.toml": BIMORPH}, check=_damping_user),
    Case("forced-json-with-plot", "text", "ok", argv=("forced", "{file}", "--outputs", "tip", "--json", "--plot",
                                                             "{tmp}/p.png"),
         files={"bimorph.toml": BIMORPH}, check=_json_ok),
    Case("forced-json-twice-identical", "text", "ok", call=_twice_identical, check=bool),
    Case("assumptions-follow-set", "text", "ok", call=_assumptions_follow, check=bool),
    Case("modes-json-pure", "text", "ok", argv=("modes", "{file}", "--json", *SOLVE), files={"scene.toml": TINY},
         check=_json_ok),
    Case("friction-json-with-plot", "text", "ok", argv=("friction", "--amplitude", "0:2e-6:3", "--json", "--plot",
                                                        "{tmp}/f.png"), check=_json_ok),
    Case("report-json-pure", "text", "ok", argv=("report", "--scene", "tile_eq5", "--fidelity", "solid",
                                                 "--no-error-estimate", "--json", "--jobs", "1"), check=_json_ok),
]


def _raise_interrupt(*_args, **_kw):
    raise KeyboardInterrupt


def _patched(target: str, argv: list[str]):
    """Run the CLI with ``target`` (module.attribute) replaced by a function raising KeyboardInterrupt."""
    import importlib

    def call(tmp: Path):
        from tests.hostile.harness import _run_cli

        module_name, attribute = target.rsplit(".", 1)
        module = importlib.import_module(module_name)
        saved = getattr(module, attribute)
        setattr(module, attribute, _raise_interrupt)
        try:
            (tmp / "scene.toml").write_text(TINY)
            status, _out, err = _run_cli([a.replace("{file}", str(tmp / "scene.toml")) for a in argv])
        finally:
            setattr(module, attribute, saved)
        return status == 130 and err.strip() == "modalfe: interrupted"
    return call


def _sigint(args: list[str], after: float):
    def shell(tmp: Path):
        (tmp / "scene.toml").write_text(TINY)
        return modalfe_subprocess([a.replace("{file}", str(tmp / "scene.toml")) for a in args],
                                  interrupt_after=after, timeout=60, env={"MODALFE_CACHE": str(tmp / "cache")})
    return shell


def _cache_file(tmp: Path) -> None:
    (tmp / "cache_is_a_file").write_text("not a folder")


def _damaged_cache(tmp: Path) -> None:
    from tests.hostile.harness import _run_cli

    (tmp / "scene.toml").write_text(TINY)
    _run_cli(["modes", str(tmp / "scene.toml"), *SOLVE])
    import modalfe.caches as caches

    caches.clear()
    for path in (tmp / "cache").rglob("*.npz"):
        path.write_bytes(path.read_bytes()[:100])


INTERRUPTS_AND_CACHES = [
    Case("interrupt-during-solve", "interrupts", "ok", call=_patched("modalfe.solve.api.solve_modes",
                                                                      ["modes", "{file}"]), check=bool),
    Case("interrupt-during-load", "interrupts", "ok", call=_patched("modalfe.scene.load_scene", ["modes", "{file}"]),
         check=bool),
    Case("sigint-subprocess-modes", "interrupts", "interrupt",
         # a finer mesh than the default (~10 s), so that the solve cannot finish before the signal at 3 s
         shell=_sigint(["modes", "cube_plate", "--fidelity", "solid", "--set", "mesh.elements_per_wavelength=16"], 3.0),
         timeout=60),
    Case("sigint-subprocess-report", "interrupts", "interrupt", shell=_sigint(["report", "--jobs", "2"], 6.0),
         timeout=90, slow=True),
    Case("cache-is-a-file", "caches", "ok", argv=("modes", "{file}", *SOLVE), files={"scene.toml": TINY},
         prepare=_cache_file, env={"MODALFE_CACHE": "{tmp}/cache_is_a_file"}, check=_modes_listed, owner=OTHERS),
    Case("cache-under-a-file", "caches", "ok", argv=("modes", "{file}", *SOLVE), files={"scene.toml": TINY},
         prepare=_cache_file, env={"MODALFE_CACHE": "{tmp}/cache_is_a_file/sub"}, check=_modes_listed,
         owner=OTHERS),
    Case("cache-damaged-npz", "caches", "ok", argv=("modes", "{file}", *SOLVE), files={"scene.toml": TINY},
         prepare=_damaged_cache, env={"MODALFE_CACHE": "{tmp}/cache"}, check=_modes_listed, owner=OTHERS),
    Case("max-memory-env-word", "sizes", "error", "MODALFE_MAX_MEMORY", argv=("modes", "{file}", *SOLVE),
         files={"scene.toml": TINY}, env={"MODALFE_MAX_MEMORY": "lots"}),
    Case("max-memory-too-small", "sizes", "error", "mesh", argv=("modes", "{file}", *SOLVE),
         files={"scene.toml": TINY}, env={"MODALFE_MAX_MEMORY": "1e6"}),
]

# a disc on a plate (curved parts: tetrahedra), for the cases of parts beyond boxes
DISC = """name = "disc"
units = "mm"
[analysis]
near = 20000.0
count = 2
[mesh]
max_size = 6
min_layers = 1
[[parts]]
name = "plate"
material = "CuBe"
origin = [0, 0, 0]
size = [30, 30, 1]
[[parts]]
name = "disc"
shape = "cylinder"
material = "PZT-5A"
centre = [15, 15, 1]
axis = "z"
radius = 6
height = 0.5
poling = "+z"
[faces]
top = ["disc.top"]
bottom = ["disc.bottom"]
[electrodes]
top = "drive"
bottom = "ground"
"""

MEASURED = """[[mode]]
label = "bending-z 1"
frequency = 520.0
sigma = 5.0
"""


def _disc(id: str, old: str, new: str, field: str, **kw) -> Case:
    return _file(id, "curved parts", _edit(DISC, old, new), field, **kw)


def _calibrate(id: str, measured: str, field: str, *args: str) -> Case:
    return _cli(id, "calibrate", ("calibrate", "{file}", "--measured", "{tmp}/measured.toml", *args), field,
                files={"scene.toml": TINY, "measured.toml": measured})


DESIGN = [
    _disc("disc-radius-negative", "radius = 6", "radius = -6", "parts[1].radius"),
    _disc("disc-radius-word", "radius = 6", 'radius = "six"', "parts[1].radius"),
    _disc("disc-axis-w", 'axis = "z"', 'axis = "w"', "parts[1].axis"),
    _disc("disc-radial-poling", 'poling = "+z"', 'poling = "radial"', "part 'disc': radial poling"),
    _disc("disc-poling-sideways", 'poling = "+z"', 'poling = "up"', "part 'disc': poling"),
    _disc("disc-shape-sphere", 'shape = "cylinder"', 'shape = "sphere"', "parts[1].shape"),
    _disc("disc-hex-two-axes", "[faces]", '[[parts]]\nname = "pin"\nshape = "cylinder"\nmaterial = "CuBe"\n'
          'centre = [30, 15, 0.5]\naxis = "x"\nradius = 0.4\nheight = 3\n[faces]', "mesh.element",
          extra=("--set", "mesh.element=hex")),
    _disc("disc-side-unknown", 'top = ["disc.top"]', 'top = ["disc.zmax"]', "faces.top"),
    _disc("disc-overlaps-plate", "centre = [15, 15, 1]", "centre = [15, 15, 0.5]", "parts"),
    _disc("ring-inner-outside", 'shape = "cylinder"\nmaterial = "PZT-5A"\ncentre = [15, 15, 1]\naxis = "z"\nradius = 6',
          'shape = "ring"\nmaterial = "PZT-5A"\ncentre = [15, 15, 1]\naxis = "z"\ninner = 7\nouter = 6',
          "part 'disc': inner radius"),
    _tiny("window-outside-face", "windows", 'tip = ["beam.xmax"]',
          'tip = [{face = "beam.zmax", window = [[0, 0], [50, 4]]}]', "faces.tip"),
    _tiny("window-one-corner", "windows", 'tip = ["beam.xmax"]', 'tip = [{face = "beam.zmax", window = [[0, 0]]}]',
          "faces.tip[0].window"),
    _tiny("window-no-face", "windows", 'tip = ["beam.xmax"]', 'tip = [{window = [[0, 0], [5, 4]]}]', "faces.tip[0]"),
    _calibrate("calibrate-sigma-missing", MEASURED.replace("sigma = 5.0\n", ""),
               "{tmp}/measured.toml: mode[0].sigma", "--vary",
               "materials.steel.E"),
    _calibrate("calibrate-sigma-negative", MEASURED.replace("sigma = 5.0", "sigma = -5.0"),
               "{tmp}/measured.toml: mode[0].sigma", "--vary",
               "materials.steel.E"),
    _calibrate("calibrate-no-modes", "title = 'nothing'\n", "{tmp}/measured.toml: title", "--vary",
               "materials.steel.E"),
    _calibrate("calibrate-frequency-word", MEASURED.replace("520.0", '"fast"'),
               "{tmp}/measured.toml: mode[0].frequency", "--vary",
               "materials.steel.E"),
    _calibrate("calibrate-vary-unknown", MEASURED, "wingspan", "--vary", "wingspan"),
    _cli("calibrate-measured-missing", "calibrate",
         ("calibrate", "{file}", "--measured", "{tmp}/nowhere.toml", "--vary", "materials.steel.E"),
         "{tmp}/nowhere.toml"),
    _cli("tune-separation-word", "tune", ("tune", "{file}", "--target", "bending-z 1=900", "--vary",
                                          "materials.steel.E", "--separation", "wide"), "--separation"),
    _cli("tune-maximize-unknown", "tune", ("tune", "{file}", "--target", "bending-z 1=900", "--vary",
                                           "materials.steel.E", "--maximize", "beauty"), "--maximize"),
    _cli("tune-starts-without-bounds", "tune", ("tune", "{file}", "--target", "bending-z 1=900", "--vary",
                                                "materials.steel.E", "--starts", "3"), "--bounds"),
    _cli("tune-out-directory", "tune", ("tune", "{file}", "--target", "bending-z 1=900", "--vary",
                                        "materials.steel.E", "--out", "{tmp}"), "--out"),
]



def _bimorph(id: str, argv: tuple[str, ...], field: str, **kw) -> Case:
    """A case of issue 35 on the user guide's bimorph: refused before the solve, or answered."""
    return _cli(id, "issue 35", argv, field, files={"bimorph.toml": BIMORPH, **kw.pop("files", {})}, **kw)


ISSUE_35 = [
    _bimorph("forced-point-named-like-a-face-group", ("forced", "{file}", "--point", "tip=0.04,0.002,0.001"),
             "--point: 'tip' is a face group"),
    _bimorph("forced-point-twice", ("forced", "{file}", "--point", "p=0.02,0.002,0.001", "--point",
                                    "p=0.03,0.002,0.001"), "--point: 'p' given twice"),
    _bimorph("forced-volts-beside-force", ("forced", "{file}", "--force", "tip=0,0,1", "--volts", "50", "--plot",
                                           "{tmp}/f.png"), "--volts"),
    _bimorph("forced-volts-without-plot", ("forced", "{file}", "--volts", "50"), "--volts"),
    _bimorph("forced-base-acceleration-unsupported", ("forced", "{file}", "--base-acceleration", "z", "--set",
                                                      "clamps={}"), "drive.load: a base acceleration"),
    _bimorph("admittance-points-million", ("admittance", "{file}", "--band", "400", "700", "--points", "1000000"),
             "--points: needs 2 to 100,000"),
    _bimorph("admittance-zeta-2", ("admittance", "{file}", "--band", "400", "700", "--damping", "zeta=2"),
             "--damping: damping.zeta: modal damping ratio 2 is overdamped"),
    _bimorph("admittance-eta-3", ("admittance", "{file}", "--band", "400", "700", "--damping", "eta=3"),
             "--damping: modal damping ratio 1.5 is overdamped"),
    _bimorph("admittance-mode-damping-twice", ("admittance", "{file}", "--band", "400", "700", "--mode-damping",
                                               "bending-z 1=Q=10", "--mode-damping", "bending-z 1=Q=20"),
             "--mode-damping: mode 'bending-z 1' given twice"),
    _bimorph("admittance-mode-damping-once", ("admittance", "{file}", "--band", "400", "700", "--mode-damping",
                                              "bending-z 1=Q=10"), "", expect="ok",
             check=lambda out: "Q=10 (per mode)" in out),
    _bimorph("admittance-band-without-resonance", ("admittance", "{file}", "--band", "1000", "1200"), "", expect="ok",
             check=lambda out: "no resonance in the band" in out and "maxima (near fr) [Hz]: none" in out),
    _bimorph("admittance-band-centred-on-resonance", ("admittance", "{file}", "--band", "445.222", "645.222",
                                                      "--points", "5"), "", expect="ok",
             check=lambda out: _fr_fa_beside_the_mode(out)),
    _bimorph("set-damping-overdamped", ("forced", "{file}", "--set", 'drive.damping="zeta=2"'),
             "drive.damping: modal damping ratio 2 is overdamped"),
    _bimorph("forced-mode-index", ("forced", "{file}", "--mode", "0"), "--mode: '0' is a number"),
    _bimorph("tune-target-index", ("tune", "{file}", "--target", "1=900", "--vary", "materials.steel.E"),
             "target: '1' is a number"),
    _bimorph("admittance-mode-damping-index", ("admittance", "{file}", "--band", "400", "700", "--mode-damping",
                                               "0=Q=10"), "--mode-damping: '0' is a number"),
    _bimorph("show-mode-not-a-label", ("show", "{file}", "--mode", "bending 1", "--out", "{tmp}/m.png"),
             "--mode: 'bending 1' is not a mode label"),
    _bimorph("show-out-upper-case-png", ("show", "{file}", "--out", "{tmp}/m.PNG"), "", expect="ok",
             check=lambda out: out.strip().endswith("m.PNG")),
    _bimorph("calibrate-measured-binary", ("calibrate", "{file}", "--measured", "{tmp}/measured.toml", "--vary",
                                           "materials.steel.E"), "{tmp}/measured.toml: not UTF-8 text",
             files={"measured.toml": bytes(range(256))}),
    _bimorph("admittance-coarse-grid", ("admittance", "{file}", "--band", "400", "700", "--points", "4"), "",
             expect="ok", check=lambda out: _fr_fa_beside_the_mode(out) and "wider than the resonance" in out),
]

# issue 35, contact: the orbit reported is the one the motion from rest reaches (1.5 kHz, dn 20 N s/m, Fn 10 N; onset
# 1.295 um). Reference flight ratios from the brute force from rest (RK23, max step 1e-6 s): 23.46 % at 1.0 um, 75.86 %
# at 1.3 um (modalfe answered 2.04 %), 76.01 % at 1.4 um (75.23 %, a period-3 orbit); 0.2 pp as the benchmark's target
def _foot_from_rest(amplitude: float):
    import modalfe
    from modalfe.contact.foot import FootParameters

    return lambda _tmp: modalfe.simulate_contact(amplitude=[amplitude], preload=10.0,
                                                 parameters=FootParameters(frequency=1500.0, dn=20.0))


def _onset_1500() -> float:
    from modalfe.contact.foot import FootParameters

    return FootParameters(frequency=1500.0, dn=20.0).onset_amplitude(10.0)


# issue 35, labels: bodies of revolution with a hole were labelled "?"
def _revolution(name: str, axis: str, inner: float, outer: float, height: float, near: float) -> str:
    """A free steel ring or tube (mm) as a scene file, its part on one line."""
    return (f'name = "{name}"\nunits = "mm"\nanalysis = {{near = {near}, count = 12}}\n'
            f'mesh = {{max_size = 3, min_layers = 1}}\nmaterials = {{steel = {{E = 200e9, nu = 0.3, rho = 7850.0}}}}\n'
            f'parts = [{{name = "{name}", shape = "ring", material = "steel", centre = [0, 0, 0], axis = "{axis}", '
            f'inner = {inner}, outer = {outer}, height = {height}}}]\n')


RING = _revolution("ring", "z", 15, 20, 3, 5000.0)
TUBE = _revolution("tube", "x", 9, 10, 12, 8000.0)


def _labelled(out: str) -> bool:
    """Every listed mode has a label (no "?")."""
    return _modes_listed_any(out) and " ? " not in out and "?#" not in out


def _modes_listed_any(out: str) -> bool:
    return "(2,0)" in out and "n=2" in out


ISSUE_35_TRUST = [
    _api("contact-from-rest-below-onset", "contact", _foot_from_rest(1.0e-6), expect="ok",
         check=lambda c: abs(c.flight_ratio[0] - 23.46) < 0.2),
    _api("contact-from-rest-above-onset", "contact", _foot_from_rest(1.3e-6), expect="ok",
         check=lambda c: abs(c.flight_ratio[0] - 75.86) < 0.2),
    _api("contact-from-rest-period-one", "contact", _foot_from_rest(1.4e-6), expect="ok",
         check=lambda c: abs(c.flight_ratio[0] - 76.01) < 0.2 and bool(c.periodic[0])),
    _api("contact-from-rest-at-onset", "contact", lambda tmp: _foot_from_rest(_onset_1500())(tmp), expect="ok",
         check=lambda c: bool(c.periodic[0]) and c.flight_ratio[0] >= 0),
    _file("ring-labels", "labels", RING, "", expect="ok", check=_labelled),
    _file("tube-labels", "labels", TUBE, "", expect="ok", check=_labelled),
]

# issue 35, today's features: tune --objective, sweep --outcome (one parser, ``parse_outcome``), the admittance's FE
# open-circuit table, show's second rendering process; and what they met on the way
TUNE = ("tune", "{file}", "--target", "bending-z 1=900", "--vary", "materials.steel.E", "--objective")
SWEEP = ("sweep", "{file}", "--param", "materials.steel.E=190e9:210e9:2", "--out", "{tmp}/s.csv", "--outcome")
ADMITTANCE = ("admittance", "{file}", "--band", "400", "700", *SOLVE)


def _open_circuit_rows(out: str) -> list[tuple[float, float, float]]:
    """(fr, fa, k_eff) of the admittance's "FE open circuit" table."""
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if "FE open circuit" in line) + 2
    rows = []
    for line in lines[start:]:
        words = line.split()  # the label, which may hold spaces, then fr, fa, k_eff
        try:
            fr, fa, k = (float(w) for w in words[-3:]) if len(words) >= 4 else ()
        except ValueError:
            break
        rows.append((fr, fa, k))
    return rows


def _fa_above_fr(out: str) -> bool:
    rows = _open_circuit_rows(out)
    return bool(rows) and all(fa >= fr and 0 < k < 1 for fr, fa, k in rows)


def _shaped_box(poling: str) -> str:
    """A free PZT-4 box poled by ``poling`` beside a Cu-Be disc: a scene with shapes (mm)."""
    return (f'name = "shaped"\nunits = "mm"\nanalysis = {{near = 50000.0, count = 4}}\n'
            f'parts = [{{name = "bar", material = "PZT-4", origin = [0, 0, 0], size = [10, 4, 1], '
            f'poling = "{poling}"}}, {{name = "disc", shape = "cylinder", material = "CuBe", centre = [5, 2, 1], '
            f'axis = "z", radius = 1.5, height = 0.5}}]\n')


NEW_FEATURES = [
    *[_bimorph(f"tune-objective-{id}", (*TUNE, text), field) for id, text, field in [
        ("empty", "", "--objective: expected"),
        ("volts-missing", "reduction-at", "--objective: give volts=V"),
        ("volts-word", "reduction-at volts=abc", "--objective: volts must be a number"),
        ("volts-negative", "reduction-at volts=-5", "--objective: volts must be a positive finite number"),
        ("volts-nan", "reduction-at volts=nan", "--objective: volts must be a positive finite number"),
        ("volts-inf", "reduction-at volts=inf", "--objective: volts must be a positive finite number"),
        ("volts-twice", "reduction-at volts=50 volts=60", "--objective: 'volts=60' is not one of"),
        ("preload-negative", "reduction-at volts=50 preload=-3", "--objective: preload: must be >= 0"),
        ("preload-inf", "reduction-at volts=50 preload=inf", "--objective: preload: must be finite"),
        ("contact-bad", "reduction-at volts=50 contact=bad", "--objective: contact must be foot or finger"),
        ("reduction-over-one", "volts-for reduction=150%", "--objective reduction: expected a fraction"),
        ("no-outputs", "reduction-at volts=50", "objective: the scene has no outputs"),
    ]],
    _bimorph("tune-objective-and-maximize", (*TUNE, "reduction-at volts=50", "--maximize", "k_eff"),
             "--objective: give it or --maximize"),
    *[_bimorph(f"sweep-outcome-{id}", (*SWEEP, text), field) for id, text, field in [
        ("volts-missing", "reduction", "--outcome: give volts=V"),
        ("volts-word", "reduction volts=x", "--outcome: volts must be a number"),
        ("volts-overflow", "reduction volts=1e400", "--outcome: volts must be a positive finite number"),
        ("tune-kind", "volts-for reduction=0.5", "--outcome: expected"),
        ("no-space", "reduction=0.5", "--outcome: expected"),
        ("contact-glass", "reduction volts=10 contact=glass", "--outcome: contact must be foot or finger"),
        ("preload-word", "reduction volts=10 preload=abc", "--outcome: preload and speed must be numbers"),
        ("preload-negative", "reduction volts=10 preload=-1", "--outcome: preload: must be >= 0"),
        ("speed-negative", "reduction volts=10 speed=-1", "--outcome: speed: must be >= 0"),
    ]],
    _bimorph("admittance-open-circuit-table", ADMITTANCE, "", expect="ok", check=_fa_above_fr),
    _bimorph("admittance-no-ground", ADMITTANCE, "electrodes: the scene has no ground electrode",
             files={"bimorph.toml": BIMORPH.replace('electrode_bottom = "ground"\n', "")}),
    _bimorph("forced-no-ground", ("forced", "{file}", *SOLVE), "electrodes: the scene has no ground electrode",
             files={"bimorph.toml": BIMORPH.replace('electrode_bottom = "ground"\n', "")}),
    _bimorph("admittance-both-faces-driven", ADMITTANCE, "electrodes.electrode_top: on the zmax face",
             files={"bimorph.toml": BIMORPH.replace('electrode_bottom = "ground"', 'electrode_bottom = "drive"')}),
    _bimorph("show-out-in-proc", ("show", "{file}", "--out", "/proc/modalfe-hostile.png"), "--out"),
    _bimorph("show-out-in-sys", ("show", "{file}", "--out", "/sys/modalfe-hostile.png"), "--out"),
    _file("box-poled-along-x-among-shapes", "scene file", _shaped_box("+x"), "parts[0].poling: a box is poled along z"),
    _file("box-poled-radial-among-shapes", "scene file", _shaped_box("radial"), "parts[0].poling"),
    _file("box-poled-plus-z-among-shapes", "scene file", _shaped_box("+z"), "", expect="ok",
          check=lambda out: "Hz" in out),
    # session 20: tune's area objective and mode bounds, a load that does not drive the mode
    *[_bimorph(f"tune-area-{id}", (*TUNE, text), field) for id, text, field in [
        ("empty", "area", "--objective: give reduction=R"),
        ("volts-missing", "area reduction=0.2", "--objective: give volts=V"),
        ("width-over-one", "area reduction=0.2 volts=10 width=2", "--objective width: expected a fraction"),
        ("width-zero", "area reduction=0.2 volts=10 width=0", "--objective width: expected a fraction"),
        ("width-twice", "area reduction=0.2 volts=10 width=0.02 width=0.03", "--objective: 'width=0.03' is not one of"),
        ("volts-negative", "area reduction=0.2 volts=-1", "--objective: volts must be a positive finite number"),
        ("no-outputs", "area reduction=0.2 volts=10 contact=finger", "objective: the scene has no outputs"),
    ]],
    *[_bimorph(f"tune-mode-bound-{id}", (*TUNE[:-1], *bound), field) for id, bound, field in [
        ("no-operator", ("--mode-bound", "(0,6)"), '--mode-bound: expected "LABEL>=HZ"'),
        ("no-frequency", ("--mode-bound", "(0,6)>="), "--mode-bound: '(0,6)>=' has no frequency"),
        ("word", ("--mode-bound", "(0,6)>=abc"), "--mode-bound: the frequency must be a number"),
        ("negative", ("--mode-bound", "(0,6)>=-5"), "--mode-bound: the frequency must be a positive finite number"),
        ("infinite", ("--mode-bound", "(0,6)>=inf"), "--mode-bound: the frequency must be a positive finite number"),
        ("not-a-label", ("--mode-bound", "nonsense>=5"), "--mode-bound: 'nonsense' is not a mode label"),
        ("twice", ("--mode-bound", "bending-z 1>=100", "--mode-bound", "bending-z 1>=200"), "mode_bounds: give each"),
    ]],
    _bimorph("forced-sideways-force-on-bending", ("forced", "{file}", *SOLVE, "--force", "tip=0,1,0", "--outputs",
                                                  "tip"), "load: the force along (0, 1, 0) on 'tip'"),
]

CASES: list[Case] = [*SCENE_FILES, *MATERIALS, *FLAGS, *SETS, *PATHS, *SWEEPS, *API, *ELECTRODES_AND_MODELS,
                     *TEXT, *INTERRUPTS_AND_CACHES, *DESIGN, *ISSUE_35,
                     *ISSUE_35_TRUST, *NEW_FEATURES]
