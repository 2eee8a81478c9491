"""The claims of one rung: the paper's headline claims by letter, the report's rows of a rung's
files (read and judged as the report rule does) sorted into them, and the ladder's error and
"not run" verdict, which every ladder module shares."""
import math
import re
from pathlib import Path

from ..core.claims import CLAIMS, OTHER, claim_of  # noqa: F401  (re-exported for the ladder modules)
from ..core.table import load_csv, reference_params
from ..fits.fitset import load_results
from ..report.report import comparisons

NOT_RUN = "not run"


def cell_verdict(row):
    """A ladder cell's verdict: the report's, with "(model rejected)" when the data reject the fit."""
    rejected = row.get("rejected")
    return f"{row.verdict} (model rejected)" if isinstance(rejected, str) and rejected else row.verdict


class LadderError(ValueError):
    """A rung or ladder file that is missing or unusable; the message names it and the fix."""


# --- the claims of a rung --------------------------------------------------

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
    rejected (the report's "model rejected (...)" when the data reject the fit the number
    comes from, goodness.py; "" otherwise), notes. `quantity` drops the rung's own reference
    K_n from the report's text (the ladder varies K_n between rungs; rows of another K_n keep
    theirs), so one quantity lines up across rungs. Claims the rung did not study have no rows."""
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
                    "rejected": row.rejected, "notes": "; ".join(row.notes)})
    return out


def _requested_depths(df):
    """{the report's text of a measured depth: the depth the config asked for}. The report names
    a depth series by its measured h (the beds' mean), which moves between realizations and bed
    counts (9.46 with one bed, 9.42 with two); the ladder lines rungs up by the requested one."""
    if "h_requested" not in df.columns:
        return {}
    pairs = df[["h", "h_requested"]].dropna().drop_duplicates()
    return {f"{h:.3g}": float(req) for h, req in zip(pairs.h, pairs.h_requested)}
