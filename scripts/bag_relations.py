#!/usr/bin/env python3
"""A relations file (Kümmerle et al. 2009: `t1 t2 x y z roll pitch yaw` per line, t1 and t2 a raw CARMEN log's
FLASER timestamps) in the clock of a ROS bag of the same run. The benchmark bags in ../shared are re-timed (a scan
every 0.1 s), so the scans are paired by their order: both files are read with the `partslam` Python module and
must hold as many scans. Used by scripts/slam-bench.sh to judge `slam` on the bags by the logs' relations.
Usage: /usr/bin/python3 scripts/bag_relations.py CLF BAG RELATIONS OUT"""
import bisect
import os
import sys


def partslam_module():
    """The project's Python module, from build/python."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "python"))
    import partslam
    return partslam


def paired_scans(clf, bag):
    """The scans of a CARMEN log and of a bag of the same run, read by the project's readers; exits naming both
    files when they do not hold as many scans (scan i of one is scan i of the other)."""
    partslam = partslam_module()
    clf_scans, bag_scans = partslam.load_scan_source(clf).scans, partslam.load_scan_source(bag).scans
    if len(clf_scans) != len(bag_scans):
        sys.exit(f"{clf} holds {len(clf_scans)} scans, {bag} {len(bag_scans)}: they cannot be paired")
    return clf_scans, bag_scans


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__.strip().splitlines()[-1])
    clf, bag, relations, out = argv
    clf_scans, bag_scans = paired_scans(clf, bag)
    clf_times = [s.timestamp for s in clf_scans]
    bag_times = [s.timestamp for s in bag_scans]
    order = sorted(range(len(clf_times)), key=lambda i: clf_times[i])
    sorted_times = [clf_times[i] for i in order]

    def scan_of(t, where):
        k = bisect.bisect_left(sorted_times, t - 1e-4)
        if k < len(sorted_times) and abs(sorted_times[k] - t) < 1e-3:
            return order[k]
        sys.exit(f"{where}: no scan of {clf} at {t}")

    lines = []
    try:
        with open(relations) as f:
            for n, line in enumerate(f, 1):
                v = line.split()
                if not v or v[0].startswith("#"):
                    continue
                if len(v) < 8:
                    sys.exit(f"{relations}:{n}: expected 't1 t2 x y z roll pitch yaw'")
                a = scan_of(float(v[0]), f"{relations}:{n}")
                b = scan_of(float(v[1]), f"{relations}:{n}")
                lines.append(f"{bag_times[a]:.6f} {bag_times[b]:.6f} {' '.join(v[2:8])}\n")
    except (OSError, ValueError) as e:
        sys.exit(f"{relations}: cannot read it ({e})")
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        f.writelines(lines)
    os.replace(tmp, out)


if __name__ == "__main__":
    main(sys.argv[1:])
