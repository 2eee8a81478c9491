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


FAKE_SNAKEMAKE = """#!/usr/bin/env bash
# A stand-in for Snakemake: makes the target (after --) and its job benchmark, and logs the call.
echo "$@" >> "$FAKE_LOG"
for a in "$@"; do last=$a; done
case "$last" in *.h5) ;; *) exit 0 ;; esac
[ -n "${FAKE_FAIL:-}" ] && case "$last" in *"$FAKE_FAIL"*) exit 1 ;; esac
results=${last%%/beds/*}; results=${results%%/pulls/*}; results=${results%%/columns/*}
rel=${last#"$results"/}; kind=${rel%%/*}; key=${rel#*/}; key=${key%/*}
mkdir -p "$(dirname "$last")" "$(dirname "$results/benchmarks/$kind/$key")"
echo made > "$last"
{ printf 's\\th:m:s\\tmax_rss\\tmax_vms\\tmax_uss\\tmax_pss\\tio_in\\tio_out\\tmean_load\\tcpu_time\\n'
  printf '1\\t0\\t0\\t0\\t0\\t0\\t0\\t0\\t0\\t42.5\\n'; } > "$results/benchmarks/$kind/$key.tsv"
"""


def _piece_setup(tmp_path):
    results = tmp_path / "results"
    config = tmp_path / "rung.yaml"
    config.write_text(f"results: {results}\n")
    fake = tmp_path / "snakemake"
    fake.write_text(FAKE_SNAKEMAKE)
    fake.chmod(0o755)
    pieces = tmp_path / "repo" / "pieces"
    pieces.mkdir(parents=True)
    subprocess.run(["git", "init", "-q", str(tmp_path / "repo")], check=True)
    for k, v in (("user.email", "t@example.org"), ("user.name", "t")):
        subprocess.run(["git", "-C", str(tmp_path / "repo"), "config", k, v], check=True)
    env = dict(os.environ, RUNG_PIECES_DIR=str(pieces), SNAKEMAKE=str(fake), FAKE_LOG=str(tmp_path / "calls"))
    return results, config, pieces, env


BED = "system~II/D~4/h~49.7/mu~0/kn~2e4/gn~199.05359/seed~2"


