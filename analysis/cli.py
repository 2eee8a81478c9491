"""`python -m analysis`: refit a pull table, write its report, predict a drag.

    python -m analysis fit TABLE.csv --output fits.json [--n-boot 200] [--seed 0]
                                     [--h-min 45] [--alpha-speeds 0.5,1,2,4,6]
    python -m analysis report TABLE.csv --fits fits.json --output-dir DIR [--trace trace.csv ...]
    python -m analysis predict --fits fits.json --D 4 --h 50 --mu 0.5 --V 2
    python -m analysis validate {yield_speed,box_size,stiffness,pull_length} RUNS.csv --output-dir DIR
    python -m analysis pool active_region results/validate/*/validate_active_region.csv --output-dir DIR
    python -m analysis ladder collect --config config/ladder/X.yaml --results results/ladder/X
                                      --wall-seconds 1234 --cores 2 [--started ISO] [--out DIR]
    python -m analysis ladder table results/reproduction [--n-boot 100] [--seed 0]
    python -m analysis regime-tests TABLE.csv --out DIR
    python -m analysis deep-law TABLE.csv --out DIR [--h-min 45] [--phi fits.json]

`fit` does what the workflow's `fits` rule does, on any table with the columns of
results/table.csv (analysis.core.table.COLUMNS); the file it writes is described in
analysis/README.md. `report` draws every figure and writes report.md and report.html as the
workflow's figure and report rules do (figures whose data are not given are listed as not
drawn). `predict` is `python -m analysis.predict`. `validate` compares a validation study's
runs with the reference protocol (analysis.validation.validation), or finds how long pulls must be
(analysis.validation.pull_length), and writes a figure, the comparison table and a sentence; `pool` pools
one study's comparison tables over several studies (analysis.validation.validation_pool). `ladder`
keeps the reproduction ladder (analysis.ladder.ladder): `collect` copies a finished study's small
files into a rung directory (default results/reproduction/<config stem>), `table` writes the
claims-by-rungs table, its figures and README section. `regime-tests` tests claim (a) with
calibrated power (analysis.regime_tests); `deep-law` reads claims (d)-(f) on deep intruders and on
every depth apart, the sum rule with phi_mu from another study's fit file (analysis.deep_law).
Errors go to standard error with exit
status 2; outputs are written under a temporary name and renamed when complete.
"""
import argparse
import sys
from pathlib import Path

from .core.result import LADDER_N_BOOT, N_BOOT
from .fits.alpha_drag import ALPHA_SPEEDS
from .fits.fit_file import FitFileError


def _speeds(text):
    try:
        v = tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"--alpha-speeds: {text!r} is not a comma-separated "
                                         "list of speeds, e.g. 0.5,1,2,4,6") from None
    if not v or min(v) <= 0:
        raise argparse.ArgumentTypeError("--alpha-speeds: give one or more positive speeds")
    return v


def _non_negative(kind, name):
    def parse(text):
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}: {text!r} is not a number") from None
        if v < 0:
            raise argparse.ArgumentTypeError(f"{name}: must be >= 0, got {text}")
        return v
    return parse


def _fit(args):
    from .core.table import load_csv, mark_yield
    from .fits.fitset import Options, run_fits, save_results

    df = load_csv(args.table)
    if args.yield_speed is not None:
        df = mark_yield(df, args.yield_speed)
    if Path(args.output).resolve() == Path(args.table).resolve():
        raise ValueError(f"--output {args.output} is the input table; name another file")
    opt = Options(n_boot=args.n_boot, seed=args.seed, h_min=args.h_min, alpha_speeds=args.alpha_speeds)
    r = run_fits(df, options=opt)
    save_results(args.output, r)
    print(f"{args.output}: {len(r.regimes)} regime fits, {len(r.laws)} scaling laws, "
          f"{len(r.alpha)} alpha (F_Y), {len(r.alpha_drag)} alpha (drag), {len(r.phi)} phi; "
          f"{len(r.notes)} fits not made")
    for note in r.notes:
        print(f"note: {note}", file=sys.stderr)
    return 0


def _report(args):
    from .figures.figure_list import NAMES, draw, read_inputs
    from .fits.fitset import load_results
    from .report.report import write_report

    results = load_results(args.fits)
    inputs = read_inputs(table=args.table, restitution=args.restitution, theory=args.theory,
                         trace=args.trace, coordination=args.coordination, flow=args.flow)
    out = Path(args.output_dir)
    out.mkdir(parents=True, exist_ok=True)
    for name in NAMES:
        draw(name, inputs, results, out)
    md = write_report(inputs.table, results, out, results.options.n_boot, results.options.seed)
    print(f"{md} and {md.with_suffix('.html')}")
    return 0


def _validate(args):
    from .core.table import load_csv
    from .validation.validation import validate

    paths = validate(load_csv(args.table), args.study, args.output_dir)
    print(paths[-1].read_text().split("\n\n")[-1].strip())
    return 0


