#!/usr/bin/env python3
"""Writes EN 1991-2 Annex D's fatigue trains Types 1-12 as train files (data/trains/fatigue/typeN.csv).

Each vehicle is given as the standard's figures draw it: the distances from its front buffer to
its first axle, between its axles and from its last axle to its rear buffer [m], and its axle
loads [kN]. A train file holds the axles' positions from the first axle and their loads; its
header names the type, the speed of the figure and the totals: Sum Q [kN] and L, buffer to
buffer [m].

To confirm against the standard's figures D.1-D.12 (REFERENCE.md §11 gives Type 1, the rest
were taken from a public implementation of Annex D and checked against the captions' Sum Q and
L, which every type reproduces: tests/unit/io/test_fatigue_trains.cpp). The speeds are the
figures' as that implementation gives them and are not checked.

    scripts/generate/make_fatigue_trains.py [OUTDIR]     (default data/trains/fatigue)
"""
import os
import sys

# (spacings buffer-axle-...-axle-buffer [m], axle loads [kN])
LOCO_6 = ([1.4, 2.2, 2.2, 6.9, 2.2, 2.2, 1.4], [225] * 6)       # Types 1, 7, 8, 11, 12
LOCO_6B = ([2.0, 2.1, 2.1, 4.4, 2.1, 2.1, 2.0], [225] * 6)      # Types 5, 6


def bogie(end, axle, inner, load):
    """A four-axle bogie wagon: buffer to first axle `end`, axles `axle` apart in a bogie, the
    bogies' inner axles `inner` apart."""
    return ([end, axle, inner, axle, end], [load] * 4 if not isinstance(load, list) else load)


def two_axle(end, base, load):
    return ([end, base, end], [load] * 2)


def type6_wagons():
    a = two_axle(1.9, 6.5, 70)
    b = bogie(1.8, 1.8, 12.8, 225)
    c = bogie(1.6, 1.8, 8.0, 225)
    return [{"A": a, "B": b, "C": c}[k] for k in "AABACCABBBAACCABCAACCB"]


def type10_cars():
    a = bogie(1.75, 2.4, 7.9, [150, 100, 100, 150])
    b = bogie(1.75, 2.4, 7.9, 100)
    return [a, b, b, a, a, b, b, a]


# type: (description, speed of the figure [km/h], Sum Q [kN], L [m] of the caption, vehicles)
TYPES = {
    1: ("locomotive-hauled passenger train", 200, 6630, 262.10,
        [LOCO_6] + [bogie(1.8, 2.6, 11.5, 110)] * 12),
    2: ("locomotive-hauled passenger train", 160, 5300, 281.10,
        [([1.4, 3.3, 6.7, 3.3, 1.4], [225] * 4)] + [bogie(2.5, 2.5, 16.5, 110)] * 10),
    3: ("high-speed passenger train", 250, 9400, 385.52,
        [([4.7, 3.0, 8.46, 3.0, 2.0], [200] * 4)] + [bogie(2.45, 2.5, 16.5, 150)] * 13 +
        [([2.0, 3.0, 8.46, 3.0, 4.7], [200] * 4)]),
    4: ("high-speed passenger train (articulated)", 250, 5100, 237.60,
        [([3.5, 3.0, 11.0, 3.0, 1.65], [170] * 4), ([1.65, 3.0, 15.7, 1.5], [170] * 3)] +
        [([1.5, 15.7, 1.5], [170] * 2)] * 8 +
        [([1.5, 15.7, 3.0, 1.65], [170] * 3), ([1.65, 3.0, 11.0, 3.0, 3.5], [170] * 4)]),
    5: ("locomotive-hauled freight train", 100, 21600, 270.30,
        [LOCO_6B] + [([2.0, 1.8, 1.8, 5.7, 1.8, 1.8, 2.0], [225] * 6)] * 15),
    6: ("locomotive-hauled freight train", 100, 14310, 333.10, [LOCO_6B] + type6_wagons()),
    7: ("locomotive-hauled freight train", 80, 10350, 196.50, [LOCO_6] + [bogie(1.6, 1.8, 11.0, 225)] * 10),
    8: ("locomotive-hauled freight train", 100, 10350, 212.50, [LOCO_6] + [two_axle(2.1, 5.5, 225)] * 20),
    9: ("suburban multiple unit", 120, 2960, 134.80,
        [bogie(2.15, 2.5, 14.0, 130), bogie(2.15, 2.5, 11.5, 110), bogie(2.15, 2.5, 14.0, 130),
         bogie(2.15, 2.5, 14.0, 130), bogie(2.15, 2.5, 11.5, 110), bogie(2.15, 2.5, 14.0, 130)]),
    10: ("underground", 120, 3600, 129.60, type10_cars()),
    11: ("locomotive-hauled freight train, 25 t axles", 120, 11350, 198.50, [LOCO_6] + [bogie(1.5, 2.0, 11.0, 250)] * 10),
    12: ("locomotive-hauled freight train, 25 t axles", 100, 11350, 212.50, [LOCO_6] + [two_axle(2.1, 5.5, 250)] * 20),
}


def axles(vehicles):
    """(positions from the front buffer [m], loads [kN], length buffer to buffer [m])."""
    x, pos, loads = 0.0, [], []
    for spacing, load in vehicles:
        assert len(spacing) == len(load) + 1
        at = x
        for s, q in zip(spacing[:-1], load):
            at += s
            pos.append(at)
            loads.append(q)
        x = at + spacing[-1]
    return pos, loads, x


def write(n, outdir):
    desc, speed, sum_q, length, vehicles = TYPES[n]
    pos, loads, total = axles(vehicles)
    if abs(sum(loads) - sum_q) > 1e-9 or abs(total - length) > 1e-9:
        sys.exit("type %d: %g kN over %.2f m, the caption says %g kN over %.2f m" % (n, sum(loads), total, sum_q, length))
    first, last = pos[0], total - pos[-1]
    lines = [
        "# EN 1991-2 Annex D, fatigue train Type %d: %s." % (n, desc),
        "# V = %d km/h, Sum Q = %d kN over L = %.2f m buffer to buffer (to confirm against the" % (speed, sum_q, length),
        "# standard's figure; REFERENCE.md §11).",
        "# positions from the first axle (the front buffer %.2f m ahead of it, the rear buffer %.2f m" % (first, last),
        "# behind the last): %d axles, %.2f m first to last. Written by" % (len(pos), pos[-1] - first),
        "# scripts/generate/make_fatigue_trains.py; checked in tests/unit/io/test_fatigue_trains.cpp.",
        "position_m,load_kN",
    ]
    lines += ["%.2f,%d" % (p - first, q) for p, q in zip(pos, loads)]
    path = os.path.join(outdir, "type%d.csv" % n)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote %s: %d axles, %d kN, %.2f m" % (path, len(pos), sum(loads), total))


def main():
    outdir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "data", "trains", "fatigue")
    for n in TYPES:
        write(n, outdir)


if __name__ == "__main__":
    main()
