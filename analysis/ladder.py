"""The reproduction ladder: studies ("rungs") that each move one factor toward the paper's
conditions, their small result files kept under results/reproduction/<rung>/, and a table of
the paper's claims against the rungs.

    granudrag-analysis ladder collect --config config/ladder/X.yaml --results results/ladder/X \\
        --wall-seconds 1234 --cores 2 [--started ISO] [--out results/reproduction/X]
    granudrag-analysis ladder table results/reproduction [--n-boot 100] [--seed 0]

`collect` copies what a finished study says into <out>/: config.yaml, table.csv, runs.csv,
fits.json, report.md, kappa_shells.csv (Z and κ in nested shells around the intruder, one row
per run and shell width) and run.json (cost, machine, commit), run.json last: a rung directory
without run.json counts as not run.

`table` reads <root>/ladder.yaml (the rungs in order, each with a label; a description per
claim) and writes ladder.csv, ladder.md, claim_<letter>.png, and two diagnostics:
kappa_shells.csv/.png (the slope of κ(Fr) against the shell width Z is counted in) and
fr2_range.csv/.png (Fr_2 refitted on the points with Fr <= fr_max). If <root>/README.md has
the markers LADDER_BEGIN and LADDER_END, the text between them becomes ladder.md's.

The verdicts are the report's: each rung's fits.json and table.csv are read as the report
rule reads them and passed to analysis.report.comparisons; nothing is re-judged here.
"""
import json
import math
import os
import platform
import re
import shutil
import subprocess
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pandas as pd

from . import paper
from .fits import fit_linear, write_text_atomic
from .fitset import load_results, point_bed_scatter
from .regimes import fit_regimes, profile_fr2
from .report import comparisons
from .runs import RunFileError, read_run
from .table import is_yield, load_csv, pooled_drag_err, reference_params, select, write_csv

LADDER_BEGIN, LADDER_END = "<!-- ladder:begin -->", "<!-- ladder:end -->"

# The paper's headline claims, by letter (ladder.yaml may word them otherwise).
CLAIMS = {
    "a": "three regimes, Fr_1 ≈ 1 and Fr_2 ≈ 5, independent of D and h",
    "b": "θ(Fr) = Υ1 Fr^Υ2 + π/Υ3 (Eq. 7): Υ1 = -0.15, Υ2 = 0.38, Υ3 = 2.45",
    "c": "κ(Fr) = 0.887 + 0.185 Fr (Eq. 8, Fig. 8)",
    "d": "φ_0 ≈ 2 and F_Y saturating in μ",
    "e": "α_0 ≈ 1",
    "f": "α_μ + φ_μ ≈ 3",
    "g": "Table I: the μ = 0 drag in regime I is a'' + b'' Fr^c''",
}
OTHER = "other"     # a report row no claim names (a row the report gained later)

# A rung's files: (name in the rung directory, path under the study's results, required).
RUNG_FILES = (("table.csv", "table.csv", True), ("runs.csv", "runs.csv", False),
              ("fits.json", "report/fits.json", True), ("report.md", "report/report.md", False))
SHELL_GROUP = "observables/bulk_coordination/shells"
# The run's keys (analysis.runs.read_run), then the shell's; ring_grains: grains seen in the ring
# [R + w_prev, R + w) summed over the samples (its weight in Z), run: the run directory.
SHELL_COLUMNS = ["system", "D", "h", "mu", "kn", "Fr", "V", "seed", "n_contacts", "width", "Z", "kappa",
                 "gamman", "ring_grains", "run", "lx", "ly"]
NOT_RUN = "not run"
FR_MAX_VALUES = (8.0, 10.0, 12.0, 15.0)


class LadderError(ValueError):
    """A rung or ladder file that is missing or unusable; the message names it and the fix."""


# --- collect ---------------------------------------------------------------