def _pool(args):
    from .validation.validation_pool import write

    paths = write(args.tables, args.study, args.output_dir, args.wake_relative)
    print(paths[-1].read_text().split("\n\n")[-1].strip())
    return 0


def _ladder(args):
    from .ladder import ladder

    if args.ladder_command == "collect":
        out = args.out or Path("results/reproduction") / Path(args.config).stem
        info = ladder.collect(args.config, args.results, out, wall_seconds=args.wall_seconds,
                              cores=args.cores, started=args.started, phi=args.phi,
                              machine_cpu=args.machine_cpu)
        hours = info["core_hours"]
        print(f"{out}: rung {info['rung']}, {info['jobs']} jobs, "
              + (f"{hours:.3g} core-hours ({info['core_hours_from']})" if hours is not None
                 else f"core-hours unknown ({info['core_hours_from']})") + f", commit {info['commit']}")
        for note in info["notes"]:
            print(f"note: {note}", file=sys.stderr)
        return 0
    paths = ladder.write_ladder(args.root, n_boot=args.n_boot, seed=args.seed)
    print("\n".join(map(str, paths)))
    return 0


def _regime_tests(args):
    from .core.table import load_csv
    from .regime_tests.regime_figure import draw
    from .regime_tests.regime_tests import write_tests

    df = load_csv(args.table)
    tests, path = write_tests(df, args.out, n_sim=args.n_sim, seed=args.seed, averaging=args.averaging)
    draw(df, args.out, averaging=args.averaging)
    for r in tests[tests.verdict.notna()].itertuples():
        print(f"D={r.D:g} mu={r.mu:g} {r.averaging} Fr {r.fr_low:g}-{r.fr_high:g} {r.test}: {r.verdict}")
    print(path)
    return 0


def _deep_law(args):
    from .core.table import load_csv
    from .deep_law.deep_law import phi_from_fits, write_deep_law
    from .deep_law.deep_law_figure import draw

    df = load_csv(args.table)
    phi = phi_from_fits(args.phi) if args.phi else None
    if args.phi and phi is None:
        raise ValueError(f"{args.phi}: its fit file has no phi table (phi_mu needs system I yield pulls at "
                         f"several D); give --phi the fits.json of a study that has them")
    table, path = write_deep_law(df, args.out, h_min=args.h_min, speeds=args.alpha_speeds, phi=phi)
    draw(df, args.out, h_min=args.h_min, speeds=args.alpha_speeds)
    for r in table.itertuples():
        what = (f"{r.value:.3f} ± {r.err:.3f}" if r.value == r.value
                else f"chi2 {r.chi2:.1f} for {r.n} points, p {r.p:.2g}")
        print(f"D={r.D:g} mu={r.mu:g} {r.quantity} [{r.depths}]: {what} {r.verdict}".rstrip())
    print(path)
    return 0


def _predict(argv):
    from .predict import main as predict_main

    return predict_main(argv)


