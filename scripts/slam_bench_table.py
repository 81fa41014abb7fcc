"""The SLAM bench's table (scripts/slam-bench.sh): one row per run of build/slam_bench, from its JSON lines."""
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


if __name__ == "__main__":
    main(sys.argv[1])
