"""Shifts the beds resolve: in a paired validation study (the variants pulled through the same
beds, analysis.validation.validation), the per-bed differences of three or more beds measure the paired
error directly (`<obs>_beds_err`, `<obs>_beds_z`, a Student t with beds - 1 dof). A shift smaller
than the runs' errors but the same in every bed shows there while z calls the point agreeing;
the study's sentence names each such point with its size, beside the verdict on z."""

import numpy as np
import pandas as pd
from scipy.stats import t as student

# Point keys named when a resolved shift is listed, where they differ between the study's points.
_POINT_LABELS = (("D", "D"), ("mu", "mu"), ("kn", "K_n"), ("Fr", "Fr"), ("h_requested", "h"),
                 ("z_requested", "z"))


def resolved_shifts(cmp, study):
    """The paired points whose shift the beds resolve, though the verdict (on z) may call them
    agreeing: the per-bed differences' t (`<obs>_beds_z`) beyond Student's 97.5 % point at
    beds - 1 dof. A shift the same in every bed is real however small; the sentence names it with
    its size, so a reader sees a +12 % drift the runs' errors hide and can dismiss a 0.7 % one."""
    if "beds" not in cmp.columns:
        return ""
    labels = (*_POINT_LABELS, *((c, c) for c in study.settings))   # settings: regions of one radius
    varying = [(k, name) for k, name in labels if k in cmp.columns and cmp[k].nunique(dropna=True) > 1]
    found = []
    for r in cmp.itertuples():
        for col, _ in study.judged:
            # NaN below three beds (analysis.validation.validation._beds); infinite when every bed differs alike
            t = getattr(r, f"{col}_beds_z", np.nan)
            dof = int(r.beds) - 1
            if np.isnan(t) or abs(t) <= student.ppf(0.975, dof):
                continue
            where = ", ".join(f"{name} = {getattr(r, k):g}" for k, name in varying if pd.notna(getattr(r, k)))
            size = f"{100 * r.rel_diff:+.1f} %, " if col == "drag" else ""
            found.append(f"{study.variant} = {r.variant:g}" + (f" at {where}" if where else "")
                         + f" ({col}: {size}t {t:.2g}, {dof} dof)")
    if not found:
        return ""
    return (" The beds resolve a shift (the per-bed differences' t beyond Student's 97.5 % point, which "
            "1 point in 20 passes by chance; the verdict stays on z) at: " + "; ".join(found) + ".")
