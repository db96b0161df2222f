"""The command line ``python -m rollcontact``: help that reads as text, results as CSV with units that read back as
the solves' numbers, scenes of every geometry (line, elliptic, wheel/rail), and a CSV written whatever happens to
standard output."""

from __future__ import annotations

import csv
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

import rollcontact
from rollcontact.__main__ import CSV_COLUMNS, main

ROOT = Path(__file__).resolve().parents[1]
CARTER = ROOT / "models" / "carter.toml"
CORRUGATED = ROOT / "models" / "corrugated.toml"

REST = re.compile(r"``|:(func|class|meth|mod|data|attr|ref):`")
"""reST markup that must not reach a terminal: inline literals and roles."""


def help_text(module: str) -> str:
    done = subprocess.run([sys.executable, "-m", module, "--help"], capture_output=True, text=True, timeout=60,
                          cwd=ROOT)
    assert done.returncode == 0, done.stderr
    return done.stdout


def description(text: str) -> str:
    """The first line after the usage block: what the command does."""
    return text.split("\n\n")[1].splitlines()[0]


def test_help_reads_as_text_and_opens_with_what_it_does():
    text = help_text("rollcontact")
    assert REST.search(text) is None, f"reST markup in the help: {REST.search(text).group(0)!r}\n{text}"
    first = description(text)
    assert first.startswith("Solve rolling-contact scenes") and len(first) <= 100, first
    assert "examples:\n  python -m rollcontact models/carter.toml" in text, "an example command"
    assert "models/wheelrail/manchester_a22.toml" in text, "a wheel/rail example"
    for unit in ("[1]", "[m]", "[N/m]"):
        assert unit in text, f"the options and quantities name their units ({unit} missing):\n{text}"


def test_csv_reads_back_with_units_and_the_solved_values(tmp_path, capsys):
    path = tmp_path / "out.csv"
    assert main([str(CARTER), str(CORRUGATED), "--creep-curve", "--csv", str(path)]) == 0
    capsys.readouterr()
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    header = list(rows[0])
    assert "tangential_force_per_length [N/m]" in header and "creep [1]" in header and \
        "contact_half_width [m]" in header and "max_pressure [Pa]" in header, header
    assert len(header) == len(CSV_COLUMNS)
    assert [r["case"] for r in rows] == (["scene"] + ["creep curve"] * 11) * 2, "a row per solve, in order"
    for file in (CARTER, CORRUGATED):
        scene = rollcontact.load_scene(file)
        first = next(r for r in rows if r["scene_file"] == str(file) and r["case"] == "scene")
        expected = rollcontact.solve(scene)
        assert first["method"] == expected.method and first["success"] == "True", first
        for name, unit in CSV_COLUMNS:
            if unit is not None:
                value = float(first[f"{name} [{unit}]"])
                assert value == float(getattr(expected, name)), f"{file.name}: {name} {value} != the solve's"
    numbers = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert np.all(np.diff(numbers["creep_1"][1:12]) > 0.0), "numpy reads the creep column of the curve"


def test_a_csv_that_cannot_be_written_is_one_line_and_exit_code_2(tmp_path, capsys):
    assert main([str(CARTER), "--csv", str(tmp_path / "no" / "such" / "dir.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--csv" in err, err


ELLIPTIC = """[scene]
geometry = "elliptic"
name = "wheel on rail"
[ellipse]
longitudinal_curvature = 1.087
lateral_curvature = 1.667
[load]
normal_load = 1e5
longitudinal_creepage = 1e-3
spin_creepage = 0.2
[rolling]
rolling_speed = 20.0
[friction]
law = "coulomb"
mu = 0.3
"""


def test_an_elliptic_scene_is_solved_by_the_elliptic_dispatcher(tmp_path, capsys):
    path = tmp_path / "ellipse.toml"
    path.write_text(ELLIPTIC)
    out = tmp_path / "out.csv"
    assert main([str(path), "--method", "strips", "--csv", str(out)]) == 0
    assert "elliptic" in capsys.readouterr().out
    with open(out, newline="") as fh:
        row = next(csv.DictReader(fh))
    expected = rollcontact.solve_elliptic(rollcontact.EllipticScene(1e5, 1.087, 1.667, 1e-3, 0.0, 0.2,
                                                                    rolling_speed=20.0), "strips")
    assert float(row["longitudinal_force [N]"]) == expected.longitudinal_force, "the CSV holds the solve's Fx"
    assert row["method"] == "strips"


WHEELRAIL = ROOT / "models" / "wheelrail" / "manchester_a22.toml"
COLUMNS = ("case, lateral_shift, yaw, wheel, patch, normal_force, contact_angle, rolling_radius, "
           "rail_lateral_position, longitudinal_creepage, lateral_creepage, spin_creepage, longitudinal_force, "
           "lateral_force, spin_moment, max_pressure, length, width, method, wheel_force_x, wheel_force_y, "
           "wheel_force_z").split(", ")


def test_the_manchester_scene_writes_a_row_per_case_wheel_and_patch(tmp_path):
    """Through a pipe into head, which closes standard output after a line: the CSV is complete all the same."""
    out = tmp_path / "a22.csv"
    done = subprocess.run(f"{sys.executable} -m rollcontact {WHEELRAIL} --method hertz --csv {out} | head -1",
                          shell=True, capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert "BrokenPipeError" not in done.stderr and "Traceback" not in done.stderr, done.stderr
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == COLUMNS, f"the columns of the issue, in order: {list(rows[0])}"
    assert {int(r["case"]) for r in rows} == set(range(1, 22)), "the 21 positions"
    for case in (1, 21):
        for wheel in ("left", "right"):
            mine = [r for r in rows if int(r["case"]) == case and r["wheel"] == wheel]
            assert [int(r["patch"]) for r in mine] == list(range(1, len(mine) + 1)), "patches numbered from 1"
            forces = [float(r["normal_force"]) for r in mine]
            assert forces == sorted(forces, reverse=True), "by decreasing normal force"
            assert abs(float(mine[0]["wheel_force_z"]) - 1e4) <= 1e2, "each wheel carries its 10 kN"
    assert all(r["method"] == "hertz" for r in rows)


def test_a_scene_of_an_unknown_geometry_is_one_line_and_exit_code_2(tmp_path, capsys):
    path = tmp_path / "odd.toml"
    path.write_text('[scene]\ngeometry = "sphere"\n')
    assert main([str(path)]) == 2
    err = capsys.readouterr().err
    assert "geometry = 'sphere'" in err and err.count("\n") == 1, err
