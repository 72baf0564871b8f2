"""The four seed devices as built-in scenes, with their targets and the assumptions they rest on.

Geometry defaults live in the builders' signatures (``modalfe.geometry/``); this module adds what a
scene needs beyond geometry. Every number carries its source.
"""

from __future__ import annotations

from modalfe.scene.scene import Analysis, Drive, MeshSettings, Scene, Target, WorkingMode


def rubber_mount_stiffness(*, E: float, nu: float, area: float, height: float) -> tuple[float, float, float]:
    """(kx, ky, kz) [N/m] of a square rubber block bonded at both ends.

    kz = E A / h (seed 002, sec. 4.3); lateral: shear G A / h in series with fixed-guided bending
    h^3 / (12 E I) (Timoshenko beam), I = side^4 / 12. The shape-factor stiffening of a bonded
    block in compression (Gent 2012, ch. 3) is about 1 + 2 (0.28)^2 ~ 1.16 here and is left out,
    as in the seed's lumped model.
    """
    G = E / (2 * (1 + nu))
    side = area**0.5
    inertia = side**4 / 12
    lateral = 1 / (height / (G * area) + height**3 / (12 * E * inertia))
    return (lateral, lateral, E * area / height)


# seed 002: SBR E = 2 MPa, A = 8 cm^2, h = 2.5 cm; nu 0.49 (docs/assumptions.md, Honeycomb tile)
MOUNT_STIFFNESS = rubber_mount_stiffness(E=2.0e6, nu=0.49, area=8e-4, height=0.025)


def cube_plate() -> Scene:
    """Cu-Be plate with ten PZT ceramics and four feet, working mode (0,6) (seeds 000, 001)."""
    return Scene(
        name="cube_plate",
        device="cube_plate",
        symmetry=("y",),  # mirror-symmetric about y = width / 2; working modes are symmetric too
        params={},
        electrodes={"electrode_top": "drive", "electrode_bottom": "ground"},
        analysis=Analysis(near=40.7e3, count=8),
        drive=Drive(
            damping_fallback="Q=150",
            damping_fallback_source="assumption: the seeds give no Q for the plate (docs/assumptions.md, Damping: "
                                    "default ~150)",
            outputs=("foot_1", "foot_2", "foot_3", "foot_4"),
            targets=(
                Target("amplitude_available", 1.7e-6, "m", "measured", "seed 001, 0-peak at the feet"),
                Target("amplitude_strong_feeling", 0.65e-6, "m", "measured", "seed 001"),
                Target("response_time", 1e-3, "s", "measured", "seed 001, amplitude step with preload"),
            ),
        ),
        mesh=MeshSettings(elements_per_wavelength=6.0, max_frequency=50e3),
        working_modes=(
            WorkingMode("(0,6)", 40.7e3, (
                Target("f_measured", 40.7e3, "Hz", "measured", "seed 001, measured resonance"),
                Target("f_reference_fe", 42.7e3, "Hz", "reference", "seed 001, Abaqus C3D8E, no bond layer"),
            ), symmetric=("x",)),  # six nodal lines across x, placed alike about the mid-length: even in x
        ),
        assumptions=_cube_plate_assumptions({}),
        assumption_writer=builtin_assumptions,
    )


