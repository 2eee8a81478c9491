"""Loading granudrag run files (HDF5, written by `granudrag pull`) into the tidy table.

A run file holds one pull: attributes on /run (D, depth, speed, froude, mu,
kn, gamman, dt, steps), the observables under /observables (drag with its
standard error, that error's Student-t degrees of freedom `error_dof` and its
convergence flag `plateau`, intruder coordination n, contact angle theta (per contact
formation; theta_present over the contacts present, NaN in files before it), bulk
coordination Z, kappa, the force series) and the resolved parameters of the
pull and of its bed, one typed attribute per key under /parameters/pull and
/parameters/pour (`read_parameters`). `read_run` turns one file into a row of
`analysis.core.table.COLUMNS`; `load_runs` reads many and says by name which files
it could not use. The row's drag error, dof and plateau are recomputed from the
force series, and the cumulative average from t = 0 read beside the steady drag, over the pull
and at the paper's length of one box (analysis.runs.run_series); the engine's are drag_err_engine and plateau_engine.

Format versions: 2 stores the parameters by key. Version 1 (granudrag 0.1)
stored them as one YAML text, /parameters attribute `yaml`; its run files are
still read, the box and grain count through `_legacy_scale_v1`, the only code
that looks at that text. `read_parameters` refuses version 1 by name.

The table's `h` is the depth measured after settling (free surface at half
the bulk packing fraction, see `granudrag pour`), the depth the intruder
really had. Where a run's path names its parameters (the workflow writes
`.../system~I/D~2/h~10/mu~0.5/.../Fr~1/run.h5`; the components and the table
column each fills are declared in analysis.core.path_scheme), the `system~` component
gives the table's `system` and an `h~` component the requested depth,
kept as `h_requested` (NaN for beds placed by height, `z~`), and a `z~`
component the requested height as `z_requested` (NaN for beds placed by
depth): the point a run belongs to is told by what was asked, not by the
depth each bed settled to; `seed~` gives `seed`, which tells replicate beds of
one point apart (analysis.core.table.combine_beds). The others name a stored
quantity (D, mu, kn, gn as gamman, Fr, V) and are checked against the file,
so a run copied to the wrong place is refused rather than filed under the
wrong parameters.

Sanity: a run file records its verdict, /sanity attribute `verdict`: "clean",
or the first failure of a pull run with `--keep_going` (grains lost, an
overlap over `max_overlap`, energy gained beyond the work done). A run whose
verdict is not clean is refused (RunFileError naming the file and the
verdict), so the table leaves it out and lists it with the other unusable
files (results/table_problems.txt). Run files written before the verdict
existed have none: they are read as before, with column `sanity` = "unknown"
(granudrag then stopped only on NaN or exploding kinetic energy, so their
overlaps were not bounded); new files have `sanity` = "clean".
"""
import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..core import path_scheme, physics
from ..core.table import COLUMNS, froude, validate_table
from . import bed_origin
from .run_series import SeriesError, box_cumulative, drags, first_travel, kappa_error, read_series

RUN_FORMAT = "granudrag-run"
RUN_VERSIONS = (1, 2, 3)   # 1: parameters as YAML text (legacy path), 2: parameters by key,
                           # 3: version 2 with a checksum on every dataset (h5py checks it)

# Extra columns after the schema's: what a reader of the table may want to
# check (requested depth, time step, how much of the pull was discarded) and
# the scale of the run (box, grains poured, distance pulled; NaN when the file
# does not record them).
EXTRA_COLUMNS = ["h_requested", "z_requested", "dt", "collision_steps", "steps", "transient_distance", "theta_err",
                 "theta_present", "theta_present_err", "kappa_err",
                 "drag_dof", "plateau", "drag_err_engine", "plateau_engine", "drag_cumulative",
                 "drag_cumulative_err", "drag_cumulative_box", "drag_cumulative_box_err", "seed", "lx", "ly",
                 "grains", "distance", "stop_reason",
                 "active_radius", "wake_force", "wake_load", "sleep_speed", "sleep_time", "perturbation", "asleep",
                 "settle_damping", "placed", "sanity", "path"]
SCALE_KEYS = ("lx", "ly", "grains")

# The table's columns that a run file's /run group holds: column -> attribute. A path component
# (analysis.core.path_scheme) whose column is one of these is checked against the file; the others
# (system, requested depth or height, seed) are the table's from the path alone.
_FROM_RUN = {"D": "D", "h": "depth", "mu": "mu", "kn": "kn", "gamman": "gamman", "V": "speed",
             "Fr": "froude"}
