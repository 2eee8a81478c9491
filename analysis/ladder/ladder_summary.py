"""The ladder's claim table: one row per claim of the paper, (a)-(g), at the rung closest to the
paper's conditions for it, and one figure of that claim's evidence at that rung.

ladder.yaml says, per claim (`summary: {letter: {...}}`):

    closest   the rungs in order of closeness to the paper's conditions for this claim, closest
              first (a judgement: which settings the axes found to move the claim's numbers)
    show      the quantities of ladder.csv the row quotes ({quantity: short name}, or a list)
    reading   the verdict in words (no numbers: those come from the rung's files)
    differs   what still differs from the paper at that rung (K_n, box, depth, pull, pour)
    next      the one next run and its price (estimate_cost.py)
    deep      optional: {rung: a rung of system II depths, show: {deep-law quantity: short name}},
              or a list of them (one per friction, say): the row adds each rung's depth-law
              verdicts (its deep_law.csv, analysis.deep_law; written by `ladder collect`), each
              with the depth range it holds for, beside the top rung's (ladder_deep)
    beside    optional: [{rung: a listed rung, show: {quantity: short name}}]: the row adds these
              quantities of ladder.csv at another rung, named, beside the top rung's: a rung
              closer to the paper for one quantity of the claim but not the others (φ₀ read at
              system I's depth, where the saturation in μ was not pulled); nothing before it is run

The "top rung" of a claim, and of each of its quantities in ladder.md's "Verdict at the top
rung", is the first rung of `closest` that has been run and measures it; rungs not in the list
come after it, the later listed first (the ladder's old rule). The numbers, their verdicts and the
figure follow that rung's files, so a newer rung moves the row by a change of `closest`.

The figure, evidence_<letter>.png (analysis.ladder.ladder_summary.evidence_figures): (a) the drag of the
quoted series against Fr with the line, the quadratic and the paper's shape and their residuals
(analysis.regime_tests.regime_figure, the figure `python -m analysis regime-tests` draws, a column per
averaging: the steady drag and the paper's cumulative average over one box, whose verdicts on Fr 1-15
the row quotes, regime_cells); (b) θ against Fr with the rung's
Eq. 7 fit and the paper's, and the time-weighted θ (theta_present) with its own fit where the rung
has it; (c) κ against Fr with the rung's line and Eq. 8; (d) and (e)
the report's Figs. 13 and 17 drawn from the rung's table and fits; (f) α_μ + φ_μ against μ, both
ways of α_μ, each with its standard error and the 95 % interval its verdict takes (Student's t at
the sum's degrees of freedom), beside the paper's 3; (g) the μ = 0 drag of regime I per D with the
rung's a'' + b'' Fr^c'' and the paper's Table I.
"""
import re
import shutil
import tempfile
from pathlib import Path

import numpy as np

from ..core import paper
from .ladder_claims import NOT_RUN, LadderError, cell_verdict
from .ladder_deep import deep_sums, depth_words, read_deep

FIELDS = ("closest", "show", "reading", "differs", "next", "deep", "beside")
EVIDENCE = {"a": "regime_tests", "b": "theta", "c": "kappa", "d": "fig13_yield_vs_D", "e": "fig17_yield_vs_h",
            "f": "sum_rule", "g": "table1"}
CLAIMS_BEGIN, CLAIMS_END = "<!-- claims:begin -->", "<!-- claims:end -->"
THUMB = 260     # px: the width of a figure beside its row


