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


def check(j):
    m = j.get("map_check")
    if not m:
        return "-"
    if not m["judged"]:
        return "not judged"
    return f'{100 * m["share"]:.1f} % / {100 * m["worst_share"]:.1f} %' + ("" if m["passed"] else " **failed**")


def verdict_floors(rows):
    """The verdict's floors (issue: no trusted result over 0.15 m; at most 10 % of those under 0.10 m untrusted)."""
    trusted = lambda r: r.get("verdict") in ("closed", "open")
    scored = [r for r in rows if r["slam"].get("relations")]
    bad_trusted = [r for r in scored if trusted(r) and r["slam"]["translation_m"]["mean"] > 0.15]
    good = [r for r in scored if r["slam"]["translation_m"]["mean"] < 0.10]
    good_flagged = [r for r in good if not trusted(r)]
    over = [r for r in scored if r["slam"]["translation_m"]["mean"] > 0.15]
    print(f"verdict: trusted results over 0.15 m: {len(bad_trusted)} of {len(over)} results over 0.15 m" +
          "".join(f"\n- {label(r)}: {r['slam']['translation_m']['mean']:.3f} m, {r['verdict']}" for r in bad_trusted))
    print(f"verdict: results under 0.10 m not trusted: {len(good_flagged)} of {len(good)}" +
          "".join(f"\n- {label(r)}: {r['slam']['translation_m']['mean']:.3f} m, {r['verdict']} ({r.get('reason', '')})"
                  for r in good_flagged))


def label(r):
    name = os.path.basename(r["log"]).split(".")[0].replace("-corrected", "")
    what = "raw" if r["kind"] == "raw" else f'{r["level"]} seed {r["seed"]}'
    return f'{name} {what} inject {r["inject"]:g}{" forced" if r.get("forced") else ""}'


def main(path):
    rows = [json.loads(line) for line in open(path) if line.strip()]
    print("| input | odometry | injected wrong closures | relations | slam | odometry | front end only | closures offered "
          "| injected (used) | map check: crossing beams, all / worst place | verdict | time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
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
        inject = f'{j["inject"]:g}' + (" forced" if j.get("forced") else "")
        judged = j["kind"] == "raw" and c["judged"] == 0 and c["accepted"] > 0  # no twin: closures not judged
        print(f'| {name} | {odo} | {inject} | {j["slam"].get("relations", 0)} | {slam}{flag} | {odom} | {fe} '
              f'| {c["accepted"]} ({c["wrong"]} wrong, {c.get("used_wrong", 0)} of them used{", not judged" if judged else ""}) '
              f'| {c["injected"]} ({c.get("injected_used", 0)}) | {check(j)} | {verdict} | {j["seconds"]:.1f} s |')
    print(f"\n{len(rows)} runs; slam worse than odometry on {worse}.")
    verdict_floors(rows)
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
