#!/usr/bin/python3
"""Snakemake cluster-status command for SLURM without the accounting database (sacct).

Called as `status.py JOBID` (JOBID as printed by `sbatch --parsable`, possibly
"id;cluster"); prints running, success or failed. Asks `scontrol show job`, which
knows a job until MinJobAge (default 300 s) after it ends, then `squeue`. A job
neither knows has left the controller's memory; Snakemake polls far more often
than that, so such a job is reported as success and Snakemake then checks that
its output files exist (a missing output fails the job anyway).
"""
import subprocess
import sys
import time

RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED",
           "REQUEUE_HOLD", "REQUEUE_FED", "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED",
           "RESV_DEL_HOLD", "SPECIAL_EXIT", "POWER_UP_NODE", "UPDATE_DB"}
FAILED = {"FAILED", "CANCELLED", "TIMEOUT", "OUT_OF_MEMORY", "NODE_FAIL", "PREEMPTED",
          "BOOT_FAIL", "DEADLINE", "REVOKED"}


def ask(cmd):
    """stdout of cmd, or None when SLURM does not answer (retried a few times)."""
    for attempt in range(3):
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode == 0:
            return r.stdout
        if "Invalid job id" in r.stderr:
            return ""
        time.sleep(1 + attempt)
    return None


def state(jobid):
    out = ask(["scontrol", "show", "job", "--oneliner", jobid])
    if out:
        for field in out.split():
            if field.startswith("JobState="):
                return field.split("=", 1)[1]
    out2 = ask(["squeue", "--noheader", "--jobs", jobid, "--format", "%T"])
    if out2 and out2.strip():
        return out2.split()[0]
    if out is None and out2 is None:
        return "UNREACHABLE"
    return "UNKNOWN"


def main(argv):
    if len(argv) != 2:
        sys.exit("usage: status.py JOBID")
    s = state(argv[1].split(";")[0].strip()).split("+")[0]
    if s == "COMPLETED" or s == "UNKNOWN":
        print("success")
    elif s in FAILED:
        print("failed")
    else:           # running states, and a controller that did not answer: ask again later
        print("running")


if __name__ == "__main__":
    main(sys.argv)
