"""The ladder's outputs for reading: ladder.md (the rungs, the claims against them, the verdict
at the top rung and the diagnostics' tables) and its figures claim_<letter>.png,
kappa_shells.png, fr2_range.png and the axes' box_axis.png and stiffness_axis.png."""
import math

import numpy as np

from ..core import paper
from .ladder_axes import HEADS, SAME_DEPTH, SPLIT_FR, setting
from .ladder_claims import CLAIMS, NOT_RUN, OTHER, cell_verdict
from .ladder_diagnostics import kappa_points
from .ladder_summary import _pyplot, _savefig, top_rows

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
    label = rung["label"] + (f"; extends `{rung['extends']}` in place (one point on the axes)"
                             if rung.get("extends") else "")
    if info is None:
        return [i + 1, rung["name"], label, "—", NOT_RUN, "—", "—", "—", "—"]
    m = info.get("machine") or {}
    mem = f", {m['memory_gib']:g} GiB" if m.get("memory_gib") else ""
    ch = info.get("core_hours")
    date = str(info.get("started") or info.get("date") or "")[:10]
    return [i + 1, rung["name"], label, f"`{info.get('config', '?')}`",
            f"{_hms(info.get('wall_seconds', 0))} on {info.get('cores', '?')} cores",
            f"{ch:.2f}" if isinstance(ch, (int, float)) else "—",
            f"{m.get('cpu', '?')} ({m.get('cores', '?')} cores{mem})", date, info.get("commit", "?")]