_FROM_PATH = [c for c in dict.fromkeys(path_scheme.COLUMN_OF.values()) if c not in _FROM_RUN]


class RunFileError(ValueError):
    """A file that is not a usable granudrag run file; the message says why."""


def path_parameters(path):
    """{'system': 'I', 'D': '2', 'h': '10', ...} from the key~value components of a path."""
    return path_scheme.named(path)


def _path_columns(params, get, path):
    """The table's columns that only the path gives ({'h_requested': 10.0, ...}: NaN for those it
    does not name, the system aside), after checking those the file holds too against it."""
    out = {c: math.nan for c in _FROM_PATH if c != "system"}
    for name, text in params.items():
        column = path_scheme.COLUMN_OF[name]
        if column == "system":
            continue
        try:
            value = float(text)
        except ValueError:
            raise RunFileError(f"{path}: path component '{path_scheme.part(name, text)}' "
                               "is not a number") from None
        attr = _FROM_RUN.get(column)
        if attr is None:
            out[column] = value
        elif not math.isclose(value, get[attr], rel_tol=1e-5, abs_tol=1e-12):
            raise RunFileError(f"{path}: the path says {name} = {text} but the file has "
                               f"{attr} = {get[attr]:.6g} (run file in the wrong place?)")
    return out


def _attr(group, name, path, where):
    if name not in group.attrs:
        raise RunFileError(f"{path}: damaged run file: no attribute '{name}' on {where}")
    value = group.attrs[name]
    if isinstance(value, bytes):
        value = value.decode()
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    return value


def _number(group, name, path, where):
    value = _attr(group, name, path, where)
    try:
        return float(value)
    except (TypeError, ValueError):
        raise RunFileError(f"{path}: damaged run file: {where} attribute '{name}' "
                           f"is not a number ({value!r})") from None


def _group(f, name, path):
    if name not in f:
        raise RunFileError(f"{path}: damaged run file: no group {name}")
    return f[name]


def _open(path):
    import h5py
    path = Path(path)
    if not path.is_file():
        raise RunFileError(f"{path}: no such file (the pull did not finish or was not run)")
    with open(path, "rb") as fh:
        head = fh.read(8)
    if head != b"\x89HDF\r\n\x1a\n":
        raise RunFileError(f"{path}: not an HDF5 file (a run file is written by `granudrag pull`)")
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        raise RunFileError(f"{path}: unreadable HDF5 file (truncated or corrupt?): {exc}") from None


def _check_header(f, path):
    if "granudrag" not in f or "format" not in f["granudrag"].attrs:
        raise RunFileError(f"{path}: not a granudrag file (no /granudrag format attribute)")
    fmt = _attr(f["granudrag"], "format", path, "/granudrag")
    if fmt != RUN_FORMAT:
        hint = " (a bed: pull it with `granudrag pull` first)" if fmt == "granudrag-bed" else ""
        raise RunFileError(f"{path}: is a '{fmt}' file, not a '{RUN_FORMAT}' file{hint}")
    version = int(_number(f["granudrag"], "version", path, "/granudrag"))
    if version not in RUN_VERSIONS:
        raise RunFileError(f"{path}: run file version {version} is not supported "
                           f"(this reader knows {', '.join(map(str, RUN_VERSIONS))})")
    return version