def parser():
    ap = argparse.ArgumentParser(prog="python -m analysis", description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="command", required=True,
                            metavar="{fit,report,predict,validate,pool,ladder,regime-tests,deep-law}")
    f = sub.add_parser("fit", help="every fit of the report -> fits.json")
    f.add_argument("table", help="pull table (CSV with the columns of results/table.csv)")
    f.add_argument("--output", required=True, help="fit file to write (JSON, analysis/README.md)")
    f.add_argument("--n-boot", type=_non_negative(int, "--n-boot"), default=N_BOOT,
                   help=f"bootstrap refits of the regime fits (default {N_BOOT})")
    f.add_argument("--seed", type=_non_negative(int, "--seed"), default=0, help="bootstrap seed")
    f.add_argument("--h-min", type=_non_negative(float, "--h-min"), default=0.0,
                   help="Eq. 12 and Fig. 19 use pulls at depth h >= this only [d] (paper: 45; 0 = all)")
    f.add_argument("--yield-speed", type=_non_negative(float, "--yield-speed"),
                   help="speed of the yield pulls (default: the table's yield_pull column, else 0.01)")
    f.add_argument("--alpha-speeds", type=_speeds, default=ALPHA_SPEEDS,
                   help="speeds the paper's alpha_mu is averaged over (default 0.5,1,2,4,6)")
    r = sub.add_parser("report", help="every figure, report.md and report.html")
    r.add_argument("table", help="pull table (CSV)")
    r.add_argument("--fits", required=True, help="fit file written by `fit`")
    r.add_argument("--output-dir", required=True, help="directory of the figures and the report")
    for name, what in (("restitution", "granudrag restitution CSV (Fig. 2)"),
                       ("theory", "restitution theory CSV (Fig. 2)"), ("trace", "force trace CSV (Fig. 4)"),
                       ("coordination", "P(Z) CSV (Fig. 7)"), ("flow", "velocity-field CSV (Fig. 9)")):
        r.add_argument(f"--{name}", help=what)
    v = sub.add_parser("validate", help="a validation study: does a cheaper protocol agree?")
    from .validation.validation import NAMES, STUDIES

    v.add_argument("study", choices=NAMES, help="what is varied")
    v.add_argument("table", help="run table (results/.../runs.csv; or the point table)")
    v.add_argument("--output-dir", required=True, help="directory of validate_<study>.png/.csv/.md")

    pl = sub.add_parser("pool", help="one validation's comparisons pooled over its studies: a shift too small for one")
    pl.add_argument("study", choices=list(STUDIES), help="the validation the tables compare")
    pl.add_argument("tables", nargs="+", help="comparison tables (validate_<study>.csv), one per study")
    pl.add_argument("--output-dir", required=True, help="directory of pool_<study>.csv/.md")
    pl.add_argument("--wake-relative", action="store_true",
                    help="group the active region's wake test by its ratio to granudrag's default at "
                         "each row's K_n (1: the default), so rows at the default pool across stiffnesses")
    sub.add_parser("predict", help="drag from a fit file (python -m analysis predict --help)",
                   add_help=False)
    _ladder_parser(sub)
    rt = sub.add_parser("regime-tests", help="claim (a) tested with calibrated power: regime_tests.csv, figures")
    rt.add_argument("table", help="pull table (CSV)")
    rt.add_argument("--out", required=True, help="directory of regime_tests.csv and the figures")
    rt.add_argument("--n-sim", type=_non_negative(int, "--n-sim"), default=2000, help="synthetic copies per test")
    rt.add_argument("--seed", type=_non_negative(int, "--seed"), default=0, help="seed of the copies")
    rt.add_argument("--averaging", choices=("both", "steady", "cumulative"), default="both",
                    help="the drag tested: steady (column drag), the paper's cumulative average from t = 0 "
                         "over one box length (drag_cumulative_box), or both (default: each the table has)")
    dl = sub.add_parser("deep-law", help="claims (d)-(f) on deep intruders and on every depth: deep_law.csv, figures")
    dl.add_argument("table", help="pull table (CSV) with system II pulls at several depths")
    dl.add_argument("--out", required=True, help="directory of deep_law.csv, deep_law.md and the figures")
    dl.add_argument("--h-min", type=_non_negative(float, "--h-min"), default=45.0,
                    help="the deep intruders: h >= this [d] (paper: 45)")
    dl.add_argument("--phi", help="fits.json of a study with phi_mu at the same contact law (system I yield "
                                  "pulls at several D), for the sum rule alpha_mu + phi_mu")
    dl.add_argument("--alpha-speeds", type=_speeds, default=ALPHA_SPEEDS,
                    help="speeds alpha_mu is averaged over (default 0.5,1,2,4,6)")
    return ap


def _ladder_parser(sub):
    lad = sub.add_parser("ladder", help="the reproduction ladder: collect a rung, write its table")
    lsub = lad.add_subparsers(dest="ladder_command", required=True, metavar="{collect,table}")
    c = lsub.add_parser("collect", help="a finished study's small files -> a rung directory")
    c.add_argument("--config", required=True, help="the study's config (config/ladder/<rung>.yaml)")
    c.add_argument("--results", required=True, help="the study's results directory (results/ladder/<rung>)")
    c.add_argument("--wall-seconds", required=True, type=_non_negative(float, "--wall-seconds"),
                   help="wall time of the study [s]")
    c.add_argument("--cores", required=True, type=_non_negative(int, "--cores"),
                   help="cores the study ran on")
    c.add_argument("--started", help="when the study started (ISO 8601)")
    c.add_argument("--out", help="rung directory (default results/reproduction/<config stem>)")
    c.add_argument("--phi", help="another rung's fits.json whose phi_mu the depth law's sum rule takes "
                                 "(a rung of system II depths at one D has none of its own)")
    c.add_argument("--machine-cpu", help="the CPU the study's jobs ran on, when not this host's (a rung run "
                                         "in pieces elsewhere); default: this host's")
    t = lsub.add_parser("table", help="ladder.csv, ladder.md, figures and README section of a ladder root")
    t.add_argument("root", help="the ladder's root with ladder.yaml (results/reproduction)")
    t.add_argument("--n-boot", type=_non_negative(int, "--n-boot"), default=LADDER_N_BOOT,
                   help=f"bootstrap refits of the Fr_2-range fits (default {LADDER_N_BOOT})")
    t.add_argument("--seed", type=_non_negative(int, "--seed"), default=0, help="bootstrap seed")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] == "predict":
        return _predict(argv[1:])
    args = parser().parse_args(argv)
    from .core.table import TableError

    try:
        commands = {"fit": _fit, "report": _report, "validate": _validate, "pool": _pool, "ladder": _ladder,
                    "regime-tests": _regime_tests, "deep-law": _deep_law}
        return commands[args.command](args)
    except (TableError, FitFileError, ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
