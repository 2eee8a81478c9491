"""Collecting a rung: a finished study's small result files copied into its rung directory,
with the per-run κ shells and pull starts, and run.json (cost, machine, commit) written last."""
import json
import os
import platform
import shutil
import subprocess
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pandas as pd

from ..core.table import write_csv, write_text_atomic
from ..runs.runs import RunFileError, read_run
from .ladder_claims import LadderError

# A rung's files: (name in the rung directory, path under the study's results, required).
RUNG_FILES = (("table.csv", "table.csv", True), ("runs.csv", "runs.csv", False),
              ("fits.json", "report/fits.json", True), ("report.md", "report/report.md", False))
SHELL_GROUP = "observables/bulk_coordination/shells"
# The run's keys (analysis.runs.runs.read_run), then the shell's; ring_grains: grains seen in the ring
# [R + w_prev, R + w) summed over the samples (its weight in Z), run: the run directory.
SHELL_COLUMNS = ["system", "D", "h", "mu", "kn", "Fr", "V", "seed", "n_contacts", "width", "Z", "kappa",
                 "gamman", "ring_grains", "run", "lx", "ly"]


# --- collect ---------------------------------------------------------------

def collect(config, results_dir, out_dir, *, wall_seconds, cores, started=None, phi=None,
            machine_cpu=None):
    """Copy a finished study's small result files into out_dir (a rung directory) and write
    its run.json. Returns run.json's content. run.json's machine is this host's unless
    `machine_cpu` names the CPU the jobs ran on (a rung run in pieces elsewhere: the cost
    estimate's machine table reads it), noted with the collecting host's. Every file is written
    under a temporary name and renamed; run.json comes last, so an interrupted collect leaves a
    rung that reads "not run"."""
    config, results, out = Path(config), Path(results_dir), Path(out_dir)
    if not config.is_file():
        raise LadderError(f"{config}: no such study config (give the config the study ran with)")
    if not (wall_seconds >= 0 and cores >= 1):
        raise LadderError(f"wall seconds must be >= 0 and cores >= 1, got {wall_seconds} and {cores}")
    hint = f"run the study first: tools/study.sh --configfile {config}"
    for _, rel, required in RUNG_FILES:
        if required and not (results / rel).is_file():
            raise LadderError(f"{results / rel}: no such file ({hint})")
    out.mkdir(parents=True, exist_ok=True)
    notes = _config_notes(config, results)
    _copy_atomic(config, out / "config.yaml")
    for name, rel, _ in RUNG_FILES:
        if (results / rel).is_file():
            _copy_atomic(results / rel, out / name)
        else:
            notes.append(f"{name}: the study has no {results / rel}; not copied")
            (out / name).unlink(missing_ok=True)       # never keep an older study's copy
    notes += write_kappa_shells(results, out / "kappa_shells.csv")
    notes += write_startup(results, out / "startup.csv")
    notes += write_depth_law(config, out, phi)
    hours, source, jobs = core_hours(results, threads=_config_threads(config))
    host = machine()
    if machine_cpu:
        notes.append(f"machine.cpu given at collect (the jobs' host); collected on {host['cpu']}")
        host = {**host, "cpu": str(machine_cpu)}
    info = {"rung": config.stem, "config": str(config), "results": str(results),
            "wall_seconds": float(wall_seconds), "cores": int(cores), "started": started,
            "core_hours": hours, "core_hours_from": source, "jobs": jobs, "machine": host,
            "commit": commit(), "engine_commits": engine_commits(results),
            "date": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "notes": notes}
    write_text_atomic(out / "run.json", json.dumps(info, indent=1, ensure_ascii=False) + "\n")
    return info


def engine_commits(results):
    """The engines that wrote the study's files: the distinct /granudrag commit stamps of its
    run and bed files, with how many files each ({stamp: count}). `commit` in run.json is the
    repository at collect time (the analysis); these are what simulated."""
    import h5py
    counts = {}
    for p in sorted(Path(results).glob("pulls/**/run.h5")) + sorted(Path(results).glob("beds/**/bed.h5")):
        try:
            with h5py.File(p, "r") as f:
                stamp = f["granudrag"].attrs.get("commit", b"unknown")
        except (OSError, KeyError):
            stamp = b"unreadable"
        stamp = stamp.decode() if isinstance(stamp, bytes) else str(stamp)
        counts[stamp] = counts.get(stamp, 0) + 1
    return counts


def _copy_atomic(src, dst):
    tmp = dst.with_name(dst.name + ".tmp")
    shutil.copyfile(src, tmp)
    tmp.replace(dst)


