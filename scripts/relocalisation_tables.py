#!/usr/bin/env python3
"""The relocalisation tables, from the reports build/relocalisation_check writes (docs/results/relocalisation_LOG.txt,
through scripts/make-relocalisation.sh):
- per log: queries, those in the map, how many came back within the tool's tolerance and within 0.1 m / 1 deg,
  confident wrong answers, confident answers outside the map, median / p95 time (docs/USAGE.md's table);
- per log, the in-map queries split by their true overlap with the map (30-50, 50-70, >= 70 %): whether a log's
  misses are partial views or places the query sees whole.
The in-map overlap and the tolerance are read from each report's own summary line ("in the map (overlap >= 30 %):
N, pose within 0.30 m / 3 deg: ..."), so the tables count with what relocalisation_check counted with. Rows:
the tuning logs first (fr079, intel), then the others by name, in whatever order the reports are given.
Usage: /usr/bin/python3 scripts/relocalisation_tables.py [--readme README.md | --check README.md] REPORT...
  --readme FILE  also replaces the block between FILE's relocalisation markers with the per-log table
  --check FILE   prints nothing; exits 1 when FILE's block is not the per-log table of the reports"""
import os
import re
import sys

import readme_block

TUNING = ("fr079", "intel")  # the logs the defaults were chosen on: first in the tables, the others by name
FINE = (0.1, 1.0)  # the second tolerance column [m, deg]: the refined pose, as `locate`'s floor asks
BINS = ((0.3, 0.5, "30-50 %"), (0.5, 0.7, "50-70 %"), (0.7, 1.01, ">= 70 %"))
QUERY = re.compile(r"^\s+[\d.]+ m\s+overlap ([\d.]+) .* err ([\d.]+) m ([\d.]+) deg")
SUMMARY = re.compile(r"^in the map \(overlap >= ([\d.]+) %\): (\d+), pose within ([\d.]+) m / ([\d.]+) deg: "
                     r"(\d+) \(([\d.]+) %\)$", re.M)
FIELDS = {
    "queries": re.compile(r"^queries: (\d+)", re.M),
    "confident": re.compile(r"^confident \(>= [\d.]+, probability >= [\d.]+\): (\d+), wrong among them: (\d+)", re.M),
    "outside": re.compile(r"^outside the map \(overlap < [\d.]+ %\): (\d+), reported confidently: (\d+)", re.M),
    "time": re.compile(r"median ([\d.]+) ms, p95 ([\d.]+) ms", re.M),
}


class Report:
    """One relocalisation_check report: its summary lines and its per-query (overlap, error m, error deg)."""

    def __init__(self, path):
        try:
            text = open(path).read()
        except (OSError, UnicodeDecodeError) as e:
            sys.exit(f"{path}: cannot read it ({e})")
        self.name = os.path.basename(path).removeprefix("relocalisation_").removesuffix(".txt")
        summary = SUMMARY.search(text)
        if not summary:
            sys.exit(f"{path}: no line 'in the map (overlap >= P %): N, pose within M m / D deg: K (S %)' "
                     "(not a relocalisation_check report)")
        self.min_overlap = float(summary[1]) / 100
        self.in_map, self.max_err, self.max_deg = int(summary[2]), float(summary[3]), float(summary[4])
        self.within, self.share = int(summary[5]), summary[6]
        self.fields = {}
        for key, pattern in FIELDS.items():
            m = pattern.search(text)
            if not m:
                sys.exit(f"{path}: no '{key}' line (pattern {pattern.pattern!r})")
            self.fields[key] = m.groups()
        self.queries = [tuple(float(g) for g in m.groups()) for m in map(QUERY.match, text.splitlines()) if m]
        if not any(o >= self.min_overlap for o, _, _ in self.queries) and self.in_map:
            sys.exit(f"{path}: {self.in_map} queries in the map but no per-query line with an overlap of "
                     f"{summary[1]} % or more")


def per_log_table(reports):
    first = reports[0]
    overlap = f"{100 * first.min_overlap:g}"
    for r in reports:
        if (r.min_overlap, r.max_err, r.max_deg) != (first.min_overlap, first.max_err, first.max_deg):
            sys.exit(f"{r.name}: counted with another overlap or tolerance than {first.name}; one table cannot hold both")
    lines = [f"| log | queries | in the map (overlap >= {overlap} %) | pose within {first.max_err:g} m / "
             f"{first.max_deg:g} deg | within {FINE[0]:g} m / {FINE[1]:g} deg | confident wrong | outside, confident | "
             "median / p95 ms |",
             "|---|---|---|---|---|---|---|---|"]
    for r in reports:
        # In the map and within the second tolerance (the refined pose; errors as the lines print them).
        fine = sum(1 for o, e, a in r.queries if o >= r.min_overlap and e < FINE[0] and a < FINE[1])
        conf, wrong = r.fields["confident"]
        out, out_conf = r.fields["outside"]
        median, p95 = r.fields["time"]
        lines.append(f"| {r.name} | {r.fields['queries'][0]} | {r.in_map} | {r.within} ({r.share} %) | "
                     f"{fine} ({100.0 * fine / max(1, r.in_map):.1f} %) | {wrong} of {conf} | {out_conf} of {out} | "
                     f"{median} / {p95} |")
    return "\n".join(lines) + "\n"


def by_overlap_table(reports):
    lines = ["| log | " + " | ".join(f"overlap {b[2]}" for b in BINS) + " |", "|---|" + "---|" * len(BINS)]
    for r in reports:
        counts = [[0, 0] for _ in BINS]
        for overlap, err, deg in r.queries:
            if overlap < r.min_overlap:
                continue
            for (low, high, _), c in zip(BINS, counts):
                if low <= overlap < high:
                    c[0] += err <= r.max_err and deg <= r.max_deg  # the printed errors, rounded as printed
                    c[1] += 1
        lines.append(f"| {r.name} | " + " | ".join(f"{c[0]} of {c[1]}" if c[1] else "-" for c in counts) + " |")
    return "\n".join(lines) + "\n"


def tables(paths):
    if not paths:
        sys.exit(__doc__.strip().splitlines()[-3])
    reports = sorted((Report(p) for p in paths),
                     key=lambda r: (TUNING.index(r.name) if r.name in TUNING else len(TUNING), r.name))
    return per_log_table(reports), "\n" + by_overlap_table(reports)


if __name__ == "__main__":
    readme_block.run(sys.argv[1:], "relocalisation", tables, "make relocalisation")
