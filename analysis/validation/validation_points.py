"""Every point of a validation study, as a markdown table under its sentence
(analysis.validation.validation): the keys that tell the points apart, the variant, each judged
observable's difference from the reference with its error and z, the reported ones' relative
differences, and the verdict. The sentence says how many points agree; this table is what a
reader checks it against, and what a study's log entry quotes, so nobody copies numbers by hand."""

import numpy as np
import pandas as pd

from .agreement import Z_AGREE, label_value

# Headers of the point keys (a study's keys and settings, shown where they differ between its
# points) and of the reported observables; other columns go under their own names.
_HEADERS = {"h_requested": "h", "z_requested": "z", "mu": "μ", "kn": "K_n", "gamman": "γ_n",
            "n_contacts": "n"}


def _cell(v):
    if isinstance(v, float) and np.isnan(v):
        return "–"
    return label_value(float(f"{v:.3g}")) if isinstance(v, float) else label_value(v)


def _signed(x, digits=2):
    if np.isnan(x):
        return "–"
    return ("+∞" if x > 0 else "−∞") if np.isinf(x) else f"{x:+.{digits}f}"


def point_table(cmp, study):
    """The markdown table of every comparison in `cmp` (a `compare` frame of `study`) under its
    heading, one row per point and variant, sorted by the point keys; "" for an empty frame."""
    if cmp.empty:
        return ""
    # A key with one value and NaN (a setting unset in one variant) tells points apart too.
    keys = [(k, _HEADERS.get(k, k)) for k in (*study.keys, *study.settings)
            if k in cmp.columns and cmp[k].nunique(dropna=False) > 1]
    judged = [col for col, _ in study.also_judged if f"{col}_diff" in cmp.columns]
    reported = [col for col in study.also_reported if f"{col}_rel_diff" in cmp.columns]
    head = [name for _, name in keys] + [study.variant, "drag, variant − reference", "z"]
    for col in judged:
        head += [f"{col}, variant − reference", "z"]
    head += [_HEADERS.get(col, col) for col in reported] + ["agrees"]
    rows = []
    order = [k for k, _ in keys] + ["variant"]
    for _, r in cmp.sort_values(order, kind="stable").iterrows():
        cells = [_cell(r[k]) for k, _ in keys] + [_cell(r["variant"])]
        cells += [f"{100 * r.rel_diff:+.1f} ± {100 * r.rel_diff_err:.1f} %", _signed(r.z)]
        for col in judged:
            cells += [f"{r[f'{col}_diff']:+.3f} ± {r[f'{col}_diff_err']:.3f}", _signed(r[f"{col}_z"])]
        cells += [f"{100 * r[f'{col}_rel_diff']:+.1f} %" if pd.notna(r[f"{col}_rel_diff"]) else "–"
                  for col in reported]
        cells.append("yes" if bool(r.agrees) else "**no**")
        rows.append(cells)
    lines = ["", f"Every point (z: the difference over its error; |z| < {Z_AGREE:g} agrees):", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(c) + " |" for c in rows]
    return "\n".join(lines) + "\n"