def _read_config(config):
    import yaml
    try:
        doc = yaml.safe_load(Path(config).read_text())
    except yaml.YAMLError as exc:
        raise LadderError(f"{config}: not a readable YAML file ({exc})") from None
    return doc if isinstance(doc, dict) else {}


def _config_threads(config):
    """Threads of each simulation job (the config's `threads`, default 1): what a benchmark's
    wall seconds are multiplied by when it has no cpu_time."""
    t = _read_config(config).get("threads", 1)
    return int(t) if isinstance(t, int) and t >= 1 else 1


def _config_notes(config, results):
    """A note when the config names another results directory than the one collected (a copy
    moved elsewhere is fine; a mix-up of studies is not)."""
    named = _read_config(config).get("results")
    if named and Path(named).resolve() != results.resolve():
        return [f"the config's results directory is {named}, collected from {results}"]
    return []


def core_hours(results, threads=1):
    """(core-hours, how they were counted, number of jobs) from the study's Snakemake benchmark
    files <results>/benchmarks/**/*.tsv (columns s, h:m:s, max_rss, ..., cpu_time; seconds).
    cpu_time counts what each job really used; a file without it (NA or no column) counts its
    wall seconds s times `threads`. (None, reason, 0) when the study left no benchmark file."""
    files = sorted(Path(results).glob("benchmarks/**/*.tsv"))
    if not files:
        return None, "no benchmark files under " + str(Path(results) / "benchmarks"), 0
    total, by_cpu, by_wall = 0.0, 0, 0
    for f in files:
        try:
            b = pd.read_csv(f, sep="\t")
        except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
            raise LadderError(f"{f}: not a Snakemake benchmark file ({exc})") from None
        cpu = pd.to_numeric(b["cpu_time"], errors="coerce") if "cpu_time" in b.columns else None
        if cpu is not None and len(cpu) and cpu.notna().all():
            total += float(cpu.sum())
            by_cpu += 1
        elif "s" in b.columns:
            total += float(pd.to_numeric(b["s"], errors="coerce").fillna(0.0).sum()) * threads
            by_wall += 1
        else:
            raise LadderError(f"{f}: a benchmark file without the columns cpu_time and s")
    wall = f"s × {threads} thread{'s' if threads > 1 else ''}"
    source = ("cpu_time" if not by_wall else wall if not by_cpu
              else f"cpu_time ({by_cpu} files); {wall} ({by_wall} files without cpu_time)")
    return total / 3600.0, source, len(files)


def machine():
    """CPU model, logical cores and memory of this machine (Linux /proc; 'unknown' elsewhere)."""
    cpu, mem = platform.processor() or "unknown", None
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                mem = round(int(line.split()[1]) / 1024 ** 2, 1)
                break
    except (OSError, ValueError, IndexError):
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "memory_gib": mem}


def commit(repo=None):
    """`git rev-parse --short HEAD` of the repository holding this package, "-dirty" added when
    a tracked or new file outside results/ differs (results/ is where the rungs are written);
    "unknown" outside a git work tree."""
    repo = Path(repo) if repo else Path(__file__).resolve().parents[1]
    try:
        head = _git(repo, "rev-parse", "--short", "HEAD").strip()
        status = _git(repo, "status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    changed = [p for line in status.splitlines() if line.strip()
               for p in line[3:].split(" -> ") if not p.strip('"').startswith("results/")]
    return head + ("-dirty" if changed else "")


def _git(repo, *args):
    return subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True, check=True,
                          timeout=60).stdout


def write_depth_law(config, out, phi_fits=None):
    """deep_law.csv, deep_law.md and a figure per series in the rung directory `out` (its table.csv
    copied in), when the study pulled system II at two or more depths: the depth law read on the
    deep intruders (h >= the config's report.h_min, else the paper's 45 d) and on every depth
    (analysis.deep_law), phi_mu for the sum rule from the fit file `phi_fits` (another rung's:
    a study of system II depths at one D has no phi of its own), else from the rung's own
    fits.json when it has one. Notes, naming where phi came from."""
    from ..core import paper
    from ..core.table import load_csv
    from ..deep_law.deep_law import phi_from_fits, write_deep_law
    from ..deep_law.deep_law_figure import draw
    from ..fits.fit_file import FitFileError

    df = load_csv(out / "table.csv")
    deep = df[df.system == "II"] if "system" in df.columns else df.iloc[:0]
    if deep.h.round(3).nunique() < 2:
        return []
    h_min = float((_read_config(config).get("report") or {}).get("h_min") or paper.DEEP_H)
    if phi_fits is not None:
        try:
            phi = phi_from_fits(phi_fits)
        except (FitFileError, OSError) as exc:
            raise LadderError(f"--phi {phi_fits}: not a readable fit file ({exc}); give a rung's fits.json") from None
        if phi is None:
            raise LadderError(f"--phi {phi_fits}: the fit file has no phi_mu table (a study with yield pulls "
                              "at several D has one)")
        source = f"phi_mu from {phi_fits}"
    else:
        try:
            phi = phi_from_fits(out / "fits.json")
        except FitFileError:
            phi = None
        source = "phi_mu from the rung's own fits.json" if phi is not None else "no phi_mu: no sum rule"
    table, _ = write_deep_law(df, out, h_min=h_min, phi=phi)
    draw(df, out, h_min=h_min)
    return [f"deep_law.csv: the depth law on h >= {h_min:g} d and on every depth ({len(table)} rows; {source})"]


