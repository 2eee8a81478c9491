"""Refitting the recorded rungs with the current analysis, from the files each rung keeps:
runs.csv (one row per pull, as the study's table rule wrote it) -> table.csv (replicate beds
combined, analysis.core.table.combine_beds) -> fits.json (analysis.fits.fitset.run_fits, with the options
the rung's own fits.json recorded) -> report.md (every figure the table and fits allow, drawn
in a scratch directory; only report.md is kept). Nothing is simulated again: run.json,
kappa_shells.csv and startup.csv come from the run files and stay as collected.

    python -m analysis.ladder_refit results/reproduction [--rung NAME ...] [--report-only]
    python -m analysis ladder table results/reproduction      # then the ladder from the rungs

A rung without run.json (not run) or without runs.csv (collected before runs.csv was kept) is
left alone and named on standard error. --report-only rewrites report.md from the rung's
table.csv and fits.json (after a change of the report's rules, which need no refit). --rejudge
decides each fit's `rejected` again by the current rule (analysis.fits.goodness.is_rejected) from the
goodness fits.json records beside it, changing nothing else in fits.json, then rewrites
report.md: after a change of that rule alone, which moves no fitted number.
"""
import argparse
import json
import math
import sys
import tempfile
from pathlib import Path

from .core.table import write_text_atomic
from .ladder.ladder_claims import LadderError

__all__ = ["refit_table", "refit_fits", "rejudge_fits", "rewrite_report", "refit_rung", "main"]


def _bed_scatter_prior(rung_dir, root=Path(".")):
    """The table.bed_scatter prior of the config the rung was run with (its config.yaml); when
    that has none, the one its config declares now (run.json's `config`, relative to `root`, the
    repository): a prior is the table stage's, which a refit does again with today's analysis,
    not the simulations'. None if neither has one."""
    import yaml

    def prior_of(path):
        config = yaml.safe_load(path.read_text()) if path.is_file() else None
        return ((config or {}).get("table") or {}).get("bed_scatter")

    d = Path(rung_dir)
    prior = prior_of(d / "config.yaml")
    if prior is None and (d / "run.json").is_file():
        name = json.loads((d / "run.json").read_text()).get("config")
        if name and (Path(root) / name).is_file():
            prior = prior_of(Path(root) / name)
            if prior is not None:
                print(f"ladder refit: {d.name}: the bed-scatter prior of {name} (its run's config had none)",
                      file=sys.stderr)
    return prior


def refit_table(rung_dir):
    """table.csv of a rung again from its runs.csv (what workflow/scripts/make_table.py does after
    reading the run files, with the bed-scatter prior of the rung's config.yaml; runs.csv already
    has the yield pulls marked). Returns the point table."""
    from .core.table import combine_beds, load_csv, save_csv

    d = Path(rung_dir)
    runs = load_csv(d / "runs.csv")
    points = combine_beds(runs, prior=_bed_scatter_prior(d))
    save_csv(points, d / "table.csv")
    return points


def _options(rung_dir):
    """The fits' options the rung's fits.json was written with (n_boot, seed, h_min, alpha_speeds)."""
    from .fits.fitset import Options

    path = Path(rung_dir) / "fits.json"
    try:
        doc = json.loads(path.read_text()) if path.is_file() else {}
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise LadderError(f"{path}: not a readable fits.json ({exc})") from None
    return Options.from_dict(doc.get("options"))


def refit_fits(rung_dir):
    """fits.json of a rung again from its table.csv, with the options it recorded. Returns Results."""
    from .core.table import load_csv
    from .fits.fitset import run_fits, save_results

    d = Path(rung_dir)
    r = run_fits(load_csv(d / "table.csv"), options=_options(d))
    save_results(d / "fits.json", r)
    return r