def read_summary(doc, names, path="ladder.yaml"):
    """{letter: {closest, show, reading, differs, next}} of ladder.yaml's `summary` (doc: the
    parsed file; names: the listed rungs). `show` becomes {quantity: short name}."""
    spec = doc.get("summary") if isinstance(doc, dict) else None
    if spec is None:
        return {}
    if not isinstance(spec, dict):
        raise LadderError(f"{path}: `summary` must map a claim letter to its row "
                          "({closest: [rung, ...], show: {quantity: name}, reading, differs, next})")
    out = {}
    for letter, entry in spec.items():
        entry = entry or {}
        if not isinstance(entry, dict) or set(entry) - set(FIELDS):
            raise LadderError(f"{path}: summary.{letter} takes only {', '.join(FIELDS)}")
        closest = [str(n) for n in entry.get("closest") or []]
        unknown = [n for n in closest if n not in names]
        if unknown:
            raise LadderError(f"{path}: summary.{letter}.closest names rungs not listed: {', '.join(unknown)}")
        show = entry.get("show") or {}
        show = {str(q): str(q) for q in show} if isinstance(show, list) else {str(k): str(v) for k, v in show.items()}
        out[str(letter)] = {"closest": closest, "show": show, **{k: str(entry.get(k) or "") for k in FIELDS[2:5]},
                            "deep": read_deep(entry.get("deep"), names, f"{path}: summary.{letter}.deep"),
                            "beside": _read_beside(entry.get("beside"), names, f"{path}: summary.{letter}.beside")}
    return out


def _read_beside(entry, names, where):
    """A claim's `beside` entries, [{rung, show: {quantity: short name}}] ([] without one)."""
    entries = [] if entry is None else entry
    ok = isinstance(entries, list) and all(isinstance(e, dict) and set(e) == {"rung", "show"}
                                           and isinstance(e["show"], dict) for e in entries)
    if not ok:
        raise LadderError(f"{where} takes a list of {{rung: <a listed rung>, show: {{<quantity>: <short name>}}}}")
    for i, e in enumerate(entries):
        if str(e["rung"]) not in names:
            raise LadderError(f"{where}[{i}].rung names a rung not listed: {e['rung']}")
    return [{"rung": str(e["rung"]), "show": {str(k): str(v) for k, v in e["show"].items()}} for e in entries]


def beside_cells(ran, spec):
    """The cells a claim's `beside` entries add: each named quantity of ladder.csv's rows that were
    run at that rung, with the rung's name, beside the paper's and its verdict."""
    cells = []
    for entry in (spec or {}).get("beside") or []:
        mine = ran[ran.rung == entry["rung"]]
        for q, short in entry["show"].items():
            for _, hit in mine[mine.quantity == q].iterrows():
                cells.append(f"{short}, `{entry['rung']}`: {hit.fitted} (paper {hit.published}) — {cell_verdict(hit)}")
    return cells


def rank(summary, letter, rung, order, n_rungs):
    """A rung's place for a claim, 0 the closest to the paper's conditions: its place in the
    claim's `closest`, else after those, the later listed first."""
    closest = summary.get(letter, {}).get("closest", [])
    return closest.index(rung) if rung in closest else len(closest) + (n_rungs - 1 - int(order))


def top_rows(ran, summary, n_rungs):
    """The row of each (claim, quantity) of ladder.csv's rows that were run at its top rung."""
    out = []
    for (letter, _), rows in ran.groupby(["claim", "quantity"], sort=False):
        ranks = [rank(summary, letter, r.rung, r.order, n_rungs) for r in rows.itertuples()]
        out.append(rows.iloc[int(np.argmin(ranks))])
    return out


def top_rung(ran, summary, letter, n_rungs):
    """The claim's top rung: the closest rung that was run and has any of its quantities."""
    rows = ran[ran.claim == letter]
    if rows.empty:
        return None
    ranks = [rank(summary, letter, r.rung, r.order, n_rungs) for r in rows.itertuples()]
    return rows.iloc[int(np.argmin(ranks))].rung


def summary_rows(table, summary, claims, n_rungs, knee=None):
    """One dict per claim of `summary`: letter, claim, rung, measured (cells quoting the rung's
    numbers beside the paper's and their verdicts), reading, differs, next, figure."""
    ran = table[table.verdict != NOT_RUN]
    out = []
    for letter in sorted(summary):
        spec = summary[letter]
        rung = top_rung(ran, summary, letter, n_rungs)
        measured = []
        if rung is not None:
            mine = ran[(ran.claim == letter) & (ran.rung == rung)]
            for q, short in (spec["show"] or {q: q for q in mine.quantity}).items():
                hit = mine[mine.quantity == q]
                measured.append(f"{short}: {hit.fitted.iloc[0]} (paper {hit.published.iloc[0]}) — "
                                f"{cell_verdict(hit.iloc[0])}" if len(hit) else f"{short}: not measured at this rung")
            if letter == "a" and knee is not None and len(knee):
                k, D = knee[knee.rung == rung], _shown_D(spec)
                measured += _knee_cells(k[np.isclose(k.D.astype(float), D)] if D is not None else k)
            measured += beside_cells(ran, spec)
        out.append({"letter": letter, "claim": claims.get(letter, ""), "rung": rung, "measured": measured,
                    "reading": spec["reading"], "differs": spec["differs"], "next": spec["next"],
                    "figure": f"evidence_{letter}.png" if rung is not None else None})
    return out


