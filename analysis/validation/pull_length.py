"""Validation of the pull length: how far must a pull travel before its drag and error hold?

Sequential stopping (`granudrag pull --target_error`) stops a pull as soon as the drag's
error meets a target after `min_distance`. That is only safe from the travel on where the
error estimate can be trusted and the drag no longer drifts; and the transient discarded at
the start must cover the approach to the steady state. This study answers both from long
pulls, per regime (the pull's Fr, or V for the yield pulls):

- the drag of the first L d after the transient (each run file's
  /observables/drag/convergence: the first 8, 11, 16, ... samples, then all) against the
  whole pull's, F over T d with error e: z = (F_L - F) / (e sqrt(T/L - 1)). F_L's samples are
  part of F's, so the difference has the variance of the rest, e^2 (T/L - 1) when the error
  falls as L^-1/2; the prefixes' own errors are too noisy for it (a few degrees of freedom
  each, and often below the whole pull's);
- `min_distance`: the shortest L from which every longer prefix agrees (|z| < Z_AGREE: the
  drag has stopped drifting beyond its error) and has an error at least HONEST of the one
  the whole pull implies there, e sqrt(T/L) (shorter, the estimator sees too little of the
  series' correlations and its error is too small to stop on); the largest over the
  regime's beds, and none when only the whole pull passes;
- where the error converges (the estimator's plateau, protocol/observables.cpp): sequential
  stopping trusts an error only with >= 10 effective samples, so a regime whose pulls never
  converge needs longer ones before `target_error` can stop them;
- the travel at which the relative error reaches TARGET (measured, or extrapolated as
  e ~ L^-1/2 from the whole pull when it never does);
- the transient: windows of the raw force series from the start; the drag "settles" at the
  first window inside the steady band (the mean of the windows of the pull's second half,
  +- 2 of their standard deviations: a band from the windows after the configured transient
  would be widened by the very drift a too-short transient leaves); the configured transient
  is long enough when every bed settles within it.

    python -m analysis validate pull_length results/validate/pull_length/runs.csv --output-dir DIR

writes DIR/validate_pull_length.png, .pdf, .csv (every prefix of every run) and .md.
"""

from pathlib import Path

import numpy as np
import pandas as pd

from ..core.table import write_csv, write_text_atomic
from ..runs.runs import _open
from .agreement import Z_AGREE, ValidationError

TARGET = 0.05      # the relative error quoted (a 5 % drag)
HONEST = 0.5       # a prefix's error below half the whole pull's e sqrt(T/L) is too small to stop on
BAND = 2.0         # the steady band: mean +- BAND standard deviations of the window means


class PullLengthError(ValidationError):
    """The runs cannot answer the study's question (says what is missing)."""


def read_convergence(path):
    """The run file's convergence table, its raw drag series and the pull's speed and transient:
    (DataFrame of samples, travel, value, error, dof, plateau; dict of travel, drag, transient)."""
    with _open(path) as f:      # a missing, foreign or damaged file: a RunFileError naming it
        if "observables/drag/convergence" not in f:
            raise PullLengthError(
                f"{path}: no /observables/drag/convergence (a run file from before 2026-11-25): "
                "rerun the pull with this granudrag")
        g = f["observables/drag/convergence"]
        conv = pd.DataFrame({k: np.asarray(g[k]) for k in ("samples", "travel", "value", "error", "dof", "plateau")})
        speed = float(f["run"].attrs["speed"])
        series = {"travel": np.asarray(f["observables/intruder_force/time"]) * speed,
                  "drag": -np.asarray(f["observables/intruder_force/value"])[:, 0],
                  "transient": float(f["observables/drag"].attrs["transient_distance"])}
    conv["plateau"] = conv.plateau.astype(bool)
    return conv, series


def prefixes(conv):
    """Each prefix against the whole pull (the last row): z and whether it agrees, and its error
    against the one the whole pull implies at its length."""
    whole = conv.iloc[-1]
    expected = whole.error * np.sqrt(whole.travel / conv.travel)
    sd = whole.error * np.sqrt(np.maximum(whole.travel / conv.travel - 1, 0.0))
    diff = conv.value - whole.value
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(sd > 0, diff / sd, np.where(diff == 0, 0.0, np.inf))
    return conv.assign(rel_error=conv.error / conv.value.abs(), rel_to_whole=conv.value / whole.value,
                       z=z, agrees=np.abs(z) < Z_AGREE, error_ratio=conv.error / expected,
                       honest=conv.error >= HONEST * expected)


def _holds_from(rows, ok):
    """The travel of the first prefix from which `ok` holds to the end (NaN when it does not
    hold before the whole pull)."""
    ok = np.asarray(ok, bool)
    first = len(ok)
    while first > 0 and ok[first - 1]:
        first -= 1
    return float(rows.travel.iloc[first]) if first < len(ok) - 1 else np.nan


