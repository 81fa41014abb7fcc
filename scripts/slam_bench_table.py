"""The SLAM bench's table (scripts/slam-bench.sh): one row per run of build/slam_bench, from its JSON lines.
Usage: /usr/bin/python3 scripts/slam_bench_table.py [--check TABLE.md] RUNS.jsonl
  (prints the table; --check prints nothing and exits 1 when TABLE.md is not the table of RUNS.jsonl)"""
import contextlib
import io
import json
import os
import sys


def err(e):
    if not e.get("relations"):
        return "no relation matched", None
    t, r = e["translation_m"], e["rotation_deg"]
    return f'{t["mean"]:.3f} ± {t["std"]:.3f} m, {r["mean"]:.2f}°', t["mean"]


def main(path):
    rows = [json.loads(line) for line in open(path) if line.strip()]
    print("| input | odometry | injected wrong closures | relations | slam | odometry | front end only | closures offered "
          "| injected (used) | verdict | time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    worse = 0
    for j in rows:
        name = os.path.basename(j["log"]).split(".")[0].replace("-corrected", "")
        if j["kind"] == "raw":
            name += " (raw)"
        odo = "real" if j["kind"] == "raw" else f'{j["level"]} seed {j["seed"]}'
        slam, s = err(j["slam"])
        odom, o = err(j["odometry"])
        fe, _ = err(j["front_end"])
        flag = ""
        if s is not None and o is not None and s > o:
            flag, worse = " **worse than odometry**", worse + 1
        c = j["closures"]
        verdict = j.get("verdict", "-")
        print(f'| {name} | {odo} | {j["inject"]:g} | {j["slam"].get("relations", 0)} | {slam}{flag} | {odom} | {fe} '
              f'| {c["accepted"]} ({c["wrong"]} wrong, {c.get("used_wrong", 0)} of them used) '
              f'| {c["injected"]} ({c.get("injected_used", 0)}) | {verdict} | {j["seconds"]:.1f} s |')
    print(f"\n{len(rows)} runs; slam worse than odometry on {worse}.")
    # The floors of the bench (docs/NOTES.md "SLAM bench"), run by run.
    over = [r for r in rows if r["kind"] != "raw" and r["slam"].get("relations") and
            r["slam"]["translation_m"]["mean"] > 0.10]
    used_wrong = [r for r in rows if r["closures"].get("used_wrong", 0) > 0]
    print(f"drifted twins and simulations over 0.10 m: {len(over)} of "
          f"{sum(1 for r in rows if r['kind'] != 'raw')}" +
          "".join(f"\n- {os.path.basename(r['log']).split('.')[0]} {r['level']} seed {r['seed']} inject {r['inject']:g}: "
                  f"{r['slam']['translation_m']['mean']:.3f} m" for r in over))
    print(f"runs that used a closure more than 0.5 m / 5 degrees from the truth: {len(used_wrong)}" +
          "".join(f"\n- {os.path.basename(r['log']).split('.')[0]} {r.get('level', 'raw')} seed {r.get('seed', '-')} "
                  f"inject {r['inject']:g}: {r['closures']['used_wrong']} of {r['closures']['used']} used"
                  for r in used_wrong))
    clean = {}
    for r in rows:
        key = (r["log"], r["kind"], r.get("level"), r.get("seed"))
        if r["inject"] == 0 and r["slam"].get("relations"):
            clean[key] = r["slam"]["translation_m"]["mean"]
    ratios = []
    for r in rows:
        key = (r["log"], r["kind"], r.get("level"), r.get("seed"))
        if r["inject"] > 0 and key in clean and r["slam"].get("relations"):
            ratios.append((r["slam"]["translation_m"]["mean"] / clean[key], r))
    if ratios:
        worst = max(ratios, key=lambda x: x[0])
        print(f"with injected wrong closures, the largest error / clean run's: {worst[0]:.3f} "
              f"({os.path.basename(worst[1]['log']).split('.')[0]}, inject {worst[1]['inject']:g})")


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--check":
        made = io.StringIO()
        with contextlib.redirect_stdout(made):
            main(sys.argv[3])
        try:
            current = open(sys.argv[2]).read()
        except (OSError, UnicodeDecodeError) as e:
            sys.exit(f"{sys.argv[2]}: cannot read it ({e})")
        if current != made.getvalue():
            sys.exit(f"{sys.argv[2]} is not the table of {sys.argv[3]} (make slam-bench rewrites both)")
    elif len(sys.argv) == 2:
        main(sys.argv[1])
    else:
        sys.exit(__doc__.strip().splitlines()[-2])
