"""The main job's command line and figure: help that reads as text, a figure whose title names the friction law and
its values, axes that say what they show, the summary and the run as CSV with its units."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rollcontact.core.materials import Material
from rollcontact.line.carter import carter
from rollcontact.line.hertz import hertz
from rollcontact_cosim.__main__ import figure, friction_title
from rollcontact_cosim.__main__ import main as main_job
from rollcontact_cosim.master import CosimResult
from rollcontact_cosim.scenes import CONTACT, HOST, load_cosim_scene

ROOT = Path(__file__).resolve().parents[2]
CREEP, FORCE = f"{HOST}.creep", f"{CONTACT}.tangential_force"
REST = re.compile(r"``|:(func|class|meth|mod|data|attr|ref):`")


@pytest.mark.parametrize(("module", "opens"), [
    ("rollcontact_cosim", "Co-simulate a wheel rig with a rolling contact"),
    ("rollcontact_cosim.sweep", "Parameter sweeps and regression suites"),
    ("rollcontact_cosim.reference", "Regenerate or check the co-simulation reference results"),
])
def test_help_reads_as_text_and_opens_with_what_it_does(module, opens):
    done = subprocess.run([sys.executable, "-m", module, "--help"], capture_output=True, text=True, timeout=60,
                          cwd=ROOT)
    assert done.returncode == 0, done.stderr
    text = done.stdout
    assert REST.search(text) is None, f"reST markup in the help: {REST.search(text).group(0)!r}\n{text}"
    first = text.split("\n\n")[1].splitlines()[0]
    assert first.startswith(opens) and not first.startswith("Main job"), first
    if module == "rollcontact_cosim":
        assert "--step-size H         macro step H [s]" in text and "examples:\n  python -m rollcontact_cosim" in text


def carter_run(mu=0.3, steps=200, reach=2.0) -> CosimResult:
    """A synthetic run: the creep ramps through Carter's curve to ``reach`` saturation creeps (creep > 0, then its
    mirror, braking)."""
    radius, load, width = 0.46, 98.1e3, 0.02
    modulus = Material(210e9, 0.28).contact_modulus
    a = hertz(load / width, radius, modulus)[0]
    creep = np.concatenate([np.linspace(0.0, reach, steps), -np.linspace(0.0, reach, steps)]) * mu * a / radius
    traction = np.array([carter(load / width, x, radius, modulus, mu)[0] / (load / width) for x in creep])
    time = np.linspace(0.0, 1.0, creep.size)
    values = np.empty(time.size, dtype=[("time", float), ("WheelRig.creep", float),
                                        ("RollingContact2D.traction_coefficient", float),
                                        ("RollingContact2D.stick_half_width", float)])
    values["time"], values["WheelRig.creep"], values["RollingContact2D.traction_coefficient"] = time, creep, traction
    values["RollingContact2D.stick_half_width"] = a * np.clip(1.0 - np.abs(traction) / mu, 0.0, 1.0)
    return CosimResult("synthetic", "fmpy", "gauss-seidel", 5e-3, values, time.size, 0.0, True, "completed")


def test_the_title_names_the_friction_law_and_its_values_and_the_axes_say_what_they_show():
    friction = friction_title(load_cosim_scene("traction_ramp").contact_parameters())
    assert friction == ("friction: exponential falling mu(v) = mu_s [(1 - A) exp(-B v) + A], mu_s = 0.35, A = 0.4, "
                        "B = 0.6 s/m"), friction
    fig = figure(carter_run(), friction)
    try:
        title = fig._suptitle.get_text()
        assert "synthetic: fmpy master" in title and friction in title, title
        adhesion = [ax for ax in fig.axes if ax.get_title().startswith("adhesion curve")]
        assert [ax.get_xscale() for ax in adhesion] == ["linear", "log"], "the linear curve, then the log one"
        linear = adhesion[0]
        legend = [t.get_text() for t in linear.get_legend().get_texts()]
        assert legend == ["traction (creep xi > 0): T/N", "braking (creep xi < 0): -T/N"], legend
        assert linear.get_xlim()[0] == 0.0 and linear.get_xlabel() == "|creep| xi [1]", linear.get_xlabel()
        labels = [ax.get_ylabel() for ax in fig.axes]
        assert "stick-zone half-width a* [m]" in labels and not any(label == "a* [m]" for label in labels), labels
    finally:
        plt.close(fig)


def test_a_scene_file_friction_is_named_from_the_file(tmp_path):
    scene = tmp_path / "rational.toml"
    scene.write_text('[load]\nnormal_load_per_length = 1e6\n[friction]\nlaw = "rational"\nmu_static = 0.4\n'
                     'mu_kinetic = 0.2\nreference_velocity = 0.5\n')
    text = friction_title({"scene_file": str(scene)})
    assert text == ("friction: rational falling mu(v) = mu_k + (mu_s - mu_k) / (1 + v / v_ref), mu_s = 0.4, "
                    "mu_k = 0.2, v_ref = 0.5 m/s"), text


def test_a_rail_condition_is_named_with_its_law():
    text = friction_title({"rail_condition": 2, "friction_coefficient": 0.9})
    assert text == ("friction: wet rail (Polach 2005), exponential falling mu(v) = mu_s [(1 - A) exp(-B v) + A], "
                    "mu_s = 0.3, A = 0.4, B = 0.2 s/m"), text


def test_the_linear_curve_shows_the_start_and_the_peak_of_a_long_run():
    """A run to 20 saturation creeps: the linear panel ends at LINEAR_SPAN times the peak's creep and says so, the
    log panel spans the run."""
    from rollcontact_cosim.__main__ import LINEAR_SPAN

    result = carter_run(reach=20.0, steps=2000)
    fig = figure(result)
    try:
        linear, log = [ax for ax in fig.axes if ax.get_title().startswith("adhesion curve")]
        creep = result.values["WheelRig.creep"]
        peak = abs(creep[int(np.argmax(np.abs(result.values["RollingContact2D.traction_coefficient"])))])
        assert linear.get_xlim() == (0.0, LINEAR_SPAN * peak), (linear.get_xlim(), peak)
        assert "up to 4 x the peak's" in linear.get_xlabel(), linear.get_xlabel()
        assert log.get_xlim()[1] >= np.max(np.abs(creep)), "the log panel shows the whole run"
    finally:
        plt.close(fig)


def test_main_job_prints_the_summary_and_writes_the_plot(fmu_dir, tmp_path, capsys):
    png = tmp_path / "carter.png"
    assert main_job(["carter_sanity", "--plot", str(png), "--fmu-dir", str(fmu_dir)]) == 0, "main job failed"
    out = capsys.readouterr().out
    assert "peak adhesion T/N = 0.15" in out and "500 macro steps" in out and "us per step" in out, out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", "the plot must be a PNG"


def test_main_job_writes_the_run_as_csv_with_units(fmu_dir, run, tmp_path, capsys):
    import csv

    path = tmp_path / "carter.csv"
    assert main_job(["carter_sanity", "--plot", str(tmp_path / "c.png"), "--csv", str(path),
                     "--fmu-dir", str(fmu_dir)]) == 0, "main job failed"
    assert f"csv: {path}" in capsys.readouterr().out
    with open(path, newline="") as fh:
        header, *rows = list(csv.reader(fh))
    expected = run("carter_sanity").values
    names = expected.dtype.names
    assert header[0] == "time [s]" and f"{FORCE} [N]" in header and f"{CREEP} [1]" in header and \
        f"{HOST}.velocity [m/s]" in header and f"{CONTACT}.contact_half_width [m]" in header, header
    assert [h.split(" [")[0] for h in header] == list(names), "one column per recorded variable, in order"
    table = np.genfromtxt(path, delimiter=",", skip_header=1)
    assert table.shape == (expected.size, len(names)) and len(rows) == expected.size
    for j, name in enumerate(names):
        assert np.array_equal(table[:, j], expected[name]), f"{name}: the CSV holds other values than the run"