def collect(config, results_dir, out_dir, *, wall_seconds, cores, started=None):
    """Copy a finished study's small result files into out_dir (a rung directory) and write
    its run.json. Returns run.json's content. Every file is written under a temporary name and
    renamed; run.json comes last, so an interrupted collect leaves a rung that reads "not run"."""
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
    hours, source, jobs = core_hours(results, threads=_config_threads(config))
    info = {"rung": config.stem, "config": str(config), "results": str(results),
            "wall_seconds": float(wall_seconds), "cores": int(cores), "started": started,
            "core_hours": hours, "core_hours_from": source, "jobs": jobs, "machine": machine(),
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


# --- the claims of a rung --------------------------------------------------

def claim_of(quantity):
    """The claim letter of a report row, from its quantity text (analysis/report.py)."""
    for prefix, letter in (("Fr_1 (", "a"), ("Fr_2 (", "a"), ("θ(Fr)", "b"), ("κ(Fr)", "c"),
                           ("φ_0", "d"), ("F_Y saturating", "d"), ("α_0", "e"), ("α_μ + φ_μ", "f"),
                           ("Table I", "g")):
        if quantity.startswith(prefix):
            return letter
    return OTHER


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def parse_fitted(text):
    """(value, error) of a report cell "1.23 ± 0.05", "μ_c = 0.12 ± 0.03", "1.234" (no error:
    NaN) or "n/a" (NaN, NaN). The value is as the report rounds it (to its error's 2nd digit)."""
    m = re.search(rf"({_NUMBER})(?:\s*±\s*({_NUMBER}))?\s*$", text)
    if not m:
        return math.nan, math.nan
    return float(m.group(1)), float(m.group(2)) if m.group(2) else math.nan


def parse_published(text):
    """The paper's number of a report cell ("0.887", "≈ 5"); NaN for words ("saturates")."""
    m = re.fullmatch(rf"\s*≈?\s*({_NUMBER})\s*", text)
    return float(m.group(1)) if m else math.nan


def load_rung(rung_dir):
    """(table, Results) of a rung, read as the report rule reads them (table.load_csv,
    fitset.load_results)."""
    d = Path(rung_dir)
    for name in ("table.csv", "fits.json"):
        if not (d / name).is_file():
            raise LadderError(f"{d / name}: no such file (collect the rung again: "
                              "granudrag-analysis ladder collect --config ... --results ...)")
    return load_csv(d / "table.csv"), load_results(d / "fits.json")


def rung_claims(rung_dir):
    """The report's rows of a rung as dicts, each with its claim letter (claim_of): claim,
    quantity, report_quantity, fitted, value, error, published, published_value, verdict,
    notes. `quantity` drops the rung's own reference K_n from the report's text (the ladder
    varies K_n between rungs; rows of another K_n keep theirs), so one quantity lines up
    across rungs. Claims the rung did not study have no rows."""
    df, r = load_rung(rung_dir)
    kn = f"{reference_params(df)[0]:.3g}"
    depths = _requested_depths(df)
    out = []
    for row in comparisons(r, df):
        value, error = parse_fitted(row.fitted)
        q = (row.quantity.replace(f" (K_n = {kn})", "").replace(f", K_n = {kn}", "")
             .replace(f"; K_n = {kn}", ""))
        q = re.sub(r"\bh = ([^,;)\s]+)", lambda m: f"requested h = {depths[m.group(1)]:g}"
                   if m.group(1) in depths else m.group(0), q)
        out.append({"claim": claim_of(row.quantity), "quantity": q, "report_quantity": row.quantity,
                    "fitted": row.fitted, "value": value, "error": error, "published": row.published,
                    "published_value": parse_published(row.published), "verdict": row.verdict,
                    "notes": "; ".join(row.notes)})
    return out


def _requested_depths(df):
    """{the report's text of a measured depth: the depth the config asked for}. The report names
    a depth series by its measured h (the beds' mean), which moves between realizations and bed
    counts (9.46 with one bed, 9.42 with two); the ladder lines rungs up by the requested one."""
    if "h_requested" not in df.columns:
        return {}
    pairs = df[["h", "h_requested"]].dropna().drop_duplicates()
    return {f"{h:.3g}": float(req) for h, req in zip(pairs.h, pairs.h_requested)}


# --- the ladder -------------------------------------------------------------

def read_ladder(root):
    """(rungs [{name, label}], claims {letter: description}) of root/ladder.yaml."""
    import yaml
    root = Path(root)
    if not root.is_dir():
        raise LadderError(f"{root}: no such directory (the ladder's root, e.g. results/reproduction)")
    path = root / "ladder.yaml"
    example = "rungs: [{name: crossover-k2e5-box12, label: 'K_n 2e5, 12 d box'}, ...]"
    if not path.is_file():
        raise LadderError(f"{path}: no such file; write the rungs in order: {example}")
    try:
        doc = yaml.safe_load(path.read_text()) or {}
    except yaml.YAMLError as exc:
        raise LadderError(f"{path}: not a readable YAML file ({exc})") from None
    entries = doc.get("rungs") if isinstance(doc, dict) else None
    if not isinstance(entries, list) or not entries:
        raise LadderError(f"{path}: needs a non-empty list `rungs`, e.g. {example}")
    rungs = []
    for i, e in enumerate(entries):
        e = {"name": e} if isinstance(e, str) else e
        if not isinstance(e, dict) or not e.get("name"):
            raise LadderError(f"{path}: rungs[{i}] has no name ({example})")
        rungs.append({"name": str(e["name"]), "label": str(e.get("label", e["name"]))})
    names = [r["name"] for r in rungs]
    if len(set(names)) != len(names):
        raise LadderError(f"{path}: a rung is listed twice: {', '.join(names)}")
    claims = dict(CLAIMS)
    claims.update({str(k): str(v) for k, v in (doc.get("claims") or {}).items()})
    return rungs, claims


def rung_run(root, name):
    """A rung's run.json as a dict, or None when the rung has not been run (no run.json)."""
    path = Path(root) / name / "run.json"
    if not path.is_file():
        return None
    try:
        return json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise LadderError(f"{path}: not a readable run.json ({exc}); collect the rung again") from None


def ladder_rows(root, rungs):
    """The rows of ladder.csv: one per claim, quantity and rung that has it; a rung not run
    gets one row per quantity (or one row if no rung has any) with verdict "not run"."""
    root = Path(root)
    found, order = [], {}
    for i, rung in enumerate(rungs):
        info = rung_run(root, rung["name"])
        base = {"rung": rung["name"], "label": rung["label"], "order": i}
        if info is None:
            found.append((base, None))
            continue
        machine_ = info.get("machine") or {}
        base.update(core_hours=info.get("core_hours"), wall_seconds=info.get("wall_seconds"),
                    cores=info.get("cores"), machine_cpu=machine_.get("cpu"))
        claims = rung_claims(root / rung["name"])
        for c in claims:
            order.setdefault((c["claim"], c["quantity"]), len(order))
        found.append((base, claims))
    keys = sorted(order, key=lambda k: (k[0], order[k]))
    rows = []
    for base, claims in found:
        if claims is None:
            for claim, q in keys or [("", "")]:
                rows.append({**base, "claim": claim, "quantity": q, "verdict": NOT_RUN})
        else:
            rows += [{**base, **c} for c in sorted(claims, key=lambda c: keys.index((c["claim"], c["quantity"])))]
    cols = ["claim", "quantity", "rung", "label", "value", "error", "fitted", "published", "published_value",
            "verdict", "core_hours", "wall_seconds", "cores", "machine_cpu", "notes", "order"]
    return pd.DataFrame(rows, columns=cols)


def write_ladder(root, *, n_boot=100, seed=0, fr_max_values=FR_MAX_VALUES):
    """ladder.csv, ladder.md, claim_<letter>.png, kappa_shells.csv/.png and fr2_range.csv/.png
    in root, from ladder.yaml and each rung's directory; README.md's ladder section replaced
    when it has the markers. n_boot, seed: the bootstrap of the Fr_2-range refits. Returns the
    paths written."""
    root = Path(root)
    rungs, claims = read_ladder(root)
    table = ladder_rows(root, rungs)
    infos = {r["name"]: rung_run(root, r["name"]) for r in rungs}
    written = [root / "ladder.csv"]
    write_csv(table.drop(columns="order"), root / "ladder.csv")
    written += _claim_figures(root, table, rungs, claims)
    shells = _rung_frames(root, rungs, infos, "kappa_shells.csv")
    slopes = kappa_shell_slopes(shells) if len(shells) else pd.DataFrame(columns=SLOPE_COLUMNS)
    write_csv(slopes, root / "kappa_shells.csv")
    written.append(root / "kappa_shells.csv")
    written += _kappa_figure(root, slopes, shells, rungs)
    decomposition = kappa_decomposition(shells) if len(shells) else pd.DataFrame(columns=DECOMPOSITION_COLUMNS)
    write_csv(decomposition, root / "kappa_decomposition.csv")
    written.append(root / "kappa_decomposition.csv")
    fr2 = [fr2_vs_range(load_csv(root / r["name"] / "table.csv"), fr_max_values, n_boot=n_boot, seed=seed,
                        rung=r["name"]) for r in rungs if infos[r["name"]] is not None]
    fr2 = pd.concat(fr2, ignore_index=True) if fr2 else pd.DataFrame(columns=FR2_COLUMNS)
    write_csv(fr2, root / "fr2_range.csv")
    written.append(root / "fr2_range.csv")
    written += _fr2_figure(root, fr2, rungs)
    startup = [startup_refit(pd.read_csv(root / r["name"] / "startup.csv"), load_csv(root / r["name"] / "table.csv"),
                             n_boot=n_boot, seed=seed, rung=r["name"])
               for r in rungs if infos[r["name"]] is not None and (root / r["name"] / "startup.csv").is_file()]
    startup = pd.concat(startup, ignore_index=True) if startup else pd.DataFrame(columns=STARTUP_FIT_COLUMNS)
    write_csv(startup, root / "startup_fr2.csv")
    written.append(root / "startup_fr2.csv")
    md = ladder_markdown(table, rungs, claims, infos, slopes, fr2, figures=[p.name for p in written],
                         decomposition=decomposition, startup=startup)
    write_text_atomic(root / "ladder.md", md)
    written.append(root / "ladder.md")
    readme = root / "README.md"
    if readme.is_file() and _replace_section(readme, md):
        written.append(readme)
    return written


def _rung_frames(root, rungs, infos, name):
    """A per-rung CSV of every rung that has been run, concatenated with a `rung` column."""
    parts = []
    for r in rungs:
        path = root / r["name"] / name
        if infos[r["name"]] is None or not path.is_file():
            continue
        try:
            df = pd.read_csv(path)
        except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
            raise LadderError(f"{path}: not a readable CSV file ({exc}); collect the rung again") from None
        if len(df):
            parts.append(df.assign(rung=r["name"]))
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()


def _replace_section(readme, md):
    """Put md between the README's ladder markers (atomically); False if it has none."""
    text = readme.read_text()
    a, b = text.find(LADDER_BEGIN), text.find(LADDER_END)
    if a < 0 or b < a:
        return False
    new = text[:a + len(LADDER_BEGIN)] + "\n" + md.rstrip("\n") + "\n" + text[b:]
    if new != text:
        write_text_atomic(readme, new)
    return True


# --- ladder.md ---------------------------------------------------------------

def _hms(seconds):
    s = int(round(float(seconds)))
    return f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}"