def min_distance(rows):
    """The shortest prefix travel from which every longer prefix agrees with the whole pull and
    has an honest error; NaN when only the whole pull passes (the drag drifts to the end)."""
    return _holds_from(rows, rows.agrees & rows.honest)


def converged_from(rows):
    """The shortest prefix travel from which every longer prefix's error has converged (NaN
    when not before the whole pull)."""
    return _holds_from(rows, rows.plateau)


def target_distance(rows, target=TARGET):
    """(travel at which the relative error first reaches `target` with a converged error,
    whether it was measured or extrapolated as e ~ L^-1/2 from the whole pull)."""
    hit = rows[(rows.rel_error <= target) & rows.plateau]
    if len(hit):
        return float(hit.travel.iloc[0]), True
    whole = rows.iloc[-1]
    return float(whole.travel * (whole.rel_error / target) ** 2), False


def settling(series, windows_per_transient=2, min_samples=4):
    """(travel at which the drag first enters the steady band, the window width, the travel per
    sample): windows of the raw series from the start of the pull, the band from the windows of
    its second half."""
    travel, drag, transient = series["travel"], series["drag"], series["transient"]
    if len(travel) < 2:
        return np.nan, np.nan, np.nan
    step = travel[1] - travel[0]
    width = max(transient / windows_per_transient, min_samples * step)
    per = max(int(round(width / step)), 1)
    n = len(drag) // per
    starts = travel[: n * per : per] - step      # a sample's travel is its interval's end
    means = drag[: n * per].reshape(n, per).mean(axis=1)
    steady = means[starts >= 0.5 * travel[-1]]
    if len(steady) < 3:
        return np.nan, width, step
    lo, hi = steady.mean() - BAND * steady.std(ddof=1), steady.mean() + BAND * steady.std(ddof=1)
    inside = np.nonzero((means >= lo) & (means <= hi))[0]
    return (float(starts[inside[0]]) if len(inside) else np.nan), width, step


def regime_of(run):
    """A run's regime label: its mu and Fr, or V for pulls slower than Fr 0.1 (yield pulls)."""
    speed = f"V = {run.V:g}" if run.Fr < 0.1 else f"Fr = {run.Fr:g}"
    return f"mu = {run.mu:g}, {speed}"


def study(runs):
    """(every prefix of every run, one row per regime with the answers)."""
    if "path" not in runs.columns:
        raise PullLengthError("pull_length: the run table has no 'path' column (make it with analysis.runs.runs)")
    if "sanity" in runs.columns:
        runs = runs[runs.sanity.fillna("clean") == "clean"]
    if runs.empty:
        raise PullLengthError("pull_length: no clean run in the table")
    rows, per_run = [], []
    for _, run in runs.iterrows():
        conv, series = read_convergence(run.path)
        if len(conv) < 2:
            raise PullLengthError(f"{run.path}: under 11 samples after the transient: pull longer")
        p = prefixes(conv).assign(regime=regime_of(run), Fr=run.Fr, V=run.V, D=run.D, mu=run.mu,
                                  seed=run.get("seed", np.nan), path=run.path)
        rows.append(p)
        settled, width, step = settling(series)
        l_target, measured = target_distance(p)
        per_run.append(dict(regime=regime_of(run), mu=run.mu, Fr=run.Fr, V=run.V, seed=run.get("seed", np.nan),
                            travel=float(p.travel.iloc[-1]), drag=float(p.value.iloc[-1]),
                            rel_error=float(p.rel_error.iloc[-1]), plateau=bool(p.plateau.iloc[-1]),
                            min_distance=min_distance(p), converged_from=converged_from(p),
                            dof=float(p.dof.iloc[-1]), target_distance=l_target, target_measured=measured,
                            transient=series["transient"], settled_at=settled, window=width,
                            # a window starts on a sample: one sample's slack
                            transient_enough=bool(settled <= series["transient"] + step),
                            transient_checked=bool(np.isfinite(settled))))
    per_run = pd.DataFrame(per_run)
    answers = []
    for regime, g in per_run.groupby("regime", sort=False):
        answers.append(dict(
            regime=regime, mu=g.mu.iloc[0], Fr=g.Fr.iloc[0], V=g.V.iloc[0], beds=len(g), travel=g.travel.min(),
            rel_error=g.rel_error.median(),
            min_distance=g.min_distance.max() if g.min_distance.notna().all() else np.nan,
            converged_from=g.converged_from.max() if g.converged_from.notna().all() else np.nan,
            converged=int(g.plateau.sum()), dof=g.dof.median(),
            target_distance=g.target_distance.median(), target_measured=bool(g.target_measured.all()),
            transient=g.transient.iloc[0], settled_at=g.settled_at.max(),
            transient_enough=bool(g.transient_enough.all()),
            transient_checked=bool(g.transient_checked.all())))
    answers = pd.DataFrame(answers).sort_values(["mu", "Fr"]).reset_index(drop=True)
    return pd.concat(rows, ignore_index=True), answers


