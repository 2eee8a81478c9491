"""A claim's depth-law cells in the ladder's claim table: the verdicts of rungs pulled at system
II's depths (their deep_law.csv, analysis.deep_law, written by `ladder collect`), quoted beside the
claim's top rung with the depth range each holds for, and their sum rules drawn in (f)'s figure.

ladder.yaml's `summary.<letter>.deep` names them: {rung: <a listed rung>, show: {<deep-law
quantity>: <short name>}}, or a list of such entries when several rungs read the law (one per
friction: the paper's α_μ + φ_μ at μ = 0.5 and at μ = 0 come from different rungs). A rung not
collected yet adds nothing, so the entry can be written before its rung lands.
"""
from pathlib import Path

import numpy as np
import pandas as pd

from ..core import paper
from .ladder_claims import LadderError


def read_deep(entry, names, where):
    """The entries of a claim's `deep` ([{rung, show}], [] without one): each rung must be listed
    and each shown quantity one that analysis.deep_law writes."""
    if entry is None:
        return []
    return [_read_entry(e, names, f"{where}[{i}]" if isinstance(entry, list) else where)
            for i, e in enumerate(entry if isinstance(entry, list) else [entry])]


def _read_entry(entry, names, where):
    from ..deep_law.deep_law import QUANTITIES
    if not isinstance(entry, dict) or set(entry) != {"rung", "show"} or not isinstance(entry["show"], dict):
        raise LadderError(f"{where} takes {{rung: <a listed rung>, show: {{<deep-law quantity>: <short name>}}}}"
                          " or a list of them")
    if str(entry["rung"]) not in names:
        raise LadderError(f"{where}.rung names a rung not listed: {entry['rung']}")
    unknown = [str(q) for q in entry["show"] if str(q) not in QUANTITIES]
    if unknown:
        raise LadderError(f"{where}.show names no depth-law quantity: {', '.join(unknown)} "
                          f"(the quantities: {', '.join(QUANTITIES)})")
    return {"rung": str(entry["rung"]), "show": {str(k): str(v) for k, v in entry["show"].items()}}


def deep_cells(root, spec):
    """The cells a claim's `deep` entries add, rung by rung: each shown quantity of the rung's
    deep_law.csv, a cell per depth set it was read on ("h >= 45", "all", "h < 45"), its value (or
    p) and verdict, and the paper's number for the sum rule. Nothing for a rung without its
    deep_law.csv yet."""
    from ..core.result import format_pm
    cells = []
    for deep in (spec or {}).get("deep") or []:
        table = _deep_table(root, deep)
        if table is None:
            continue
        for quantity, short in deep["show"].items():
            for r in table[table.quantity == quantity].itertuples():
                where = depth_words(r.depths, r.h_lo, r.h_hi)
                value = format_pm(r.value, r.err) if np.isfinite(r.value) else f"p = {r.p:.2g}"
                paper_says = f" (paper ≈ {paper.SUM_RULE:g})" if quantity.startswith("sum_") else ""
                verdict = f" — {r.verdict}" if isinstance(r.verdict, str) and r.verdict else ""
                cells.append(f"{short}, {where}, `{deep['rung']}`: {value}{paper_says}{verdict}")
    return cells


def deep_sums(root, spec):
    """The sum-rule rows (sum_yield, sum_drag) of the deep_law.csv of a claim's `deep` rungs, with
    a `rung` column, as one DataFrame (None without an entry, a file or such rows): the paper's
    depths that a shallower top rung cannot reach, drawn beside its own sums in (f)'s figure."""
    parts = []
    for deep in (spec or {}).get("deep") or []:
        table = _deep_table(root, deep)
        if table is not None:
            rows = table[table.quantity.isin(["sum_yield", "sum_drag"]) & np.isfinite(table.value)]
            parts.append(rows.assign(rung=deep["rung"]))
    rows = pd.concat(parts, ignore_index=True) if parts else None
    return rows if rows is not None and len(rows) else None


def _deep_table(root, deep):
    """The deep_law.csv of one `deep` entry's rung (None before the rung is collected)."""
    from ..deep_law.deep_law import load_deep_law
    path = Path(root) / deep["rung"] / "deep_law.csv"
    if not path.is_file():
        return None
    try:
        return load_deep_law(path)
    except ValueError as exc:
        raise LadderError(str(exc)) from None


def depth_words(depths, lo, hi):
    """"h ≥ 45 d (45-65 d)" of a deep-law row's depth set and the measured depths it spans."""
    words = {"all": "every depth"}.get(depths, depths.replace(">=", "≥") + " d")
    return f"{words} ({lo:.3g}-{hi:.3g} d)"