REGIME_RANGE = (1.0, 15.0)   # Fr: the paper's regimes II and III and the fast speeds the rungs pulled


def regime_cells(table, spec):
    """Claim (a)'s cells from the regime tests (analysis.regime_tests) of the series the row quotes
    (system I, μ = 0.5, its D) on Fr 1-15, one per averaging the rung's table has (the steady drag;
    the paper's cumulative average over one box): the quadratic's curvature and the paper's shape
    from Fr₂ = 5 against one line, each with its calibrated verdict in short."""
    from ..core.bed_shift import covariance
    from ..core.result import format_pm
    from ..regime_tests.regime_tests import averagings, regime3_rows, series_beds
    found = _shown_series(table, spec)
    if found is None:
        return []
    keys, g = found
    beds = series_beds(g)
    cells = []
    for name, col, err in averagings(g):
        rows = {r["test"]: r for r in regime3_rows(g.Fr, g[col], covariance(g, col, err), *REGIME_RANGE, beds=beds)}
        quad, shape = rows["quadratic"], rows["paper_fr2_5"]
        where = f"regime III, {name} drag (D = {keys['D']:g}, Fr {REGIME_RANGE[0]:g}–{REGIME_RANGE[1]:g})"
        if "verdict" not in quad:
            cells.append(f"{where}: not tested ({quad['note']})")
            continue
        cells.append(f"{where}: c = {format_pm(quad['coef_value'], quad['coef_err'])} ({_short_verdict(quad)}); "
                     f"the paper's shape from Fr 5, Δχ² = {shape['delta_chi2']:+.1f} ({_short_verdict(shape)})")
    return cells


def _short_verdict(row):
    """A regime test's verdict in a few words, by its kind (analysis.regime_tests.regime_power.outcome)."""
    kind, p = row["outcome"], f"p = {row['p']:.2g}"
    if kind == "neither":
        return f"not shown: it fits worse than one line, {p}"
    if kind == "shown":
        drop = ", its slope dropping at Fr₂" if "slope drops" in str(row.get("note", "")) else ""
        return f"shown, {p}{drop}"
    if kind == "cannot tell":
        return f"these data cannot tell: power {row['power']:.2f}"
    size = f"{'≥ ' if row['excluded_at_limit'] else ''}{row['excluded_sigma']:.1f} σ"
    return f"the paper's size {'disfavoured only' if kind == 'disfavoured' else 'excluded'} at {size}, {p}"


def _knee_cells(knee):
    cells = []
    for r in knee.itertuples():
        if np.isfinite(r.ratio) and r.slope_below > 0:
            from ..core.result import format_pm
            cells.append(f"the slope past Fr {r.knee:g} over the slope below (D = {r.D:g}, "
                         f"Fr {r.fr_low:g}–{r.fr_high:g}): {format_pm(r.ratio, r.ratio_err)} "
                         "(the paper's quadratic from Fr 5: 1.5 or more)")
    return cells


