#!/usr/bin/env python3
"""A relations file (Kümmerle et al. 2009: `t1 t2 x y z roll pitch yaw` per line, t1 and t2 a raw CARMEN log's
FLASER timestamps) in the clock of a ROS bag of the same run. The benchmark bags in ../shared are re-timed (a scan
every 0.1 s), so their stamps do not name the log's scans, and they do not always list the scans in the log's order
(intel's bag holds 2591 of its 13631 scans up to 14 places away from their place in the .clf): each bag scan is
paired with the log's scan, within SEARCH places of its own, whose ranges are the same (both files read with the
`partslam` Python module; they must hold as many scans, each paired once). Used by scripts/slam-bench.sh to judge
`slam` on the bags by the logs' relations, and by scripts/track_other_recording.py.
Usage: /usr/bin/python3 scripts/bag_relations.py CLF BAG RELATIONS OUT"""
import bisect
import math
import os
import sys

import numpy as np

import readme_block

SEARCH = 50        # places either side of a bag scan's own where its log scan is looked for
RANGE_TOL = 2e-3   # [m]: the .clf prints ranges to 1 mm
MIN_R, MAX_R = 0.1, 49.9  # [m]: beams both files keep (the bags' range_min; aces's bag drops its 50 m code)


def partslam_module():
    """The project's Python module: the one on PYTHONPATH (ctest's build tree), else build/python."""
    try:
        import partslam
    except ImportError:
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "python"))
        import partslam
    return partslam


def read_relations(path):
    """The relations: each its eight numbers, the text of its last six and its line; exits naming the file and line
    of one that is not eight finite numbers (a file without any, too)."""
    rows = []
    try:
        with open(path) as f:
            for n, line in enumerate(f, 1):
                v = line.split()
                if not v or v[0].startswith("#"):
                    continue
                try:
                    row = [float(x) for x in v[:8]]
                except ValueError:
                    row = []
                if len(row) < 8 or not all(math.isfinite(x) for x in row):
                    sys.exit(f"{path}:{n}: expected 't1 t2 x y z roll pitch yaw' (eight finite numbers)")
                rows.append((row, v[2:8], n))
    except OSError as e:
        sys.exit(f"{path}: cannot read it ({e})")
    if not rows:
        sys.exit(f"{path}: no relations")
    return rows


def write_atomically(out, lines):
    """Writes the lines to out atomically (readme_block.write_atomically); exits naming out (no .tmp left) when it
    cannot."""
    try:
        readme_block.write_atomically(out, "".join(lines))
    except OSError as e:
        sys.exit(f"{out}: cannot write it ({e})")


def ranges(scan):
    """A scan's beam lengths that both files keep, in beam order (independent of how each file spaces its beams)."""
    r = np.linalg.norm(np.asarray(scan.points_laser, dtype=float).reshape(-1, 2), axis=1)
    return r[(r > MIN_R) & (r < MAX_R)]


def paired_scans(clf, bag):
    """The scans of a CARMEN log and of a bag of the same run, read by the project's readers, and for each bag scan
    the index of the log's scan with the same ranges (the nearest in order when several have them); exits naming
    both files when they do not hold as many scans or a bag scan has no unpaired match within SEARCH places."""
    partslam = partslam_module()
    clf_scans, bag_scans = partslam.load_scan_source(clf).scans, partslam.load_scan_source(bag).scans
    if len(clf_scans) != len(bag_scans):
        sys.exit(f"{clf} holds {len(clf_scans)} scans, {bag} {len(bag_scans)}: they cannot be paired")
    clf_r, bag_r = [ranges(s) for s in clf_scans], [ranges(s) for s in bag_scans]
    n = len(bag_scans)
    pair, used = [0] * n, [False] * n
    for i in range(n):
        near = sorted(range(max(0, i - SEARCH), min(n, i + SEARCH + 1)), key=lambda j: (abs(j - i), j))
        same = [j for j in near if not used[j] and len(clf_r[j]) == len(bag_r[i]) and
                (len(bag_r[i]) == 0 or np.max(np.abs(clf_r[j] - bag_r[i])) < RANGE_TOL)]
        if not same:
            sys.exit(f"{bag}: scan {i} has no scan of {clf} with the same ranges within {SEARCH} places")
        pair[i], used[same[0]] = same[0], True
    return clf_scans, bag_scans, pair


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__.strip().splitlines()[-1])
    clf, bag, relations, out = argv
    clf_scans, bag_scans, pair = paired_scans(clf, bag)
    clf_times = [s.timestamp for s in clf_scans]
    bag_time_of = [0.0] * len(bag_scans)  # the bag's stamp of each log scan
    for i, j in enumerate(pair):
        bag_time_of[j] = bag_scans[i].timestamp
    order = sorted(range(len(clf_times)), key=lambda i: clf_times[i])
    sorted_times = [clf_times[i] for i in order]

    def scan_of(t, where):
        k = bisect.bisect_left(sorted_times, t - 1e-4)
        if k < len(sorted_times) and abs(sorted_times[k] - t) < 1e-3:
            return order[k]
        sys.exit(f"{where}: no scan of {clf} at {t}")

    lines = []
    for r, text, n in read_relations(relations):
        a = scan_of(r[0], f"{relations}:{n}")
        b = scan_of(r[1], f"{relations}:{n}")
        lines.append(f"{bag_time_of[a]:.6f} {bag_time_of[b]:.6f} {' '.join(text)}\n")
    write_atomically(out, lines)


if __name__ == "__main__":
    main(sys.argv[1:])
