#!/usr/bin/env python3
"""docs/USAGE.md's raw-log table, from what `make raw-logs` commits in docs/results: slam_LOG.json (the slam.json of
`partslam slam LOG --relations LOG.relations`: relation errors of the corrected and of the odometry's trajectory,
the stages' seconds) and loops_LOG.json (`partslam loops --truth`: the places closed at 100 % precision), beside
the published figures of two peers on the same relations.
Usage: /usr/bin/python3 scripts/raw_logs_table.py [--readme README.md | --check README.md] [FOLDER]
  (FOLDER: docs/results by default; prints the table; --readme also writes it into README.md's raw-logs block,
  --check prints nothing and exits 1 when that block is not the table)"""
import json
import pathlib
import sys

import readme_block

# fr079, intel and aces: the logs the defaults were chosen on; mit-csail: a building nothing here was tuned on.
LOGS = ("mit-csail", "fr079", "intel", "aces")
# Relation errors published for the same logs and relations: Hess et al. 2016 (Cartographer), and the
# Graph Mapping figures of Kuemmerle et al. 2009 as Hess et al. quote them.
CARTOGRAPHER = {"mit-csail": "0.032 m", "fr079": "0.0452 ± 0.0354 m, 0.538 ± 0.718°", "intel": "0.0229 ± 0.0239 m, 0.453 ± 1.335°",
                "aces": "0.0375 ± 0.0426 m, 0.373 ± 0.469°"}
GRAPH_MAPPING = {"mit-csail": "-", "fr079": "0.056 ± 0.042 m, 0.6 ± 0.6°", "intel": "0.031 ± 0.026 m, 1.3 ± 4.7°",
                 "aces": "0.044 ± 0.044 m, 0.4 ± 0.4°"}


class Json:
    """One JSON file, read once; field(*keys) exits naming the file and the key when it is not there."""

    def __init__(self, path):
        self.path = path
        try:
            self.value = json.loads(pathlib.Path(path).read_text())
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
            raise SystemExit(f"{path}: cannot read it ({e})")

    def field(self, *keys):
        value = self.value
        for k in keys:
            if not isinstance(value, dict) or k not in value:
                raise SystemExit(f"{self.path}: no '{'.'.join(keys)}' (make raw-logs writes it)")
            value = value[k]
        return value


def table(folder):
    folder = pathlib.Path(folder)
    rows = ["| raw log | relation error, translation [m] | rotation [deg] | Cartographer (Hess et al. 2016) | "
            "Graph Mapping (Kümmerle et al. 2009, as quoted by Hess et al.) | odometry, translation [m] | "
            "places closed by `loops` at 100 % precision | verdict | "
            "slam's stages (front end, loops, refinement, graph, neighbours, check) [s] |",
            "|---|---|---|---|---|---|---|---|---|"]
    for log in LOGS:
        slam = Json(folder / f"slam_{log}.json")
        ours, odometry = slam.field("relations", "slam"), slam.field("relations", "odometry")
        seconds = slam.field("seconds")
        closed = Json(folder / f"loops_{log}.json").field("evaluation", "query_recall_at_full_precision")
        t, r = ours["translation_m"], ours["rotation_deg"]
        rows.append(f"| {log} | {t['mean']:.4f} ± {t['std']:.3f} | {r['mean']:.2f} ± {r['std']:.2f} | "
                    f"{CARTOGRAPHER[log]} | {GRAPH_MAPPING[log]} | {odometry['translation_m']['mean']:.2f} | "
                    f"{100 * closed:.0f} % | {slam.field('verdict')} | "
                    f"{sum(v for k, v in seconds.items() if k != 'second_opinion'):.1f} |")  # beside the front end
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    readme_block.run(sys.argv[1:], "raw-logs", lambda args: (table(args[0] if args else "docs/results"), ""),
                     "make raw-logs")