def _cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def summary_markdown(rows):
    """The claim table: a row per claim, its figure beside it (a thumbnail linking the PNG)."""
    head = ["claim", "top rung", "measured, beside the paper's", "in words", "still differs from the paper",
            "next run and its price", "evidence"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        fig = (f'<a href="{r["figure"]}"><img src="{r["figure"]}" width="{THUMB}" alt="claim ({r["letter"]}) at '
               f'{r["rung"]}"></a>') if r["figure"] else "—"
        rung = f"`{r['rung']}`" if r["rung"] else NOT_RUN
        measured = "<br>".join(_cell(m) for m in r["measured"]) or "—"
        out.append("| " + " | ".join([f"**({r['letter']})** {_cell(r['claim'])}", rung, measured, _cell(r["reading"]),
                                      _cell(r["differs"]), _cell(r["next"]), fig]) + " |")
    return "\n".join(out) + "\n"


def _shown_series(table, spec):
    """(keys, rows) of claim (a)'s series at a rung: system I, μ = 0.5, the D its row quotes (else
    the first D); None when the table has none."""
    from ..regime_tests.regime_tests import series
    found = [(k, g) for k, g in series(table) if str(k["system"]) == "I" and np.isclose(k["mu"], 0.5)]
    want = _shown_D(spec)
    found = [kg for kg in found if want is None or np.isclose(kg[0]["D"], want)] or found
    return found[0] if found else None


def _shown_D(spec):
    for q in spec.get("show", {}):
        m = re.search(r"\bD = ([0-9.]+)", q)
        if m:
            return float(m.group(1))
    return None


def evidence_figures(root, rows, summary):
    """evidence_<letter>.png in root for each row with a top rung, drawn from that rung's
    table.csv and fits.json; a claim with no top rung, or whose figure cannot be drawn, has
    its stale file removed. Returns the paths written."""
    from ..core.table import load_csv
    from ..fits.fitset import load_results
    root = Path(root)
    written = []
    for letter in sorted(set(EVIDENCE) - {r["letter"] for r in rows}):    # no row: no figure
        (root / f"evidence_{letter}.png").unlink(missing_ok=True)
    for r in rows:
        path = root / f"evidence_{r['letter']}.png"
        png = None
        if r["rung"] is not None:
            d = root / r["rung"]
            table, fits = load_csv(d / "table.csv"), load_results(d / "fits.json")
            with tempfile.TemporaryDirectory() as tmp:
                spec = summary.get(r["letter"], {})
                png = _draw(r["letter"], table, fits, Path(tmp), spec, r["rung"], deep_sums(root, spec))
                if png is not None:
                    shutil.copyfile(png, path.with_name(path.name + ".tmp"))
                    path.with_name(path.name + ".tmp").replace(path)
                    written.append(path)
        if png is None:
            path.unlink(missing_ok=True)
            r["figure"] = None
    return written


def _draw(letter, table, fits, tmp, spec, rung, deep=None):
    """The PNG of one claim's evidence in tmp, or None when the rung's files cannot draw it;
    `deep` (deep_sums) adds the claim's deep-rung sum rules to (f)'s figure."""
    kind = EVIDENCE.get(letter)
    if kind == "regime_tests":
        from ..regime_tests.regime_figure import draw_series
        found = _shown_series(table, spec)
        if found is None:
            return None
        paths = draw_series(*found, tmp)
        return next(p for p in paths if p.suffix == ".png")
    if kind in ("theta", "kappa"):
        return _observable_figure(kind, table, fits, tmp, rung)
    if kind == "sum_rule":
        return _sum_rule_figure(fits, tmp, rung, deep)
    if kind == "table1":
        return _table1_figure(table, fits, tmp, rung)
    from ..figures.figure_list import Inputs, draw
    paths, why = draw(kind, Inputs(table=table), fits, tmp)
    return None if why else next(p for p in paths if p.suffix == ".png")


def _observable_figure(kind, table, fits, tmp, rung):
    """θ or κ against Fr at the rung (system I, μ = 0.5, the reference contact law, pulls at
    speed), per D, with the rung's fit (dashed when the data reject it) and the paper's curve."""
    from ..core.table import is_yield, reference_params, select
    from ..fits.fits import evaluate, series_labels
    fit = getattr(fits, kind)
    kn, gn = reference_params(table)
    rows = select(table, mu=0.5, system="I", kn=kn, gamman=gn)
    rows = rows[~is_yield(rows) & rows[kind].notna()]
    if fit is None or rows.empty:
        return None
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.6, 4.2), layout="constrained")
    err = rows[f"{kind}_err"] if f"{kind}_err" in rows.columns else None
    labels = series_labels(rows)
    for i, label in enumerate(dict.fromkeys(labels)):
        g = rows[labels == label]
        ax.errorbar(g.Fr, g[kind], yerr=None if err is None else err[g.index], fmt="o", ms=4, capsize=2,
                    color=f"C{i}", label=label)
    fr = np.linspace(max(float(rows.Fr.min()), 1e-3), float(rows.Fr.max()), 200)
    g = fit.meta.get("goodness") or {}
    if kind == "theta":
        p = paper.THETA
        ax.plot(fr, p["U1"] * fr ** p["U2"] + np.pi / p["U3"], "k--", lw=1.2, label="paper, Eq. 7")
        v = fit.values()
        name = f"fit: {v['U1']:.3g} Fr^{v['U2']:.2g} + π/{v['U3']:.2g}"
        ax.set_ylabel("θ [rad]")
    else:
        p = paper.KAPPA
        ax.plot(fr, p["k0"] + p["k1"] * fr, "k--", lw=1.2, label="paper, Eq. 8")
        v = fit.values()
        name = f"fit: {v['k0']:.3f} {'+' if v['k1'] >= 0 else '−'} {abs(v['k1']):.4f} Fr"
        ax.set_ylabel("κ")
    bad = bool(g.get("rejected")) or bool(fit.meta.get("at_bounds"))
    ax.plot(fr, evaluate(fit, fr), color="C3", lw=1.2, ls=":" if bad else "-",
            label=name + (" (model rejected)" if g.get("rejected") else "")
            + ("; on a bound" if fit.meta.get("at_bounds") else ""))
    if kind == "theta":
        _theta_present(ax, rows, getattr(fits, "theta_present", None), fr)
    ax.set_xlabel("Fr")
    what = "θ(Fr), Eq. 7" if kind == "theta" else "κ(Fr), Eq. 8"
    ax.set_title(f"({'b' if kind == 'theta' else 'c'}) {what}: {rung}", fontsize=9)
    ax.legend(fontsize=7)
    return _savefig(fig, tmp / f"{kind}.png")


