"""Smoke tests of the figure gallery ``docs/figures/make_figures.py`` (paper figures 2-6 and the elliptic figure 7),
at small resolution.

Each figure function is run with ``quick=True`` into a temporary directory: the PNG must exist and hold a real
picture, and the key numbers it returns must show the physics the figure is about.  One test runs the command
line as a user would, so the gallery cannot rot.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "make_figures.py"
MIN_PNG_BYTES = 10_000
"""A blank or broken PNG of the gallery's size is a few kB; every real figure is well above 10 kB."""


def load_gallery():
    """The gallery script as a module (it is a script, not part of the package)."""
    spec = importlib.util.spec_from_file_location("make_figures", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


gallery = load_gallery()


def render(number: int, tmp_path: Path):
    """Draw figure ``number`` quickly into ``tmp_path``; check the PNG and return the key numbers."""
    path, numbers = gallery.FIGURES[number](tmp_path, quick=True)
    assert path.parent == tmp_path and path.suffix == ".png", f"figure {number} written to {path}, not tmp_path"
    assert path.is_file(), f"figure {number}: {path} was not written"
    size = path.stat().st_size
    assert size > MIN_PNG_BYTES, f"figure {number}: {path.name} is only {size} bytes (blank?)"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"figure {number}: {path.name} is not a PNG"
    return numbers


def test_fig2_carter_creep_curve_saturates_at_mu(tmp_path):
    n = render(2, tmp_path)
    assert n["monotone"], "Carter's creep curve must not decrease"
    assert n["max_ratio"] <= 1.0 + 1e-12, f"T' exceeds mu N': max T'/(mu N') = {n['max_ratio']}"
    assert n["saturated_ratio"] == pytest.approx(1.0, abs=1e-12), \
        f"beyond the full-slip creep T' = mu N', got T'/(mu N') = {n['saturated_ratio']}"
    assert n["initial_slope_ratio"] == pytest.approx(1.0, rel=1e-4), \
        f"slope at zero creep / (pi E* a / 2) = {n['initial_slope_ratio']}"
    assert n["discretised_error"] < 0.01, \
        f"discretised solver off Carter's curve by {n['discretised_error']} mu N'"


def test_fig3_corrugation_changes_the_traction_admissibly(tmp_path):
    n = render(3, tmp_path)
    assert n["success"], "the polynomial method must solve the corrugated scene"
    assert n["bound_excess"] <= 1e-9, f"|q| > mu p by {n['bound_excess']} mu p0"
    assert n["force_integral_error"] < 5e-3, f"integral of q misses T' by {n['force_integral_error']} (relative)"
    assert n["load_integral_error"] < 5e-3, f"integral of p misses N' by {n['load_integral_error']} (relative)"
    assert abs(n["offset"]) > 0.1 * n["half_width"], \
        f"on the flank of the corrugation the patch must shift off the axis: Delta = {n['offset']} m"
    assert abs(n["force"] / n["carter_force"] - 1.0) > 0.01, \
        f"the corrugation must change T' visibly: {n['force']} vs Carter {n['carter_force']} N/m"
    assert n["max_traction_difference"] > 0.1, \
        f"the figure must show a difference from Carter, max |q - q_C| = {n['max_traction_difference']} mu p0"


def test_fig4_falling_friction_creep_curve_has_its_maximum_below_mu_static(tmp_path):
    n = render(4, tmp_path)
    assert n["success"], "every solve of the creep curve must succeed"
    assert 0 < n["sampled_peak_index"] < n["samples"] - 1, \
        f"the maximum must lie inside the creep range (sample {n['sampled_peak_index']} of {n['samples']})"
    assert n["peak_coefficient"] < n["mu_static"], \
        f"maximum T'/N' = {n['peak_coefficient']} must stay below mu_s = {n['mu_static']}"
    assert n["rises_to_peak"] and n["falls_after_peak"], "the creep curve must rise to the maximum, then fall"
    assert n["last_coefficient"] < n["peak_coefficient"] - 0.05, \
        f"the curve must fall distinctly beyond the maximum: {n['peak_coefficient']} -> {n['last_coefficient']}"
    assert n["last_coefficient"] == pytest.approx(n["last_friction"], abs=0.01), \
        f"far in full slip T'/N' = {n['last_coefficient']} must approach mu(V xi) = {n['last_friction']}"


def test_fig5_spike_sits_at_the_stick_slip_boundary_within_the_friction_bound(tmp_path):
    n = render(5, tmp_path)
    assert n["success"], "the falling-friction and Carter solves must succeed"
    assert n["spike_ratio"] <= n["mu_static"] * (1.0 + 1e-6), \
        f"q/p = {n['spike_ratio']} exceeds mu_s = {n['mu_static']}"
    assert abs(n["spike_position"] - n["boundary"]) < 0.05 * n["half_width"], \
        f"q/p peaks at x = {n['spike_position']} m, the stick/slip boundary is at {n['boundary']} m"
    assert n["spike_ratio"] > n["trailing_ratio"] + 0.05, \
        f"q/p must fall behind the spike: {n['spike_ratio']} -> {n['trailing_ratio']} at the trailing edge"
    # q = mu(V s) p holds at the nodes of the slip iteration; between them next to the boundary the returned
    # series overshoot by up to ~1 % at the quick (default) resolution
    assert n["bound_ratio"] < 1.02, f"|q| exceeds mu(V|s|) p by the factor {n['bound_ratio']}"
    assert n["carter_max_ratio"] == pytest.approx(gallery.MU, rel=1e-9), \
        f"Carter's q/p in the slip zone must be mu, max is {n['carter_max_ratio']}"
    assert n["force"] < n["carter_force"], \
        f"falling friction must lower T' below Carter's: {n['force']} vs {n['carter_force']} N/m"


def test_fig6_instationary_traction_deviates_from_carter_by_the_paper_rule(tmp_path):
    n = render(6, tmp_path)
    assert n["success"], "the paper's route must hold at every phase (one stick zone, |q| <= mu p)"
    assert n["wavelength_over_a"] < 20.0, f"lambda/a = {n['wavelength_over_a']} must be instationary (< 20)"
    assert n["max_residual"] < 1e-4, f"force misfit {n['max_residual']} mu N' of the truncated travelling wave"
    assert n["bound_excess"] <= 1e-6, f"|q| > mu p by {n['bound_excess']} mu p0"
    ratio = n["deviation"] / n["deviation_rule"]
    assert 0.7 < ratio < 1.3, f"deviation from quasi-steady Carter / (2.5 a/lambda) = {ratio}"
    assert n["max_difference"] > 0.05, \
        f"the figure must show a difference from Carter, max |q - q_C| = {n['max_difference']} mu p0"


def test_fig7_elliptic_traction_respects_the_bound_and_the_levels_follow_the_discretised_curve(tmp_path):
    n = render(7, tmp_path)
    assert n["success"], "every elliptic solve of the figure must succeed"
    assert n["bound_excess"] <= 1e-9, f"|q| > mu p by {n['bound_excess']} mu p0"
    assert 0.05 < n["stick_fraction"] < 0.95, f"the spin case must show stick and slip: {n['stick_fraction']}"
    assert n["leading_stick"] > 0.6, f"the stick area must lie at the leading edge (x > 0): {n['leading_stick']}"
    assert n["largest_force"] <= 1.0 + 1e-9, f"|Fy| exceeds mu Fn on the discretised curve: {n['largest_force']}"
    gaps = n["level_gaps"]
    assert gaps["fastsim"] < 0.1 and gaps["strips"] < 0.1, f"FASTSIM or strips far off the discretised curve: {gaps}"
    assert gaps["linear"] > 0.5, f"beyond saturation the linear theory must leave the curve: {gaps}"


def test_one_command_writes_the_gallery(tmp_path):
    run = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--out", str(tmp_path)], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0, f"make_figures.py --quick failed:\n{run.stderr}"
    expected = ["fig2_carter_creep_curve.png", "fig3_corrugation.png", "fig4_falling_friction_creep_curve.png",
                "fig5_stick_slip_spike.png", "fig6_instationary.png", "fig7_elliptic_contact.png"]
    written = sorted(p.name for p in tmp_path.glob("*.png"))
    assert written == sorted(expected), f"the command wrote {written}, expected {expected}"
    assert all((tmp_path / name).stat().st_size > MIN_PNG_BYTES for name in expected), "a PNG is (nearly) empty"
    assert "6 figures" in run.stdout, f"the command must report what it wrote:\n{run.stdout}"
