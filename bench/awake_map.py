#!/usr/bin/python3
"""Where the grains that an active region keeps awake are, and whether they move.

    /usr/bin/python3 bench/awake_map.py RUN.h5
    /usr/bin/python3 bench/awake_map.py REFERENCE.h5 --radius R

RUN.h5 is a `granudrag pull --active_radius R ... --dump_interval T` run file. For each frame it
prints the fraction of the bed asleep and, of the grains farther than R from the intruder (which
could sleep), how many are awake, how many of those move faster than the pull's rest test
(sleep_speed V, at most sleep_speed_max: a grain that fast cannot fall asleep) and ten times
faster, where they are (depth below the bed's top and horizontal distance from the intruder,
percentiles) and the awake fraction per 4 d depth band and per 5 d horizontal band.

Asleep = velocity exactly zero: a grain that falls asleep has its velocity and spin set to zero
and is not integrated until it wakes (src/engine/active_region.cpp); an awake grain at exactly
zero velocity does not occur in a bed under gravity. A pull without the region (REFERENCE.h5, the
same bed and options) shows how many grains outside R move faster than the rest test when nothing
is held. So the question "is the region's cost set by its wake test or by grains that really
move?" is answered from the frames alone.
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


def frame_summary(x, v, species, radius, lx, ly, rest_speed):
    """One frame's figures (a dict): see the module's docstring."""
    mobile = species == MOBILE
    speed = np.linalg.norm(v, axis=1)
    asleep = mobile & (speed == 0.0)
    d = periodic_offsets(x, x[np.flatnonzero(species == INTRUDER)[0]], lx, ly)
    horizontal = np.hypot(d[:, 0], d[:, 1])
    outside = mobile & (np.linalg.norm(d, axis=1) > radius)
    awake = outside & ~asleep
    depth = x[mobile, 2].max() - x[:, 2]
    out = {"asleep": asleep.sum() / max(1, mobile.sum()), "outside": int(outside.sum()),
           "awake": int(awake.sum()), "moving": int((awake & (speed > rest_speed)).sum()),
           "moving10": int((awake & (speed > 10 * rest_speed)).sum())}
    if awake.any():
        out["depth_pct"] = np.percentile(depth[awake], [10, 50, 90])
        out["horizontal_pct"] = np.percentile(horizontal[awake], [10, 50, 90])
        out["above"] = float(np.mean(d[awake, 2] > 0))

    def by_band(coord, width):
        bands = []
        for lo in np.arange(0.0, coord[outside].max() + 1e-9, width):
            sel = outside & (coord >= lo) & (coord < lo + width)
            bands.append(float(np.mean(~asleep[sel])) if sel.any() else float("nan"))
        return bands

    out["awake_by_depth"] = by_band(depth, 4.0)
    out["awake_by_horizontal"] = by_band(horizontal, 5.0)
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
        print(f"{args.run}: R = {radius:g} d, V = {speed:g}, rest test {rest:.3g} sqrt(gd); "
              "awake = of the grains outside R; moving = faster than the rest test")
        for k, t in enumerate(times):
            s = frame_summary(f["particles/frames/position/value"][k], f["particles/frames/velocity/value"][k],
                              species, radius, lx, ly, rest)
            line = (f"t = {t:7.2f}  asleep {s['asleep']:.3f}  awake {s['awake']:6d} of {s['outside']}"
                    f"  moving {s['moving']:6d} (x10 {s['moving10']:6d})")
            if "above" in s:
                depth, horizontal = np.round(s["depth_pct"], 1), np.round(s["horizontal_pct"], 1)
                line += f"  depth p10/50/90 {depth}  horizontal {horizontal}  above the intruder {s['above']:.2f}"
            print(line)
            if s["awake"]:
                print("          awake by depth (4 d bands):", np.round(s["awake_by_depth"], 2),
                      " by horizontal distance (5 d):", np.round(s["awake_by_horizontal"], 2))


if __name__ == "__main__":
    main()