def _theta_present(ax, rows, fit, fr):
    """θ over the contacts present (time-weighted, column theta_present) beside θ per formation:
    grey squares and its own Eq. 7 fit, when the rung has both."""
    from ..fits.fits import evaluate
    if fit is None or "theta_present" not in rows.columns or rows.theta_present.isna().all():
        return
    err = rows["theta_present_err"] if "theta_present_err" in rows.columns else None
    ax.errorbar(rows.Fr, rows.theta_present, yerr=err, fmt="s", ms=3.5, mfc="none", capsize=2, color="0.45",
                label="θ time-weighted (contacts present)")
    v, rejected = fit.values(), bool((fit.meta.get("goodness") or {}).get("rejected"))
    ax.plot(fr, evaluate(fit, fr), color="0.3", lw=1.0, ls=":" if rejected or fit.meta.get("at_bounds") else "-.",
            label=f"its fit: {v['U1']:.3g} Fr^{v['U2']:.2g} + π/{v['U3']:.2g}"
            + (" (model rejected)" if rejected else ""))


def _sum_rule_figure(fits, tmp, rung, deep=None):
    """α_μ + φ_μ against μ (reference K_n) with α_μ from the yield force and from the drag, each
    ± its standard error (thick) and ± the 95 % interval its verdict takes (thin), the paper's 3;
    the deep rung's sums (deep_sums) as squares beside them, each at the dof its verdict took."""
    from ..report.verdicts import sum_dof, within_quantile
    parts = [(fits.sums, fits.alpha, "α_μ from the yield force", "C0", -0.012),
             (fits.sums_drag, None, "α_μ from the drag, averaged over speeds (Fig. 18)", "C1", 0.012)]
    if all(t is None or not len(t) for t, *_ in parts) and deep is None:
        return None
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.6, 4.2), layout="constrained")
    for tab, alphas, label, color, dx in parts:
        if tab is None or not len(tab):
            continue
        for i in range(len(tab)):
            t = tab.iloc[i]
            q = within_quantile(sum_dof(t, fits.phi, alphas))
            ax.errorbar(t.mu + dx, t["sum"], yerr=q * t.sum_err, fmt="none", ecolor=color, elinewidth=0.8,
                        alpha=0.5, capsize=2)
            ax.errorbar(t.mu + dx, t["sum"], yerr=t.sum_err, fmt="o", color=color, elinewidth=2.2, capsize=3,
                        label=label if i == 0 else None)
    title = f"(f) the sum rule: {rung}"
    if deep is not None:
        title += f" (circles), {', '.join(dict.fromkeys(deep.rung))} (squares)"
    for t in deep.itertuples() if deep is not None else []:
        yield_force = t.quantity == "sum_yield"
        color, dx = ("C0", -0.036) if yield_force else ("C1", 0.036)
        ax.errorbar(t.mu + dx, t.value, yerr=within_quantile(t.dof) * t.err, fmt="none", ecolor=color,
                    elinewidth=0.8, alpha=0.5, capsize=2)
        ax.errorbar(t.mu + dx, t.value, yerr=t.err, fmt="s", mfc="white", color=color, elinewidth=2.2,
                    capsize=3, label=f"{'α from F_Y' if yield_force else 'α from the drag'}, "
                    f"{depth_words(t.depths, t.h_lo, t.h_hi)} ({t.rung})")
    ax.axhline(paper.SUM_RULE, color="k", ls="--", lw=1.2, label="paper ≈ 3")
    ax.set(xlabel="μ", ylabel="α_μ + φ_μ", ylim=(0.0, 6.0))
    ax.set_title(f"{title}\nthin: the verdict's 95 % interval", fontsize=8)
    ax.legend(fontsize=7)
    return _savefig(fig, tmp / "sum_rule.png")


