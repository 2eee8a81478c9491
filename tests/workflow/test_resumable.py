"""workflow/scripts/resumable.sh: one attempt of a checkpointed job (rules bed and pull)."""
import subprocess
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "workflow" / "scripts" / "resumable.sh"


def attempt(tmp_path, n, command, args="--speed 1", newer=""):
    out, log = tmp_path / "run.h5", tmp_path / "run.log"
    r = subprocess.run([str(SCRIPT), str(out), str(log), str(n), args, newer, "--", "sh", "-c", command],
                       capture_output=True, text=True)
    return r, out, log


def test_a_run_finished_by_a_killed_job_is_kept_for_the_next_attempt(tmp_path):
    r, out, log = attempt(tmp_path, 1, f"echo simulated; echo data > {tmp_path / 'run.h5'}")
    assert r.returncode == 0 and out.read_text() == "data\n"
    assert (tmp_path / "run.h5.done").samefile(out)               # a hard link: no extra disk
    out.unlink()                                                   # the job was killed: Snakemake deletes it
    log.unlink()                                                   # and the log, before the next attempt
    r, out, log = attempt(tmp_path, 2, "echo must not run; exit 1")
    assert r.returncode == 0 and out.read_text() == "data\n"
    text = log.read_text()
    assert "attempt 1" in text and "simulated" in text and "attempt 2" in text      # every attempt's log
    assert "finished by an earlier attempt" in text and "must not run" not in text


def test_a_new_run_or_other_arguments_simulate_again(tmp_path):
    write = f"echo again > {tmp_path / 'run.h5'}"
    attempt(tmp_path, 1, f"echo first > {tmp_path / 'run.h5'}")
    r, out, _ = attempt(tmp_path, 1, write)                        # attempt 1: --forcerun, a deleted output
    assert out.read_text() == "again\n"
    out.write_text("first\n")
    r, out, _ = attempt(tmp_path, 2, write, args="--speed 2")      # a retry with other arguments
    assert out.read_text() == "again\n"


def test_a_stale_checkpoint_is_removed_and_a_failure_is_reported(tmp_path):
    bed = tmp_path / "bed.h5"
    ckpt = tmp_path / "run.h5.checkpoint.h5"
    ckpt.write_text("old")
    (tmp_path / "run.h5.checkpoint.h5.args").write_text("--speed 1\n")
    bed.write_text("new bed")                                      # newer than the checkpoint
    r, out, log = attempt(tmp_path, 2, f"test -e {ckpt} && echo resumed; echo boom; exit 3", newer=str(bed))
    assert r.returncode == 3 and not ckpt.exists()
    text = log.read_text()
    assert "checkpoint older than" in text and "boom" in text and "resumed" not in text
    assert not (tmp_path / "run.h5.done").exists()
    # A checkpoint newer than the bed, same arguments: kept for --resume.
    ckpt.write_text("good")
    (tmp_path / "run.h5.checkpoint.h5.args").write_text("--speed 1\n")
    r, _, log = attempt(tmp_path, 3, f"test -e {ckpt} && echo resumed && touch {tmp_path / 'run.h5'}", newer=str(bed))
    assert r.returncode == 0 and "resumed" in log.read_text()
