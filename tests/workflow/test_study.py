"""granudrag_study, the workflow's library: the plan of beds and pulls, paths, arguments, cost."""
import copy
import math
import os
import subprocess
from pathlib import Path

import pytest
import yaml

import granudrag_study as study
from analysis.core import physics

ROOT = Path(__file__).resolve().parents[2]

SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"


def load(name):
    with open(ROOT / "config" / name) as fh:
        return yaml.safe_load(fh)


BASE = {
    "threads": 1, "throughput": 1e7,
    "defaults": {"kn": 2e4, "mu": 0.5, "seed": 1},
    "systems": {"I": {"lx": 8, "ly": 8, "grains": 800, "pull": {"distance": 2}}},
    "sweeps": [
        {"name": "drag", "system": "I", "D": [1, 2], "depth": 4, "Fr": [0.5, 1]},
        {"name": "yield", "system": "I", "D": 2, "depth": 4, "mu": [0.5, 0], "V": 0.01,
         "pull": {"distance": 0.1}},
    ],
}


def test_fmt_is_short_and_exact_enough():
    assert [study.fmt(x) for x in (2, 0.5, 1.0, 10, 2e4, 2e8, 2.45e8, 0.01, 1e-4)] == \
        ["2", "0.5", "1", "10", "2e4", "2e8", "2.45e8", "0.01", "1e-4"]
    g = physics.gamman_for(2e4)
    assert abs(float(study.fmt(g)) / g - 1) < 1e-7


def test_beds_are_shared_and_pulls_are_bed_times_speed():
    plan = study.plan(copy.deepcopy(BASE))
    # D = 1, 2 at mu = 0.5 and D = 2 at mu = 0: the yield sweep reuses the D = 2, mu = 0.5 bed.
    assert len(plan.beds) == 3
    assert len(plan.pulls) == 2 * 2 + 2
    gn = study.fmt(physics.gamman_for(2e4))
    key = f"system~I/D~2/h~4/mu~0.5/kn~2e4/gn~{gn}/seed~1"
    assert key in plan.beds
    assert {p.speed for p in plan.pulls.values() if p.bed.key == key} == {"Fr~0.5", "Fr~1", "V~0.01"}
    assert study.Bed.parse(key) == plan.beds[key]


def test_seeds_give_replicate_beds_each_pulled_at_every_speed():
    config = copy.deepcopy(BASE)
    config["sweeps"][0]["seeds"] = [1, 2, 3]
    study.validate_config(config, SCHEMA)
    plan = study.plan(config)
    gn = study.fmt(physics.gamman_for(2e4))
    for D in ("1", "2"):
        beds = [f"system~I/D~{D}/h~4/mu~0.5/kn~2e4/gn~{gn}/seed~{s}" for s in (1, 2, 3)]
        assert all(b in plan.beds for b in beds)
        for b in beds:
            assert {p.speed for p in plan.pulls.values() if p.bed.key == b} >= {"Fr~0.5", "Fr~1"}
    # seed 1's D = 2 bed is still shared with the yield sweep: 2 D x 3 seeds + mu = 0.
    assert len(plan.beds) == 2 * 3 + 1
    config["sweeps"][0]["seed"] = 4
    with pytest.raises(study.ConfigError, match="'seed' or 'seeds', not both"):
        study.plan(config)


def test_adding_a_grid_value_only_adds_jobs():
    before = study.plan(copy.deepcopy(BASE))
    config = copy.deepcopy(BASE)
    config["sweeps"][0]["Fr"].append(2)
    after = study.plan(config)
    assert set(before.beds) == set(after.beds)
    assert set(after.pulls) - set(before.pulls) == {
        k for k in after.pulls if k.endswith("/Fr~2")}
    assert set(before.pulls) < set(after.pulls)


def test_the_plan_file_is_rewritten_only_when_the_pulls_change(tmp_path):
    """Its time stamp is what remakes the table when a sweep grows (manifest.py): the same
    pulls leave the file untouched, in any order; one more rewrites it, sorted."""
    results = str(tmp_path / "results")
    pulls = study.plan(copy.deepcopy(BASE)).pulls
    path = Path(study.write_plan(results, pulls))
    assert path == Path(study.plan_file(results)) and path.read_text().splitlines() == sorted(pulls)
    os.utime(path, ns=(1, 1))
    study.write_plan(results, list(reversed(list(pulls))))
    assert path.stat().st_mtime_ns == 1
    config = copy.deepcopy(BASE)
    config["sweeps"][0]["Fr"].append(2)
    grown = study.plan(config).pulls
    study.write_plan(results, grown)
    assert path.stat().st_mtime_ns > 1 and path.read_text().splitlines() == sorted(grown)
    assert [p.name for p in path.parent.iterdir()] == ["pulls.txt"]      # no temporary left