def _cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def _md_table(head, body):
    return ("| " + " | ".join(map(_cell, head)) + " |\n|" + "---|" * len(head) + "\n"
            + "".join("| " + " | ".join(map(_cell, r)) + " |\n" for r in body))


def _rung_line(i, rung, info):
    if info is None:
        return [i + 1, rung["name"], rung["label"], "—", NOT_RUN, "—", "—", "—", "—"]
    m = info.get("machine") or {}
    mem = f", {m['memory_gib']:g} GiB" if m.get("memory_gib") else ""
    ch = info.get("core_hours")
    date = str(info.get("started") or info.get("date") or "")[:10]
    return [i + 1, rung["name"], rung["label"], f"`{info.get('config', '?')}`",
            f"{_hms(info.get('wall_seconds', 0))} on {info.get('cores', '?')} cores",
            f"{ch:.2f}" if isinstance(ch, (int, float)) else "—",
            f"{m.get('cpu', '?')} ({m.get('cores', '?')} cores{mem})", date, info.get("commit", "?")]


def ladder_markdown(table, rungs, claims, infos, slopes=None, fr2=None, figures=(), decomposition=None,
                    startup=None):
    """ladder.md: the rungs, each claim's quantities against the rungs, the verdict at the top
    rung, and the two diagnostics. Deterministic: only what the rungs' files say."""
    names = [r["name"] for r in rungs]
    out = ["The reproduction ladder: each rung is a study that moves one factor toward the paper's "
           "conditions (ladder.yaml). Verdicts are the report's (analysis/report.py): within error bars = "
           "the paper's value inside the 95 % interval (the Student-t quantile at the fit's degrees of "
           "freedom times its standard error; 1.96 without a fit of its own), qualitatively = within 25 % "
           "of it, inconclusive = no error bar, an error above 30 % of the value, a fit that breaks its "
           "model or ended on a bound, or one with no degrees of freedom left. A rung not run "
           "shows no numbers; — : the rung does not study the quantity. Written by "
           "`granudrag-analysis ladder table`; do not edit by hand.\n",
           "### Rungs\n",
           _md_table(["#", "rung", "label", "config", "wall time", "core-hours", "machine", "date", "commit"],
                     [_rung_line(i, r, infos.get(r["name"])) for i, r in enumerate(rungs)])]
    ran = table[table.verdict != NOT_RUN]
    for letter in sorted(set(ran.claim)):
        sub = ran[ran.claim == letter]
        out.append(f"### ({letter}) {claims.get(letter, 'rows no claim names')}\n")
        if f"claim_{letter}.png" in figures:
            out.append(f"![claim ({letter}) along the ladder](claim_{letter}.png)\n")
        body = []
        for q in dict.fromkeys(sub.quantity):
            rows = sub[sub.quantity == q]
            cells = []
            for n in names:
                hit = rows[rows.rung == n]
                cells.append(f"{hit.fitted.iloc[0]} — {hit.verdict.iloc[0]}" if len(hit)
                             else NOT_RUN if infos.get(n) is None else "—")
            body.append([q, rows.published.iloc[0]] + cells)
        out.append(_md_table(["quantity", "paper"] + names, body))
    if len(ran):
        out.append("### Verdict at the top rung\n")
        body = []
        for (letter, q), rows in ran.groupby(["claim", "quantity"], sort=False):
            top = rows.loc[rows.order.idxmax()]
            body.append([letter, q, top.rung, top.fitted, top.published, top.verdict])
        out.append(_md_table(["claim", "quantity", "top rung", "fitted", "paper", "verdict"], body))
    out += _diagnostics_markdown(slopes, fr2, names, infos, figures, decomposition, startup)
    return "\n".join(out)


