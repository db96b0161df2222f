"""The package's shape: imports go one way, no module or class too large to read, and a fidelity level is added
through the public extension point alone (``docs/contributing.md``, "Adding a method")."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

import rollcontact
from rollcontact import METHODS, Coulomb, Scene, register_method, solve
from rollcontact.closed_form import hertz
from rollcontact.method import AccuracyModel
from rollcontact.result import ContactResult
from rollcontact.stepping import ContactModel, ContactParameters

SRC = Path(__file__).resolve().parents[1] / "src"

LAYERS = ("rollcontact.checks rollcontact.friction rollcontact.scene rollcontact.result rollcontact.closed_form",
          "rollcontact.method",
          "rollcontact.halfspace",
          "rollcontact.methods",
          "rollcontact.dispatch",
          "rollcontact.elliptic.scene rollcontact.elliptic.hertz rollcontact.elliptic.result "
          "rollcontact.elliptic.creep_table rollcontact.elliptic.creep_coefficients rollcontact.elliptic",
          "rollcontact.elliptic.methods",
          "rollcontact.elliptic.dispatch",
          "rollcontact.instationary",
          "rollcontact.stepping",
          "rollcontact rollcontact.__main__")
"""Layers from data up to the package's entry points: a module imports only from its own layer or those below.
The elliptic (3D) package stands above the 2D dispatcher: it may use the 2D data, methods and dispatcher, and no 2D
module may import it."""


def modules() -> dict[str, Path]:
    found = {}
    for path in SRC.rglob("*.py"):
        name = ".".join(path.relative_to(SRC).with_suffix("").parts)
        found[name.removesuffix(".__init__")] = path
    return found


def imports_of(name: str, path: Path, known) -> set[str]:
    """Modules of ``known`` that the module imports, anywhere in it (lazy imports too)."""
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
    return {m for m in out if m in known and m != name and not (path.name == "__init__.py"
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


def test_imports_go_one_way_from_data_to_stepping():
    known = modules()
    wrong = []
    for name, path in known.items():
        if not name.startswith("rollcontact.") and name != "rollcontact":
            continue
        for target in imports_of(name, path, known):
            if target.startswith("rollcontact") and not target.startswith("rollcontact_cosim") \
                    and layer(target) > layer(name):
                wrong.append(f"{name} imports {target}")
    assert not wrong, "imports against the layers: " + "; ".join(sorted(wrong))


def test_the_solver_never_imports_fmi_tools():
    for name, path in modules().items():
        if name.startswith("rollcontact.") or name == "rollcontact":
            text = path.read_text()
            for tool in ("pythonfmu", "fmpy"):
                assert f"import {tool}" not in text and f"from {tool}" not in text, f"{name} imports {tool}"


@pytest.mark.parametrize(("kind", "limit"), [("module", 800), ("class", 310)])
def test_no_module_or_class_too_long_to_read(kind, limit):
    long = []
    for name, path in modules().items():
        text = path.read_text()
        if kind == "module" and text.count("\n") > limit:
            long.append(f"{name}: {text.count(chr(10))} lines")
        if kind == "class":
            long += [f"{name}.{node.name}: {node.end_lineno - node.lineno + 1} lines"
                     for node in ast.walk(ast.parse(text))
                     if isinstance(node, ast.ClassDef) and node.end_lineno - node.lineno + 1 > limit]
    assert not long, f"{ {'module': 'modules', 'class': 'classes'}[kind]} above {limit} lines: " + "; ".join(long)


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