def read_run(path, system=None, root=None):
    """One run file as a dict with the table's columns (and EXTRA_COLUMNS).

    system: the table's system label; default: the path's `system~` component.
    root: `run` is the run's directory relative to root (default: the path
    of the run's directory as given).
    Raises RunFileError naming the file and what is wrong with it.
    """
    path = Path(path)
    params = path_parameters(path)
    f = _open(path)
    try:
        version = _check_header(f, path)
        run = _group(f, "run", path)
        obs = _group(f, "observables", path)
        get = {k: _number(run, k, path, "/run")
               for k in ("D", "depth", "speed", "froude", "mu", "kn", "gamman", "dt", "steps")}

        def observable(name, attr="value"):
            return _number(_group(obs, name, path), attr, path, f"/observables/{name}")

        drag, drag_err = observable("drag"), observable("drag", "error")
        drag_err_engine, plateau_engine = drag_err, _drag_convergence(_group(obs, "drag", path), drag_err)[1]
        recorded = read_series(f, path)
        series = drags(*recorded[1:3])
        drag_err, drag_dof, plateau = series["drag_err"], series["drag_dof"], series["plateau"]
        # Why the pull ended: "distance", or "target_error" (sequential stopping); files from
        # before sequential stopping travelled their distance.
        stop = _group(obs, "drag", path).attrs.get("stop_reason", "distance")
        stop_reason = stop.decode() if isinstance(stop, bytes) else str(stop)
        transient = observable("drag", "transient_distance")
        n = observable("coordination")
        theta, theta_err = observable("theta"), observable("theta", "error")
        theta_present = _theta_present(obs)
        Z, kappa = observable("bulk_coordination"), observable("kappa")
        kappa_err = kappa_error(obs, kappa, n, transient / get["speed"] if get["speed"] > 0 else 0.0)
        scale = _scale(f, path) if version >= 2 else _legacy_scale_v1(f)
        cumulative_box = box_cumulative(*recorded, scale["lx"])
        region = ({k: _setting(f, path, "pull", k) for k in ("active_radius", "active_diameters")}
                  if version >= 2 else {})
        active_radius = physics.active_radius(region, get["D"])
        # The region's wake and rest tests, with it on only (NaN without: every grain is awake).
        wake_force = wake_load = sleep_speed = sleep_time = math.nan
        if active_radius > 0:
            wake_force = _wake_force_used(f, path, obs)
            wake_load = _setting(f, path, "pull", "wake_load")  # 0 (off) before the key existed
            sleep_speed = _setting(f, path, "pull", "sleep_speed") or math.nan
            # 0 is a valid sleep_time: a file without the key reads NaN, not 0
            sleep_time = _setting(f, path, "pull", "sleep_time", default=math.nan)
        perturbation = _setting(f, path, "pull", "perturbation") if version >= 2 else 0.0
        settle_damping = _setting(f, path, "pour", "settle_damping") if version >= 2 else 0.0
        placed = bed_origin.placed(_parameters(f, path)) if version >= 2 and "parameters" in f else 0.0
        asleep = _asleep(obs, scale["grains"])
        sanity = _verdict(f, path)
    except (KeyError, OSError, RuntimeError, UnicodeDecodeError) as exc:
        raise RunFileError(f"{path}: damaged run file: {exc}") from None
    except SeriesError as exc:
        raise RunFileError(str(exc)) from None
    finally:
        f.close()

    system = system if system is not None else params.get("system")
    if not system:
        raise RunFileError(f"{path}: no system given and no '{path_scheme.part('system', '<name>')}' "
                           "component in the path")
    from_path = _path_columns(params, get, path)
    fr = float(froude(get["speed"], get["D"]))
    if not math.isclose(fr, get["froude"], rel_tol=1e-6, abs_tol=1e-12):
        raise RunFileError(f"{path}: stored Froude number {get['froude']:.6g} is not paper Eq. 4 "
                           f"of its speed and D ({fr:.6g})")
    if sanity != "clean" and sanity != "unknown":
        raise RunFileError(f"{path}: sanity verdict is not clean, left out: {sanity}")
    if not math.isfinite(drag):
        raise RunFileError(f"{path}: the pull produced no drag (value {drag}); see its log")
    run_dir = path.parent
    if root is not None:
        try:
            run_dir = run_dir.relative_to(root)
        except ValueError:
            pass
    return {"system": str(system), **{c: get[a] for c, a in _FROM_RUN.items()}, "drag": drag,
            "drag_err": drag_err, "n_contacts": n, "theta": theta, "Z": Z, "kappa": kappa,
            "run": str(run_dir), **from_path, "dt": get["dt"],
            "collision_steps": round(physics.collision_time(get["kn"]) / get["dt"], 1),
            "steps": int(get["steps"]), "transient_distance": transient, "theta_err": theta_err,
            "theta_present": theta_present[0], "theta_present_err": theta_present[1],
            "kappa_err": kappa_err, "drag_dof": drag_dof, "plateau": plateau,
            "drag_err_engine": drag_err_engine, "plateau_engine": plateau_engine,
            "drag_cumulative": series["drag_cumulative"], "drag_cumulative_err": series["drag_cumulative_err"],
            "drag_cumulative_box": cumulative_box[0], "drag_cumulative_box_err": cumulative_box[1],
            **scale, "distance": get["speed"] * get["steps"] * get["dt"], "stop_reason": stop_reason,
            "active_radius": active_radius, "wake_force": wake_force, "wake_load": wake_load,
            "sleep_speed": sleep_speed,
            "sleep_time": sleep_time,
            "perturbation": perturbation, "asleep": asleep,
            "settle_damping": settle_damping, "placed": placed, "sanity": sanity, "path": str(path)}