def ladder_markdown(table, rungs, claims, infos, slopes=None, fr2=None, figures=(), decomposition=None,
                    startup=None, axes=(), knee=None, summary=None):
    """ladder.md: the rungs, each claim's quantities against the rungs, the verdict at the top
    rung, and the diagnostics. Deterministic: only what the rungs' files say."""
    names = [r["name"] for r in rungs]
    out = ["The reproduction ladder: each rung is a study that moves one factor toward the paper's "
           "conditions (ladder.yaml). Verdicts are the report's (analysis/report/report.py): within error bars = "
           "the paper's value inside the 95 % interval (the Student-t quantile at the fit's degrees of "
           "freedom times its standard error; 1.96 without a fit of its own), qualitatively = within 25 % "
           "of it, inconclusive = no error bar, an error above 30 % of the value, a fit that breaks its "
           "model or ended on a bound, one with no degrees of freedom left or an interval of Student's t at "
           "fewer than 2 degrees of freedom (untestable there), or one the data reject (its residuals trend, "
           "or its χ² is far out, analysis/fits/goodness.py: \"model rejected\", which a sum rule built on it "
           "inherits; hollow markers in the figures). A rung not run "
           "shows no numbers; — : not studied (the rung does not measure the quantity, or, for θ and κ, measures "
           "it at fewer than 5 speeds at speed or from yield pulls only: analysis/report/verdicts.py). Written by "
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
                cells.append(f"{hit.fitted.iloc[0]} — {_verdict(hit.iloc[0])}" if len(hit)
                             else NOT_RUN if infos.get(n) is None else "—")
            body.append([q, rows.published.iloc[0]] + cells)
        out.append(_md_table(["quantity", "paper"] + names, body))
    if len(ran):
        out.append("### Verdict at the top rung\n")
        out.append("The top rung of a quantity is the rung closest to the paper's conditions for its claim that "
                   "measures it (ladder.yaml's `summary: {claim: {closest: [...]}}`, closest first; rungs not listed "
                   "there after those, the later listed first), not the last one listed.\n")
        body = [[top.claim, top.quantity, top.rung, top.fitted, top.published, _verdict(top)]
                for top in top_rows(ran, summary or {}, len(rungs))]
        out.append(_md_table(["claim", "quantity", "top rung", "fitted", "paper", "verdict"], body))
    out += _diagnostics_markdown(slopes, fr2, names, infos, figures, decomposition, startup, axes, knee)
    return "\n".join(out)


_verdict = cell_verdict


# What each axis's section says before its table: what is held, what is compared, how to read it.
_AXIS_ABOUT = {
    "box_axis": "The same points (K_n, D, Fr; depths within {depth:g} d) in rungs whose periodic box is wider "
                "(the paper's system I: 40 d); each box's drag over the next narrower box's (box_axis.csv, per "
                "point; analysis.ladder.ladder_axes). A ratio near 1 says the narrower box was wide enough.",
    "stiffness_axis": "The same points (box, D, Fr; depths within {depth:g} d) in rungs with stiffer contacts (the "
                      "paper: K_n = 2e+08); each rung's drag over the next softer rung's (stiffness_axis.csv, per "
                      "point; analysis.ladder.ladder_axes). The paper finds the levels of regimes I and II moving with "
                      "K_n and the crossovers not (Sec. III I): the same ratio on both sides of Fr {split:g} says the "
                      "curve's shape held.",
    "length_axis": "The same points (K_n, box, D, Fr; depths within {depth:g} d) in rungs whose pulls are longer "
                   "(the paper: one box length, Sec. II), the same transient discarded at the start; each pull's drag "
                   "over the next shorter pull's (length_axis.csv, per point; analysis.ladder.ladder_axes). A ratio "
                   "near 1 says the shorter pull had reached the steady drag; one away from 1, a drag that drifts "
                   "along the pull.",
}


def _held(axis, values):
    """The held settings of one group, as a table cell or a title: "K_n 2e+06, box 20 d"."""
    return ", ".join(f"{HEADS[c]} {setting(c, v)}" for c, v in zip(axis.held, values))


def _axis_markdown(axis, summary, figures):
    """One axis of the ladder: per step along it, the drag's ratio over Fr up to SPLIT_FR and beyond."""
    out = [f"### {axis.title}\n",
           _AXIS_ABOUT[axis.name].format(depth=SAME_DEPTH, split=SPLIT_FR) + " Cells: the median ratio (least – "
           "greatest; points beyond 2 errors of the previous rung's drag).\n"]
    if f"{axis.name}.png" in figures:
        out.append(f"![{axis.title.removeprefix('The ')}]({axis.name}.png)\n")
    body = []
    for (*held, D, value, previous), g in summary.groupby([*axis.held, "D", axis.along, "previous"]):
        cells = []
        for lo in (0.0, SPLIT_FR):
            hit = g[np.isclose(g.fr_lo, lo)]
            r = hit.iloc[0] if len(hit) else None
            cells.append("—" if r is None else f"×{r.ratio_median:.2f} ({r.ratio_min:.2f} – {r.ratio_max:.2f}; "
                         f"{int(r.n_beyond_2sigma)} of {int(r.n_points)})")
        step = f"{setting(axis.along, previous)} → {setting(axis.along, value)}"
        body.append([_held(axis, held), f"{D:g}", step] + cells)
    heads = ["held", "D", HEADS[axis.along], f"Fr ≤ {SPLIT_FR:g}", f"Fr > {SPLIT_FR:g}"]
    out.append(_md_table(heads, body))
    return out


def _diagnostics_markdown(slopes, fr2, names, infos, figures, decomposition=None, startup=None, axes=(),
                          knee=None):
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
    if knee is not None and len(knee):
        out += _knee_markdown(knee, names)
    if startup is not None and len(startup):
        out.append("### Fr_2 with the start of each pull kept, as a cumulative average over 40 d\n")
        out.append("The paper's drag is \"the cumulative average\" of the force (Fig. 4); it does not say a start was "
                   "discarded. Here: each pull's start (discarded in the table) kept and its excess spread over a 40 d "
                   "pull (startup_fr2.csv; analysis.ladder.ladder.startup_refit), beside the steady drag. Cells: Fr_2 "
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
    for axis, summary in axes:   # (Axis, axis_summary) pairs, in order
        if len(summary):
            out += _axis_markdown(axis, summary, figures)
    return out


def _knee_markdown(knee, names):
    r0 = knee.iloc[0]
    out = [f"### The drag's slope above Fr {r0.knee:g} against below\n",
           f"The paper's regime III is quadratic from Fr_2 ≈ {r0.knee:g} on, so the drag must steepen there: a "
           f"line broken at Fr = {r0.knee:g} through the μ = 0.5 points with {r0.fr_low:g} ≤ Fr ≤ {r0.fr_high:g} "
           "(analysis.ladder.ladder.knee_at_five; knee_fr5.csv) has a slope above the knee at least that below it (1.5 "
           "times it for a quadratic joined smoothly to the line). A test that needs no fitted crossover. Cells: "
           "the slopes (ρ d³ g per unit Fr), their ratio, and z of the difference (above 2: steepens; below −2: "
           "flattens).\n"]
    order = {n: i for i, n in enumerate(names)}
    body = []
    for r in sorted(knee.itertuples(), key=lambda r: (order.get(r.rung, len(order)), r.D)):
        if not np.isfinite(r.slope_below):
            body.append([r.rung, f"{r.D:g}", "—", "—", "—", "—", str(r.note)])
            continue
        ratio = _pm(r.ratio, r.ratio_err) if r.slope_below > 0 else "n/a"
        body.append([r.rung, f"{r.D:g}", _pm(r.slope_below, r.slope_below_err), _pm(r.slope_above, r.slope_above_err),
                     ratio, f"{r.z:.1f}", f"{int(r.n_points)}"])
    out.append(_md_table(["rung", "D", "slope below", "slope above", "above / below", "z", "points"], body))
    return out


def _pm(value, err):
    from ..core.result import format_pm
    return format_pm(float(value), float(err)) if np.isfinite(value) else "n/a"


# --- figures ---------------------------------------------------------------------

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
            bad = (rows.rejected.fillna("").astype(str) != "").to_numpy() if "rejected" in rows \
                else np.zeros(len(rows), bool)
            for mask, face in ((~bad, None), (bad, "none")):     # a rejected model's number: hollow
                if mask.any():
                    ax.errorbar(rows.order[mask], rows.value.astype(float)[mask], fmt="o", capsize=3, color="C0",
                                mfc=face, yerr=np.where(np.isfinite(err), err, 0.0)[mask])
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


def _axis_figure(root, axis, steps):
    """<axis.name>.png: per held setting and D with more than one value along the axis, the drag
    against Fr at each value (top) and each value's drag over the previous one's (bottom)."""
    path = root / f"{axis.name}.png"
    if steps.empty:
        path.unlink(missing_ok=True)
        return []
    plt = _pyplot()
    groups = list(steps.groupby([*axis.held, "D"]))
    fig, axes = plt.subplots(2, len(groups), figsize=(4.5 * len(groups), 6.5), squeeze=False, sharex=True,
                             layout="constrained")
    for col, ((*held, D), g) in enumerate(groups):
        top, bottom = axes[0, col], axes[1, col]
        for value, s in g.groupby(axis.along):
            s = s.sort_values("Fr")
            label = f"{HEADS[axis.along]} {setting(axis.along, value)}"
            top.errorbar(s.Fr, s.drag, yerr=s.drag_err, fmt="o-", capsize=3, ms=4, label=label)
            r = s[np.isfinite(s.ratio.astype(float))]
            if len(r):
                bottom.errorbar(r.Fr, r.ratio, yerr=r.ratio_err, fmt="o-", capsize=3, ms=4,
                                label=f"{label} / {setting(axis.along, r.previous.iloc[0])}")
        top.set(ylabel="drag F_D [ρ g d³]", title=f"{_held(axis, held)}, D = {D:g}")
        top.legend(fontsize=7)
        bottom.axhline(1.0, color="k", lw=0.8)
        bottom.set(xlabel="Fr", ylabel="drag ratio to the previous rung")
        bottom.legend(fontsize=7)
    return [_savefig(fig, path)]
