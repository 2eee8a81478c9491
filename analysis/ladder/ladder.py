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

`table` reads <root>/ladder.yaml (the rungs in order, each with a label and, for a rung grown in
place from another, `extends`; a description per claim; the claim table's `summary`, per claim the
rungs closest to the paper's conditions first: analysis.ladder.ladder_summary) and writes ladder.csv,
ladder.md, claims.md (one row per claim at its top rung) with evidence_<letter>.png (that claim's
evidence there), claim_<letter>.png (each quantity along the rungs), and its diagnostics:
kappa_shells.csv/.png (the slope of κ(Fr) against the shell width Z is counted in),
fr2_range.csv/.png (Fr_2 refitted on the points with Fr <= fr_max), knee_fr5.csv (the drag's
slope above Fr 5 against below, a test of regime III that needs no fitted crossover), box_axis.csv/.png,
stiffness_axis.csv/.png and length_axis.csv/.png (the drag of the same points in rungs of wider
boxes, of stiffer contacts, of longer pulls; a rung and its extension are one point). If
<root>/README.md has the markers LADDER_BEGIN and LADDER_END, the text between them becomes
ladder.md's; between CLAIMS_BEGIN and CLAIMS_END, claims.md's.

The verdicts are the report's: each rung's fits.json and table.csv are read as the report
rule reads them and passed to analysis.report.report.comparisons; nothing is re-judged here.

The rest of the ladder lives beside this module (all re-exported here): analysis.ladder.ladder_collect
(collect), analysis.ladder.ladder_claims (the claims of a rung), analysis.ladder.ladder_diagnostics (κ shells,
Fr_2 range and startup refits), analysis.ladder.ladder_axes (the box, stiffness and length axes),
analysis.ladder.ladder_report (ladder.md and the figures) and analysis.ladder.ladder_summary (the claim table).
analysis.ladder_refit makes each recorded rung's table.csv, fits.json and report.md again from
its runs.csv after a change of the analysis (`python -m analysis.ladder_refit <root>`; `--rejudge`
after a change of the rule that decides `rejected` alone).
"""
import json
from pathlib import Path

import pandas as pd

from ..core.result import LADDER_N_BOOT
from ..core.table import load_csv, write_csv, write_text_atomic
from .ladder_axes import (
    AXES,
    BOX,
    LENGTH,
    STIFFNESS,
    SUMMARY_COLUMNS,
    axis_steps,
    axis_summary,
    box_axis,
    independent,
    length_axis,
    stiffness_axis,
)
from .ladder_axes import COLUMNS as AXIS_COLUMNS
from .ladder_claims import (
    CLAIMS,
    NOT_RUN,
    OTHER,
    LadderError,
    claim_of,
    load_rung,
    parse_fitted,
    parse_published,
    rung_claims,
)
from .ladder_collect import (
    RUNG_FILES,
    SHELL_COLUMNS,
    SHELL_GROUP,
    STARTUP_COLUMNS,
    collect,
    commit,
    core_hours,
    engine_commits,
    machine,
    read_shells,
    write_kappa_shells,
    write_startup,
)
from .ladder_deep import deep_cells
from .ladder_diagnostics import (
    DECOMPOSITION_COLUMNS,
    DECOMPOSITION_FR,
    DECOMPOSITION_WIDTHS,
    FR2_COLUMNS,
    FR_MAX_VALUES,
    KNEE_COLUMNS,
    PAPER_PULL,
    SLOPE_COLUMNS,
    STARTUP_FIT_COLUMNS,
    fr2_vs_range,
    inside_box,
    kappa_decomposition,
    kappa_points,
    kappa_shell_slopes,
    kept_drag,
    knee_at_five,
    startup_refit,
)
from .ladder_report import _axis_figure, _claim_figures, _fr2_figure, _kappa_figure, ladder_markdown
from .ladder_summary import (
    CLAIMS_BEGIN,
    CLAIMS_END,
    evidence_figures,
    read_summary,
    regime_cells,
    replace_claims,
    replace_marked,
    summary_markdown,
    summary_rows,
)

__all__ = [
    "LADDER_BEGIN", "LADDER_END", "CLAIMS", "OTHER", "NOT_RUN", "LadderError", "claim_of", "parse_fitted",
    "parse_published", "load_rung", "rung_claims", "RUNG_FILES", "SHELL_GROUP", "SHELL_COLUMNS",
    "STARTUP_COLUMNS", "collect", "engine_commits", "core_hours", "machine", "commit", "write_kappa_shells",
    "write_startup", "read_shells", "FR_MAX_VALUES", "SLOPE_COLUMNS", "inside_box", "kappa_points",
    "kappa_shell_slopes", "DECOMPOSITION_COLUMNS", "DECOMPOSITION_FR", "DECOMPOSITION_WIDTHS",
    "kappa_decomposition", "STARTUP_FIT_COLUMNS", "PAPER_PULL", "kept_drag", "startup_refit", "FR2_COLUMNS",
    "fr2_vs_range", "KNEE_COLUMNS", "knee_at_five",
    "AXES", "BOX", "STIFFNESS", "LENGTH", "AXIS_COLUMNS", "SUMMARY_COLUMNS", "axis_steps", "independent",
    "axis_summary", "box_axis", "stiffness_axis", "length_axis", "ladder_markdown",
    "read_ladder", "rung_run", "ladder_rows", "write_ladder", "ladder_summary", "CLAIMS_BEGIN", "CLAIMS_END",
    "summary_rows", "summary_markdown", "evidence_figures", "regime_cells", "deep_cells",
]

LADDER_BEGIN, LADDER_END = "<!-- ladder:begin -->", "<!-- ladder:end -->"


# --- the ladder -------------------------------------------------------------

_EXAMPLE = "rungs: [{name: crossover-k2e5-box12, label: 'K_n 2e5, 12 d box'}, ...]"


def _ladder_doc(root):
    """(path, parsed root/ladder.yaml)."""
    import yaml
    root = Path(root)
    if not root.is_dir():
        raise LadderError(f"{root}: no such directory (the ladder's root, e.g. results/reproduction)")
    path = root / "ladder.yaml"
    if not path.is_file():
        raise LadderError(f"{path}: no such file; write the rungs in order: {_EXAMPLE}")
    try:
        return path, yaml.safe_load(path.read_text()) or {}
    except yaml.YAMLError as exc:
        raise LadderError(f"{path}: not a readable YAML file ({exc})") from None


def read_ladder(root):
    """(rungs [{name, label, extends}], claims {letter: description}) of root/ladder.yaml; a
    rung's `extends` names the rung whose results it grew in place (None: its own study)."""
    path, doc = _ladder_doc(root)
    example = _EXAMPLE
    entries = doc.get("rungs") if isinstance(doc, dict) else None
    if not isinstance(entries, list) or not entries:
        raise LadderError(f"{path}: needs a non-empty list `rungs`, e.g. {example}")
    rungs = []
    for i, e in enumerate(entries):
        e = {"name": e} if isinstance(e, str) else e
        if not isinstance(e, dict) or not e.get("name"):
            raise LadderError(f"{path}: rungs[{i}] has no name ({example})")
        rungs.append({"name": str(e["name"]), "label": str(e.get("label", e["name"])),
                      "extends": str(e["extends"]) if e.get("extends") else None})
    names = [r["name"] for r in rungs]
    if len(set(names)) != len(names):
        raise LadderError(f"{path}: a rung is listed twice: {', '.join(names)}")
    for r in rungs:
        if r["extends"] is not None and (r["extends"] not in names or r["extends"] == r["name"]):
            raise LadderError(f"{path}: {r['name']} extends {r['extends']}, which is not another listed rung")
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
            "verdict", "rejected", "core_hours", "wall_seconds", "cores", "machine_cpu", "notes", "order"]
    return pd.DataFrame(rows, columns=cols)