def glass_plate() -> Scene:
    """1.9 mm glass plate with two piezo strips; modes near 66 and 225 kHz (seed 004)."""
    return Scene(
        name="glass_plate",
        device="glass_plate",
        # mirror-symmetric about both mid-planes; the two piezos are driven in phase, so modes
        # antisymmetric about x = L / 2 get no net drive: the quarter model keeps just the driven ones
        symmetry=("x", "y"),
        params={},
        electrodes={"electrode_outer": "drive", "electrode_inner": "ground"},
        analysis=Analysis(near=66e3, count=8),
        drive=Drive(
            damping_fallback="Q=150",
            damping_fallback_source="docs/assumptions.md, Damping: Q ~ pi f tau from seed 004's response times, "
                                    "default 150",
            outputs=(("centre_top", (0.03, 0.01, 1.9e-3)), ("quarter_top", (0.015, 0.01, 1.9e-3))),
            targets=(
                Target("amplitude_pp_66kHz", 2.8e-6, "m", "measured", "seed 004, peak-to-peak"),
                Target("amplitude_pp_225kHz", 194e-9, "m", "measured", "seed 004, peak-to-peak"),
                Target("response_time_66kHz", 1.3e-3, "s", "measured", "seed 004"),
                Target("response_time_225kHz", 0.5e-3, "s", "measured", "seed 004"),
            ),
        ),
        mesh=MeshSettings(elements_per_wavelength=6.0, max_frequency=250e3),
        working_modes=(
            WorkingMode("(0,n)", 66e3, (
                Target("f_measured", 66e3, "Hz", "measured", "seed 004"),
                Target("wavelength_measured", 15e-3, "m", "measured", "seed 004"),
            )),
            WorkingMode("(0,n)", 225e3, (
                Target("f_measured", 225e3, "Hz", "measured", "seed 004"),
                Target("wavelength_measured", 7.5e-3, "m", "measured", "seed 004"),
            )),
        ),
        assumptions=_glass_plate_assumptions({}),
        assumption_writer=builtin_assumptions,
    )


def honeycomb_tile() -> Scene:
    """Honeycomb sandwich tile on four SBR mounts with a 2.3 kg actuator at the centre (seed 002)."""
    return Scene(
        name="honeycomb_tile",
        device="honeycomb_tile",
        params={},
        springs={f"mount_{i}": MOUNT_STIFFNESS for i in range(1, 5)},
        # moving mass 2.7 kg (seed 002, M0) minus the 0.4 kg panel: actuator, bracket and rod
        masses={"actuator": 2.3},
        analysis=Analysis(band=(1.0, 1500.0)),
        drive=Drive(
            damping_fallback="Q=150",
            damping_fallback_source="assumption: seed 002 gives no damping for the tile (docs/assumptions.md, Damping: "
                           "default ~150)",
            load="force actuator=0,0,1",
            load_source="seed 002: an inertial actuator at the centre drives the tile (1 N along z on its "
                        "40 x 40 mm pad; results per newton)",
            outputs=("actuator", "mean:actuator", "mount_1"),
        ),
        reference_spectra={"suspension": "seed 002 FEM: 28, 45, 51, 77 Hz",  # sec. 4.4.1
                           "plate": "seed 002 FEM: 896, 1032 Hz"},  # sec. 4.4.1 and Fig. 10
        mesh=MeshSettings(elements_per_wavelength=6.0, max_frequency=1500.0, max_size=0.02),
        working_modes=(
            WorkingMode("heave", 45.0, (
                Target("f_reference_fe", 45.0, "Hz", "reference", "seed 002, FEM heave mode"),
                Target("f_lumped", 49.0, "Hz", "analytic", "seed 002, f0 = sqrt(4EA/(h M0)) / 2 pi"),
            ), symmetric=("x", "y")),  # the whole tile bouncing on its four mounts
            WorkingMode("(1,1)", 896.0, (
                Target("f_analytic_eq5", 845.0, "Hz", "analytic", "seed 002, eq. (5)"),
                Target("f_reference_fe", 896.0, "Hz", "reference", "seed 002, FEM (1,1)"),
            ), antisymmetric=("x", "y")),  # twisting: w ~ (x - a/2)(y - b/2), odd about both mid-planes
        ),
        assumptions=_honeycomb_tile_assumptions({}),
        assumption_writer=builtin_assumptions,
        kind="plate",
    )


# seed 002 eq. (5) inputs: facing E_f 60 GPa, t_f 0.083 cm, core h 2.5 cm, mean density 170 kg/m^3
EQ5_FACING_MODULUS, EQ5_FACING_THICKNESS, EQ5_CORE_HEIGHT, EQ5_DENSITY = 60e9, 0.83e-3, 0.025, 170.0


