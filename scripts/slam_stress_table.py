"""The SLAM stress bench's table (scripts/slam-stress.sh): one row per run of build/slam_bench on a raw log as
recorded or degraded by scripts/log_variants.py (the variant read from the file name), from its JSON lines.
Usage: /usr/bin/python3 scripts/slam_stress_table.py [--check TABLE.md] RUNS.jsonl
  (prints the table; --check prints nothing and exits 1 when TABLE.md is not the table of RUNS.jsonl)"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from slam_bench_table import check, cli, run_errors  # noqa: E402


def main(path):
    rows = [json.loads(line) for line in open(path) if line.strip()]
    print("| raw log | variant | slam | odometry | front end only | map check: crossing beams, all / worst place "
          "| verdict | time |")
    print("|---|---|---|---|---|---|---|---|")
    worse, wrong_trusted, over = 0, [], 0
    for j in rows:
        parts = os.path.basename(j["log"]).split(".")
        log, variant = parts[0], parts[1] if parts[1] not in ("clf", "log") else "as recorded"
        slam, odom, fe, s, worse_than_odometry = run_errors(j)
        flag = " **worse than odometry**" if worse_than_odometry else ""
        worse += worse_than_odometry
        trusted = j.get("verdict") in ("closed", "open")
        if s is not None and s > 0.15:
            over += 1
            if trusted:
                wrong_trusted.append(f"{log} {variant}")
        print(f'| {log} | {variant} | {slam}{flag} | {odom} | {fe} | {check(j)} | {j.get("verdict", "-")} '
              f'| {j["seconds"]:.1f} s |')
    print(f"\n{len(rows)} runs (one thread each); slam worse than odometry on {worse}; results over 0.15 m: {over}, "
          f"trusted: {len(wrong_trusted)}" + "".join(f"\n- {w}" for w in wrong_trusted))


if __name__ == "__main__":
    cli(main, __doc__, "make slam-stress")