def _diagnostics_markdown(slopes, fr2, names, infos, figures, decomposition=None, startup=None):
    out = []
    if slopes is not None and len(slopes):
        pooled = slopes[slopes.D.astype(str) == "all"]
        out.append("### κ(Fr) slope against the shell width Z is counted in\n")
        out.append("The paper counts Z \"within a certain distance\" of the intruder without saying which; "
                   f"its slope is {paper.KAPPA['k1']:g}. Slope k1 of κ = k0 + k1 Fr in shells R + w "
                   "(all D pooled; kappa_shells.csv also per D):\n")
        if "kappa_shells.png" in figures:
            out.append("![κ slope against shell width](kappa_shells.png)\n")
        body = []
        for w in sorted(pooled.width.unique()):
            cells = []
            for n in names:
                hit = pooled[(pooled.rung == n) & np.isclose(pooled.width, w)]
                cells.append(_pm(hit.k1.iloc[0], hit.k1_err.iloc[0]) if len(hit)
                             else NOT_RUN if infos.get(n) is None else "—")
            body.append([f"{w:g}"] + cells)
        out.append(_md_table(["width w [d]"] + names, body))
    if decomposition is not None and len(decomposition):
        out.append("### κ's rise taken apart: n and Z from Fr ≈ 1 to Fr ≈ 10\n")
        out.append("κ = (Z/n)(D+d)²/(2√3 d²) rises by the factor Z_ratio / n_ratio (high/low Fr); the paper's "
                   "line rises by 2.55 from Fr 1 to 10, with n falling faster than Z (Sec. III B). "
                   "kappa_decomposition.csv has the numbers.\n")
        order = {n: i for i, n in enumerate(names)}
        dec = decomposition.assign(_o=decomposition.rung.map(order)).sort_values(["_o", "D", "width"])
        body = [[r.rung, f"{r.D:g}", f"{r.width:g}", f"{r.Fr_low:g} → {r.Fr_high:g}",
                 f"{r.n_low:.3g} → {r.n_high:.3g} (×{r.n_ratio:.2f})",
                 f"{r.Z_low:.3g} → {r.Z_high:.3g} (×{r.Z_ratio:.2f})",
                 f"×{r.kappa_ratio:.2f}"] for r in dec.itertuples()]
        out.append(_md_table(["rung", "D", "shell w [d]", "Fr", "n", "Z", "κ"], body))
    if fr2 is not None and len(fr2):
        out.append("### Fr_2 against the largest Fr fitted\n")
        out.append(f"The three-regime law refitted (μ = 0.5, per D) on the points with Fr ≤ fr_max; paper: "
                   f"Fr_2 ≈ {paper.CROSSOVER_FR2:g}.\n")
        if "fr2_range.png" in figures:
            out.append("![Fr_2 against fr_max](fr2_range.png)\n")
        out.append("Cells: Fr_2 (points fitted; Δ₅: the fit's χ² profile at Fr_2 = 5, above 3.84 the data "
                   "exclude 5 at 95 %); * the fit ends on a bound or breaks its model, fr2_range.csv says how.\n")
        fr_max = sorted(fr2.fr_max.unique())
        body = []
        for (rung, D, cont), g in fr2.groupby(["rung", "D", "continuous"], sort=False):
            cells = []
            for m in fr_max:
                hit = g[np.isclose(g.fr_max, m)]
                r = hit.iloc[0] if len(hit) else None
                delta = f"; Δ₅ = {r.delta_at_5:.1f}" if r is not None and np.isfinite(r.delta_at_5) else ""
                cells.append("—" if r is None else f"{_pm(r.Fr2, r.Fr2_err)} ({int(r.n_points)}{delta})"
                             + (" *" if isinstance(r.note, str) and r.note else ""))
            body.append([rung, f"{D:g}", "continuous" if cont else "discontinuous"] + cells)
        order = {n: i for i, n in enumerate(names)}
        body.sort(key=lambda b: (order.get(b[0], len(order)), float(b[1]), b[2] != "continuous"))
        out.append(_md_table(["rung", "D", "fit"] + [f"Fr ≤ {m:g}" for m in fr_max], body))
    if startup is not None and len(startup):
        out.append("### Fr_2 with the start of each pull kept, as a cumulative average over 40 d\n")
        out.append("The paper's drag is \"the cumulative average\" of the force (Fig. 4); it does not say a start was "
                   "discarded. Here: each pull's start (discarded in the table) kept and its excess spread over a 40 d "
                   "pull (startup_fr2.csv; analysis.ladder.startup_refit), beside the steady drag. Cells: Fr_2 "
                   "(Δ₅); * at a bound or breaking the model.\n")
        body = []
        for (rung, D, pull, fr_max), g in startup.groupby(["rung", "D", "pull", "fr_max"], sort=False):
            cells = []
            for cont in (True, False):
                hit = g[g.continuous == cont]
                r = hit.iloc[0] if len(hit) else None
                delta = f" (Δ₅ = {r.delta_at_5:.1f})" if r is not None and np.isfinite(r.delta_at_5) else ""
                cells.append("—" if r is None else f"{_pm(r.Fr2, r.Fr2_err)}{delta}"
                             + (" *" if isinstance(r.note, str) and r.note else ""))
            body.append([rung, f"{D:g}", pull, f"≤ {fr_max:g}"] + cells)
        order = {n: i for i, n in enumerate(names)}
        body.sort(key=lambda b: (order.get(b[0], len(order)), float(b[1]), b[2] != "steady", b[3]))
        out.append(_md_table(["rung", "D", "drag", "Fr", "continuous fit", "discontinuous fit"], body))
    return out


