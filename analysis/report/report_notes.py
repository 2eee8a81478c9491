"""The report's notes on what each fitted number rests on: its points' replicate beds, their
plateaus, and where the scatter between beds in their errors came from (the point table's
bed_scatter_source: analysis.core.table.combine_beds); and the notes several rows share, stated once."""
from collections import Counter

import numpy as np
import pandas as pd

from ..core.table import BED_SCATTER_SOURCES as WORDS

SEED_COLUMN = "seed"         # replicate bed of a pull (absent: one bed per point)
PLATEAU_COLUMN = "plateau"   # 1/True when the run's drag error converged (observables.cpp)
RUN_TABLE = "runs"           # a run table's rows: beds not combined, each pull its own point


def bed_scatter_sources(rows):
    """Per row, where the bed scatter in its drag error came from: the point table's
    bed_scatter_source (replicates, pooled, prior, none); for a point table written before that
    column, replicates (n_beds >= 2), pooled (one bed with a between-bed error) or none; for a
    run table (no n_beds: beds not combined), RUN_TABLE."""
    if "bed_scatter_source" in rows.columns:
        return rows["bed_scatter_source"].astype(str)
    if "n_beds" not in rows.columns:
        return pd.Series(RUN_TABLE, index=rows.index)
    k = rows["n_beds"].astype(float)
    between = rows.get("drag_err_between", pd.Series(np.nan, index=rows.index)).astype(float)
    return pd.Series(np.where(k >= 2, "replicates", np.where(np.isfinite(between) & (between > 0), "pooled", "none")),
                     index=rows.index)


def _number(row, column):
    v = row.get(column) if hasattr(row, "get") else None
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return v if np.isfinite(v) else None


def _source_text(source, row):
    """(the words for one source, [its r and dof]): pooled and prior with r and dof when the
    table has them."""
    r, dof = _number(row, "bed_scatter_r"), _number(row, "bed_scatter_dof")
    if source == "replicates":
        return WORDS["replicates"], []
    if source == "pooled":
        return (WORDS["pooled"],
                ([f"r = {r:.3g}"] if r is not None else []) + ([f"dof {dof:.0f}"] if dof is not None else []))
    if source == "prior":
        study = row.get("bed_scatter_study") if hasattr(row, "get") else None
        study = study if isinstance(study, str) and study else "a study not named"
        measured = (f" r = {r:.3g}" if r is not None else "") + (f" (dof {dof:.0f})" if dof is not None else "")
        return f"{WORDS['prior']}{measured} from {study}", []
    if source == RUN_TABLE:
        return "none in the errors (a run table: each bed's pull its own point)", []
    return WORDS["none"], []


def bed_scatter_note(rows):
    """Where the bed scatter of the rows' drag errors came from, in words: "bed scatter: replicate
    beds", or one clause per source with its points ("replicate beds (12 points); prior r = 0.011
    (dof 26) from … (3 points)"); "" for no rows."""
    if rows is None or len(rows) == 0:
        return ""
    sources = bed_scatter_sources(rows)
    parts = []
    for source, n in Counter(sources).items():
        text, details = _source_text(source, rows[sources == source].iloc[0])
        if sources.nunique() > 1:
            details = details + [f"{n} point{'s' if n != 1 else ''}"]
        parts.append(text + (f" ({', '.join(details)})" if details else ""))
    return "bed scatter: " + "; ".join(parts)


def observable_sources(rows):
    """Per row, where the bed scatter in its θ and κ errors came from: replicates (n_beds >= 2:
    their scatter over the beds) or none (one bed: θ and κ take no pooled or prior scatter);
    RUN_TABLE for a run table, as the drag's."""
    if "n_beds" not in rows.columns:
        return pd.Series(RUN_TABLE, index=rows.index)
    return pd.Series(np.where(rows["n_beds"].astype(float) >= 2, "replicates", "none"), index=rows.index)


def observable_note(rows):
    """Where the bed scatter of the rows' θ and κ errors came from, in words."""
    sources = observable_sources(rows)
    words = {"replicates": WORDS["replicates"], RUN_TABLE: _source_text(RUN_TABLE, {})[0],
             "none": "none (single beds: θ and κ take no pooled or prior scatter)"}
    parts = [words[s]
             + (f" ({n} point{'s' if n != 1 else ''})" if sources.nunique() > 1 else "")
             for s, n in Counter(sources).items()]
    return "θ and κ bed scatter: " + "; ".join(parts)


def basis_notes(rows, bed_scatter=True, observable=False):
    """How many replicate beds the rows rest on, whether any of their runs lacked a plateau and
    where the bed scatter in their errors came from: with bed_scatter, the drag's
    (bed_scatter_note); for a θ or κ number (observable), θ's and κ's (observable_note), stated
    with bed_scatter or where it differs from the drag's (which the report then states once)."""
    if rows is None or len(rows) == 0:
        return []
    if "n_beds" in rows.columns:           # the point table: replicate beds already combined
        per = rows["n_beds"].astype(int)
        beds = f"{per.min()}–{per.max()}" if per.min() != per.max() else f"{per.min()}"
        out = [f"{beds} replicate bed(s) per point"]
    elif SEED_COLUMN in rows.columns:      # a run table: one row per bed
        per = rows.groupby(["system", "D", "h", "mu", "kn", "gamman", "V"])[SEED_COLUMN].nunique()
        beds = f"{per.min()}–{per.max()}" if per.min() != per.max() else f"{per.min()}"
        out = [f"{beds} replicate bed(s) per point"]
    else:
        out = ["1 bed per point (no replicates)"]
    if observable:
        if bed_scatter or (observable_sources(rows) != bed_scatter_sources(rows)).any():
            out.append(observable_note(rows))
    elif bed_scatter:
        out.append(bed_scatter_note(rows))
    if PLATEAU_COLUMN in rows.columns:
        flat = rows[PLATEAU_COLUMN].astype(float)
        bad = int((flat == 0).sum())
        out.append(f"{bad} of {len(rows)} runs whose drag error reached no plateau (a conservative bound)"
                   if bad else "every run reached a plateau")
    return out


def uniform_bed_scatter(df):
    """True when every row of the table has the same bed-scatter source (and, for pooled or prior,
    the same r): the report then states it once, not beside each number."""
    if df is None or len(df) == 0:
        return True
    sources = bed_scatter_sources(df)
    if sources.nunique() > 1:
        return False
    r = df["bed_scatter_r"].astype(float) if "bed_scatter_r" in df.columns else pd.Series([np.nan])
    return r.dropna().nunique() <= 1


def bed_scatter_sentence(df):
    """The report's one sentence on the bed scatter of every fit's points."""
    note = bed_scatter_note(df).removeprefix("bed scatter: ")
    if not note:
        return ""
    tail = "" if uniform_bed_scatter(df) else " Each number's notes say which of these its points used."
    return f"Scatter between beds in the drags' errors, every fit: {note}.{tail}"


def shared_caveats(rows):
    """(the notes several rows share, as "[k] note (n rows)", and a function that writes a row's
    notes with those replaced by their [k]): a caveat is stated once, not on every row."""
    seen = Counter(n for x in rows for n in dict.fromkeys(x.notes))
    shared = [n for n, k in seen.items() if k > 1]
    number = {n: i + 1 for i, n in enumerate(shared)}

    def refs(notes):
        own = [n for n in notes if n not in number]
        cited = sorted({number[n] for n in notes if n in number})
        return "; ".join(own + ([", ".join(f"[{k}]" for k in cited)] if cited else []))

    return [f"[{number[n]}] {n} ({seen[n]} rows)" for n in shared], refs
