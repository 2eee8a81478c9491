"""The analysis package as installed: its command-line entry and its import without the
repository on sys.path.

Runs under whichever interpreter runs pytest: Debian's /usr/bin/python3 (the package in the
user site) and the project environment's .venv/bin/python (tools/test.sh runs both).
"""
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest
import tomllib

ROOT = Path(__file__).resolve().parents[2]


def test_pyproject_declares_the_analysis_command():
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts["granudrag-analysis"] == "analysis.cli:main"


@pytest.mark.slow
def test_python_m_analysis_offers_fit_report_predict():
    r = subprocess.run([sys.executable, "-m", "analysis", "--help"], capture_output=True, text=True,
                       timeout=120, cwd=ROOT)
    assert r.returncode == 0, r.stderr[-2000:]
    for command in ("fit", "report", "predict"):
        assert command in r.stdout, command


def test_granudrag_analysis_command_is_installed():
    """The console script pip made from [project.scripts], beside the interpreter (a venv)
    or in the user's scripts folder (Debian's interpreter, user site), runs analysis.cli."""
    in_venv = sys.prefix != sys.base_prefix
    scripts = Path(sysconfig.get_path("scripts") if in_venv else sysconfig.get_path("scripts", "posix_user"))
    command = scripts / "granudrag-analysis"
    assert command.is_file(), f"{command} missing: run tools/install-deps.sh"
    r = subprocess.run([str(command), "--help"], capture_output=True, text=True, timeout=120, cwd="/")
    assert r.returncode == 0, r.stderr[-2000:]
    for sub in ("fit", "report", "predict"):
        assert sub in r.stdout, sub


def test_workflow_does_not_touch_sys_path():
    """The workflow imports the installed package; nothing in it edits sys.path."""
    offenders = [str(p.relative_to(ROOT)) for p in (ROOT / "workflow").rglob("*")
                 if p.is_file() and p.suffix in (".py", ".smk", "") and "sys.path" in p.read_text(errors="ignore")]
    assert offenders == []


def test_every_room_and_module_the_package_docstring_names_exists():
    # The list of rooms and commands in analysis/__init__.py's docstring: each name at the list's
    # indent is a subpackage (a room) or a module at the top of the package, and every room is
    # named (tests/python/test_layout.py checks how the rooms import each other).
    import ast
    import re

    pkg = ROOT / "analysis"
    doc = ast.get_docstring(ast.parse((pkg / "__init__.py").read_text()))
    listed = doc.split("The rooms", 1)[1]
    names = [name for line in listed.splitlines()
             if (m := re.match(r"    ([a-z_]+(?:, [a-z_]+)*)", line)) and not line.startswith("     ")
             for name in m.group(1).split(", ")]
    rooms = {p.parent.name for p in pkg.glob("*/__init__.py")}
    modules = {p.stem for p in pkg.glob("*.py")}
    assert len(names) >= 10, names
    missing = [name for name in names if name not in rooms | modules]
    assert missing == [], f"analysis/__init__.py names rooms or modules that do not exist: {missing}"
    assert rooms <= set(names), f"analysis/__init__.py does not name the rooms {sorted(rooms - set(names))}"


def test_no_source_file_is_over_500_lines():
    """One concept per file: a file past 500 lines holds more than one (the C++ engine, the
    analysis package, the workflow, tools and tests alike)."""
    files = subprocess.run(["git", "ls-files", "*.py", "*.cpp", "*.hpp", "*.smk", "*.sh", "workflow/Snakefile"],
                           cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    assert len(files) > 100
    long = {f: n for f in files if (n := len((ROOT / f).read_text().splitlines())) > 500}
    assert not long, f"split these by concept: {long}"