def _pm(value, err):
    from .result import format_pm
    return format_pm(float(value), float(err)) if np.isfinite(value) else "n/a"


# --- κ in shells ---------------------------------------------------------------

SLOPE_COLUMNS = ["rung", "D", "width", "k0", "k0_err", "k1", "k1_err", "n_points", "n_runs", "errors_from"]


def inside_box(shells):
    """The rows whose shell stays a ball: D/2 + w <= min(lx, ly)/2. Beyond it the minimum-image
    distance clips the shell by the periodic box (it counts the images' neighbourhoods), so its Z
    is not a shell's. Rows without lx, ly (files collected before they were recorded) are kept."""
    if not {"lx", "ly"} <= set(shells.columns):
        return shells
    half = np.minimum(shells.lx.astype(float), shells.ly.astype(float)) / 2
    reach = shells.D.astype(float) / 2 + shells.width.astype(float)
    return shells[~(reach > half)]


def _fig8_shells(shells):
    """The rows of a kappa_shells table (one rung's) that Fig. 8 is about: finite κ, shells that
    stay inside the box, system I, μ = 0.5, the most common K_n (the rows fitset's κ fit uses)."""
    df = inside_box(shells[np.isfinite(shells.kappa.astype(float))])
    df = df[(df.system.astype(str) == "I") & np.isclose(df.mu.astype(float), 0.5)]
    return df[np.isclose(df.kn, df.kn.value_counts().idxmax())] if len(df) else df


def kappa_points(shells):
    """The runs of a kappa_shells table that Fig. 8 is about (_fig8_shells), replicate beds
    (same D, Fr and width, other seed) averaged: columns D, Fr, width, kappa, n_beds, var (their
    variance, NaN for one bed)."""
    df = _fig8_shells(shells)
    if df.empty:
        return pd.DataFrame(columns=["D", "Fr", "width", "kappa", "n_beds", "var"])
    df = df.assign(Fr=df.Fr.astype(float).round(6), width=df.width.astype(float).round(6))
    g = df.groupby(["D", "Fr", "width"]).kappa
    return pd.DataFrame({"kappa": g.mean(), "n_beds": g.size(), "var": g.var(ddof=1)}).reset_index()


def _fit_slope(points):
    """κ = k0 + k1 Fr through bed-averaged points; weights from the pooled between-bed variance
    (see kappa_shell_slopes). Returns (Fit, errors_from)."""
    rep = points[points.n_beds >= 2]
    dof = (rep.n_beds - 1).sum()
    s2 = float(((rep.n_beds - 1) * rep["var"]).sum() / dof) if dof else math.nan
    if np.isfinite(s2) and s2 > 0:
        sigma = np.sqrt(s2 / points.n_beds.to_numpy(float))
        return fit_linear(points.Fr, points.kappa, sigma), f"between-bed spread ({int(dof)} dof)"
    return fit_linear(points.Fr, points.kappa), "residual scatter (no replicate beds)"


