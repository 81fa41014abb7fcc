#!/usr/bin/env python3
"""Relocalisation by true overlap: reads the per-query lines of docs/results/relocalisation_LOG.txt (written by
build/relocalisation_check through scripts/make-relocalisation.sh) and prints, per log, how many of the queries in
the map (true overlap >= 30 %) came back within 0.3 m / 3 deg, split by their true overlap with the map (30-50,
50-70, >= 70 %). It says whether a log's misses are partial views or places the query sees whole.
Usage: /usr/bin/python3 scripts/relocalisation_by_overlap.py docs/results/relocalisation_*.txt"""
import os
import re
import sys

BINS = ((0.3, 0.5, "30-50 %"), (0.5, 0.7, "50-70 %"), (0.7, 1.01, ">= 70 %"))
LINE = re.compile(r"^\s+[\d.]+ m\s+overlap ([\d.]+) .* err ([\d.]+) m ([\d.]+) deg")


def main(paths):
    if not paths:
        sys.exit(__doc__.strip().splitlines()[-1])
    print("| log | " + " | ".join(f"overlap {b[2]}" for b in BINS) + " |")
    print("|---|" + "---|" * len(BINS))
    for path in paths:
        counts = [[0, 0] for _ in BINS]
        try:
            lines = open(path).read().splitlines()
        except (OSError, UnicodeDecodeError) as e:
            sys.exit(f"{path}: cannot read it ({e})")
        for line in lines:
            m = LINE.match(line)
            if not m:
                continue
            overlap, err, deg = (float(g) for g in m.groups())
            for (low, high, _), c in zip(BINS, counts):
                if low <= overlap < high:
                    c[0] += err <= 0.3 and deg <= 3  # the printed errors, rounded as the lines print them
                    c[1] += 1
        if not any(c[1] for c in counts):
            sys.exit(f"{path}: no per-query lines with an overlap of 30 % or more")
        name = os.path.basename(path).removeprefix("relocalisation_").removesuffix(".txt")
        print(f"| {name} | " + " | ".join(f"{c[0]} of {c[1]}" if c[1] else "-" for c in counts) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