def tile_eq5() -> Scene:
    """The seed's eq. (5) as an equivalent homogeneous plate, simply supported (seed 002).

    Eq. (5) is thin-plate theory with E = E_f t_f / h (its own substitution into eq. (3)), the
    panel's mean density and no Poisson factor, at k = pi sqrt(2) / L: the (1,1) mode of a
    simply supported square plate. This scene is that plate in 3-D, with diaphragm supports (no
    in-plane tangential and no normal displacement on the side faces), so the FE value differs from
    eq. (5) only by shear and rotary inertia (h / L = 0.082) and discretization.
    """
    L = 0.304
    return Scene(
        name="tile_eq5",
        device="boxes",
        params={
            "parts": [{"name": "plate", "region": "plate", "material": "eq5", "origin": [0, 0, 0],
                       "size": [L, L, EQ5_CORE_HEIGHT]}],
            "faces": {"side_x": ["plate.xmin", "plate.xmax"], "side_y": ["plate.ymin", "plate.ymax"]},
        },
        materials={"eq5": {"E": EQ5_FACING_MODULUS * EQ5_FACING_THICKNESS / EQ5_CORE_HEIGHT, "nu": 0.0,
                           "rho": EQ5_DENSITY, "source": "seed 002 eq. (5): E = E_f t_f / h"}},
        clamps={"side_x": "yz", "side_y": "xz"},
        analysis=Analysis(near=845.0, count=4),
        mesh=MeshSettings(elements_per_wavelength=6.0, max_frequency=2000.0),
        working_modes=(
            # labels count nodal lines: the simply supported one-half-wave (1,1) mode has none
            WorkingMode("(0,0)", 845.0, (
                Target("f_analytic_eq5", 845.0, "Hz", "analytic", "seed 002, eq. (5)"),
            )),
        ),
        assumptions=("equivalent plate of eq. (5), simply supported: a check of the formula, not of the tile",),
        symmetry=("x", "y"),
    )


def ciliary_beam() -> Scene:
    """100 x 5 x 5 mm brass cantilever with a PZT bimorph at x0 = 68 mm; mode 6 (seed 003)."""
    return Scene(
        name="ciliary_beam",
        device="ciliary_beam",
        symmetry=("y",),  # mirror-symmetric about y = width / 2; working modes are symmetric too
        params={},
        clamps={"clamp": "xyz"},
        electrodes={"electrode_outer": "drive", "electrode_inner": "ground"},
        analysis=Analysis(near=24e3, count=8),
        drive=Drive(
            damping="zeta=0.025",
            damping_source="seed 003 (zeta = 0.025)",
            outputs=(("tip", (0.1, 2.5e-3, 5e-3)), ("x_47.25mm", (0.04725, 2.5e-3, 5e-3)),
                     ("x_74.70mm", (0.0747, 2.5e-3, 5e-3))),
            targets=(
                Target("amplitude_100V", 1.44e-6, "m", "analytic", "seed 003, mode 6 at 100 V (e31 = 2.0 C/m^2)"),
                Target("amplitude_200V", 2.62e-6, "m", "analytic", "seed 003, mode 6 at 200 V"),
                Target("acceleration_max", 69324.0, "m/s^2", "analytic", "seed 003, half-period average"),
            ),
        ),
        mesh=MeshSettings(elements_per_wavelength=6.0, max_frequency=30e3),
        working_modes=(
            WorkingMode("bending-z 6", 24.2e3, (
                Target("f_analytic", 24221.0, "Hz", "analytic", "seed 003, Euler-Bernoulli theory"),
                Target("f_measured", 23.2e3, "Hz", "measured", "seed 003"),
            )),
        ),
        assumptions=_ciliary_beam_assumptions({}),
        assumption_writer=builtin_assumptions,
        kind="beam",
    )


BUILTIN = {
    "cube_plate": cube_plate,
    "glass_plate": glass_plate,
    "honeycomb_tile": honeycomb_tile,
    "tile_eq5": tile_eq5,
    "ciliary_beam": ciliary_beam,
}