def conclusion(answers, target=TARGET):
    """The sentence: per regime, min_distance, the travel for the target error, the transient."""
    parts = []
    for _, a in answers.iterrows():
        if np.isfinite(a.min_distance):
            md = f"min_distance {a.min_distance:.2g} d"
        else:
            md = (f"no min_distance (the drag drifts, or its error is too small, until the end of "
                  f"the {a.travel:.3g} d pull)")
        if np.isfinite(a.converged_from):
            md += f", error converged from {a.converged_from:.2g} d"
        elif a.converged == a.beds:
            md += f", error converged only over the whole {a.travel:.3g} d"
        else:
            md += (f", error not converged in {a.beds - a.converged} of {a.beds} pulls "
                   f"({a.dof:.2g} effective samples; a conservative bound)")
        how = "" if a.target_measured else ", extrapolated"
        if not a.transient_checked:
            tr = "the transient not checked (under 3 windows in a pull's second half: pull longer)"
        elif a.transient_enough:
            tr = f"the {a.transient:.2g} d transient covers the approach (settled by {a.settled_at:.2g} d)"
        else:
            tr = f"the {a.transient:.2g} d transient is too short (settled only at {a.settled_at:.2g} d)"
        beds = f"{a.beds} bed" + ("s" if a.beds != 1 else "")
        parts.append(f"{a.regime} ({beds}): {md}; {100 * target:g} % error after "
                     f"{a.target_distance:.2g} d{how}; {tr}")
    return "Pull length per regime: " + "; ".join(parts) + "."


def draw(rows, answers, outdir, target=TARGET):
    """validate_pull_length.png/.pdf: F_L/F and the relative error against the travel L."""
    import matplotlib.pyplot as plt

    plt.switch_backend("Agg")
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
    colours = dict(zip(answers.regime, plt.rcParams["axes.prop_cycle"].by_key()["color"] * 4))
    markers = "os^vD<>p"
    for (regime, seed), g in rows.groupby(["regime", "seed"], sort=False, dropna=False):
        c = colours.get(regime, "k")
        bed = int(seed) if np.isfinite(seed) else 0
        m = markers[bed % len(markers)]
        first = bed == int(rows[rows.regime == regime].seed.fillna(0).min())
        a.errorbar(g.travel, g.rel_to_whole, yerr=g.error / g.value.iloc[-1], fmt=m + "-", color=c, ms=3,
                   lw=0.7, capsize=1.5, mfc="none", label=regime if first else None)
        conv = g[g.plateau]
        b.loglog(g.travel, g.rel_error, m + "-", color=c, ms=3, lw=0.7, mfc="none")
        b.loglog(conv.travel, conv.rel_error, m, color=c, ms=3)
    for _, ans in answers.iterrows():
        if np.isfinite(ans.min_distance):
            a.axvline(ans.min_distance, color=colours[ans.regime], ls=":", lw=0.8)
    a.axhline(1.0, color="k", lw=0.8, ls="--")
    a.set_xscale("log")
    a.set_xlabel("travel after the transient, L (d)")
    a.set_ylabel(r"$F_L / F$ (whole pull: 1)")
    a.legend(fontsize=7)
    a.set_title("(a) drag of the first L d; dotted: min_distance", fontsize=8)
    b.axhline(target, color="k", lw=0.8, ls="--")
    x = np.geomspace(rows.travel.min(), rows.travel.max(), 20)
    T, e = answers.travel.max(), answers.rel_error.median()     # through the whole pulls' errors
    b.loglog(x, e * np.sqrt(T / x), color="0.6", lw=0.8, ls="-.")
    b.set_xlabel("travel after the transient, L (d)")
    b.set_ylabel("relative error of the drag")
    b.set_title(f"(b) filled: converged error; dashed: {100 * target:g} %; dash-dot: L^-1/2", fontsize=8)
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    paths = [outdir / "validate_pull_length.png", outdir / "validate_pull_length.pdf"]
    for p in paths:
        fig.savefig(p, dpi=150)
    plt.close(fig)
    return paths


def validate(runs, outdir):
    """Study, draw, write the prefix table and the sentence; returns the paths."""
    rows, answers = study(runs)
    outdir = Path(outdir)
    paths = draw(rows, answers, outdir)
    write_csv(rows, outdir / "validate_pull_length.csv")
    write_csv(answers, outdir / "validate_pull_length_answers.csv")
    md = outdir / "validate_pull_length.md"
    write_text_atomic(md, "### Validation: pull length\n\n"
                          "![the travel from which a pull's drag and error hold](validate_pull_length.png)\n\n"
                          f"{conclusion(answers)}\n")
    return paths + [outdir / "validate_pull_length.csv", md]