def kappa_shell_slopes(shells):
    """k0, k1 of κ = k0 + k1 Fr at each shell width, all D pooled (D = "all") and per D, per
    rung (column `rung`, when the table has one).

    Errors: the replicate beds of a point (same D and Fr, other seed) are averaged first; the
    between-bed variance, pooled over every replicated point of the fit (a point's own rests on
    1 dof with 2 beds and would weigh the points by luck; analysis.table.pooled_drag_err), over
    the beds of each point weighs it. The line's covariance is the one these errors give,
    scaled up by the reduced χ² when it exceeds 1 (the points scatter about the line more than
    the beds do: κ is not linear in Fr, or the beds' spread is underestimated), as fits.fit_linear
    does. Without replicate beds: unweighted, the residual-variance-scaled covariance. A fit
    needs 3 points."""
    shells = shells if "rung" in shells.columns else shells.assign(rung="")
    rows = []
    for rung, s in shells.groupby("rung", sort=False):
        pts = kappa_points(s)
        groups = [("all", pts)] + [(f"{D:g}", g) for D, g in pts.groupby("D")]
        for D, g in groups:
            for w, p in g.groupby("width"):
                if len(p) < 3:
                    continue
                fit, how = _fit_slope(p)
                rows.append({"rung": rung, "D": D, "width": float(w), "k0": fit["k0"].value,
                             "k0_err": fit["k0"].err, "k1": fit["k1"].value, "k1_err": fit["k1"].err,
                             "n_points": len(p), "n_runs": int(p.n_beds.sum()), "errors_from": how})
    return pd.DataFrame(rows, columns=SLOPE_COLUMNS)


DECOMPOSITION_COLUMNS = ["rung", "D", "width", "Fr_low", "Fr_high", "n_low", "n_high", "Z_low", "Z_high",
                         "n_ratio", "Z_ratio", "kappa_ratio"]
# The Froude numbers the decomposition compares: the paper's Fig. 8 runs from about Fr = 1 to 10.
DECOMPOSITION_FR = (1.0, 10.0)
DECOMPOSITION_WIDTHS = (2.0, 4.0, 6.0)


def kappa_decomposition(shells, fr=DECOMPOSITION_FR, widths=DECOMPOSITION_WIDTHS):
    """Why κ = (Z/n)(D+d)²/(2√3 d²) rises or not: n and Z at the pulled Froude numbers nearest
    fr (low, high) for each D and shell width, bed-averaged, and their ratios high/low. κ rises
    by n_ratio⁻¹ Z_ratio; the paper's line rises by (0.887 + 0.185·10)/(0.887 + 0.185) = 2.55
    from Fr 1 to 10, and says "n … decreases faster than Z" (Sec. III B)."""
    shells = shells if "rung" in shells.columns else shells.assign(rung="")
    df = pd.concat([_fig8_shells(s) for _, s in shells.groupby("rung", sort=False)]) if len(shells) else shells
    rows = []
    for (rung, D), g in df.groupby(["rung", "D"], sort=False):
        frs = np.unique(g.Fr.astype(float))
        lo, hi = (float(frs[np.argmin(np.abs(frs - f))]) for f in fr)
        if lo == hi:
            continue
        for w in widths:
            at = g[np.isclose(g.width.astype(float), w)]
            if at.empty:
                continue
            a, b = at[np.isclose(at.Fr, lo)], at[np.isclose(at.Fr, hi)]
            n_lo, n_hi = a.n_contacts.mean(), b.n_contacts.mean()
            z_lo, z_hi = a.Z.mean(), b.Z.mean()
            rows.append({"rung": rung, "D": float(D), "width": w, "Fr_low": lo, "Fr_high": hi, "n_low": n_lo,
                         "n_high": n_hi, "Z_low": z_lo, "Z_high": z_hi, "n_ratio": n_hi / n_lo,
                         "Z_ratio": z_hi / z_lo, "kappa_ratio": (z_hi / n_hi) / (z_lo / n_lo)})
    return pd.DataFrame(rows, columns=DECOMPOSITION_COLUMNS)


# --- the start of a pull, kept as the paper may have kept it ----------------------

STARTUP_FIT_COLUMNS = ["rung", "D", "pull", "fr_max", "continuous", "Fr1", "Fr1_err", "Fr2", "Fr2_err",
                       "delta_at_5", "note"]
PAPER_PULL = 40.0  # d: system I's box length, the paper's pull


def _drag_series(table):
    """The μ = 0.5 drag-vs-Fr series that fitset.run_fits fits (system I, the reference contact
    law, yield pulls out) and the table's bed scatter."""
    kn, gn = reference_params(table)
    series = select(select(table, kn=kn, gamman=gn), mu=0.5, system="I")
    return series[~is_yield(series)], point_bed_scatter(table), kn


def _crossover_fit(fr, drag, err, continuous, *, bed_scatter, beds, n_boot, seed):
    """Fr1, Fr2 (with errors), the χ² profile at the paper's Fr2 (delta_at_5) and the fit's
    notes, as a row's fields; NaN and the reason when the fit cannot be made."""
    try:
        fit = fit_regimes(fr, drag, err, regime1="constant", continuous=continuous, n_boot=n_boot, seed=seed,
                          bed_scatter=bed_scatter, beds=beds)
    except ValueError as exc:
        return {**dict.fromkeys(("Fr1", "Fr1_err", "Fr2", "Fr2_err", "delta_at_5"), math.nan), "note": str(exc)}
    delta = profile_fr2(fr, drag, err, [paper.CROSSOVER_FR2], continuous=continuous)[0][2]
    return {"Fr1": fit["Fr1"].value, "Fr1_err": fit["Fr1"].err, "Fr2": fit["Fr2"].value,
            "Fr2_err": fit["Fr2"].err, "delta_at_5": delta,
            "note": "; ".join(fit.meta.get("at_bounds", []) + fit.meta.get("violations", []))}


