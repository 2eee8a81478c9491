"""The cost of a study split by what it is for: by sweep, and by figure of the paper.

A sweep names the figures its runs feed (`figures: ["5", "15a", "Table I"]` in the config).
A figure's cost is that of every bed and pull behind it, each counted once however many of
its sweeps ask for it; a run that feeds several figures counts in each, so the figures' costs
add up to more than the study's.
"""

from .cost import bed_work, column_work, pull_work
from .plan import plan


def core_hours(particle_steps, config):
    """Core-hours of `particle_steps` at the config's throughput on its threads."""
    return particle_steps / float(config["throughput"]) * int(config["threads"]) / 3600.0


def _runs(config, sweeps):
    """(beds, pulls, work) of the config restricted to `sweeps`: the beds' work (cost.bed_work, placed
    beds' columns in them) and the pulls' (cost.pull_work)."""
    sub = plan(dict(config, sweeps=sweeps))
    steps = sum(bed_work(b, config) for b in sub.beds.values())
    steps += sum(column_work(b, config) for b in sub.columns.values())
    steps += sum(pull_work(p, config) for p in sub.pulls.values())
    return len(sub.beds), len(sub.pulls), steps


def by_figure(config):
    """[(figures, beds, pulls, core-hours, sweep names)] in the order the figures are first
    named; figures resting on the same sweeps share a row (figures: their names, in order);
    sweeps that name no figure are listed last, with figures = []."""
    figures = {}
    for sweep in config["sweeps"]:
        for fig in [str(f) for f in sweep.get("figures", [])] or [None]:
            figures.setdefault(fig, []).append(sweep["name"])
    groups = {}
    for fig in [f for f in figures if f is not None] + ([None] if None in figures else []):
        groups.setdefault(tuple(figures[fig]), []).append(fig)
    rows = []
    for names, figs in groups.items():
        beds, pulls, steps = _runs(config, [s for s in config["sweeps"] if s["name"] in names])
        rows.append(([f for f in figs if f is not None], beds, pulls, core_hours(steps, config), list(names)))
    return rows


def by_sweep(config):
    """[(sweep, beds, pulls, core-hours)] of each sweep alone (its shared runs counted in each)."""
    rows = []
    for sweep in config["sweeps"]:
        beds, pulls, steps = _runs(config, [sweep])
        rows.append((sweep["name"], beds, pulls, core_hours(steps, config)))
    return rows
