"""Scene: validated construction, precise errors, TOML round trip, the repository's model files, Surface."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import rollcontact
from rollcontact import (
    Coulomb,
    ExponentialFalling,
    Harmonic,
    LinearFalling,
    Material,
    RationalFalling,
    Scene,
    SceneError,
    Surface,
    TabulatedFriction,
    load_scene,
    solve,
)

MODELS = Path(__file__).resolve().parents[2] / "models"

FULL_TOML = """
[scene]
name = "round trip"

[material]
youngs_modulus = 2.05e11
poisson_ratio = 0.27

[geometry]
radius = 0.43
axis_position = 0.0031

[load]
normal_load_per_length = 1.25e6
creep = -7.5e-4

[rolling]
rolling_speed = 12.5

{friction}

[surface]
polynomial = [1e-6, 2e-4, 0.0, -3.0e-2]

[[surface.corrugations]]
wavelength = 0.04
amplitude = 2.0e-5
phase = 0.7

[[surface.corrugations]]
wavelength = 0.013
amplitude = 3.0e-6
phase = -1.1

[[surface.harmonics]]
wavenumber = 250.0
cos_amplitude = 1.5e-6
sin_amplitude = -2.5e-6
"""

MINIMAL_TOML = """
[load]
normal_load_per_length = 1.0e6
"""


def write_scene(tmp_path: Path, text: str, name: str = "scene.toml") -> Path:
    """Write TOML text to ``tmp_path / name``.

    Parameters
    ----------
    tmp_path : Path
        Directory (pytest's tmp_path).
    text : str
        File content.
    name : str
        File name.

    Returns
    -------
    Path
        The written file.
    """
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def central_difference(f, x, h):
    """Fourth-order central difference of ``f`` at ``x`` with step ``h``.

    Parameters
    ----------
    f : callable
        Vectorised function.
    x : ndarray
        Points.
    h : float
        Step.

    Returns
    -------
    ndarray
        ``(-f(x+2h) + 8 f(x+h) - 8 f(x-h) + f(x-2h)) / (12 h)``.
    """
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h)


# ---------------------------------------------------------------------------------------------------------------
# construction
def test_valid_scene_holds_values_and_derived_quantities():
    surf = Surface(polynomial=(0.0, 1e-3), harmonics=(Harmonic(300.0, 1e-6, -2e-6),))
    scene = Scene(2e6, creep=-1e-3, radius=0.3, material=Material(200e9, 0.3), friction=0.25, surface=surf,
                  axis_position=0.004, rolling_speed=30.0, name="s")
    assert (scene.normal_load_per_length, scene.creep, scene.radius) == (2e6, -1e-3, 0.3), f"values: {scene}"
    assert (scene.axis_position, scene.rolling_speed, scene.name) == (0.004, 30.0, "s"), f"values: {scene}"
    assert scene.friction == Coulomb(0.25), f"a float friction must become Coulomb(0.25), got {scene.friction!r}"
    assert scene.friction_coefficient == 0.25, f"friction_coefficient = {scene.friction_coefficient}"
    estar = 200e9 / (2.0 * (1.0 - 0.3**2))
    np.testing.assert_allclose(scene.material.contact_modulus, estar, rtol=1e-15,
                               err_msg="E* = E / (2 (1 - nu^2)) for two identical bodies")
    assert scene.surface.harmonics[0].amplitude == pytest.approx(math.hypot(1e-6, 2e-6), rel=1e-15), \
        f"amplitude = {scene.surface.harmonics[0].amplitude}"


def test_defaults_are_a_smooth_hertzian_steel_scene():
    scene = Scene(1e6)
    assert scene.surface.is_flat and scene.surface.is_hertzian, f"default surface not flat: {scene.surface}"
    assert scene.material == Material(210e9, 0.28), f"default material {scene.material}"
    assert scene.creep == 0.0 and scene.axis_position == 0.0, f"defaults {scene}"


@pytest.mark.parametrize("surface, flat, hertzian", [
    (Surface(), True, True),
    (Surface(polynomial=(5e-6,)), True, True),
    (Surface(polynomial=(0.0, 2e-3)), True, False),
    (Surface(polynomial=(0.0, 0.0, 1e-3)), False, False),
    (Surface(harmonics=(Harmonic(100.0, 1e-6),)), False, False),
    (Surface(harmonics=(Harmonic(100.0, 0.0, 0.0),)), True, True),
])
def test_surface_flat_and_hertzian_flags(surface, flat, hertzian):
    assert surface.is_flat is flat, f"is_flat of {surface} should be {flat}"
    assert surface.is_hertzian is hertzian, f"is_hertzian of {surface} should be {hertzian}"


INVALID = [
    # (id, constructor, regex that must name the field and the value)
    ("load nan", lambda: Scene(float("nan")), r"normal_load_per_length.*nan"),
    ("load inf", lambda: Scene(float("inf")), r"normal_load_per_length.*inf"),
    ("load negative", lambda: Scene(-1.0), r"normal_load_per_length.*-1\.0"),
    ("load not a number", lambda: Scene("heavy"), r"normal_load_per_length.*heavy"),
    ("creep nan", lambda: Scene(1e6, creep=float("nan")), r"creep.*nan"),
    ("creep -inf", lambda: Scene(1e6, creep=-math.inf), r"creep.*-inf"),
    ("radius zero", lambda: Scene(1e6, radius=0.0), r"radius.*0\.0"),
    ("radius negative", lambda: Scene(1e6, radius=-0.46), r"radius.*-0\.46"),
    ("radius inf", lambda: Scene(1e6, radius=math.inf), r"radius.*inf"),
    ("axis nan", lambda: Scene(1e6, axis_position=float("nan")), r"axis_position.*nan"),
    ("speed negative", lambda: Scene(1e6, rolling_speed=-2.0), r"rolling_speed.*-2\.0"),
    ("youngs zero", lambda: Material(0.0, 0.28), r"youngs_modulus.*0\.0"),
    ("youngs negative", lambda: Material(-2.5e9, 0.28), r"youngs_modulus.*-2500000000\.0"),
    ("youngs nan", lambda: Material(float("nan"), 0.28), r"youngs_modulus.*nan"),
    ("poisson 0.5", lambda: Material(210e9, 0.5), r"poisson_ratio.*0\.5"),
    ("poisson 0.7", lambda: Material(210e9, 0.7), r"poisson_ratio.*0\.7"),
    ("poisson negative", lambda: Material(210e9, -0.1), r"poisson_ratio.*-0\.1"),
    ("friction negative", lambda: Scene(1e6, friction=-0.1), r"mu.*-0\.1"),
    ("friction zero", lambda: Coulomb(0.0), r"mu.*0\.0"),
    ("friction nan", lambda: Coulomb(float("nan")), r"mu.*nan"),
    ("exp kinetic ratio zero", lambda: ExponentialFalling(0.4, 0.0, 0.6), r"kinetic_ratio.*0\.0"),
    ("exp kinetic ratio > 1", lambda: ExponentialFalling(0.4, 1.5, 0.6), r"kinetic_ratio.*1\.5"),
    ("exp decay negative", lambda: ExponentialFalling(0.4, 0.4, -1.0), r"decay.*-1\.0"),
    ("wavenumber zero", lambda: Harmonic(0.0, 1e-6), r"wavenumber.*0\.0"),
    ("wavenumber negative", lambda: Harmonic(-5.0, 1e-6), r"wavenumber.*-5\.0"),
    ("wavenumber nan", lambda: Harmonic(float("nan"), 1e-6), r"wavenumber.*nan"),
    ("harmonic amplitude inf", lambda: Harmonic(10.0, math.inf), r"cos_amplitude.*inf"),
    ("wavelength zero", lambda: Harmonic.from_wavelength(0.0, 1e-6), r"wavelength.*0\.0"),
    ("polynomial nan", lambda: Surface(polynomial=(0.0, 0.0, float("nan"))), r"polynomial\[2\].*nan"),
    ("replace revalidates", lambda: Scene(1e6).replace(radius=-1.0), r"radius.*-1\.0"),
]


@pytest.mark.parametrize("build, pattern", [case[1:] for case in INVALID], ids=[case[0] for case in INVALID])
def test_invalid_value_raises_scene_error_naming_field_and_value(build, pattern):
    with pytest.raises(SceneError, match=pattern) as info:
        build()
    assert isinstance(info.value, ValueError), "SceneError must be a ValueError"


@pytest.mark.parametrize("bad", [Material, "steel", 3])
def test_wrong_material_type_is_rejected(bad):
    with pytest.raises(SceneError, match="material"):
        Scene(1e6, material=bad)


def test_wrong_friction_type_is_rejected():
    with pytest.raises(SceneError, match="friction.*'rough'"):
        Scene(1e6, friction="rough")


# ---------------------------------------------------------------------------------------------------------------
# TOML
@pytest.mark.parametrize("friction_table, expected", [
    ('[friction]\nlaw = "coulomb"\nmu = 0.27', Coulomb(0.27)),
    ('[friction]\nlaw = "exponential"\nmu_static = 0.42\nkinetic_ratio = 0.35\ndecay = 0.8',
     ExponentialFalling(0.42, 0.35, 0.8)),
])
def test_toml_round_trip_sets_every_field(tmp_path, friction_table, expected):
    path = write_scene(tmp_path, FULL_TOML.format(friction=friction_table))
    scene = load_scene(path)
    assert scene.name == "round trip", f"name = {scene.name!r}"
    assert scene.material == Material(2.05e11, 0.27), f"material = {scene.material}"
    assert (scene.radius, scene.axis_position) == (0.43, 0.0031), f"geometry = {scene.radius}, {scene.axis_position}"
    assert (scene.normal_load_per_length, scene.creep) == (1.25e6, -7.5e-4), \
        f"load = {scene.normal_load_per_length}, {scene.creep}"
    assert scene.rolling_speed == 12.5, f"rolling_speed = {scene.rolling_speed}"
    assert scene.friction == expected, f"friction = {scene.friction!r}, expected {expected!r}"
    assert scene.surface.polynomial == (1e-6, 2e-4, 0.0, -3.0e-2), f"polynomial = {scene.surface.polynomial}"
    harmonics = scene.surface.harmonics
    assert len(harmonics) == 3, f"expected 1 harmonic + 2 corrugations, got {harmonics}"
    # Z = A cos(2 pi X / lambda + phase) = A cos(phase) cos(kX) - A sin(phase) sin(kX)
    want = {(round(2 * math.pi / 0.04, 9), 2e-5 * math.cos(0.7), -2e-5 * math.sin(0.7)),
            (round(2 * math.pi / 0.013, 9), 3e-6 * math.cos(-1.1), -3e-6 * math.sin(-1.1)),
            (250.0, 1.5e-6, -2.5e-6)}
    got = {(round(h.wavenumber, 9), h.cos_amplitude, h.sin_amplitude) for h in harmonics}
    for w in want:
        assert any(g[0] == w[0] and math.isclose(g[1], w[1], rel_tol=1e-14, abs_tol=1e-22)
                   and math.isclose(g[2], w[2], rel_tol=1e-14, abs_tol=1e-22) for g in got), \
            f"harmonic {w} missing from {got}"
    X = np.linspace(-0.05, 0.05, 41)
    z = (1e-6 + 2e-4 * X - 3.0e-2 * X**3 + 2e-5 * np.cos(2 * np.pi * X / 0.04 + 0.7)
         + 3e-6 * np.cos(2 * np.pi * X / 0.013 - 1.1) + 1.5e-6 * np.cos(250 * X) - 2.5e-6 * np.sin(250 * X))
    np.testing.assert_allclose(scene.surface.height(X), z, rtol=0, atol=1e-18,
                               err_msg="Surface.height of the loaded scene differs from the TOML's Z(X)")


def test_a_toml_scene_takes_a_rail_condition_and_names_a_mixed_one(tmp_path):
    path = write_scene(tmp_path, FULL_TOML.format(friction='[friction]\nrail_condition = "dry"'))
    assert load_scene(path).friction == rollcontact.rail_condition("dry") == ExponentialFalling(0.55, 0.4, 0.6), \
        "the dry rail condition is the scene's law"
    mixed = write_scene(tmp_path, FULL_TOML.format(friction='[friction]\nrail_condition = "wet"\nmu_static = 0.4'),
                        "mixed.toml")
    with pytest.raises(SceneError, match="mixed.toml.*rail_condition = 'wet' sets the whole law; remove mu_static"):
        load_scene(mixed)


@pytest.mark.parametrize("friction", [
    Coulomb(0.27), ExponentialFalling(0.42, 0.35, 0.8), RationalFalling(0.3, 0.2, 0.5), LinearFalling(0.4, 0.25, 0.02),
    TabulatedFriction((0.0, 0.5, 3.0), (0.4, 0.3, 0.22)),
], ids=lambda law: type(law).__name__)
def test_scene_toml_is_read_back_as_the_same_scene(tmp_path, friction):
    # awkward floats (subnormal, huge, -0.0, the shortest repr of 0.1 + 0.2) and a name with quotes, a backslash, a
    # newline and a non-ASCII letter: every value must come back to the bit
    scene = Scene(5e-324 + 1.25e6, creep=-(0.1 + 0.2) * 1e-3, radius=0.43, material=Material(2.05e11, 0.27),
                  friction=friction, axis_position=-0.0,
                  surface=Surface(polynomial=(1e-300, -2e-4, 0.0, 3.0e2), harmonics=(
                      Harmonic.from_wavelength(0.04, 2e-5, 0.7), Harmonic(250.0, 1.5e-6, -2.5e-6))),
                  rolling_speed=12.5, name='rail "A"\\ \n ø')
    path = tmp_path / "written.toml"
    path.write_text(rollcontact.scene_toml(scene), encoding="utf-8")
    back = load_scene(path)
    assert back == scene, f"read back {back!r}\nwrote     {scene!r}"


def test_scene_toml_names_a_friction_law_without_a_file_form():
    class Custom(Coulomb):
        pass

    with pytest.raises(SceneError, match="Custom has no scene-file form.*'coulomb'"):
        rollcontact.scene_toml(Scene(1e6, friction=Custom(0.3)))
    with pytest.raises(SceneError, match="needs a Scene, got dict"):
        rollcontact.scene_toml({"normal_load_per_length": 1e6})


def test_toml_defaults_and_name_from_file_stem(tmp_path):
    scene = load_scene(write_scene(tmp_path, MINIMAL_TOML, name="tiny_case.toml"))
    assert scene.name == "tiny_case", f"name should default to the file stem, got {scene.name!r}"
    assert scene == Scene(1e6, name="tiny_case"), f"defaults differ from Scene(1e6): {scene}"


BAD_TOML = [
    ("unknown table", MINIMAL_TOML + "[wheel]\nradius = 0.46\n", r"wheel"),
    ("unknown key in geometry", MINIMAL_TOML + "[geometry]\nradius = 0.46\ndiameter = 0.92\n", r"diameter"),
    ("unknown key in load", MINIMAL_TOML.replace("1.0e6", "1.0e6\nlateral_load = 3.0"), r"lateral_load"),
    ("unknown key in rolling", MINIMAL_TOML + "[rolling]\nrolling_speed = 3.0\nspin = 0.1\n", r"spin"),
    ("unknown key in material", MINIMAL_TOML + "[material]\nyoungs_modulus = 2e11\ndensity = 7850.0\n",
     r"density"),
    ("unknown key in surface", MINIMAL_TOML + "[surface]\nroughness = 1e-6\n", r"roughness"),
    ("unknown key in corrugation", MINIMAL_TOML + "[[surface.corrugations]]\nwavelength = 0.04\n"
     "amplitude = 2e-5\ndepth = 1.0\n", r"depth"),
    ("unknown key in harmonic", MINIMAL_TOML + "[[surface.harmonics]]\nwavenumber = 100.0\nheight = 1e-6\n",
     r"height"),
    ("unknown key in scene", "[scene]\nname = 'x'\ncolour = 'red'\n" + MINIMAL_TOML, r"colour"),
    ("unknown key in friction", MINIMAL_TOML + '[friction]\nlaw = "coulomb"\nmu = 0.3\nmu_static = 0.4\n',
     r"mu_static"),
    ("unknown friction law", MINIMAL_TOML + '[friction]\nlaw = "magic"\nmu = 0.3\n', r"magic"),
    ("nan in TOML", MINIMAL_TOML + "[material]\nyoungs_modulus = nan\n", r"youngs_modulus.*nan"),
    ("inf in TOML", MINIMAL_TOML + "[geometry]\nradius = inf\n", r"radius.*inf"),
    ("negative load in TOML", MINIMAL_TOML.replace("1.0e6", "-5.0"), r"normal_load_per_length.*-5\.0"),
    ("poisson in TOML", MINIMAL_TOML + "[material]\npoisson_ratio = 0.5\n", r"poisson_ratio.*0\.5"),
    ("negative mu in TOML", MINIMAL_TOML + '[friction]\nlaw = "coulomb"\nmu = -0.2\n', r"mu.*-0\.2"),
    ("bad wavenumber in TOML", MINIMAL_TOML + "[[surface.harmonics]]\nwavenumber = -3.0\ncos_amplitude = 1e-6\n",
     r"wavenumber.*-3\.0"),
    ("not TOML", "normal_load_per_length = = 3\n", r"cannot read scene file"),
]


@pytest.mark.parametrize("text, pattern", [case[1:] for case in BAD_TOML], ids=[case[0] for case in BAD_TOML])
def test_bad_toml_raises_scene_error_naming_file_and_field(tmp_path, text, pattern):
    path = write_scene(tmp_path, text, name="bad_case.toml")
    with pytest.raises(SceneError, match=pattern) as info:
        load_scene(path)
    assert "bad_case.toml" in str(info.value), f"the message should name the file: {info.value}"


def test_missing_file_raises_scene_error(tmp_path):
    missing = tmp_path / "absent.toml"
    with pytest.raises(SceneError, match=re.escape("absent.toml")):
        load_scene(missing)


MODEL_FILES = sorted(MODELS.glob("*.toml")) if MODELS.is_dir() else []


@pytest.mark.parametrize("path", MODEL_FILES or [None], ids=[p.name for p in MODEL_FILES] or ["none"])
def test_repository_model_loads_and_solves(path):
    if path is None:
        pytest.skip("no models/*.toml in the repository")
    scene = load_scene(path)
    assert scene.name, f"{path.name}: scene has no name"
    result = solve(scene)
    assert isinstance(result, rollcontact.ContactResult), f"{path.name}: solve returned {type(result).__name__}"
    assert result.success, f"{path.name}: solve failed: {result.message}"
    assert result.normal_load_per_length == scene.normal_load_per_length, f"{path.name}: N' changed"
    mu_n = scene.friction_coefficient * scene.normal_load_per_length
    t = result.tangential_force_per_length
    assert math.isfinite(t) and abs(t) <= mu_n * (1 + 1e-12), f"{path.name}: T' = {t} exceeds mu N' = {mu_n}"
    if scene.creep != 0.0:
        assert t * scene.creep > 0.0, f"{path.name}: T' = {t} must have the sign of the creep {scene.creep}"
    assert result.contact_half_width > 0.0 and result.max_pressure > 0.0, f"{path.name}: no contact: {result}"


# ---------------------------------------------------------------------------------------------------------------
# Surface
SURFACES = {
    "polynomial": Surface(polynomial=(1e-5, 3e-4, -2e-2, 5.0, -40.0)),
    "harmonics": Surface(harmonics=(Harmonic(157.0, 2e-5, 0.0), Harmonic(480.0, -3e-6, 4e-6))),
    "mixed": Surface(polynomial=(0.0, -1e-3, 0.5), harmonics=(Harmonic.from_wavelength(0.011, 7e-6, 2.2),)),
    "flat": Surface(),
}


@pytest.mark.parametrize("name", sorted(SURFACES))
def test_surface_slope_is_derivative_of_height(name):
    surface = SURFACES[name]
    X = np.linspace(-0.03, 0.03, 61)
    h = 1e-5
    fd = central_difference(surface.height, X, h)
    scale = max(float(np.max(np.abs(surface.slope(X)))), 1e-12)
    np.testing.assert_allclose(surface.slope(X), fd, rtol=0, atol=1e-7 * scale,
                               err_msg=f"{name}: slope differs from the numerical derivative of height")
    assert surface.height(X).shape == X.shape and surface.slope(X).shape == X.shape, "shapes must follow X"


def test_harmonic_from_wavelength_matches_cosine_with_phase():
    lam, amp, phase = 0.017, 9e-6, 0.9
    surface = Surface(harmonics=(Harmonic.from_wavelength(lam, amp, phase),))
    X = np.linspace(-0.02, 0.02, 101)
    np.testing.assert_allclose(surface.height(X), amp * np.cos(2 * np.pi * X / lam + phase), rtol=0, atol=1e-13 * amp,
                               err_msg="from_wavelength must give amplitude cos(2 pi X / wavelength + phase)")
    np.testing.assert_allclose(surface.harmonics[0].amplitude, amp, rtol=1e-15, err_msg="amplitude")
