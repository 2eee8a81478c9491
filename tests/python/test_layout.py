"""The analysis package's layout: one room (subpackage) per concern, each saying its job in one
line, the commands at the top, and imports in one direction only.

    core  <-  runs, fits  <-  figures  <-  regime_tests, report  <-  deep_law  <-  validation, ladder  <-  commands

Imports are read with ast, relative and absolute ones, deferred ones (inside a function) too:
a cycle makes the import order matter and hides which room owns a concept.
"""
import ast
import re
from pathlib import Path

import tomllib

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "analysis"
ROOMS = sorted(p.parent.name for p in PKG.glob("*/__init__.py"))
COMMANDS = sorted(p.stem for p in PKG.glob("*.py") if p.stem not in ("__init__", "__main__"))


def _module_name(path):
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p) for p in PKG.rglob("*.py")}


def _imports(path):
    """(lineno, dotted name) of every module `path` imports: `from X import a` gives X.a when
    X.a is a module of the package (`from . import paper`), else X."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
            base = (f"{base}.{node.module}" if node.module else base) if node.level else node.module
            for a in node.names:
                found.append((node.lineno, f"{base}.{a.name}" if f"{base}.{a.name}" in MODULES else base))
    return found


def _graph(key):
    """{key(module): {key(imported module)}} over the package's own modules, self-edges dropped."""
    graph = {}
    for path in PKG.rglob("*.py"):
        here = key(_module_name(path))
        for _, target in _imports(path):
            if target.split(".")[0] == "analysis" and key(target) != here:
                graph.setdefault(here, set()).add(key(target))
    return graph


def _room(module):
    """The room of a dotted module name: analysis.fits.regimes -> fits; a command at the top,
    analysis.cli -> cli; the package itself (its __version__) -> analysis."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "analysis"


def _cycles(graph):
    def cycle_from(start, node, seen):
        for nxt in sorted(graph.get(node, ())):
            if nxt == start:
                return [node, nxt]
            if nxt not in seen:
                seen.add(nxt)
                rest = cycle_from(start, nxt, seen)
                if rest:
                    return [node, *rest]
        return None

    return [c for m in sorted(graph) if (c := cycle_from(m, m, {m}))]


def test_the_package_has_its_rooms_and_only_commands_at_the_top():
    assert len(ROOMS) >= 6, ROOMS
    assert COMMANDS == ["cli", "drag_profile", "ladder_refit", "predict"], COMMANDS


def test_every_room_says_its_job_in_one_line_and_holds_nothing_else_in_its_init():
    bad = []
    for room in ROOMS:
        tree = ast.parse((PKG / room / "__init__.py").read_text())
        doc = ast.get_docstring(tree)
        if not doc or "\n" in doc.strip() or len(tree.body) != 1:
            bad.append(room)
    assert bad == [], f"these rooms' __init__.py is not one line of docstring: {bad}"


def test_pyproject_installs_every_room():
    listed = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]
    assert sorted(p for p in listed if p.startswith("analysis")) == sorted(
        ["analysis", *(f"analysis.{room}" for room in ROOMS)])


def _readme_map():
    """[(room, [modules])] of analysis/README.md's table of rooms, in its order."""
    rows = re.findall(r"^\| `([a-z_]+)/` \| ([^|]+) \|", (PKG / "README.md").read_text(), re.M)
    return [(room, re.findall(r"`([a-z_]+)`", modules)) for room, modules in rows]


def test_the_readme_maps_every_room_and_module():
    mapped = dict(_readme_map())
    assert sorted(mapped) == ROOMS, "analysis/README.md's table of rooms lists other rooms than analysis/ has"
    wrong = {room: sorted(set(modules) ^ {p.stem for p in (PKG / room).glob("*.py")} - {"__init__"})
             for room, modules in mapped.items()}
    assert not any(wrong.values()), f"analysis/README.md's table of rooms is out of date: {wrong}"


def test_each_room_imports_only_the_rooms_before_it_in_the_readme():
    # The order the README gives is one the imports keep: a room that needs a later one says
    # the order (or the room) is wrong.
    graph = _graph(_room)
    order = [room for room, _ in _readme_map()]
    late = {room: sorted(graph.get(room, set()) - set(order[:i]) - {"analysis"}) for i, room in enumerate(order)}
    assert not any(late.values()), f"rooms importing rooms listed after them in analysis/README.md: {late}"


def test_the_rooms_import_each_other_without_a_cycle():
    graph = _graph(_room)
    assert set(graph) <= {*ROOMS, *COMMANDS, "__main__"}, graph
    assert not _cycles(graph), f"import cycles between the rooms of analysis/: {_cycles(graph)}"


def test_the_modules_import_each_other_without_a_cycle():
    # One direction per pair (analysis.validation.validation dispatches to pull_length; both take
    # what "agrees" means from agreement).
    graph = _graph(lambda module: module)
    assert not _cycles(graph), f"import cycles in analysis/: {_cycles(graph)}"


def test_no_room_imports_a_command():
    """The commands at the top drive the rooms; a room that imported one would sit above it."""
    graph = _graph(_room)
    up = {room: sorted(graph.get(room, set()) & set(COMMANDS)) for room in ROOMS}
    assert not any(up.values()), up


def test_the_analysis_does_not_import_the_workflows_study_library():
    """Layers: the workflow's study library (workflow/granudrag_study) uses the analysis (its
    physics, the fits' options), never the reverse, so the fits' package stands alone."""
    offenders = [f"{path.relative_to(ROOT)}:{line}" for path in PKG.rglob("*.py")
                 for line, target in _imports(path) if target.split(".")[0] == "granudrag_study"]
    assert offenders == []


def test_the_check_sees_a_cycle_and_every_form_of_import():
    assert _cycles({"fits": {"core"}, "core": {"report"}, "report": {"fits"}})
    assert not _cycles({"fits": {"core"}, "report": {"fits", "core"}})
    seen = lambda module: {target for _, target in _imports(PKG / module)}
    assert "analysis.ladder.ladder" in seen("cli.py")                   # deferred: inside a function
    assert "analysis.core.paper" in seen("figures/figures.py")          # from ..core import paper
    assert "analysis.fits.goodness" in seen("report/verdicts.py")       # from ..fits.goodness import
    assert "analysis" in seen("fits/fit_file.py")                       # from .. import __version__