def write_kappa_shells(results, path):
    """kappa_shells.csv: one row per run file <results>/pulls/**/run.h5 and shell width, from
    its /observables/bulk_coordination/shells (width, Z, kappa, grains per ring). Runs the
    table would refuse (RunFileError) and runs written before the engine recorded shells are
    left out and counted; with no run left the file has its header only. Returns the notes."""
    rows, unusable, without = [], [], 0
    paths = sorted(Path(results).glob("pulls/**/run.h5"))
    for p in paths:
        try:
            run = read_run(p, root=results)
            shells = read_shells(p)
        except RunFileError as exc:
            unusable.append(str(exc))
            continue
        if shells is None:
            without += 1
            continue
        keys = {k: run[k] for k in SHELL_COLUMNS if k in run and k not in shells}
        rows.append(pd.DataFrame({**keys, **shells}).reindex(columns=SHELL_COLUMNS))
    df = pd.concat(rows, ignore_index=True) if rows else pd.DataFrame(columns=SHELL_COLUMNS)
    write_csv(df, path)
    notes = []
    if unusable:
        notes.append(f"kappa_shells.csv: {len(unusable)} unusable run files left out: " + "; ".join(unusable))
    if without:
        notes.append(f"kappa_shells.csv: {without} of {len(paths)} runs have no {SHELL_GROUP} "
                     "(pulled before the engine recorded shells); left out")
    if not rows:
        notes.append(f"kappa_shells.csv: header only: no run file under {Path(results) / 'pulls'} records shells")
    return notes


STARTUP_COLUMNS = ["system", "D", "h", "mu", "kn", "Fr", "V", "seed", "drag", "drag_err", "whole_mean",
                   "travel", "transient_distance"]


def write_startup(results, path):
    """startup.csv: per run, the drag after the discarded transient (`drag`, the table's) and the
    mean of -F_x over the whole pull, start included (`whole_mean`: the last value of the run's
    cumulative average, the paper's Fig. 4 "cumulative average"), with the travel. The paper
    does not say it discarded a start; `startup_refit` asks what its drag would be if not."""
    import h5py
    rows, unusable = [], []
    for p in sorted(Path(results).glob("pulls/**/run.h5")):
        try:
            run = read_run(p, root=results)
            with h5py.File(p, "r") as f:
                whole = float(np.asarray(f["observables/cumulative_drag/value"][()], dtype=float)[-1])
        except (RunFileError, OSError, KeyError, IndexError) as exc:
            unusable.append(f"{p}: {exc}")
            continue
        rows.append({**{k: run[k] for k in STARTUP_COLUMNS if k in run}, "whole_mean": whole,
                     "travel": run["distance"]})
    write_csv(pd.DataFrame(rows, columns=STARTUP_COLUMNS), path)
    return [f"startup.csv: {len(unusable)} run files left out: " + "; ".join(unusable)] if unusable else []


def read_shells(path):
    """{width, Z, kappa, ring_grains} arrays of a run file's shells group; None if it has none."""
    import h5py
    try:
        with h5py.File(path, "r") as f:
            if SHELL_GROUP not in f:
                return None
            g = f[SHELL_GROUP]
            out = {k: np.asarray(g[k][()], dtype=float) for k in ("width", "Z", "kappa")}
            n = len(out["width"])
            out["ring_grains"] = np.asarray(g["grains"][()], dtype=float) if "grains" in g else np.full(n, np.nan)
    except (OSError, KeyError) as exc:
        raise RunFileError(f"{path}: damaged shells group {SHELL_GROUP}: {exc}") from None
    if any(v.ndim != 1 or len(v) != n for v in out.values()):
        raise RunFileError(f"{path}: the datasets of {SHELL_GROUP} differ in length")
    return out
