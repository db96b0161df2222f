"""Reference results ``models/cosim/<scene>_ref.csv`` with provenance, and the band comparison.

File format: ``# key: value`` provenance lines (how, with which versions and settings the file was made), then a
CSV header ``time,<Instance.output>,...`` and one row per communication point (12 significant digits).

The comparison follows fmpy's cross-check (``fmpy.cross_check.validate_signal``): the reference is resampled on
a uniform grid, widened horizontally by a running min/max over ``band_width`` points (which here also takes the
reference's own samples in the window) and vertically by ``band_height`` times its range, and the result's
samples outside that band are counted (:class:`rollcontact_cosim.scenes.Band`).  fmpy's defaults (10 % of the
range, 21 of 1000 points, 10 % outliers) would let a 5 % change of the friction coefficient pass; the scenes use
1 %, 5 points and at most 1 % outliers (a Jacobi master's first step, made with the contact's start values, is
one such outlier).

Regenerate (e.g. after a deliberate change of the physics) with one command::

    python -m rollcontact_cosim.reference --regenerate            # every scene
    python -m rollcontact_cosim.reference --regenerate carter_sanity
    python -m rollcontact_cosim.reference --check                 # compare reruns, print problems
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import io
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np

from rollcontact_cosim.cli import run
from rollcontact_cosim.scenes import SCENE_NAMES, Band, CosimScene, load_cosim_scene

__all__ = ["band_limits", "compare", "provenance", "read_reference", "regenerate", "write_reference"]


def git_commit(folder: Path) -> str:
    """``git rev-parse HEAD`` of ``folder`` (``+dirty`` with uncommitted changes), or ``unknown``."""
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=folder, capture_output=True, text=True, timeout=10)
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=folder,
                               capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if head.returncode != 0:
        return "unknown"
    return head.stdout.strip() + ("+dirty" if dirty.stdout.strip() else "")


def provenance(scene: CosimScene, result) -> dict[str, str]:
    """How a reference was made: command, versions, git commit, master and its settings, band, date."""
    import fmpy

    import rollcontact

    band = scene.band
    return {
        "what": f"reference result of the co-simulation scene {scene.name} ({scene.path.name})",
        "command": "python -m rollcontact_cosim.reference --regenerate " + scene.name,
        "rollcontact": rollcontact.__version__,
        "git_commit": git_commit(scene.path.parent),
        "scene_sha256": hashlib.sha256(scene.path.read_bytes()).hexdigest(),
        "master": result.master,
        "algorithm": result.algorithm,
        "step_size": repr(result.step_size),
        "start_time": repr(scene.start_time),
        "stop_time": repr(scene.stop_time),
        "steps": str(result.steps),
        "band": f"band_height={band.band_height!r} band_width={band.band_width} samples={band.samples} "
                f"max_outliers={band.max_outliers!r} stride={band.stride} variables={','.join(band.variables)}",
        "versions": f"python {platform.python_version()}, numpy {np.__version__}, fmpy {fmpy.__version__}",
        "platform": platform.platform(),
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }


def write_reference(path: Path | str, values: np.ndarray, header: dict[str, str]) -> Path:
    """Write ``values`` (structured array, ``time`` first) with the provenance ``header`` to ``path``."""
    path = Path(path)
    lines = [f"# {key}: {value}" for key, value in header.items()]
    lines.append(",".join(values.dtype.names))
    table = np.column_stack([values[name] for name in values.dtype.names])
    buffer = io.StringIO()
    np.savetxt(buffer, table, fmt="%.12g", delimiter=",")
    path.write_text("\n".join(lines) + "\n" + buffer.getvalue())
    return path


def read_reference(path: Path | str) -> tuple[np.ndarray, dict[str, str]]:
    """The structured array and the provenance header of a reference CSV."""
    header: dict[str, str] = {}
    with open(path) as fh:
        for line in fh:
            if not line.startswith("#"):
                names = line.strip().split(",")
                break
            key, _, value = line[1:].partition(":")
            header[key.strip()] = value.strip()
        else:
            raise ValueError(f"{path}: no CSV header line after the provenance")
        table = np.loadtxt(fh, delimiter=",", ndmin=2)
    if table.shape[1] != len(names):
        raise ValueError(f"{path}: {table.shape[1]} columns for the {len(names)} names {names}")
    values = np.empty(table.shape[0], dtype=[(name, float) for name in names])
    for j, name in enumerate(names):
        values[name] = table[:, j]
    return values, header


def band_limits(t_ref: np.ndarray, y_ref: np.ndarray, t_start: float, t_stop: float,
                band: Band) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Uniform times and the lower and upper limits of the band around ``y_ref(t_ref)`` (module docstring).

    As fmpy's ``validate_signal``, except that the running min/max also takes the reference's own samples within
    the window: resampling alone cuts the corners of a sharp peak that falls between two grid points, so that a
    result equal to its reference could leave the band there.
    """
    t_band = np.linspace(t_start, t_stop, band.samples)
    keep = np.concatenate(([True], np.diff(t_ref) > 0))  # duplicate times would break the interpolation
    t_ref, y_ref = t_ref[keep], y_ref[keep]
    inside = (t_ref > t_start) & (t_ref < t_stop)
    t_all = np.concatenate((t_band, t_ref[inside]))
    order = np.argsort(t_all, kind="stable")
    t_all = t_all[order]
    y_all = np.interp(t_all, t_ref, y_ref)
    half = (band.band_width // 2) * (t_stop - t_start) / (band.samples - 1) * (1.0 + 1e-12)
    lo = np.searchsorted(t_all, t_band - half, side="left")
    hi = np.searchsorted(t_all, t_band + half, side="right")
    padded = np.append(y_all, 0.0)  # reduceat needs an index past every window's end
    pairs = np.ravel(np.column_stack((lo, hi)))
    lower = np.minimum.reduceat(padded, pairs)[::2]
    upper = np.maximum.reduceat(padded, pairs)[::2]
    low, high = float(np.min(y_all)), float(np.max(y_all))
    if low != high:
        width = band.band_height * (high - low)
    else:
        width = band.band_height * abs(low) if low != 0.0 else 1e-12
    return t_band, lower - width, upper + width


def compare(values: np.ndarray, reference: np.ndarray, band: Band) -> list[str]:
    """Problems of ``values`` against ``reference`` within ``band`` (empty list: the result passes).

    Both are structured arrays with ``time`` first.  The result must span the reference's time range and contain
    every compared variable; per variable at most ``band.max_outliers`` of the result's samples in that range may
    lie outside the band.
    """
    t_ref, t = reference["time"], values["time"]
    t_start, t_stop = float(t_ref[0]), float(t_ref[-1])
    if t.size < 2:
        return ["the result must have at least two samples"]
    span = 1e-9 * max(1.0, abs(t_stop))
    if t[0] > t_start + span or t[-1] < t_stop - span:
        return [f"the result spans [{t[0]!r}, {t[-1]!r}] s, the reference [{t_start!r}, {t_stop!r}] s"]
    problems = []
    inside = (t >= t_start) & (t <= t_stop)
    for name in band.variables:
        if name not in values.dtype.names or name not in reference.dtype.names:
            problems.append(f"{name} is missing from the {'result' if name in reference.dtype.names else 'reference'}")
            continue
        t_band, lower, upper = band_limits(t_ref, reference[name], t_start, t_stop, band)
        y = values[name]
        low, high = np.interp(t, t_band, lower), np.interp(t, t_band, upper)
        outliers = inside & ~((y >= low) & (y <= high))  # NaN is an outlier
        fraction = np.count_nonzero(outliers) / np.count_nonzero(inside)
        if fraction > band.max_outliers:
            k = int(np.argmax(outliers))
            problems.append(f"{name}: {fraction:.1%} of the samples lie outside the band (allowed "
                            f"{band.max_outliers:.1%}), first at t = {t[k]:.6g} s: {y[k]:.6g} not in "
                            f"[{low[k]:.6g}, {high[k]:.6g}]")
    return problems


def check(scene: str | CosimScene, result=None, **run_options) -> list[str]:
    """Problems of a run of ``scene`` (made with ``run_options`` unless ``result`` is given) against its reference."""
    from rollcontact_cosim.master import run_cosimulation

    scene = load_cosim_scene(scene)
    if result is None:
        result = run_cosimulation(scene, **run_options)
    if not result.success:
        return [f"the run failed: {result.message}"]
    reference, _ = read_reference(scene.reference_path)
    return compare(result.values, reference, scene.band)


def regenerate(scenes=SCENE_NAMES, **run_options) -> list[Path]:
    """Run each scene with the fmpy master and its own settings and write ``<scene>_ref.csv``; the paths."""
    from rollcontact_cosim.master import run_cosimulation

    written = []
    for name in scenes:
        scene = load_cosim_scene(name)
        result = run_cosimulation(scene, **run_options)
        if not result.success:
            raise RuntimeError(f"{scene.name}: the run failed, no reference written: {result.message}")
        rows = result.values[::scene.band.stride]
        written.append(write_reference(scene.reference_path, rows, provenance(scene, result)))
    return written


def main(argv: list[str] | None = None) -> int:
    """Regenerate or check the references; a bad scene is one line and exit code 2."""
    return run("python -m rollcontact_cosim.reference", lambda: command(argv))


def command(argv: list[str] | None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rollcontact_cosim.reference",
                                     description="Regenerate or check the co-simulation reference results.")
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--regenerate", action="store_true", help="write models/cosim/<scene>_ref.csv")
    action.add_argument("--check", action="store_true", help="rerun and compare with the references")
    parser.add_argument("scenes", nargs="*", default=list(SCENE_NAMES), help="scene names (default: all)")
    args = parser.parse_args(argv)
    if args.regenerate:
        for path in regenerate(args.scenes):
            print(f"wrote {path}")
        return 0
    failed = 0
    for name in args.scenes:
        problems = check(name)
        failed += bool(problems)
        print(f"{name}: {'ok' if not problems else '; '.join(problems)}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
