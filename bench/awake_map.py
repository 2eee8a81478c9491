#!/usr/bin/python3
"""Where the grains that an active region keeps awake are, and whether they move.

    /usr/bin/python3 bench/awake_map.py RUN.h5
    /usr/bin/python3 bench/awake_map.py REFERENCE.h5 --radius R

RUN.h5 is a `granudrag pull --active_radius R ... --dump_interval T` run file. For each frame
after the first it prints the fraction of the bed asleep and, of the grains farther than R from
the intruder (which could sleep), how many are awake, and how many drifted since the frame before
faster than the pull's rest test (sleep_speed V, at most sleep_speed_max) and ten times faster:
their displacement over the frames' interval, so a grain that only vibrates about its place
does not count (in a bed under a pulled intruder nearly every grain's instantaneous speed is
above the rest test); then where the awake grains are (depth below the bed's top and horizontal
distance from the intruder, percentiles) and the awake and drifting fractions per 4 d depth band
and per 5 d horizontal band.

Asleep = velocity exactly zero: a grain that falls asleep has its velocity and spin set to zero
and is not integrated until it wakes (src/engine/active_region.cpp); an awake grain at exactly
zero velocity does not occur in a bed under gravity. A pull without the region (REFERENCE.h5, the
same bed and options, --radius R) shows how many grains outside R drift faster than the rest test
when nothing is held: those no region may hold. So the question "is the region's cost set by its
wake test or by grains that really move?" is answered from the frames alone.
"""

import argparse
import sys

import numpy as np

MOBILE, INTRUDER = 0, 2


def periodic_offsets(x, centre, lx, ly):
    """x - centre with x and y folded into the periodic box [-L/2, L/2)."""
    d = x - centre
    d[:, 0] -= lx * np.round(d[:, 0] / lx)
    d[:, 1] -= ly * np.round(d[:, 1] / ly)
    return d


def frame_summary(x, v, x_before, interval, species, radius, lx, ly, rest_speed):
    """One frame's figures (a dict, see the module's docstring); x_before: the positions
    `interval` time units earlier."""
    mobile = species == MOBILE
    asleep = mobile & (np.linalg.norm(v, axis=1) == 0.0)
    d = periodic_offsets(x, x[np.flatnonzero(species == INTRUDER)[0]], lx, ly)
    drift = np.linalg.norm(periodic_offsets(x, x_before, lx, ly), axis=1) / interval
    horizontal = np.hypot(d[:, 0], d[:, 1])
    outside = mobile & (np.linalg.norm(d, axis=1) > radius)
    awake, drifting = outside & ~asleep, outside & (drift > rest_speed)
    depth = x[mobile, 2].max() - x[:, 2]
    out = {"asleep": asleep.sum() / max(1, mobile.sum()), "outside": int(outside.sum()),
           "awake": int(awake.sum()), "drifting": int(drifting.sum()),
           "drifting10": int((outside & (drift > 10 * rest_speed)).sum()),
           "awake_drifting": int((awake & drifting).sum())}
    if awake.any():
        out["depth_pct"] = np.percentile(depth[awake], [10, 50, 90])
        out["horizontal_pct"] = np.percentile(horizontal[awake], [10, 50, 90])
        out["above"] = float(np.mean(d[awake, 2] > 0))

    def by_band(coord, width, which):
        bands = []
        for lo in np.arange(0.0, coord[outside].max() + 1e-9, width):
            sel = outside & (coord >= lo) & (coord < lo + width)
            bands.append(float(np.mean(which[sel])) if sel.any() else float("nan"))
        return bands

    for name, which in (("awake", awake), ("drifting", drifting)):
        out[f"{name}_by_depth"] = by_band(depth, 4.0, which)
        out[f"{name}_by_horizontal"] = by_band(horizontal, 5.0, which)
    return out


def _attr(group, name):
    value = group.attrs[name]
    return value.decode() if isinstance(value, bytes) else value


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", help="a pull's run file with frames (--dump_interval) and an active region")
    parser.add_argument("--radius", type=float, default=None,
                        help="R in d (default: the run's active_radius); with a pull without the region, the grains "
                             "outside R that move faster than the rest test are those a region could not hold")
    args = parser.parse_args(argv)
    import h5py

    with h5py.File(args.run, "r") as f:
        if "particles/frames/velocity" not in f:
            sys.exit(f"awake_map: {args.run} has no frames: pull with --dump_interval T")
        pull, pour = f["parameters/pull"], f["parameters/pour"]
        radius = float(_attr(pull, "active_radius")) if args.radius is None else args.radius
        if radius <= 0:
            sys.exit(f"awake_map: {args.run} was pulled without an active region (active_radius 0): give --radius R")
        speed = float(f["run"].attrs["speed"])
        rest = min(float(_attr(pull, "sleep_speed")) * speed, float(_attr(pull, "sleep_speed_max")))
        lx, ly = float(_attr(pour, "lx")), float(_attr(pour, "ly"))
        species = f["particles/frames/species/value"][:]
        times = f["particles/frames/position/time"][:]
        print(f"{args.run}: R = {radius:g} d, V = {speed:g}, rest test {rest:.3g} sqrt(gd); of the grains outside R: "
              "awake, drifting (faster than the rest test since the frame before), awake and drifting")
        position, velocity = f["particles/frames/position/value"], f["particles/frames/velocity/value"]
        x_before = position[0]
        for k in range(1, len(times)):
            x = position[k]
            s = frame_summary(x, velocity[k], x_before, times[k] - times[k - 1], species, radius, lx, ly, rest)
            x_before = x
            print(f"t = {times[k]:7.2f}  asleep {s['asleep']:.3f}  outside {s['outside']}: awake {s['awake']:6d}"
                  f"  drifting {s['drifting']:6d} (x10 {s['drifting10']:6d})"
                  f"  awake and drifting {s['awake_drifting']:6d}")
            if "above" in s:
                depth, horizontal = np.round(s["depth_pct"], 1), np.round(s["horizontal_pct"], 1)
                print(f"    awake: depth p10/50/90 {depth}  horizontal {horizontal}"
                      f"  above the intruder {s['above']:.2f}")
            for name in ("awake", "drifting"):
                print(f"    {name:8s} by depth (4 d):", np.round(s[f"{name}_by_depth"], 2),
                      " by horizontal distance (5 d):", np.round(s[f"{name}_by_horizontal"], 2))


if __name__ == "__main__":
    main()
