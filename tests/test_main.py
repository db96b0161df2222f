"""The command line ``python -m rollcontact``: help that reads as text, results as CSV with units that read back as
the solves' numbers."""

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
    assert "example:\n  python -m rollcontact models/carter.toml" in text, "an example command"
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
