"""tools/rung-pieces.sh: a long rung's finished beds, pulls and job benchmarks saved beside the
ladder and put back on a fresh checkout, each pull newer than its bed, an unfinished job's files
left behind."""
import os
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "rung-pieces.sh"


def _run(action, config, pieces):
    env = dict(os.environ, RUNG_PIECES_DIR=str(pieces))
    return subprocess.run([str(SCRIPT), action, str(config)], capture_output=True, text=True,
                          timeout=60, env=env, cwd=ROOT)


def _write(path, text, mtime):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    os.utime(path, (mtime, mtime))


def test_save_then_restore_keeps_finished_files_and_their_times(tmp_path):
    results = tmp_path / "results"
    config = tmp_path / "rung.yaml"
    config.write_text(f"results: {results}\n")
    bed = "beds/system~I/D~3/z~13.5/mu~0.5/kn~2e6/gn~1/seed~1/bed.h5"
    pull = "pulls/system~I/D~3/z~13.5/mu~0.5/kn~2e6/gn~1/seed~1/Fr~5/run.h5"
    bench = "benchmarks/pulls/system~I/D~3/z~13.5/mu~0.5/kn~2e6/gn~1/seed~1/Fr~5.tsv"
    running = "pulls/system~I/D~3/z~13.5/mu~0.5/kn~2e6/gn~1/seed~1/Fr~1/run.h5.checkpoint.h5"
    _write(results / bed, "bed", 1_000_000)
    _write(results / pull, "pull", 2_000_000)
    _write(results / bench, "s\tcpu_time\n1\t1\n", 2_000_000)
    _write(results / running, "half a pull", 3_000_000)
    pieces = tmp_path / "pieces"

    r = _run("save", config, pieces)
    assert r.returncode == 0, r.stderr
    assert "3 new file(s) saved" in r.stdout
    assert not (pieces / running).exists()  # an unfinished job stays where it ran
    assert (pieces / pull).read_text() == "pull"

    # A second save copies nothing again.
    assert "0 new file(s) saved" in _run("save", config, pieces).stdout

    # A fresh checkout: the results are gone; restore brings back the finished files, the pull
    # newer than its bed (Snakemake takes it as finished).
    fresh = tmp_path / "fresh"
    config.write_text(f"results: {fresh}\n")
    r = _run("restore", config, pieces)
    assert r.returncode == 0, r.stderr
    assert "3 file(s) restored" in r.stdout
    assert (fresh / bed).read_text() == "bed"
    assert os.stat(fresh / bed).st_mtime_ns < os.stat(fresh / pull).st_mtime_ns
    assert not (fresh / running).exists()

    # A bed not among the pieces (a rung saved before beds were committed) is poured again first
    # on a fresh clone (now), and the pull restored after it is still the newer.
    again = tmp_path / "again"
    config.write_text(f"results: {again}\n")
    (pieces / bed).unlink()
    _write(again / bed, "bed poured again", os.stat(fresh / pull).st_mtime)
    r = _run("restore", config, pieces)
    assert "2 file(s) restored" in r.stdout
    assert os.stat(again / bed).st_mtime_ns < os.stat(again / pull).st_mtime_ns
    config.write_text(f"results: {fresh}\n")

    # Nothing in place is overwritten.
    (fresh / pull).write_text("newer pull")
    _run("restore", config, pieces)
    assert (fresh / pull).read_text() == "newer pull"


def test_bad_input_is_refused_by_name(tmp_path):
    r = subprocess.run([str(SCRIPT), "save"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "usage" in r.stderr
    r = subprocess.run([str(SCRIPT), "save", str(tmp_path / "nope.yaml")], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2 and "no config" in r.stderr
    config = tmp_path / "rung.yaml"
    config.write_text(f"results: {tmp_path / 'absent'}\n")
    r = _run("save", config, tmp_path / "pieces")
    assert r.returncode == 2 and "no results directory" in r.stderr
    r = _run("restore", config, tmp_path / "no-pieces")
    assert r.returncode == 2 and "no saved pieces" in r.stderr
