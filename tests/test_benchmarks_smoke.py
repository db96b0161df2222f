"""The benchmark scripts import and parse their arguments; none imports another; each limits BLAS threads first.

The scripts (``benchmarks/*.py`` with a ``__main__`` block) share code only through the helper modules of
``benchmarks/`` (``common.py``, ``instationary_case.py``, ``pareto_*.py``).  ``common`` limits BLAS to one thread
when imported, so a script imports it before numpy.  Importing a script runs none of its measurements; the imports
and ``--help`` run in a subprocess, because ``common`` changes the environment and ``sys.path`` of its process.
"""

import ast
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCHMARKS = ROOT / "benchmarks"
MODULES = {path.stem: path for path in sorted(BENCHMARKS.glob("*.py"))}


def is_script(path: Path) -> bool:
    return 'if __name__ == "__main__":' in path.read_text()


SCRIPTS = {name for name, path in MODULES.items() if is_script(path)}


def imported(path: Path) -> list[tuple[str, int]]:
    """Top-level module names a file imports, in order, with their line numbers."""
    out = []
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Import):
            out += [(alias.name.split(".")[0], node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.append((node.module.split(".")[0], node.lineno))
    return out


def test_no_benchmark_imports_another():
    assert {"pareto", "bench_steady"} <= SCRIPTS
    offending = [(name, module) for name, path in MODULES.items() for module, _ in imported(path)
                 if module in SCRIPTS and module != name]
    assert offending == []


def test_scripts_import_common_before_anything_but_the_standard_library():
    for name in sorted(SCRIPTS):
        modules = [module for module, _ in imported(MODULES[name])]
        assert "common" in modules, name
        before = modules[:modules.index("common")]
        assert all(m == "__future__" or m in sys.stdlib_module_names for m in before), (name, before)


CHECK = """
import contextlib, io, json, os, sys
sys.path.insert(0, "benchmarks")
import common  # first, as the scripts do
import importlib
report = {"threads": os.environ.get("OPENBLAS_NUM_THREADS"), "help": {}}
modules, scripts = sys.argv[1].split(","), sys.argv[2].split(",")
for name in modules:
    module = importlib.import_module(name)
    if name in scripts and "argparse" in open(module.__file__).read():
        sys.argv[1:] = ["--help"]
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            try:
                module.main()
            except SystemExit as done:
                report["help"][name] = (done.code, out.getvalue().startswith("usage:"))
import rollcontact
report["rollcontact"] = rollcontact.__file__
calls = []
common.median_time(lambda: calls.append(1), min_repeats=4, min_seconds=0.0, warmups=2)
report["calls"] = len(calls)
calls.clear()
common.median_time(lambda: calls.append(1), min_repeats=3, min_seconds=0.0, warmups=1, batch_seconds=1e-3)
report["batched"] = len(calls)
print(json.dumps(report))
"""


def test_every_module_imports_and_every_argparse_script_answers_help():
    done = subprocess.run([sys.executable, "-c", CHECK, ",".join(MODULES), ",".join(sorted(SCRIPTS))], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["threads"] == "1"
    assert Path(report["rollcontact"]).resolve().is_relative_to(ROOT / "src")
    assert report["help"] and all(value == [0, True] for value in report["help"].values()), report["help"]
    assert {"pareto", "bench_steady", "bench_fmu"} <= set(report["help"])
    # median_time: the warm-up calls, then one call per sample; batched samples hold several calls each
    assert report["calls"] == 2 + 4
    assert report["batched"] > 1 + 3
