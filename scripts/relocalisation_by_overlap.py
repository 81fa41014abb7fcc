#!/usr/bin/env python3
"""Relocalisation by true overlap: reads the per-query lines of docs/results/relocalisation_LOG.txt (written by
build/relocalisation_check through scripts/make-relocalisation.sh) and prints, per log, how many of the queries in
the map came back within the tool's tolerance, split by their true overlap with the map (30-50, 50-70, >= 70 %).
The in-map overlap and the tolerance are read from each file's own summary line ("in the map (overlap >= 30 %):
N, pose within 0.30 m / 3 deg: ..."), so they stay those relocalisation_check counted with. It says whether a
log's misses are partial views or places the query sees whole.
Usage: /usr/bin/python3 scripts/relocalisation_by_overlap.py docs/results/relocalisation_*.txt"""
import os
import re
import sys

BINS = ((0.3, 0.5, "30-50 %"), (0.5, 0.7, "50-70 %"), (0.7, 1.01, ">= 70 %"))
LINE = re.compile(r"^\s+[\d.]+ m\s+overlap ([\d.]+) .* err ([\d.]+) m ([\d.]+) deg")
SUMMARY = re.compile(r"^in the map \(overlap >= ([\d.]+) %\): \d+, pose within ([\d.]+) m / ([\d.]+) deg:", re.M)


def main(paths):
    if not paths:
        sys.exit(__doc__.strip().splitlines()[-1])
    print("| log | " + " | ".join(f"overlap {b[2]}" for b in BINS) + " |")
    print("|---|" + "---|" * len(BINS))
    for path in paths:
        counts = [[0, 0] for _ in BINS]
        try:
            text = open(path).read()
        except (OSError, UnicodeDecodeError) as e:
            sys.exit(f"{path}: cannot read it ({e})")
        summary = SUMMARY.search(text)
        if not summary:
            sys.exit(f"{path}: no line 'in the map (overlap >= P %): N, pose within M m / D deg: ...' "
                     "(not a relocalisation_check report)")
        min_overlap, max_err, max_deg = float(summary[1]) / 100, float(summary[2]), float(summary[3])
        for line in text.splitlines():
            m = LINE.match(line)
            if not m:
                continue
            overlap, err, deg = (float(g) for g in m.groups())
            if overlap < min_overlap:
                continue
            for (low, high, _), c in zip(BINS, counts):
                if low <= overlap < high:
                    c[0] += err <= max_err and deg <= max_deg  # the printed errors, rounded as the lines print them
                    c[1] += 1
        if not any(c[1] for c in counts):
            sys.exit(f"{path}: no per-query lines with an overlap of 30 % or more")
        name = os.path.basename(path).removeprefix("relocalisation_").removesuffix(".txt")
        print(f"| {name} | " + " | ".join(f"{c[0]} of {c[1]}" if c[1] else "-" for c in counts) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