def _table1_figure(table, fits, tmp, rung):
    """The μ = 0 drag of regime I (Fr up to 1.5) per D of Table I, with the rung's a'' + b'' Fr^c''
    up to its Fr₁ and the paper's (dashed), on a log scale: their levels differ."""
    from ..core.table import is_yield, pooled_drag_err, reference_params, select
    kn, gn = reference_params(table)
    rows = select(table, mu=0.0, system="I", kn=kn, gamman=gn)
    rows = rows[~is_yield(rows) & (rows.Fr <= 1.5 + 1e-9)]
    laws = {D: f for D, f in fits.by("D", 0.0).items() if "b0" in f.params and float(D).is_integer()
            and int(D) in paper.TABLE1}
    if rows.empty or not laws:
        return None
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.6, 4.2), layout="constrained")
    err = pooled_drag_err(rows)
    for i, (D, fit) in enumerate(sorted(laws.items())):
        g = rows[np.isclose(rows.D, D)]
        c = f"C{i}"
        ax.errorbar(g.Fr, g.drag, yerr=np.asarray(err)[np.isclose(rows.D, D)], fmt="o", ms=4, capsize=2, color=c,
                    label=f"D = {D:g}")
        v = fit.values()
        fr = np.linspace(0.01, min(max(v.get("Fr1", 1.0), 0.1), 1.5), 100)
        ax.plot(fr, v["a0"] + v["b0"] * fr ** v["c0"], "-", color=c, lw=1)
        a, b, cc = paper.TABLE1[int(D)]
        ax.plot(fr, a + b * fr ** cc, "--", color=c, lw=1)
    ax.plot([], [], "k-", lw=1, label="fit a'' + b'' Fr^c''")
    ax.plot([], [], "k--", lw=1, label="paper, Table I")
    ax.set_yscale("log")
    ax.set(xlabel="Fr", ylabel="F_drag [ρ g d³], μ = 0")
    ax.set_title(f"(g) Table I: the μ = 0 drag of regime I, {rung}", fontsize=9)
    ax.legend(fontsize=7, ncol=2)
    return _savefig(fig, tmp / "table1.png")


def replace_marked(readme, begin, end, md):
    """Put md between the README's `begin` and `end` markers (atomically); False if it has none."""
    from ..core.table import write_text_atomic
    text = readme.read_text()
    a, b = text.find(begin), text.find(end)
    if a < 0 or b < a:
        return False
    new = text[:a + len(begin)] + "\n" + md.rstrip("\n") + "\n" + text[b:]
    if new != text:
        write_text_atomic(readme, new)
    return True


def replace_claims(readme, md):
    """Put md between the README's claim-table markers; False if it has none."""
    return replace_marked(readme, CLAIMS_BEGIN, CLAIMS_END, md)


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