def kept_drag(drag, whole_mean, travel, pull=PAPER_PULL):
    """The mean force over a pull of `pull` d whose start is the one pulled here (over `travel`
    d, mean whole_mean) and whose rest runs at the steady drag: the start's excess work
    (whole_mean - drag) travel spread over `pull`."""
    return drag + (whole_mean - drag) * travel / pull


def startup_refit(startup, table, fr_max_values=(10.0, 15.0), *, n_boot=100, seed=0, rung=""):
    """Fr_2 of the mu = 0.5 series per D fitted to the drag with the start of each pull kept and
    diluted over the paper's 40 d pull (kept_drag), beside the same fit of the steady drag
    (pull = "steady"): the start of a fast pull is an impact (the intruder starts at V), whose
    excess force grows about as V^2, so kept in a cumulative average it could add a quadratic
    rise by itself. Both fits take the point table's series, weights (pooled_drag_err) and bed
    scatter exactly as fr2_vs_range does; the kept drag shifts each point by the bed-averaged
    start excess of its runs in `startup`."""
    rows = []
    series, bed_scatter, kn = _drag_series(table)
    st = startup[np.isclose(startup.mu.astype(float), 0.5) & (startup.system.astype(str) == "I")]
    st = st[np.isclose(st.kn.astype(float), kn)]
    if series.empty or st.empty:
        return pd.DataFrame(rows, columns=STARTUP_FIT_COLUMNS)
    excess = (kept_drag(st.drag, st.whole_mean, st.travel) - st.drag).groupby(
        [st.D.astype(float).round(6), st.Fr.astype(float).round(6)]).mean()
    for D, g in series.groupby("D"):
        g = g.sort_values("Fr")
        shift = np.array([excess.get((round(float(D), 6), round(float(fr), 6)), np.nan) for fr in g.Fr])
        err, fr = np.asarray(pooled_drag_err(g), float), g.Fr.to_numpy(float)
        beds = int(g["n_beds"].min()) if "n_beds" in g.columns else 1
        for label, y in (("steady", g.drag.to_numpy(float)),
                         (f"start kept, {PAPER_PULL:g} d", g.drag.to_numpy(float) + shift)):
            for fr_max in fr_max_values:
                m = (fr <= fr_max + 1e-9) & np.isfinite(y)
                for continuous in (True, False):
                    rows.append({"rung": rung, "D": float(D), "pull": label, "fr_max": float(fr_max),
                                 "continuous": continuous,
                                 **_crossover_fit(fr[m], y[m], err[m], continuous, bed_scatter=bed_scatter,
                                                  beds=beds, n_boot=n_boot, seed=seed)})
    return pd.DataFrame(rows, columns=STARTUP_FIT_COLUMNS)


# --- Fr_2 against the fitted range ----------------------------------------------

FR2_COLUMNS = ["rung", "D", "fr_max", "continuous", "Fr1", "Fr1_err", "Fr2", "Fr2_err", "delta_at_5",
               "n_points", "fr_used_max", "note"]


def fr2_vs_range(table_df, fr_max_values=FR_MAX_VALUES, *, n_boot=100, seed=0, rung=""):
    """The crossovers of the μ = 0.5 drag-vs-Fr series of each D (system I, the reference
    contact law, yield pulls out: as fitset.run_fits fits them, with pooled_drag_err weights
    and the table's bed scatter) refitted on the points with Fr <= fr_max, continuous and not.
    Does Fr_2 settle as the range grows, or follow it? delta_at_5: the fit's chi-square profile
    at Fr_2 = 5, the paper's (regimes.profile_fr2; above 3.84 the data exclude 5 at 95 %
    whatever the bootstrap says). A fit that cannot be made (too few points) is a row with NaN
    and the reason in `note`. Fixed seed: deterministic."""
    series, bed_scatter, _ = _drag_series(table_df)
    rows = []
    for D, g in series.groupby("D"):
        moving = g.sort_values("Fr")
        for fr_max in fr_max_values:
            used = moving[moving.Fr <= fr_max + 1e-9]
            beds = int(used["n_beds"].min()) if "n_beds" in used.columns and len(used) else 1
            for continuous in (True, False):
                rows.append({"rung": rung, "D": float(D), "fr_max": float(fr_max), "continuous": continuous,
                             "n_points": len(used), "fr_used_max": float(used.Fr.max()) if len(used) else math.nan,
                             **_crossover_fit(used.Fr, used.drag, pooled_drag_err(used), continuous,
                                              bed_scatter=bed_scatter, beds=beds, n_boot=n_boot, seed=seed)})
    return pd.DataFrame(rows, columns=FR2_COLUMNS)


# --- figures ---------------------------------------------------------------------

def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _savefig(fig, path):
    """PNG without a timestamp or version in its metadata (a rerun gives the same bytes),
    written under a temporary name and renamed."""
    plt = _pyplot()
    tmp = path.with_name(path.name + ".tmp")
    fig.savefig(tmp, format="png", dpi=110, metadata={"Software": None})
    plt.close(fig)
    tmp.replace(path)
    return path


