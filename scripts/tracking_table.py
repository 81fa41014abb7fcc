#!/usr/bin/env python3
"""The tracking table, from the reports build/tracking_check writes (docs/results/tracking_LOG_NOISE.txt, through
scripts/make-relocalisation.sh): per log and odometry noise, the runs, the starts whose first 20 m stay in the map
and how many of them were localised (right) within 20 m, the single-shot answer on the same starts, the true pose
among the first step's hypotheses, the travel to the first localised step (median / p90), the steps declared
localised at a wrong pose, the kidnappings (localised at the jump, the new place in the map) noticed and
recovered, the in-map steps localised, and the time per step (median / p95, one core). Every figure is read from
the report's own `summary:` line. Rows: the tuning logs first (fr079, intel), then the others by name.
Usage: /usr/bin/python3 scripts/tracking_table.py [--readme FILE | --check FILE] REPORT...
  --readme FILE  also replaces the block between FILE's tracking markers with the table
  --check FILE   prints nothing; exits 1 when FILE's block is not the table of the reports"""
import os
import re
import sys

import readme_block

TUNING = ("fr079", "intel")
SUMMARY = re.compile(
    r"^summary: noise (\w+) \| runs (\d+) \| eligible (\d+) \| localised within ([\d.]+) m (\d+) \(([\d.]+) %\) "
    r"\| single-shot (\d+) \(([\d.]+) %\) \| truth among first hypotheses (\d+) \(([\d.]+) %\) "
    r"\| travel to converge median (-?[\d.]+) m p90 (-?[\d.]+) m \| declared wrong (\d+) of (\d+) steps \(in the map (\d+)\) "
    r"\| kidnappings (\d+) noticed (\d+) recovered (\d+) \(([\d.]+) %\) \| in-map steps localised (\d+) of (\d+) "
    r"\(([\d.]+) %\) \| step median ([\d.]+) ms p95 ([\d.]+) ms$", re.M)


def row(path):
    try:
        text = open(path).read()
    except (OSError, UnicodeDecodeError) as e:
        sys.exit(f"{path}: cannot read it ({e})")
    m = SUMMARY.search(text)
    if not m:
        sys.exit(f"{path}: no 'summary: noise ...' line (not a tracking_check report)")
    (noise, runs, eligible, within, localised, localised_pct, single, single_pct, first, first_pct, median, p90,
     wrong, steps, wrong_in_map, kidnaps, noticed, recovered, recovered_pct, in_map_ok, in_map, in_map_pct,
     step_median, step_p95) = m.groups()
    name = os.path.basename(path).removeprefix("tracking_").removesuffix(".txt").rsplit("_", 1)[0]
    some = int(eligible) > 0
    cells = [name, noise, runs, eligible,
             f"{localised} ({localised_pct} %)" if some else "-",
             f"{single} ({single_pct} %)" if some else "-",
             f"{first} ({first_pct} %)" if some else "-",
             f"{median} / {p90}" if some else "-",
             f"{wrong} of {steps}",
             f"{noticed} / {recovered} of {kidnaps}" if int(kidnaps) else "-",
             f"{in_map_ok} of {in_map} ({in_map_pct} %)" if int(in_map) else "-",
             f"{step_median} / {step_p95}"]
    key = (TUNING.index(name) if name in TUNING else len(TUNING), name, noise != "mild")
    return key, "| " + " | ".join(cells) + " |", within


def table(paths):
    if not paths:
        sys.exit(__doc__.strip().splitlines()[-3])
    rows = sorted(row(p) for p in paths)
    within = rows[0][2]
    lines = [f"| log | odometry | runs | starts in the map | localised within {within} m | single-shot | truth among "
             "the first hypotheses | travel to localised, median / p90 m | steps declared wrong | kidnappings "
             "noticed / recovered | in-map steps localised | step median / p95 ms |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lines += [r[1] for r in rows]
    return "\n".join(lines) + "\n", ""


if __name__ == "__main__":
    readme_block.run(sys.argv[1:], "tracking", table, "make relocalisation")
