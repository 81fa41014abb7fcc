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


def run_errors(j):
    """A run's slam, odometry and front-end cells, slam's error [m] (None: no relation) and whether slam is worse
    than the odometry."""
    slam, s = err(j["slam"])
    odom, o = err(j["odometry"])
    fe, _ = err(j["front_end"])
    return slam, odom, fe, s, s is not None and o is not None and s > o


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


# Published relation errors of Cartographer on the same relations (Hess et al. 2016; mit-csail as quoted in the
# tracker), translation [m].
CARTOGRAPHER = {"mit-csail": 0.032, "fr079": 0.0452, "intel": 0.0229, "aces": 0.0375}


def is_bag(r):
    """A raw run read from a ROS bag (the same run as a CARMEN log's, re-timed)."""
    return r["kind"] == "raw" and os.path.basename(r["log"]).endswith((".bag", ".mcap"))


def peers_table(rows, path):
    """The raw logs first: slam's clean run beside MRPT's peers (scripts/mrpt-peers.sh, mrpt_peers.jsonl beside
    the runs) and Cartographer's published figure."""
    peers_file = os.path.join(os.path.dirname(path), "mrpt_peers.jsonl")
    peers = {}
    if os.path.exists(peers_file):
        for line in open(peers_file):
            if line.strip():
                p = json.loads(line)
                peers[(p["log"], p["peer"])] = p
    print("| raw log | slam | slam time | MRPT rbpf-slam (ICP) | its time | MRPT icp-slam | its time | Cartographer |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        if r["kind"] != "raw" or r["inject"] != 0:
            continue
        log = os.path.basename(r["log"]).split(".")[0]
        bag = is_bag(r)
        slam, _ = err(r["slam"])
        cells = []
        for peer in ("rbpf-slam", "icp-slam"):
            p = None if bag else peers.get((log, peer))
            if p is None:
                cells += ["not run", "-"]
            elif p["status"] != "ok":
                cells += [p["status"], f'{p["wall_s"]:.0f} s']
            elif "trans_mean_m" not in p:
                cells += ["no relations", f'{p["wall_s"]:.0f} s']
            else:
                cells += [f'{p["trans_mean_m"]:.3f} ± {p["trans_std_m"]:.3f} m, {p["rot_mean_deg"]:.2f}°',
                          f'{p["wall_s"]:.0f} s']
        carto = f'{CARTOGRAPHER[log]} m' if log in CARTOGRAPHER and not bag else "-"
        print(f'| {log}{" (ROS 1 bag)" if bag else ""} | {slam}, {r.get("verdict", "-")} | {r["seconds"]:.1f} s | {" | ".join(cells)} | {carto} |')
    print("\n(slam: one thread, its whole run; the peers: the whole process under `nice`, one at a time, beside "
          "other work. fr101 has no relations file: slam's figure uses relations built from its corrected twin.)\n")


def main(path):
    rows = [json.loads(line) for line in open(path) if line.strip()]
    peers_table(rows, path)
    print("| input | odometry | injected wrong closures | relations | slam | odometry | front end only | closures offered "
          "| injected (used) | map check: crossing beams, all / worst place | verdict | time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    worse = 0
    for j in rows:
        name = os.path.basename(j["log"]).split(".")[0].replace("-corrected", "")
        if j["kind"] == "raw":
            name += " (ROS 1 bag)" if is_bag(j) else " (raw)"
        odo = "real" if j["kind"] == "raw" else f'{j["level"]} seed {j["seed"]}'
        slam, odom, fe, s, worse_than_odometry = run_errors(j)
        flag = " **worse than odometry**" if worse_than_odometry else ""
        worse += worse_than_odometry
        c = j["closures"]
        verdict = j.get("verdict", "-")
        inject = f'{j["inject"]:g}' + (" forced" if j.get("forced") else "")
        judged = j["kind"] == "raw" and c["judged"] == 0 and c["accepted"] > 0  # no twin: closures not judged
        print(f'| {name} | {odo} | {inject} | {j["slam"].get("relations", 0)} | {slam}{flag} | {odom} | {fe} '
              f'| {c["accepted"]} ({c["wrong"]} wrong, {c.get("used_wrong", 0)} of them used{", not judged" if judged else ""}) '
              f'| {c["injected"]} ({c.get("injected_used", 0)}) | {check(j)} | {verdict} | {j["seconds"]:.1f} s |')
    forced_worse = sum(1 for r in rows if r.get("forced") and r["slam"].get("relations") and r["odometry"].get("relations")
                       and r["slam"]["translation_m"]["mean"] > r["odometry"]["translation_m"]["mean"])
    forced_trusted = sum(1 for r in rows if r.get("forced") and r.get("verdict") in ("closed", "open"))
    print(f"\n{len(rows)} runs; slam worse than odometry on {worse} ({forced_worse} of them with forced wrong closures); "
          f"runs with forced wrong closures trusted: {forced_trusted} of {sum(1 for r in rows if r.get('forced'))}.")
    verdict_floors(rows)
    # The floors of the bench (docs/NOTES.md "SLAM bench"), run by run.
    over = [r for r in rows if r["kind"] != "raw" and r["slam"].get("relations") and not r.get("forced") and
            r["slam"]["translation_m"]["mean"] > 0.10]
    used_wrong = [r for r in rows if r["closures"].get("used_wrong", 0) > 0 and not r.get("forced")]
    print(f"drifted twins and simulations over 0.10 m (runs with forced closures apart): {len(over)} of "
          f"{sum(1 for r in rows if r['kind'] != 'raw' and not r.get('forced'))}" +
          "".join(f"\n- {os.path.basename(r['log']).split('.')[0]} {r['level']} seed {r['seed']} inject {r['inject']:g}: "
                  f"{r['slam']['translation_m']['mean']:.3f} m" for r in over))
    print(f"runs that used a closure more than 0.5 m / 5 degrees from the truth (forced apart): {len(used_wrong)}" +
          "".join(f"\n- {label(r)}: {r['closures']['used_wrong']} of {r['closures']['used']} used" for r in used_wrong))
    clean = {}
    for r in rows:
        key = (r["log"], r["kind"], r.get("level"), r.get("seed"))
        if r["inject"] == 0 and r["slam"].get("relations"):
            clean[key] = r["slam"]["translation_m"]["mean"]
    ratios = []
    for r in rows:
        key = (r["log"], r["kind"], r.get("level"), r.get("seed"))
        if r["inject"] > 0 and not r.get("forced") and key in clean and r["slam"].get("relations"):
            ratios.append((r["slam"]["translation_m"]["mean"] / clean[key], r))
    if ratios:
        worst = max(ratios, key=lambda x: x[0])
        print(f"with injected wrong closures, the largest error / clean run's: {worst[0]:.3f} "
              f"({os.path.basename(worst[1]['log']).split('.')[0]}, inject {worst[1]['inject']:g})")


def cli(main, doc, make_target):
    """`SCRIPT RUNS.jsonl` prints main's table; `SCRIPT --check TABLE.md RUNS.jsonl` exits 1 when TABLE.md is not it."""
    if len(sys.argv) == 4 and sys.argv[1] == "--check":
        made = io.StringIO()
        with contextlib.redirect_stdout(made):
            main(sys.argv[3])
        try:
            current = open(sys.argv[2]).read()
        except (OSError, UnicodeDecodeError) as e:
            sys.exit(f"{sys.argv[2]}: cannot read it ({e})")
        if current != made.getvalue():
            sys.exit(f"{sys.argv[2]} is not the table of {sys.argv[3]} ({make_target} rewrites both)")
    elif len(sys.argv) == 2:
        main(sys.argv[1])
    else:
        sys.exit(doc.strip().splitlines()[-2])


if __name__ == "__main__":
    cli(main, __doc__, "make slam-bench")
