"""The package's shape: imports go one way (core <- geometries <- stepping <- FMUs), the geometries stand in one
order (line <- elliptic <- wheel/rail), the co-simulation uses the public API only, and a fidelity level is added
through the public extension point alone (``docs/contributing.md``, "Adding a level")."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

import rollcontact
from rollcontact import METHODS, Coulomb, Scene, register_method, solve
from rollcontact.core.method import AccuracyModel
from rollcontact.line.hertz import hertz
from rollcontact.line.result import ContactResult
from rollcontact.stepping import ContactModel, ContactParameters

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"

LAYERS = ("rollcontact.core.checks",
          "rollcontact.core.materials rollcontact.core.friction",
          "rollcontact.core.method rollcontact.core.halfspace",
          "rollcontact.core.dispatch rollcontact.core",
          "rollcontact.line.scene rollcontact.line.result rollcontact.line.hertz rollcontact.line.carter "
          "rollcontact.elliptic.scene rollcontact.elliptic.hertz rollcontact.elliptic.result "
          "rollcontact.elliptic.creep_table rollcontact.elliptic.creep_coefficients",
          "rollcontact.line.halfspace",
          "rollcontact.line.methods",
          "rollcontact.line.dispatch rollcontact.line",
          "rollcontact.line.instationary",
          "rollcontact.elliptic.methods",
          "rollcontact.elliptic.dispatch rollcontact.elliptic",
          "rollcontact.wheelrail.patch rollcontact.wheelrail.profiles rollcontact.wheelrail.geometry "
          "rollcontact.wheelrail.search rollcontact.wheelrail.normal rollcontact.wheelrail.conicity "
          "rollcontact.wheelrail.scene rollcontact.wheelrail.result rollcontact.wheelrail.loads",
          "rollcontact.wheelrail.wheels",
          "rollcontact.wheelrail.methods",
          "rollcontact.wheelrail.dispatch rollcontact.wheelrail.tabulated rollcontact.wheelrail",
          "rollcontact.stepping.base rollcontact.stepping.parameters rollcontact.stepping.threads",
          "rollcontact.stepping.line rollcontact.stepping.elliptic rollcontact.stepping.wheelrail",
          "rollcontact.stepping",
          "rollcontact rollcontact.__main__")
"""Layers from the shared core up to the package's entry points: a module imports only from its own layer or those
below.  Each geometry's data stands above the core, its half-space and methods above its data, its dispatcher above
its methods; the stepping models above every geometry."""

GEOMETRIES = ("rollcontact.line", "rollcontact.elliptic", "rollcontact.wheelrail")
"""The geometries in the order they may use each other: a geometry imports only the ones before it (the elliptic
strips solve each strip with the line contact's kernel, the wheel/rail levels use the elliptic ones), never one after
it."""

PUBLIC = {"src/rollcontact_cosim": ("rollcontact", "rollcontact.stepping"), "fmu_src": ("rollcontact",)}
"""What the co-simulation package and the FMU slaves may import from the solver: the co-simulation the public API
(the names of ``rollcontact`` and ``rollcontact.stepping``), the slaves the public API and the stepping models."""


def modules(root: Path = SRC) -> dict[str, Path]:
    found = {}
    for path in root.rglob("*.py"):
        name = ".".join(path.relative_to(root).with_suffix("").parts)
        found[name.removesuffix(".__init__")] = path
    return found


def imported(name: str, path: Path) -> set[str]:
    """Every module path the module imports, anywhere in it (lazy imports too), with the names it imports from them
    as ``module.name`` (which may be modules themselves)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            out |= {base} | {f"{base}.{a.name}" for a in node.names}
    return out


def imports_of(name: str, path: Path, known) -> set[str]:
    """Modules of ``known`` that the module imports (a package's ``__init__`` not counting its own submodules)."""
    return {m for m in imported(name, path) if m in known and m != name and not (path.name == "__init__.py"
                                                                                  and m.startswith(name + "."))}


def layer(name: str) -> int:
    best = None
    for rank, members in enumerate(LAYERS):
        for member in members.split():
            if name == member or name.startswith(member + "."):
                if best is None or len(member) > best[1]:
                    best = (rank, len(member))
    assert best is not None, f"{name} belongs to no layer of LAYERS"
    return best[0]


def geometry(name: str) -> int | None:
    return next((k for k, g in enumerate(GEOMETRIES) if name == g or name.startswith(g + ".")), None)


def test_no_import_cycles_under_src():
    known = modules()
    graph = {name: imports_of(name, path, known) for name, path in known.items()}
    cycles = []

    def visit(node, stack, state):
        state[node] = 1
        stack.append(node)
        for other in sorted(graph[node]):
            if state.get(other) == 1:
                cycles.append(" -> ".join(stack[stack.index(other):] + [other]))
            elif other not in state:
                visit(other, stack, state)
        stack.pop()
        state[node] = 2

    state = {}
    for node in sorted(graph):
        if node not in state:
            visit(node, [], state)
    assert not cycles, "import cycles: " + "; ".join(cycles)


def test_imports_go_one_way_from_the_core_to_the_stepping_models():
    known = modules()
    wrong = []
    for name, path in known.items():
        if not name.startswith("rollcontact.") and name != "rollcontact":
            continue
        for target in imports_of(name, path, known):
            if not target.startswith("rollcontact_cosim") and layer(target) > layer(name):
                wrong.append(f"{name} imports {target}")
    assert not wrong, "imports against the layers: " + "; ".join(sorted(wrong))


def test_a_geometry_uses_only_the_geometries_before_it():
    known = modules()
    wrong = [f"{name} imports {target}" for name, path in known.items() if geometry(name) is not None
             for target in imports_of(name, path, known)
             if geometry(target) is not None and geometry(target) > geometry(name)]
    assert not wrong, "a geometry imports one after it: " + "; ".join(sorted(wrong))


def test_the_solver_never_imports_fmi_tools():
    for name, path in modules().items():
        if name.startswith("rollcontact.") or name == "rollcontact":
            text = path.read_text()
            for tool in ("pythonfmu", "fmpy"):
                assert f"import {tool}" not in text and f"from {tool}" not in text, f"{name} imports {tool}"


@pytest.mark.parametrize("place", sorted(PUBLIC))
def test_the_cosimulation_and_the_slaves_use_the_public_api_only(place):
    public = PUBLIC[place]
    wrong = []
    for name, path in modules(ROOT / place).items():
        for target in imported(name, path):
            if (target == "rollcontact" or target.startswith("rollcontact.")) and target not in public \
                    and target.rpartition(".")[0] not in public \
                    and not (place == "fmu_src" and target.startswith("rollcontact.stepping")):
                wrong.append(f"{place}/{name} imports {target}")
    assert not wrong, f"imports beyond what {place} may use ({', '.join(public)}): " + "; ".join(sorted(wrong))


def linear_creep(scene: Scene, *, clamp: bool = True) -> ContactResult:
    """T' = k xi with Carter's slope at zero creep, k = pi E* a / 2, clamped at mu N' (a toy: exact only at xi -> 0)."""
    a, p0 = hertz(scene.normal_load_per_length, scene.radius, scene.material.contact_modulus)
    limit = scene.friction_coefficient * scene.normal_load_per_length
    force = math.pi * scene.material.contact_modulus * a / 2 * scene.creep
    if clamp:
        force = max(-limit, min(limit, force))
    return ContactResult("linear", True, "linear creep", scene.normal_load_per_length, force, scene.creep, a, 0.0,
                         a, p0, math.pi * scene.material.contact_modulus * a / 2)


linear_creep.options = ("clamp",)


class LinearAccuracy(AccuracyModel):
    """Its error is the creep over the saturation creep (Carter's curvature), its cost next to nothing."""

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return 1e-9

    def error(self, scene, options):
        a = hertz(scene.normal_load_per_length, scene.radius, scene.material.contact_modulus)[0]
        return abs(scene.creep) / (scene.friction_coefficient * a / scene.radius)


def flat_coulomb_only(scene: Scene) -> str | None:
    if not (scene.surface.is_flat and scene.friction.is_constant):
        return "the linear law assumes a flat surface and Coulomb friction"
    return None


@pytest.fixture
def linear_method():
    register_method("linear", linear_creep, flat_coulomb_only, -1, accuracy=LinearAccuracy())
    yield METHODS["linear"]
    del METHODS["linear"]


def test_a_method_registered_through_the_extension_point_takes_part_in_auto(linear_method):
    small = Scene(1e6, creep=1e-6, friction=Coulomb(0.3))
    assert solve(small).method == "linear", "rank -1: auto without a tolerance tries it first"
    assert solve(small, tolerance=1e-2).method == "linear", "its error model meets 1e-2 at tiny creep, cheapest"
    large = small.replace(creep=2e-3)
    chosen = solve(large, tolerance=1e-3)
    assert chosen.method == "closed_form" and chosen.info["tolerance_met"], \
        f"its error model misses 1e-3 at creep 2e-3: an exact method is chosen ({chosen.method})"
    assert solve(large, method="linear", clamp=False).tangential_force_per_length > 0.3e6, "its own option reaches it"
    corrugated = small.replace(surface=rollcontact.Surface(harmonics=(rollcontact.Harmonic.from_wavelength(
        0.04, 20e-6),)))
    assert solve(corrugated).method == "polynomial", "where it is inapplicable, the next method by rank"


def test_the_fmu_stepping_model_uses_a_registered_method_of_a_family():
    """A method whose registry name starts with a family's ("polynomial_...") is one the FMU's model may choose."""
    def only_corrugation(scene):
        return None if not scene.surface.is_flat else "flat"

    register_method("polynomial_toy", linear_creep, only_corrugation, 5)
    try:
        out = ContactModel(ContactParameters(corrugation_amplitude=1e-5)).step(0.0, 1e-3, 2e4, 1e-6, 10.0)
    finally:
        del METHODS["polynomial_toy"]
    expected = linear_creep(Scene(2e4 / 0.02, creep=1e-6, radius=0.46)).tangential_force_per_length * 0.02
    assert out.method_used == 2 and math.isclose(out.tangential_force, expected, rel_tol=1e-12), \
        f"the toy, ranked before the polynomial method, answers the step: {out}"