def _verdict(f, path):
    """The run's sanity verdict: "clean", the failure it records, or "unknown" for a file
    written before granudrag recorded one."""
    group = f.get("sanity")
    if group is None or "verdict" not in group.attrs:
        return "unknown"
    value = _attr(group, "verdict", path, "/sanity")
    return value if value else "unknown"


def _theta_present(obs):
    """(value, error) of θ over the contacts present at each sample (time-weighted); (NaN, NaN) for
    a file written before the engine recorded it, or a value or error it could not estimate."""
    group = obs.get("theta_present")
    if group is None:
        return math.nan, math.nan
    return tuple(float(group.attrs.get(k, math.nan)) for k in ("value", "error"))


def _drag_convergence(group, drag_err):
    """(error_dof, plateau) of the drag's error. Files before these attributes (block
    averaging, no convergence test): (NaN, False), so a table never claims a converged error
    that was not tested."""
    dof = float(group.attrs.get("error_dof", math.nan))
    plateau = bool(int(group.attrs.get("plateau", 0))) and math.isfinite(drag_err)
    return dof, plateau


def _value(value):
    """An attribute as a plain Python value: str, bool, int, float or a list of floats."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray):
        return [float(v) for v in value] if value.ndim else _value(value[()])
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    return value


def _parameters(f, path):
    """{'pour': {key: value}, 'pull': {...}} from /parameters/<command> (format version 2)."""
    import h5py
    group = f.get("parameters")
    if not isinstance(group, h5py.Group):
        raise RunFileError(f"{path}: damaged run file: no group /parameters")
    return {command: {key: _value(v) for key, v in g.attrs.items()}
            for command, g in group.items() if isinstance(g, h5py.Group)}


def read_parameters(path):
    """The resolved parameters a run file records: {'pull': {...}, 'pour': {...}}, one dict
    per command, key -> value (str, bool, int, float or list of floats). A key without a value
    is absent; 'pour' is absent when the bed did not record its parameters by key (a bed of
    format version 1, or one made by `granudrag import-lammps`: then 'import-lammps').
    Raises RunFileError for files that are not run files of format version 2."""
    f = _open(path)
    try:
        version = _check_header(f, path)
        if version < 2:
            raise RunFileError(f"{path}: run file version {version} records its parameters as "
                               f"text, not by key; re-run the pull with this granudrag to read them")
        params = _parameters(f, path)
    except (KeyError, OSError, RuntimeError, UnicodeDecodeError) as exc:
        raise RunFileError(f"{path}: damaged run file: {exc}") from None
    finally:
        f.close()
    if "pull" not in params:
        raise RunFileError(f"{path}: damaged run file: no /parameters/pull")
    return params


def _scale(f, path):
    """Box and grain count of the bed a run was pulled through, from its bed's parameters
    (/parameters/pour); NaN when the file does not record them."""
    pour = _parameters(f, path).get("pour", {}) if "parameters" in f else {}
    out = {}
    for key in SCALE_KEYS:
        value = pour.get(key, math.nan)
        if isinstance(value, (bool, str, list)):
            raise RunFileError(f"{path}: damaged run file: /parameters/pour attribute '{key}' "
                               f"is not a number ({value!r})")
        out[key] = float(value)
    return out


def _asleep(obs, grains):
    """The mean fraction of the bed's grains asleep over the pull (the active region's saving;
    0 without the region, NaN when the bed's grain count is not recorded)."""
    if "sleeping_grains" not in obs:
        return 0.0
    counts = np.asarray(obs["sleeping_grains/value"][()], dtype=float)
    return float(counts.mean() / grains) if counts.size and grains > 0 else math.nan


def _wake_force_used(f, path, obs):
    """The wake test a pull with the region used: the run file records it beside the sleeping
    count (since the default follows the bed's K_n, an unset key is not recorded); older files
    record only the key, which then always had its value (0.5 by default); NaN if neither."""
    used = obs["sleeping_grains"].attrs.get("wake_force") if "sleeping_grains" in obs else None
    if used is not None:
        return float(used)
    return _setting(f, path, "pull", "wake_force") or math.nan


def _setting(f, path, block, key, default=0.0):
    """A numeric setting of the run's pull (`block` "pull") or of its bed's pour ("pour") that
    defaults to 0 (active_radius, d: 0 every grain integrated; perturbation: 0 not a replica;
    settle_damping: 0 the paper's pour), also for files from before the key, which record none;
    `default` for a file without it."""
    value = (_parameters(f, path).get(block, {}) if "parameters" in f else {}).get(key, default)
    if isinstance(value, (bool, str, list)):
        raise RunFileError(f"{path}: damaged run file: /parameters/{block} attribute '{key}' "
                           f"is not a number ({value!r})")
    return float(value)