def test_arguments_use_the_path_numbers():
    plan = study.plan(copy.deepcopy(BASE))
    bed = next(b for b in plan.beds.values() if b.D == "2" and b.mu == "0")
    args = study.pour_args(bed, plan.config)
    assert args[args.index("--mu") + 1] == "0" and args[args.index("--kn") + 1] == "2e4"
    assert args[args.index("--gamman") + 1] == bed.gn and args[args.index("--depth") + 1] == "4"
    pull = study.pull_args(bed, "V~0.01", plan)
    assert pull[:2] == ["--speed", "0.01"] and pull[pull.index("--distance") + 1] == "0.1"
    fr = study.pull_args(plan.beds[bed.key.replace("mu~0/", "mu~0.5/")], "Fr~1", plan)
    assert fr[:2] == ["--froude", "1"] and fr[fr.index("--distance") + 1] == "2"


def test_conflicting_pull_settings_are_refused():
    config = copy.deepcopy(BASE)
    config["sweeps"].append({"name": "again", "system": "I", "D": 2, "depth": 4, "mu": 0,
                             "V": 0.01, "pull": {"distance": 0.5}})
    with pytest.raises(study.ConfigError, match=r"sweeps\[2\] \(again\).*also in sweep 'yield'"):
        study.plan(config)


def test_a_system_with_beds_from_pulls_through_the_other_systems_beds_with_its_own_settings():
    config = copy.deepcopy(BASE)
    config["systems"]["R"] = {"beds_from": "I", "pull": {"active_radius": 5}}
    config["sweeps"].append({"name": "region", "system": "R", "D": 2, "depth": 4, "Fr": [0.5, 1]})
    study.validate_config(config, SCHEMA)
    plan = study.plan(config)
    assert len(plan.beds) == 3                        # no bed of its own: I's D = 2 bed is shared
    assert all(b.system == "I" for b in plan.beds.values())
    region = [p for p in plan.pulls.values() if p.bed.system == "R"]
    assert {p.speed for p in region} == {"Fr~0.5", "Fr~1"} and len(plan.pulls) == 6 + 2
    poured = study.poured_bed(region[0].bed, config)
    assert poured.key in plan.beds and poured.key == region[0].bed.key.replace("system~R/", "system~I/")
    args = study.pull_args(region[0].bed, region[0].speed, plan)
    # I's pull settings under R's own: the same protocol but for the region.
    assert args[args.index("--distance") + 1] == "2" and args[args.index("--active_radius") + 1] == "5"
    assert config["systems"]["R"]["grains"] == 800    # the bed's scale, for the cost estimate
    assert study.pull_cost(region[0], config) > 0


@pytest.mark.parametrize("system, message", [
    ({"beds_from": "II"}, "no system 'II'"),
    ({"beds_from": "R"}, "from itself"),
    ({"beds_from": "I", "grains": 900}, r"systems\.R\.grains.*remove it"),
])
def test_beds_from_errors_name_the_key(system, message):
    config = copy.deepcopy(BASE)
    config["systems"]["R"] = system
    config["sweeps"].append({"name": "region", "system": "R", "D": 2, "depth": 4, "Fr": 1})
    with pytest.raises(study.ConfigError, match=message):
        study.plan(config)


@pytest.mark.parametrize("change, message", [
    (lambda c: c["sweeps"][0].update(system="III"), "system 'III' is not defined"),
    (lambda c: c["sweeps"][0].update(z=3), "exactly one of 'depth'"),
    (lambda c: c["sweeps"][0].pop("Fr"), "no speeds"),
    (lambda c: c["sweeps"][0].update(gamman=10, gamman_ratio=0.5), "'gamman' or 'gamman_ratio'"),
])
def test_semantic_errors_name_the_sweep(change, message):
    config = copy.deepcopy(BASE)
    change(config)
    with pytest.raises(study.ConfigError, match=message):
        study.plan(config)