def _mm(x: float) -> str:
    return f"{1e3 * x:.4g}"


def _effective(device: str, params) -> tuple[dict, list[str]]:
    """(every builder parameter with its value, names of those changed from the default)."""
    from modalfe.geometry import builder_parameters

    defaults = {k: p.default for k, p in builder_parameters(device).items()}
    changed = sorted(k for k, value in params.items() if k in defaults and value != defaults[k])
    return {**defaults, **params}, changed


def _dropped(changed: list[str], what: str) -> str:
    return f"{what}: explained for the default geometry, not for {', '.join(changed)} as set by the user"


def _cube_plate_assumptions(params) -> tuple[str, ...]:
    p, changed = _effective("cube_plate", params)
    rows = " / ".join(_mm(y) for y in p["ceramic_rows"])
    xs = " / ".join(_mm(x) for x in sorted({f[0] for f in p["feet"]}))
    ys = " / ".join(_mm(y) for y in sorted({f[1] for f in p["feet"]}))
    grade = ("PZT grade not named by the seeds: PZT-4 (Berlincourt 1964)" if p["ceramic_material"] == "PZT-4"
             else f"ceramics: {p['ceramic_material']} (set by the user)")
    bond = ("no bond layer" if p["bond_thickness"] == 0
            else f"bond layer {_mm(p['bond_thickness'])} mm of {p['bond_material']}")
    lines = [
        f"ceramics: {len(p['ceramic_rows'])} rows x {p['ceramic_columns']} of {_mm(p['ceramic_length'])} x "
        f"{_mm(p['ceramic_width'])} x {_mm(p['ceramic_thickness'])} mm, x-pitch {_mm(p['ceramic_pitch'])} mm, "
        f"rows y = {rows} mm (docs/assumptions.md, Cu-Be plate)",
        grade,
        f"feet: {_mm(p['foot_size'])} x {_mm(p['foot_size'])} x {_mm(p['foot_height'])} mm "
        f"{'Cu-Be' if p['foot_material'] == 'CuBe' else p['foot_material']} square columns at x = {xs} mm, "
        f"y = {ys} mm",
        f"{bond}; free-free (feet not in contact)",
    ]
    if changed:
        lines.append(_dropped(changed, "the gap to the seed's Abaqus 42.7 kHz"))
    else:
        lines.append("why below the seed's Abaqus 42.7 kHz: see studies/cube_plate_sensitivity.py (PZT grade, "
                     "ceramic thickness and layout, bond layer, feet and contact stiffness each move the (0,6) "
                     "mode by 1-6 %)")
    return tuple(lines)


def _glass_plate_assumptions(params) -> tuple[str, ...]:
    p, _ = _effective("glass_plate", params)
    glass = "soda-lime glass (EN 572-1)" if p["glass_material"] == "soda-lime-glass" else p["glass_material"]
    return (
        f"in-plane size {_mm(p['length'])} x {_mm(p['width'])} mm and piezo positions not in the seed's text "
        f"(figure lost)",
        f"{glass}, piezos {p['piezo_material']}, driven in phase",
    )