def _legacy_scale_v1(f):
    """As _scale, for format version 1, which stored the resolved parameters as one text
    (/parameters attribute yaml: the pull's keys, then its bed's). Read line by line: the two
    documents share keys, and only the bed has these. Legacy: no newer file is read this way."""
    out = dict.fromkeys(SCALE_KEYS, math.nan)
    group = f.get("parameters")
    text = group.attrs.get("yaml") if group is not None else None
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    for line in (text or "").splitlines():
        key, sep, value = line.partition(":")
        if sep and key.strip() in out:
            try:
                out[key.strip()] = float(value.strip())
            except ValueError:
                pass
    return out


def load_runs(paths, system=None, root=None, errors="raise"):
    """The tidy table of many run files, one row each, in the order given.

    errors="raise": raise RunFileError listing every unusable file by name;
    errors="collect": return (table, problems) with problems a list of
    messages, one per file left out.
    """
    if errors not in ("raise", "collect"):
        raise ValueError(f"errors must be 'raise' or 'collect', not {errors!r}")
    rows, problems = [], []
    for p in paths:
        try:
            rows.append(read_run(p, system=system, root=root))
        except RunFileError as exc:
            problems.append(str(exc))
    if problems and errors == "raise":
        raise RunFileError(f"{len(problems)} of {len(rows) + len(problems)} run files unusable:\n  "
                           + "\n  ".join(problems))
    df = pd.DataFrame(rows, columns=list(COLUMNS) + EXTRA_COLUMNS)
    df = df.astype({c: float for c, (kind, _) in COLUMNS.items() if kind == "number"})
    df = df.astype({"system": object, "run": object})
    if len(df):
        validate_table(df)
    return (df, problems) if errors == "collect" else df


def read_force_trace(path):
    """(t, drag_t, transient_time) of a run: time, -F_x per sample interval, and
    the time before which samples were discarded (for Fig. 4)."""
    f = _open(path)
    try:
        _check_header(f, path)
        t = np.asarray(f["observables/intruder_force/time"][:], dtype=float)
        fx = np.asarray(f["observables/intruder_force/value"][:, 0], dtype=float)
        skip = int(_number(f["observables/drag"], "transient_samples", path, "/observables/drag"))
    except KeyError as exc:
        raise RunFileError(f"{path}: damaged run file: {exc}") from None
    finally:
        f.close()
    transient = float(t[skip - 1]) if 0 < skip <= len(t) else 0.0
    return t, -fx, transient


def window_drag(path, travel_max):
    """The steady and the cumulative drag with their errors over the first `travel_max` d of the
    pull in run file `path`, as read_run gives them over the whole pull (run_series.first_travel)."""
    f = _open(path)
    try:
        _check_header(f, path)
        return first_travel(*read_series(f, path), travel_max)
    except SeriesError as exc:
        raise RunFileError(str(exc)) from None
    finally:
        f.close()


def read_coordination_distribution(path):
    """P(Z) of a run (Fig. 7): probabilities for Z = 0, 1, ..., the last bin holding Z and
    above, over the grains of the shell around the intruder after the transient."""
    f = _open(path)
    try:
        _check_header(f, path)
        p = np.asarray(f["observables/bulk_coordination/distribution"][:], dtype=float)
    except KeyError as exc:
        raise RunFileError(f"{path}: damaged run file: {exc}") from None
    finally:
        f.close()
    if p.ndim != 1 or not len(p) or not np.all(np.isfinite(p)) or np.any(p < 0):
        raise RunFileError(f"{path}: damaged run file: P(Z) is not a distribution")
    return np.arange(len(p)), p


def read_snapshots(path):
    """The velocity-field snapshots of a run (Fig. 9): a list of DataFrames with columns
    dx, dz (grain minus intruder, d), vx, vz (grain velocity in the intruder's frame, sqrt(gd)),
    one per snapshot in time order, each with .attrs["time"]. Grains in the slab |dy| < 0.5 d."""
    f = _open(path)
    out = []
    try:
        _check_header(f, path)
        snaps = f.get("snapshots")
        for name in sorted(snaps or (), key=int):
            g = snaps[name]
            df = pd.DataFrame({c: np.asarray(g[c][:], dtype=float) for c in ("dx", "dz", "vx", "vz")})
            df.attrs["time"] = float(_number(g, "time", path, f"/snapshots/{name}"))
            out.append(df)
    except (KeyError, ValueError) as exc:
        raise RunFileError(f"{path}: damaged run file: {exc}") from None
    finally:
        f.close()
    return out