def write_ladder(root, *, n_boot=LADDER_N_BOOT, seed=0, fr_max_values=FR_MAX_VALUES):
    """ladder.csv, ladder.md, claim_<letter>.png, kappa_shells.csv/.png, fr2_range.csv/.png, knee_fr5.csv and
    each axis's <name>.csv/.png (box_axis, stiffness_axis, length_axis) in root, from ladder.yaml and each
    rung's directory; README.md's ladder section replaced when it has the markers. n_boot, seed:
    the bootstrap of the Fr_2-range refits. Returns the paths written."""
    root = Path(root)
    rungs, claims = read_ladder(root)
    summary = ladder_summary(root, rungs)
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
    # Each rung's point table, read once for the diagnostics below.
    tables = {r["name"]: load_csv(root / r["name"] / "table.csv") for r in rungs if infos[r["name"]] is not None}
    fr2 = [fr2_vs_range(t, fr_max_values, n_boot=n_boot, seed=seed, rung=name) for name, t in tables.items()]
    fr2 = pd.concat(fr2, ignore_index=True) if fr2 else pd.DataFrame(columns=FR2_COLUMNS)
    write_csv(fr2, root / "fr2_range.csv")
    written.append(root / "fr2_range.csv")
    written += _fr2_figure(root, fr2, rungs)
    knee = [knee_at_five(t, rung=name) for name, t in tables.items()]
    knee = pd.concat(knee, ignore_index=True) if knee else pd.DataFrame(columns=KNEE_COLUMNS)
    write_csv(knee, root / "knee_fr5.csv")
    written.append(root / "knee_fr5.csv")
    startup = [startup_refit(pd.read_csv(root / name / "startup.csv"), t, n_boot=n_boot, seed=seed, rung=name)
               for name, t in tables.items() if (root / name / "startup.csv").is_file()]
    startup = pd.concat(startup, ignore_index=True) if startup else pd.DataFrame(columns=STARTUP_FIT_COLUMNS)
    write_csv(startup, root / "startup_fr2.csv")
    written.append(root / "startup_fr2.csv")
    summaries = []
    for axis in AXES:
        steps = axis_steps(tables, axis, extends={r["name"]: r["extends"] for r in rungs})
        write_csv(steps, root / f"{axis.name}.csv")
        written.append(root / f"{axis.name}.csv")
        written += _axis_figure(root, axis, steps)
        summaries.append((axis, axis_summary(steps, axis)))
    md = ladder_markdown(table, rungs, claims, infos, slopes, fr2, figures=[p.name for p in written],
                         decomposition=decomposition, startup=startup, axes=summaries, knee=knee, summary=summary)
    write_text_atomic(root / "ladder.md", md)
    written.append(root / "ladder.md")
    rows = summary_rows(table, summary, claims, len(rungs), knee)
    for r in rows:
        if r["letter"] == "a" and r["rung"] in tables:
            r["measured"] += regime_cells(tables[r["rung"]], summary.get("a", {}))
        r["measured"] += deep_cells(root, summary.get(r["letter"], {}))
    written += evidence_figures(root, rows, summary)
    claims_md = summary_markdown(rows) if rows else ""
    if claims_md:
        write_text_atomic(root / "claims.md", claims_md)
        written.append(root / "claims.md")
    else:
        (root / "claims.md").unlink(missing_ok=True)
    readme = root / "README.md"
    if readme.is_file():
        changed = _replace_section(readme, md)
        changed = (claims_md and replace_claims(readme, claims_md)) or changed
        if changed:
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
    """Put md between the README's ladder markers; False if it has none."""
    return replace_marked(readme, LADDER_BEGIN, LADDER_END, md)


def ladder_summary(root, rungs):
    """The claim table's spec of root/ladder.yaml (`summary`: analysis.ladder.ladder_summary)."""
    path, doc = _ladder_doc(root)
    return read_summary(doc, [r["name"] for r in rungs], path)