def _honeycomb_tile_assumptions(params) -> tuple[str, ...]:
    p, changed = _effective("honeycomb_tile", params)
    core = ("homogenised HexWeb 5052 1/4-.001 honeycomb (Hexcel catalogue values)"
            if p["core_material"] == "honeycomb-5052-1/4-.001" else f"{p['core_material']} (set by the user)")
    side = _mm(p["actuator_side"])
    lines = [
        f"core: {core}",
        "mounts: springs kz = EA/h, kx = ky = shear + bending of a bonded block (E 2 MPa, nu 0.49, A 8 cm^2, "
        f"h 2.5 cm), centres {_mm(p['mount_inset'])} mm in from the edges"
        + ("" if "mount_side" not in changed else
           f"; the spring stiffness stays that of the seed's 8 cm^2 block, mount_side only sets the "
           f"{_mm(p['mount_side'])} mm pad"),
        f"actuator: 2.3 kg smeared over a {side} x {side} mm patch at the centre of the bottom facing",
    ]
    if changed:
        lines.append(_dropped(changed, "the differences from the seed's 51/77 Hz and 896/1032 Hz"))
        return tuple(lines)
    return (*lines,
            "why roll/pitch differ from the seed's 51/77 Hz: the seed's actuator hangs below the plate on a "
            "bracket and rod, so sway and rocking couple through its offset mass; here the mass sits on the "
            "underside (lumped estimate for pure rocking: 4 kz d^2 / I ~ 180 Hz)",
            "why the plate modes differ from the seed's 896/1032 Hz: the seed's FE replaced the honeycomb by a "
            "homogeneous solid of equivalent density with unstated stiffness; here the core carries catalogue "
            "transverse shear moduli (the twisting mode at 1118.06 Hz with quartic elements on its antisymmetric "
            "quarter, 83k DOFs: modalfe modes honeycomb_tile --near 1100 --count 4 --fidelity solid --set "
            "'antisymmetry=[\"x\",\"y\"]' --set mesh.order=4 --set mesh.max_size=0.02 --set mesh.min_layers=2); the "
            "modes at ~760-950 Hz are local: the 2.3 kg actuator mass, smeared on the 0.8 mm facing without "
            "stiffness, bouncing, rocking and bending on the core's compression stiffness under its 40 x 40 mm pad, "
            "which the seed's bonded bracket would spread and stiffen; the plate model has no core compression and "
            "misses them (its twisting mode 1115.1 Hz, 0.27 % low). The solid's mesh puts 9 elements across the pad, "
            "4 on its coarsest estimate level (modalfe.models.mesh.MASS_PATCH_ELEMENTS; with 2 on the scene's mesh "
            "the estimate grids missed these modes and stated 0.13 % at 1111.8 Hz, 0.56 % off), and the label (1,1) "
            "goes to the plate's twist, not to the pad's (~965 Hz, 97 % of its kinetic energy in the pad: "
            "modalfe.results.labels.CARRIED)")


def _ciliary_beam_assumptions(params) -> tuple[str, ...]:
    p, changed = _effective("ciliary_beam", params)
    l1 = p["x0"] - p["sheet_length"] / 2
    l3 = p["length"] - p["x0"] - p["sheet_length"] / 2
    beam = "beam nu 0.34 (brass)" if p["beam_material"] == "brass-seed003" else f"beam {p['beam_material']}"
    sheets = ("sheets PZT-5A (seed gives only E 76.5 GPa, e31 2.0 C/m^2)" if p["sheet_material"] == "PZT-5A"
              else f"sheets {p['sheet_material']} (set by the user)")
    lines = [
        f"x0 = {_mm(p['x0'])} mm (l1 / l2 / l3 = {_mm(l1)} / {_mm(p['sheet_length'])} / {_mm(l3)} mm), rigid "
        f"clamp at x = 0 (docs/assumptions.md, Ciliary beam)",
        f"{beam}; {sheets}",
    ]
    if changed:
        lines.append(_dropped(changed, "the gap to the seed's 24,221 Hz"))
    else:
        lines.append("why below 24,221 Hz: that is Euler-Bernoulli theory; at mode 6 (height / wavelength ~ 0.14) "
                     "shear and rotary inertia lower the frequency (Timoshenko); the measured 23.2 kHz lies between")
    return tuple(lines)


_ASSUMPTIONS = {"cube_plate": _cube_plate_assumptions, "glass_plate": _glass_plate_assumptions,
                "honeycomb_tile": _honeycomb_tile_assumptions, "ciliary_beam": _ciliary_beam_assumptions}


def builtin_assumptions(scene: Scene) -> tuple[str, ...]:
    """The assumption lines of a built-in scene written from its current parameters."""
    lines = _ASSUMPTIONS[scene.name](dict(scene.params))
    user_materials = sorted(scene.materials)
    if user_materials:
        lines = (*lines, f"materials set by the user: {', '.join(user_materials)}")
    return lines