def test_run_lands_the_bed_then_each_pull_one_commit_each(tmp_path):
    """A piece: the bed first, then each pull, one job per Snakemake call on one core, each saved
    and (with --commit) committed as it lands, its CPU seconds in the message; a job already
    finished is not run again."""
    results, config, pieces, env = _piece_setup(tmp_path)
    _plan(results, "V~1", "V~2")
    r = subprocess.run([str(SCRIPT), "run", "--commit", str(config), BED, "V~1", "V~2"], capture_output=True,
                       text=True, timeout=60, env=env, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    calls = (tmp_path / "calls").read_text().splitlines()
    calls = [c for c in calls if " -- " in c]                       # the jobs, after the dry run
    assert [c.split(" -- ")[1] for c in calls] == [f"{results}/beds/{BED}/bed.h5",
                                                    f"{results}/pulls/{BED}/V~1/run.h5",
                                                    f"{results}/pulls/{BED}/V~2/run.h5"]
    assert all("--cores 1" in c and "--nolock" in c and "--rerun-triggers mtime" in c for c in calls)
    assert (pieces / "pulls" / BED / "V~2" / "run.h5").read_text() == "made\n"
    log = subprocess.run(["git", "-C", str(pieces), "log", "--format=%s|%b"], capture_output=True, text=True).stdout
    subjects = [line.split("|")[0] for line in log.strip().splitlines() if "|" in line]
    assert subjects == ["rung: D~4 h~49.7 mu~0 seed~2, V~2 landed", "rung: D~4 h~49.7 mu~0 seed~2, V~1 landed",
                        "rung: D~4 h~49.7 mu~0 seed~2 bed landed"], log
    assert "CPU 42.5 s" in log
    # Again: everything is there, so nothing runs and nothing is committed.
    (tmp_path / "calls").unlink()
    r = subprocess.run([str(SCRIPT), "run", "--commit", str(config), BED, "V~1"], capture_output=True, text=True,
                       timeout=60, env=env, cwd=ROOT)
    assert r.returncode == 0 and " -- " not in (tmp_path / "calls").read_text()


def _plan(results, *leaves, bed=BED):
    (results / "plan").mkdir(parents=True, exist_ok=True)
    (results / "plan" / "pulls.txt").write_text("".join(f"{bed}/{leaf}\n" for leaf in leaves))


def _run_piece(env, *args):
    return subprocess.run([str(SCRIPT), "run", *args], capture_output=True, text=True, timeout=60, env=env, cwd=ROOT)


def test_run_refuses_an_off_plan_pull_a_busy_bed_and_a_failed_commit(tmp_path):
    """Nothing runs for a pull the plan lacks (a typo, or an option after the bed); a second runner
    on a bed one holds is refused; a commit that fails fails the piece instead of saying it landed."""
    import fcntl
    import hashlib
    results, config, pieces, env = _piece_setup(tmp_path)
    _plan(results, "V~1", "V~2")
    r = _run_piece(env, str(config), BED, "V~3")
    assert r.returncode == 2 and "is not in the plan" in r.stderr
    r = _run_piece(env, str(config), BED, "--commit")
    assert r.returncode == 2 and "is not in the plan" in r.stderr
    assert " -- " not in (tmp_path / "calls").read_text()              # nothing poured
    lock = pieces.parent / ".git" / f"rung-pieces.{hashlib.md5(f'rung/{BED}'.encode()).hexdigest()[:16]}.lock"
    with open(lock, "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        r = _run_piece(env, str(config), BED, "V~1")
        assert r.returncode == 2 and "another runner is working on" in r.stderr
    (pieces.parent / ".git" / "index.lock").write_text("")            # git cannot commit
    r = _run_piece(env, "--commit", str(config), BED, "V~1")
    assert r.returncode == 1 and "was not saved or committed" in r.stderr and "landed (" not in r.stderr


def test_run_takes_the_plans_pulls_and_stops_at_a_failed_job(tmp_path):
    results, config, pieces, env = _piece_setup(tmp_path)
    _plan(results, "V~0.5", "V~1")
    with open(results / "plan" / "pulls.txt", "a") as f:
        f.write(f"{BED.replace('seed~2', 'seed~1')}/V~1\n")
    r = subprocess.run([str(SCRIPT), "run", str(config), BED], capture_output=True, text=True, timeout=60,
                       env=dict(env, FAKE_FAIL="V~1/"), cwd=ROOT)
    assert r.returncode == 1 and "failed" in r.stderr
    assert (pieces / "pulls" / BED / "V~0.5" / "run.h5").exists()          # saved, not committed
    assert not (results / "pulls" / BED / "V~1").exists()
    assert not (results / "pulls" / BED.replace("seed~2", "seed~1")).exists()
    assert subprocess.run(["git", "-C", str(pieces), "log"], capture_output=True).returncode != 0  # no commit
    r = subprocess.run([str(SCRIPT), "run", str(config), "D~4/seed~2"], capture_output=True, text=True, timeout=60,
                       env=env, cwd=ROOT)
    assert r.returncode == 2 and "is not a bed's key" in r.stderr
    r = subprocess.run([str(SCRIPT), "run", str(config), BED.replace("seed~2", "seed~9")], capture_output=True,
                       text=True, timeout=60, env=env, cwd=ROOT)
    assert r.returncode == 2 and "has no pull on" in r.stderr


def test_a_placed_bed_lands_after_its_column_which_is_restored_first(tmp_path):
    """A placed rung (its system has `placement:`): the seed's column lands before the first bed
    placed into it, once for all of them, with its own commit; restored on a fresh checkout, the
    column is older than the beds placed into it (else Snakemake would place them again)."""
    results, config, pieces, env = _piece_setup(tmp_path)
    config.write_text(f"results: {results}\nsystems:\n  II:\n    placement: {{settle_damping: 1}}\n")
    deep, shallow = BED.replace("h~49.7", "h~45"), BED.replace("h~49.7", "h~10")
    (results / "plan").mkdir(parents=True)
    (results / "plan" / "pulls.txt").write_text(f"{deep}/V~1\n{shallow}/V~1\n")
    for bed in (deep, shallow):
        r = _run_piece(env, "--commit", str(config), bed)
        assert r.returncode == 0, r.stderr
    column = "system~II/mu~0/kn~2e4/gn~199.05359/seed~2"
    jobs = [c.split(" -- ")[1] for c in (tmp_path / "calls").read_text().splitlines() if " -- " in c]
    assert jobs == [f"{results}/columns/{column}/column.h5", f"{results}/beds/{deep}/bed.h5",
                    f"{results}/pulls/{deep}/V~1/run.h5", f"{results}/beds/{shallow}/bed.h5",
                    f"{results}/pulls/{shallow}/V~1/run.h5"]
    log = subprocess.run(["git", "-C", str(pieces), "log", "--format=%s"], capture_output=True, text=True).stdout
    assert log.strip().splitlines()[-1] == "rung: mu~0 seed~2 column landed"
    assert (pieces / "benchmarks" / "columns" / f"{column}.tsv").exists()
    # Saved pieces keep their times; touch the column to be the newest file of all, as a clock or
    # a copy might, and restore: it comes back first, so older than its beds all the same.
    newest = max(os.stat(f).st_mtime for f in pieces.rglob("*.h5")) + 100
    os.utime(pieces / "columns" / column / "column.h5", (newest, newest))
    fresh = tmp_path / "fresh"
    config.write_text(f"results: {fresh}\nsystems:\n  II:\n    placement: {{}}\n")
    r = _run("restore", config, pieces)
    assert r.returncode == 0 and "10 file(s) restored" in r.stdout, r.stdout + r.stderr
    col = os.stat(fresh / "columns" / column / "column.h5").st_mtime_ns
    assert all(col < os.stat(fresh / "beds" / b / "bed.h5").st_mtime_ns for b in (deep, shallow))


def test_every_file_a_piece_saves_is_one_git_commits():
    """The repository's .gitignore drops data files (*.h5) but a piece's: a column, a bed, a pull
    and their benchmarks under results/reproduction/<rung>/pieces/ must be committable, or the
    commit of a landed job fails (a placed rung's first column did, before columns were listed)."""
    pieces = "results/reproduction/some-rung/pieces"
    column, bed = "system~II/mu~0/kn~2e4/gn~1/seed~1", "system~II/D~4/h~45/mu~0/kn~2e4/gn~1/seed~1"
    saved = [f"{pieces}/columns/{column}/column.h5", f"{pieces}/beds/{bed}/bed.h5", f"{pieces}/pulls/{bed}/V~1/run.h5",
             f"{pieces}/benchmarks/columns/{column}.tsv", f"{pieces}/benchmarks/pulls/{bed}/V~1.tsv"]
    for path in saved:
        r = subprocess.run(["git", "check-ignore", "--no-index", "-q", path], cwd=ROOT)
        assert r.returncode == 1, f"{path} is ignored by git (.gitignore)"
    unfinished = f"{pieces}/pulls/{bed}/V~1/run.h5.checkpoint.h5"
    assert subprocess.run(["git", "check-ignore", "--no-index", "-q", unfinished], cwd=ROOT).returncode == 0
