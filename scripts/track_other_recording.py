#!/usr/bin/env python3
"""Tracking a run recorded in another format (docs/NOTES.md, "Tracking the same run from another file"): the map is
`partslam slam` of a CARMEN log, the tracked log the same run as a ROS bag (`locate --track --scan-match --json`), and
the reference is slam's own corrected pose of the same scan (the bags are re-timed and may list scans out of the
log's order, so scans are paired by their ranges: scripts/bag_relations.py's paired_scans). Per recording: the steps,
those localised, those localised more than 0.3 m / 3 deg from the reference (the issue's "declared wrong"), the
position error's median and largest, the travel to the first localised step, how often it said "lost" (never
right here: the robot is not carried anywhere), the steps not localised after the first localised one, and the
time per step. Writes one JSON line per recording with --out, and the table into FILE's markers with --readme.
--check FILE --from JSONL prints nothing and exits 1 when FILE's table is not the one the committed results give.
Usage: /usr/bin/python3 scripts/track_other_recording.py [--readme FILE] [--out JSONL] NAME:LOG:BAG:SLAM_DIR:TRACK_JSON...
       /usr/bin/python3 scripts/track_other_recording.py --check FILE --from JSONL
"""
import bisect
import json
import math
import os
import statistics
import sys

import readme_block
from bag_relations import paired_scans, partslam_module

WRONG_M, WRONG_RAD = 0.3, math.radians(3.0)


def angle(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def judge(name, log, bag, slam_dir, track_json):
    _, bag_scans, pair = paired_scans(log, bag)
    bag_times = [s.timestamp for s in bag_scans]
    corrected = os.path.join(slam_dir, "corrected.log")
    ref = [s.T_world_laser for s in partslam_module().load_scan_source(corrected).scans]
    if len(ref) != len(bag_times):
        sys.exit(f"{name}: {bag} has {len(bag_times)} scans, {corrected} {len(ref)}: the scans cannot be paired")
    try:
        track = json.load(open(track_json))
        tracked = track["tracked"]
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"{track_json}: not locate --track's JSON ({e})")
    slam = json.load(open(os.path.join(slam_dir, "slam.json")))
    errors, wrong, lost, unlocalised_after, first = [], 0, 0, 0, None
    for k, t in enumerate(tracked):
        status = t["status"]
        if status == "lost" and (k == 0 or tracked[k - 1]["status"] != "lost"):
            lost += 1
        if status != "localised":
            if first is not None:
                unlocalised_after += 1
            continue
        if first is None:
            first = k
        i = bisect.bisect_left(bag_times, t["log_time"]["from"] - 1e-6)  # the anchor scan (robot_pose's)
        x, y, th = ref[pair[min(i, len(pair) - 1)]]  # slam's pose of the log scan that is the bag's scan i
        r = t["robot_pose"]
        e, a = math.hypot(r["x"] - x, r["y"] - y), abs(angle(r["theta"] - th))
        errors.append(e)
        wrong += e > WRONG_M or a > WRONG_RAD
    times = sorted(t["time_ms"] for t in tracked)
    every = track.get("every", 2.0)
    return {
        "name": name, "log": os.path.basename(log), "bag": os.path.basename(bag),
        "slam_verdict": slam.get("verdict"), "steps": len(tracked), "localised": len(errors),
        "declared_wrong": wrong,
        "error_median_m": statistics.median(errors) if errors else None,
        "error_max_m": max(errors) if errors else None,
        "first_localised_travel_m": None if first is None else (first + 1) * every,
        "lost": lost, "not_localised_after_first": unlocalised_after,
        "step_median_ms": statistics.median(times) if times else None,
        "step_p95_ms": times[min(len(times) - 1, int(math.ceil(0.95 * len(times))) - 1)] if times else None,
    }


def table(rows):
    lines = ["| run (map from / tracked) | slam's verdict | steps | localised | declared wrong (> 0.3 m / 3 deg) | "
             "error median / max m | first localised after | said lost | steps not localised after the first | "
             "step median / p95 ms |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        err = "-" if r["error_median_m"] is None else f"{r['error_median_m']:.3f} / {r['error_max_m']:.3f}"
        first = "never" if r["first_localised_travel_m"] is None else f"{r['first_localised_travel_m']:g} m"
        lines.append(f"| {r['name']} ({r['log']} / {r['bag']}) | {r['slam_verdict']} | {r['steps']} | "
                     f"{r['localised']} ({100.0 * r['localised'] / max(r['steps'], 1):.1f} %) | {r['declared_wrong']} | "
                     f"{err} | {first} | {r['lost']} | {r['not_localised_after_first']} | "
                     f"{r['step_median_ms']:.1f} / {r['step_p95_ms']:.1f} |")
    return "\n".join(lines)


def main(argv):
    readme = out = check = source = None
    specs = []
    it = iter(argv)
    for a in it:
        if a == "--readme":
            readme = next(it, None)
        elif a == "--out":
            out = next(it, None)
        elif a == "--check":
            check = next(it, None)
        elif a == "--from":
            source = next(it, None)
        else:
            specs.append(a)
    if check or source:
        if not (check and source) or specs:
            sys.exit(__doc__.strip().splitlines()[-1])
        try:
            rows = [json.loads(line) for line in open(source) if line.strip()]
        except (OSError, ValueError) as e:
            sys.exit(f"{source}: cannot read it ({e})")
        if not readme_block.is_current(check, "other-recording", table(rows) + "\n"):
            sys.exit(f"{check}: the other-recording table is not the one {source} gives "
                     "(scripts/track-other-recording.sh rewrites both)")
        return
    if not specs or any(len(s.split(":")) != 5 for s in specs):
        sys.exit(__doc__.strip().splitlines()[-1])
    rows = [judge(*s.split(":")) for s in specs]
    text = table(rows)
    print(text)
    if out:
        readme_block.write_atomically(out, "".join(json.dumps(r, sort_keys=True) + "\n" for r in rows))
    if readme:
        readme_block.replace(readme, "other-recording", text + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