def rejudge_fits(rung_dir):
    """fits.json of a rung with each fit's goodness `rejected` decided again by the current rule
    (goodness.is_rejected on the record's χ², dof and runs test; a fitted table's row from its
    chi2_dof, n and trend_p, as verdicts.table_goodness reads it), the exponents' summary lists
    and the top-level `rejected` list with them. Nothing else moves: the fits are not redone.
    Returns the names of the fits whose verdict changed."""
    from .fits.goodness import describe, is_rejected
    from .report.verdicts import table_goodness

    path = Path(rung_dir) / "fits.json"
    try:
        doc = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError, OSError) as exc:
        raise LadderError(f"{path}: not a readable fits.json ({exc})") from None
    changed, rejected = [], []
    named = [(name, fit) for name, fit in doc.get("fits", {}).items()]
    named += [(f"law_mu{law['mu']:g}", law["regimes"]) for law in doc.get("laws") or [] if law.get("regimes")]
    for name, fit in named:
        g = (fit.get("meta") or {}).get("goodness")
        if not g:
            continue
        new = is_rejected(g)
        if new != bool(g.get("rejected")):
            changed.append(name)
        g["rejected"] = new
        if new:
            rejected.append({"fit": name, "what": describe(g)})
    for key, rows in (doc.get("tables") or {}).items():
        for i, row in enumerate(rows):
            if "rejected" not in row:
                continue
            g = table_goodness({k: math.nan if v is None else v for k, v in row.items()})
            new = float(is_rejected(g))
            if new != row["rejected"]:
                changed.append(f"{key}[{i}]")
            row["rejected"] = new
    for key, table in (("phi", "phi"), ("alpha", "alpha")):
        rows = (doc.get("tables") or {}).get(table, [])
        for entry in doc.get(key) or []:
            hit = [r for r in rows if all(r.get(k) == entry.get(k) for k in ("mu", "kn", "gamman"))]
            if hit and "rejected" in entry:
                entry["rejected"] = bool(hit[0]["rejected"])
    if "rejected" in doc:
        doc["rejected"] = rejected
    write_text_atomic(path, json.dumps(doc, indent=1, allow_nan=False))     # as fit_file.save_fits writes it
    return changed


def rewrite_report(rung_dir):
    """report.md of a rung again from its table.csv and fits.json: the figures those allow are
    drawn in a scratch directory (the rung keeps none; Figs. 1, 2, 4, 7 and 9 need files a rung
    does not keep and are listed as not drawn), the report written there and report.md copied."""
    from .core.table import load_csv
    from .figures.figure_list import NAMES, Inputs, draw
    from .fits.fitset import load_results
    from .report.report import write_report

    d = Path(rung_dir)
    df, r = load_csv(d / "table.csv"), load_results(d / "fits.json")
    with tempfile.TemporaryDirectory(prefix="ladder_refit_") as tmp:
        inputs = Inputs(table=df)
        for name in NAMES:
            draw(name, inputs, r, tmp)
        md = write_report(df, r, tmp, r.options.n_boot, r.options.seed)
        write_text_atomic(d / "report.md", md.read_text())
    return d / "report.md"


def refit_rung(rung_dir, report_only=False, rejudge=False):
    """table.csv, fits.json and report.md of one rung (report.md only with report_only; fits.json's
    `rejected` decided again and report.md with rejudge)."""
    if rejudge:
        changed = rejudge_fits(rung_dir)
        print(f"{rung_dir}: rejected decided again, changed: {', '.join(changed) or 'none'}", file=sys.stderr)
    elif not report_only:
        refit_table(rung_dir)
        refit_fits(rung_dir)
    return rewrite_report(rung_dir)


def main(argv=None):
    from .ladder.ladder import read_ladder, rung_run

    ap = argparse.ArgumentParser(prog="python -m analysis.ladder_refit", description=__doc__.split("\n")[0])
    ap.add_argument("root", help="the ladder's root with ladder.yaml (results/reproduction)")
    ap.add_argument("--rung", action="append", help="only this rung (repeatable; default: every rung run)")
    ap.add_argument("--report-only", action="store_true", help="rewrite report.md only, from table.csv and fits.json")
    ap.add_argument("--rejudge", action="store_true",
                    help="decide each fit's `rejected` again by the current rule (no refit), then report.md")
    args = ap.parse_args(argv)
    root = Path(args.root)
    try:
        rungs = [r["name"] for r in read_ladder(root)[0]]
        unknown = sorted(set(args.rung or ()) - set(rungs))
        if unknown:
            raise LadderError(f"{root / 'ladder.yaml'} lists no rung {', '.join(unknown)}")
        for name in args.rung or rungs:
            d = root / name
            if rung_run(root, name) is None:
                print(f"{d}: not run (no run.json); left alone", file=sys.stderr)
            elif not (args.report_only or args.rejudge) and not (d / "runs.csv").is_file():
                print(f"{d}: no runs.csv to refit from; left alone", file=sys.stderr)
            else:
                print(refit_rung(d, args.report_only, args.rejudge), flush=True)
    except (LadderError, ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