def test_a_pull_at_a_yield_speed_its_friction_does_not_take_is_refused_by_sweep():
    config = copy.deepcopy(BASE)
    # the yield sweep pulls mu = 0.5 and 0 at 0.01; steps that give 0.1 from mu = 0.1 on disown mu = 0.5's
    config["report"] = {"yield_speed": [{"mu": 0, "V": 0.01}, {"mu": 0.1, "V": 0.1}]}
    with pytest.raises(study.ConfigError, match=r"sweep 'yield' pulls mu = 0.5 at V = 0.01.*gives V = 0.1"):
        study.plan(config)
    # paired as the steps say: accepted, and so is a pull at a speed no step names
    config["sweeps"][1]["mu"] = 0
    config["sweeps"].append({"name": "yield_friction", "system": "I", "D": 2, "depth": 4, "mu": 0.5,
                             "V": [0.1, 0.03], "pull": {"distance": 0.1}})
    study.plan(config)
    # the same with one speed for every friction, and in a validation study comparing speeds
    config["sweeps"][2]["V"] = 0.01
    with pytest.raises(study.ConfigError, match="sweep 'yield_friction' pulls mu = 0.5 at V = 0.01"):
        study.plan(config)
    config["validation"] = "yield_speed"
    study.plan(config)
    config.pop("validation")
    config["report"] = {"yield_speed": 0.01}
    study.plan(config)


@pytest.mark.parametrize("change, key", [
    (lambda c: c["sweeps"][0].update(D="two"), "sweeps[0].D"),
    (lambda c: c["systems"]["I"].update(grains=-3), "systems.I.grains"),
    (lambda c: c["systems"]["I"]["pull"].update(speed=3), "systems.I.pull"),
    (lambda c: c.update(thread=2), "'(top level)'"),
    (lambda c: c.update(max_runtime=5), "max_runtime"),
])
def test_schema_errors_name_the_key(change, key):
    config = copy.deepcopy(BASE)
    change(config)
    with pytest.raises(study.ConfigError) as exc:
        study.validate_config(config, SCHEMA)
    assert key in str(exc.value)


@pytest.mark.parametrize("name", sorted(str(p.relative_to(ROOT / "config")) for p in (ROOT / "config").rglob("*.yaml")))
def test_shipped_configs_are_valid(name):
    config = load(name)
    study.validate_config(config, SCHEMA)
    plan = study.plan(config)
    assert plan.pulls and plan.beds
    assert all(study.pull_cost(p, config) > 0 for p in plan.pulls.values())


def test_default_config_keeps_the_paper_restitution_curve():
    config = load("config.yaml")
    plan = study.plan(config)
    ratios = {round(physics.gamman_ratio(float(b.kn), float(b.gn)), 6) for b in plan.beds.values()}
    assert round(physics.PAPER_RATIO, 6) in ratios


def test_costs_use_the_engine_time_step_and_froude_speed():
    # The formulas themselves are checked against the binary in tests/python/test_physics.py.
    plan = study.plan(copy.deepcopy(BASE))
    pull = plan.pulls[next(k for k in plan.pulls if k.endswith("/Fr~1"))]
    assert study.bed_dt(pull.bed, plan.config) == physics.default_dt(2e4)
    assert pull.V == physics.froude_speed(1.0, float(pull.bed.D))
    assert study.pull_cost(pull, plan.config) == pytest.approx(800 * 2 / (pull.V * physics.default_dt(2e4)))
    config = copy.deepcopy(BASE)
    config["systems"]["I"]["pour"] = {"dt": 1e-4}
    assert study.bed_dt(pull.bed, config) == 1e-4
    assert math.isclose(physics.PAPER_RATIO, 5e4 / 2e8**0.6)