def _claim_figures(root, table, rungs, claims):
    """claim_<letter>.png for each claim with numbers: a panel per quantity, value ± error per
    rung, the paper's value as a line. A figure of a claim that has no numbers any more is
    removed, so none shows stale numbers."""
    plt = _pyplot()
    ran = table[table.verdict != NOT_RUN]
    written = []
    names = [r["name"] for r in rungs]
    for letter in sorted({*CLAIMS, *claims, OTHER}):
        path = root / f"claim_{letter}.png"
        sub = ran[(ran.claim == letter) & np.isfinite(ran.value.astype(float))]
        if sub.empty:
            path.unlink(missing_ok=True)
            continue
        quantities = list(dict.fromkeys(sub.quantity))
        ncol = min(3, len(quantities))
        nrow = math.ceil(len(quantities) / ncol)
        fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 2.9 * nrow + 0.6), squeeze=False,
                                 layout="constrained")
        for ax, q in zip(axes.ravel(), quantities):
            rows = sub[sub.quantity == q].sort_values("order")
            err = rows.error.astype(float).to_numpy()
            ax.errorbar(rows.order, rows.value.astype(float), yerr=np.where(np.isfinite(err), err, 0.0),
                        fmt="o", capsize=3)
            pub = rows.published_value.astype(float).iloc[0]
            if np.isfinite(pub):
                ax.axhline(pub, color="k", ls="--", lw=1, label=f"paper {rows.published.iloc[0]}")
                ax.legend(fontsize=7, loc="best")
            ax.set_title(q, fontsize=8)
            ax.set_xticks(range(len(names)), names, rotation=30, ha="right", fontsize=7)
            ax.set_xlim(-0.5, len(names) - 0.5)
        for ax in axes.ravel()[len(quantities):]:
            ax.axis("off")
        fig.suptitle(f"({letter}) {claims.get(letter, 'rows no claim names')}", fontsize=10)
        written.append(_savefig(fig, path))
    return written


def _kappa_figure(root, slopes, shells, rungs):
    """kappa_shells.png: (a) the slope k1 against the shell width, a line per rung (D pooled),
    the paper's slope as a line; (b) bed-averaged κ against Fr at each width, top rung."""
    path = root / "kappa_shells.png"
    pooled = slopes[slopes.D.astype(str) == "all"] if len(slopes) else slopes
    if pooled.empty:
        path.unlink(missing_ok=True)
        return []
    plt = _pyplot()
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    for r in rungs:
        s = pooled[pooled.rung == r["name"]].sort_values("width")
        if len(s):
            a.errorbar(s.width, s.k1, yerr=s.k1_err.fillna(0.0), fmt="o-", capsize=3, label=r["name"])
    a.axhline(paper.KAPPA["k1"], color="k", ls="--", lw=1, label=f"paper {paper.KAPPA['k1']:g}")
    a.set(xlabel="shell width w beyond the intruder's radius [d]", ylabel="slope k1 of κ(Fr)",
          title="(a) κ(Fr) slope against shell width")
    a.legend(fontsize=7)
    top = [r["name"] for r in rungs if (pooled.rung == r["name"]).any()][-1]
    pts = kappa_points(shells[shells.rung == top])
    fr = np.linspace(0.0, max(float(pts.Fr.max()), 1.0), 50)
    for i, (w, p) in enumerate(pts.groupby("width")):
        c = f"C{i % 10}"
        p = p.groupby("Fr").kappa.mean()           # D pooled, for the eye
        b.plot(p.index, p.values, "o", color=c, ms=3, label=f"w = {w:g} d")
        fit = pooled[(pooled.rung == top) & np.isclose(pooled.width, w)]
        if len(fit):
            b.plot(fr, fit.k0.iloc[0] + fit.k1.iloc[0] * fr, "-", color=c, lw=1)
    b.plot(fr, paper.KAPPA["k0"] + paper.KAPPA["k1"] * fr, "k--", lw=1, label="paper (Eq. 8)")
    b.set(xlabel="Fr", ylabel="κ", title=f"(b) κ against Fr at each width: {top}")
    b.legend(fontsize=6, ncol=2)
    return [_savefig(fig, path)]


def _fr2_figure(root, fr2, rungs):
    """fr2_range.png: Fr_2 against fr_max, a series per rung and D, continuous fit and not."""
    path = root / "fr2_range.png"
    ok = fr2[np.isfinite(fr2.Fr2.astype(float))] if len(fr2) else fr2
    if ok.empty:
        path.unlink(missing_ok=True)
        return []
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True, layout="constrained")
    series = [(r["name"], D) for r in rungs for D in sorted(ok[ok.rung == r["name"]].D.unique())]
    for ax, cont in zip(axes, (True, False)):
        for i, (rung, D) in enumerate(series):
            s = ok[(ok.rung == rung) & (ok.D == D) & (ok.continuous == cont)].sort_values("fr_max")
            shift = 0.08 * (i - (len(series) - 1) / 2)
            ax.errorbar(s.fr_max + shift, s.Fr2, yerr=s.Fr2_err.fillna(0.0), fmt="o-", capsize=3,
                        label=f"{rung}, D = {D:g}")
        ax.axhline(paper.CROSSOVER_FR2, color="k", ls="--", lw=1, label=f"paper ≈ {paper.CROSSOVER_FR2:g}")
        ax.set(xlabel="largest Fr fitted, fr_max", title=f"{'continuous' if cont else 'discontinuous'} fit")
        ax.legend(fontsize=6)
    axes[0].set_ylabel("Fr_2")
    return [_savefig(fig, path)]
