"""The engine names the code it was built from: `granudrag --version` and every file's
/granudrag commit are the commit of the source tree at build time (cmake/build_stamp.cmake),
with "-dirty" when tracked files outside results/ differ from it, not the commit CMake was
configured at (a rebuilt engine used to keep its first stamp).

The engine: $GRANUDRAG if set, else build/granudrag (tools/test.sh builds it)."""
import os
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag")).resolve()


def _git(*args):
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True,
                          check=True).stdout.strip()


def test_version_names_the_commit_the_engine_was_built_from():
    assert BINARY.is_file(), f"no granudrag binary at {BINARY}: build it (cmake --build build) or set GRANUDRAG"
    if not (ROOT / ".git").exists():
        pytest.skip("a source tree without git: the engine says 'unknown' (tested below)")
    out = subprocess.run([str(BINARY), "--version"], capture_output=True, text=True, check=True).stdout
    m = re.fullmatch(r"granudrag \S+ \(commit (\S+?)(-dirty)?\)\n", out)
    assert m, out
    # The binary was built from this tree (tools/test.sh builds before testing): the same commit.
    # The dirty flag is not compared, since files may have changed since the build.
    head = _git("rev-parse", "--short", "HEAD")
    assert m.group(1) == head, (f"{BINARY} was built from {m.group(1)}, the tree is at {head}: "
                                "rebuild it (cmake --build build)")


def test_stamp_script_marks_a_dirty_tree(tmp_path):
    # The script itself on a throwaway repository: clean, then a tracked file changed, then
    # only a file under results/ changed (not dirty: that is where studies write).
    repo = tmp_path / "repo"
    repo.mkdir()
    (repo / "results").mkdir()
    (repo / "a.txt").write_text("a\n")
    (repo / "results" / "r.csv").write_text("x\n")
    for cmd in (["init", "-q"], ["add", "."],
                ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "c"]):
        subprocess.run(["git", "-C", str(repo), *cmd], check=True, capture_output=True)
    head = subprocess.run(["git", "-C", str(repo), "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True, check=True).stdout.strip()
    out = tmp_path / "stamp.cpp"

    def stamp():
        subprocess.run(["cmake", f"-DSOURCE_DIR={repo}", f"-DOUTPUT={out}", "-P",
                        str(ROOT / "cmake" / "build_stamp.cmake")], check=True, capture_output=True)
        return re.search(r'return "([^"]*)"', out.read_text()).group(1)

    assert stamp() == head
    # A tree without git of its own, inside another repository: not that repository's commit.
    (repo / "sub").mkdir()
    inner_out = subprocess.run(["cmake", f"-DSOURCE_DIR={repo / 'sub'}", f"-DOUTPUT={out}", "-P",
                                str(ROOT / "cmake" / "build_stamp.cmake")], check=True, capture_output=True)
    assert inner_out.returncode == 0 and 'return "unknown"' in out.read_text()
    (repo / "results" / "r.csv").write_text("y\n")
    assert stamp() == head
    (repo / "a.txt").write_text("b\n")
    assert stamp() == head + "-dirty"


def test_one_release_for_the_engine_the_analysis_and_the_changelog():
    # VERSION declares it once; CMake and pyproject.toml read it, CHANGELOG.md describes it.
    import analysis

    release = (ROOT / "VERSION").read_text().strip()
    assert re.fullmatch(r"\d+\.\d+\.\d+", release), f"VERSION holds {release!r}, not MAJOR.MINOR.PATCH"
    assert analysis.__version__ == release
    out = subprocess.run([str(BINARY), "--version"], capture_output=True, text=True, check=True).stdout
    assert out.startswith(f"granudrag {release} "), f"{BINARY} says {out!r}, VERSION {release}: rebuild it"
    assert f"## [{release}]" in (ROOT / "CHANGELOG.md").read_text(), "CHANGELOG.md has no entry for VERSION"
    assert re.search(rf"^version: {re.escape(release)}$", (ROOT / "CITATION.cff").read_text(), re.M), \
        "CITATION.cff's version is not VERSION's"