def test_a_damped_frictional_pour_is_expected_to_stop_at_its_measured_settling_time():
    config = copy.deepcopy(BASE)
    config["defaults"]["kn"] = 2e5                     # DAMPED_STOP's stiffness (softer: below)
    sysc = config["systems"]["I"]
    plan = study.plan(config)
    frictional = next(b for b in plan.beds.values() if b.value("mu") == 0.5)
    frictionless = next(b for b in plan.beds.values() if b.value("mu") == 0)
    # A system without max_settle_time settles as long as granudrag pour does by default (the
    # schema's text is the engine's --help)
    pour_keys = yaml.safe_load(SCHEMA.read_text())["$defs"]["pour"]["properties"]
    limit = study.SETTLE_TIME_DEFAULT
    assert f"(default: {limit:g})" in pour_keys["max_settle_time"]["description"]
    assert study.expected_settle_time(frictional, config) == limit     # the paper's pour: undamped
    sysc["pour"] = {"settle_damping": 1, "ke_threshold": 1e-7, "max_settle_time": 150}
    # 800 grains on 64 d^2, 12.5 per d^2: shallower than system I, its 28 time units at mu >= 0.25.
    assert study.expected_settle_time(frictional, config) == pytest.approx(28.0)
    assert study.expected_settle_time(frictionless, config) == 150      # creeps: to the limit
    sysc["grains"] = int(93.75 * 64)                   # system II's depth: 40
    assert study.expected_settle_time(frictional, config) == pytest.approx(40.0)
    sysc["grains"] = int(68.75 * 64)                   # half way between I and II
    assert study.expected_settle_time(frictional, config) == pytest.approx((28.0 + 40.0) / 2)
    sysc["grains"] = 800
    config["sweeps"][1]["mu"] = [0.1, 0.175, 0.05]     # mu = 0.1: 37; half way to 0.25: 32.5; below: the limit
    times = {b.value("mu"): study.expected_settle_time(b, config) for b in study.plan(config).beds.values()}
    assert times[0.1] == pytest.approx(37.0) and times[0.175] == pytest.approx(32.5) and times[0.05] == 150
    sysc["pour"]["max_settle_time"] = 20               # never beyond the limit
    assert study.expected_settle_time(frictional, config) == 20
    for pour in ({"settle_damping": 1, "ke_threshold": 1e-8}, {"settle_damping": 2, "ke_threshold": 1e-6}):
        sysc["pour"] = pour | {"max_settle_time": 150}   # not measured: to the limit
        assert study.expected_settle_time(frictional, config) == 150
    sysc["pour"] = {"settle_damping": 1, "ke_threshold": 1e-6, "max_settle_time": 140}
    assert study.expected_bed_cost(frictional, config) == pytest.approx(
        study.bed_cost(frictional, config) * 28.0 / 140)
    s = study.summary(study.plan(config))
    assert s["bed_particle_steps"] < s["bed_particle_steps_bound"]
    config["defaults"]["kn"] = 2e4                     # a softer bed settles longer (DAMPED_SOFT_FACTOR)
    soft = next(b for b in study.plan(config).beds.values() if b.value("mu") == 0.5)
    assert study.expected_settle_time(soft, config) == pytest.approx(28.0 * study.cost.DAMPED_SOFT_FACTOR)


def test_estimate_cost_prints_jobs_and_core_hours():
    out = subprocess.run(["/usr/bin/python3", str(ROOT / "workflow/scripts/estimate_cost.py"),
                          str(ROOT / "config/paper.yaml")], capture_output=True, text=True, check=True)
    assert "simulation jobs" in out.stdout and "core-hours" in out.stdout


@pytest.mark.parametrize("text, message", [
    ("systems:\n  I:\n    description: a: b\n", "is not valid YAML (quote a value that holds ': ')"),
    ("- 1\n", "is not a study config"),
    (None, "cannot read the config"),
])
def test_estimate_cost_names_a_config_it_cannot_read(tmp_path, text, message):
    path = tmp_path / "c.yaml"
    if text is not None:
        path.write_text(text)
    out = subprocess.run(["/usr/bin/python3", str(ROOT / "workflow/scripts/estimate_cost.py"), str(path)],
                         capture_output=True, text=True)
    assert out.returncode == 1 and message in out.stderr and "Traceback" not in out.stderr


def test_wall_time_on_fewer_cores_than_a_job_has_threads_is_the_core_hours_over_the_cores():
    # faithful.yaml prices 16-thread jobs at a 16-thread node's throughput; on 2 cores that
    # throughput is not available: the wall time is its core-hours / 2, not particle-steps / rate.
    out = subprocess.run(["/usr/bin/python3", str(ROOT / "workflow/scripts/estimate_cost.py"),
                          str(ROOT / "config/faithful.yaml"), "--cores", "2"],
                         capture_output=True, text=True, check=True).stdout
    core_hours = _cost_line(out)
    wall = next(ln for ln in out.splitlines() if "wall time on 2 cores" in ln)
    assert "each 16-thread job on 2 cores" in wall
    assert float(wall.split("about")[1].split()[0]) == pytest.approx(core_hours / 2, rel=0.01)
    # With the threads' cores, jobs run side by side at the stated throughput.
    out = subprocess.run(["/usr/bin/python3", str(ROOT / "workflow/scripts/estimate_cost.py"),
                          str(ROOT / "config/faithful.yaml"), "--cores", "32"],
                         capture_output=True, text=True, check=True).stdout
    wall = next(ln for ln in out.splitlines() if "wall time on 32 cores" in ln)
    assert "2 job(s) at a time" in wall
    assert float(wall.split("about")[1].split()[0]) == pytest.approx(_cost_line(out) / 32, rel=0.01)


