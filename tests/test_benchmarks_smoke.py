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
    assert {"pareto", "bench_steady", "bench_table"} <= set(report["help"])
    # median_time: the warm-up calls, then one call per sample; batched samples hold several calls each
    assert report["calls"] == 2 + 4
    assert report["batched"] > 1 + 3


def written_results() -> dict[str, str]:
    """Results file -> the script that writes it (a name in a ``publish``, ``run_and_publish`` or results path)."""
    import re

    out = {}
    for name in SCRIPTS:
        text = MODULES[name].read_text()
        for found in re.findall(r"(?:publish\([^\n]*?|RESULTS / |\"results\" / )\"([a-z_0-9]+\.(?:md|png))\"", text):
            out[found] = name
    return out


def test_every_study_writes_a_results_file_and_the_readme_lists_it():
    import re

    written = written_results()
    studies = SCRIPTS - {"common"}
    assert studies <= set(written.values()), f"studies that write no results file: {studies - set(written.values())}"
    readme = (BENCHMARKS / "README.md").read_text()
    for name in studies:
        assert f"python benchmarks/{name}.py" in readme, f"benchmarks/README.md does not list {name}.py"
    cited = set()
    for path in [*ROOT.glob("src/**/*.py"), *ROOT.glob("fmu_src/**/*.py"), *ROOT.glob("docs/*.md"), ROOT / "README.md",
                 *BENCHMARKS.glob("*.py")]:
        cited |= set(re.findall(r"results/([a-z_0-9]+\.(?:md|png))", path.read_text()))
    orphans = sorted(c for c in cited if c not in written)
    assert orphans == [], f"cited results files that no script writes: {orphans}"


PUBLISH = """
import sys
sys.path.insert(0, "benchmarks")
import common
from pathlib import Path
common.RESULTS = Path(sys.argv[1])
sys.argv[1:] = sys.argv[2:]
common.run_and_publish(lambda: print("| a | b |\\n|---|---|\\n| 1 | 2 |"), "study.md")
"""


def test_run_and_publish_writes_what_was_printed_with_the_command_and_the_machine(tmp_path):
    for argv in (["--rounds", "3"], ["--quick"]):
        folder = tmp_path / argv[0].strip("-")
        done = subprocess.run([sys.executable, "-c", PUBLISH, str(folder), *argv], cwd=ROOT, capture_output=True,
                              text=True, timeout=120)
        assert done.returncode == 0 and "| 1 | 2 |" in done.stdout, done.stderr
        path = folder / "study.md"
        if argv == ["--quick"]:
            assert not path.exists(), "--quick writes nothing"
            continue
        text = path.read_text()
        assert text.startswith("| a | b |\n|---|---|\n| 1 | 2 |\n\nRun by `python benchmarks/-c --rounds 3` on:"), text
        assert "- CPU: " in text and "logical cores" in text and "- Python " in text, text


def test_links_to_results_files_resolve():
    import re

    for page in [BENCHMARKS / "README.md", *ROOT.glob("docs/*.md")]:
        for link in re.findall(r"\]\(([^)#]*results/[^)#]+)\)", page.read_text()):
            assert (page.parent / link).resolve().is_file(), f"{page.relative_to(ROOT)} links {link}, which is missing"
