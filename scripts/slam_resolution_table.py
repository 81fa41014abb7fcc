"""slam's resolution table (scripts/slam-resolution.sh): per raw log, the relation error as recorded and with the
whole run moved rigidly (scripts/log_variants.py moved-K, the variant read from the file name), their mean and
range, from build/slam_bench's JSON lines.
Usage: /usr/bin/python3 scripts/slam_resolution_table.py [--check TABLE.md] RUNS.jsonl
  (prints the table; --check prints nothing and exits 1 when TABLE.md is not the table of RUNS.jsonl)"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from slam_bench_table import cli  # noqa: E402

FLOORS = {"mit-csail": 0.064, "fr079": 0.045, "intel": 0.023, "aces": 0.038}  # issue 55 [m]


def main(path):
    runs = {}
    for line in open(path):
        if not line.strip():
            continue
        j = json.loads(line)
        parts = os.path.basename(j["log"]).split(".")
        variant = parts[1] if parts[1] not in ("clf", "log") else "as recorded"
        slam = j["slam"]["translation_m"]["mean"] if j.get("slam") else None
        runs.setdefault(parts[0], []).append((variant, slam, j.get("verdict", "-")))
    moves = sorted({v for rows in runs.values() for v, _, _ in rows if v != "as recorded"})
    print("| raw log | as recorded | " + " | ".join(moves) + " | mean | range | floor | verdicts |")
    print("|---|---|" + "---|" * len(moves) + "---|---|---|---|")
    for log, rows in runs.items():
        by = {v: s for v, s, _ in rows}
        values = [s for _, s, _ in rows if s is not None]
        cells = [f"{by[v]:.4f}" if by.get(v) is not None else "-" for v in ["as recorded"] + moves]
        mean = sum(values) / len(values) if values else None
        verdicts = ", ".join(sorted({f"{sum(d == x for _, _, d in rows)} {x}" for _, _, x in rows}))
        floor = FLOORS.get(log)
        print(f"| {log} | " + " | ".join(cells) + f" | {mean:.4f} | {min(values):.4f}-{max(values):.4f} | "
              f"{floor if floor else '-'} | {verdicts} |" if values else f"| {log} | no relation error |")
    print(f"\nslam's mean relation error [m] on each raw log as recorded and moved rigidly as a whole ({len(moves)} "
          "moves: every pose turned by 0.61 K rad and shifted by (3.7 K, -2.3 K) m); a change smaller than a "
          "log's range is within what moving the log does.")


if __name__ == "__main__":
    cli(main, __doc__, "make slam-resolution")