def _cost_line(stdout):
    return float(next(ln for ln in stdout.splitlines() if "cost:" in ln).split("cost:")[1].split()[0])


@pytest.mark.skipif(not (ROOT / "build" / "granudrag").exists(), reason="needs build/granudrag")
def test_estimate_cost_measures_throughput_and_scales_the_cost():
    # --measure times a small bench here; the core-hours must be the particle-steps over the
    # measured rate, i.e. scale inversely with the throughput the line reports.
    script, cfg = str(ROOT / "workflow/scripts/estimate_cost.py"), str(ROOT / "config/smoke.yaml")
    measured = subprocess.run(["/usr/bin/python3", script, cfg, "--measure", "--grains", "2000",
                               "--binary", str(ROOT / "build" / "granudrag")],
                              capture_output=True, text=True, check=True).stdout
    assert "measured here:" in measured and "2000 grains" in measured, measured
    tp = float(measured.split("throughput")[1].split()[0])
    fixed = subprocess.run(["/usr/bin/python3", script, cfg, "--throughput", str(2 * tp)],
                           capture_output=True, text=True, check=True).stdout
    assert _cost_line(measured) == pytest.approx(2 * _cost_line(fixed), rel=0.02)
    bad = subprocess.run(["/usr/bin/python3", script, cfg, "--measure", "--binary", "/nonexistent/granudrag"],
                         capture_output=True, text=True)
    assert bad.returncode != 0 and "no granudrag at /nonexistent/granudrag" in bad.stderr


def _long_pull_config(**top):
    # One pull of 800 grains x 2 d at V = 0.01 with dt 4.2e-4: 3.8e8 particle-steps, ~10.6 h
    # at 1e4 particle-steps/s.
    config = copy.deepcopy(BASE)
    config.update(throughput=1e4, sweeps=[BASE["sweeps"][1] | {"mu": 0.5, "pull": {"distance": 2}}], **top)
    plan = study.plan(config)
    (pull,) = plan.pulls.values()
    return config, plan, pull


def test_long_pulls_checkpoint_every_checkpoint_minutes_of_wall_time():
    config, plan, pull = _long_pull_config(checkpoint_minutes=30)
    minutes = study.job_seconds(study.pull_cost(pull, config), config) / 60
    interval = study.checkpoint_interval(pull, config)
    pieces = (2 / 0.01) / interval
    assert 30 * (1 - 1 / pieces) < minutes / pieces <= 30 * 1.001   # one per <= 30 min, not far less
    assert pieces > 10
    assert f"--checkpoint_interval {interval:g}" in " ".join(study.pull_args(pull.bed, pull.speed, plan))
    # The default study's pulls are short: granudrag's tenth of the pull, no extra argument.
    default = study.plan(load("config.yaml"))
    assert not any("--checkpoint_interval" in study.pull_args(p.bed, p.speed, default)
                   for p in default.pulls.values())


def test_max_runtime_caps_each_job_and_splits_long_pulls():
    config, plan, pull = _long_pull_config()
    cost = study.pull_cost(pull, config)
    assert study.pull_retries(plan) is None                       # the profile's restart-times
    uncapped = [study.job_resources(cost, 800, config, a)[1] for a in (1, 2)]
    assert uncapped[1] == 2 * uncapped[0] and uncapped[0] > 3 * 600
    config, plan, pull = _long_pull_config(max_runtime=120)
    assert [study.job_resources(cost, 800, config, a)[1] for a in (1, 2)] == [120, 120]
    hours = study.job_seconds(cost, config) / 3600
    retries = study.pull_retries(plan)
    # Enough 2-hour jobs (each counted as 1.5 h: a quarter lost to restarts) for 1.5x the
    # estimated work, and not many more.
    assert hours <= retries + 1 <= hours + 2
    # Several checkpoints inside each job: at most max_runtime / 4 of wall time apart.
    minutes = study.job_seconds(cost, config) / 60
    assert minutes / ((2 / 0.01) / study.checkpoint_interval(pull, config)) <= 30 * 1.02
