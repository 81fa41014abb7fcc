#!/usr/bin/env python3
"""A relations file (Kümmerle et al. 2009: `t1 t2 x y z roll pitch yaw` per line, t1 and t2 a CARMEN log's scan
timestamps) carried onto a re-timed recording of the same run when the log it names is not at hand, so that
scripts/bag_relations.py cannot pair the scans by their ranges. MIT Killian Court's bag from INESCTEC/ricoslam is
one: its scans are stamped t0 + i / 10 s and the log's own .clf is not published beside it.

Each relation stamp is paired with a scan of POSES, a trajectory of the recording's scans that is right locally
(`partslam slam`'s corrected.log of it), by a Viterbi over the stamps in time order: a pairing costs the squared
difference between each relation of consecutive stamps and POSES's relative pose between the paired scans, plus
TIME_WEIGHT times the squared difference between the scans skipped and the log time between the stamps in scans
(the log's mean scan interval), and the scans must come in the stamps' order. Where the pairing is known (fr079 and
mit-csail, whose bags scripts/bag_relations.py pairs by ranges) it finds the same scans for 3364 of 3370 and 2344 of
2344 relation ends, and slam's relation error comes out the same to 0.1 mm (docs/NOTES.md, "MIT Killian Court's
relation error"). Pairing by the odometry instead puts most stamps one scan early on those bags and overstates
slam's error by 0.02 m, so POSES should be scan-matched. A POSES wrong by more than a scan's travel across a
relation's span would be paired around its error: the residual printed says how well the relations fit.

Assumes the relations span the recording (their first and last stamps near its first and last scans: the window
is placed by the log's mean scan interval over that span) and compares them with POSES's laser poses (a laser
mounted off the robot's origin adds about its offset times the turn to the misfit). Refuses (exit 1, nothing
written) when the mean residual of the consecutive relations is over MAX_RESIDUAL or a pairing lies at the edge of
the search window (the scans not evenly spaced enough in time, or the relations spanning only part of the run).
Usage: /usr/bin/python3 scripts/retimed_relations.py POSES RELATIONS OUT"""
import math
import sys

import numpy as np

from bag_relations import partslam_module, read_relations, write_atomically

WINDOW = 150          # scans either side of a stamp's place at the log's mean scan interval that are searched
TIME_WEIGHT = 0.002   # [m^2 per scan^2]: a scan skipped against the clock costs as much as 4.5 cm of misfit
TURN_WEIGHT = 0.5     # [m / rad]
MAX_RESIDUAL = 0.1    # [m]: mean misfit of the consecutive relations beyond which the pairing is refused


def relative(X, Y, T, a, b):
    """Where the scans b lie in the frames of the scans a (indices or index arrays): x, y and the turn."""
    dx, dy, co, si = X[b] - X[a], Y[b] - Y[a], np.cos(T[a]), np.sin(T[a])
    return co * dx + si * dy, -si * dx + co * dy, T[b] - T[a]


def pair_stamps(stamps, poses, consecutive, what):
    """For each of the sorted relation stamps, the index of its scan among the scans of `poses` (x, y, theta rows);
    `consecutive[j]` is the relation (x, y, theta) from stamp j to stamp j + 1 where there is one. Returns the
    indices, the consecutive relations' residuals and how many pairings lie at the window's edge; exits naming
    `what` when no pairing exists."""
    n, m = len(poses), len(stamps)
    dt = (stamps[-1] - stamps[0]) / max(n - 1, 1)  # the log's mean scan interval, if it spans the recording
    if dt <= 0:
        sys.exit(f"{what}: the relations name a single timestamp, nothing to pair them by")
    place = np.round((stamps - stamps[0]) / dt).astype(int)
    X, Y, T = poses[:, 0], poses[:, 1], poses[:, 2]

    def window(j):
        return np.arange(max(0, place[j] - WINDOW), min(n, place[j] + WINDOW + 1))

    prev = window(0)
    cost = np.zeros(len(prev))
    back = []
    for j in range(1, m):
        cur = window(j)
        k, kp = cur[None, :], prev[:, None]
        c = cost[:, None] + TIME_WEIGHT * (k - kp - (stamps[j] - stamps[j - 1]) / dt) ** 2
        if j - 1 in consecutive:
            rx, ry, rt = consecutive[j - 1]
            x, y, t = relative(X, Y, T, kp, k)
            turn = np.arctan2(np.sin(t - rt), np.cos(t - rt))
            c = c + (x - rx) ** 2 + (y - ry) ** 2 + (TURN_WEIGHT * turn) ** 2
        c = np.where(k > kp, c, np.inf)
        arg = np.argmin(c, axis=0)
        best = c[arg, np.arange(len(cur))]
        if not np.isfinite(best).any():
            sys.exit(f"{what}: no order of scans fits the relations' stamps around {stamps[j]:.6f} (do the relations "
                     "span the recording?)")
        back.append((prev, arg))
        cost, prev = np.where(np.isfinite(best), best, np.inf), cur
    idx = [int(prev[int(np.argmin(cost))])]
    for j in range(m - 1, 0, -1):
        p, arg = back[j - 1]
        idx.append(int(p[arg[idx[-1] - window(j)[0]]]))
    idx = np.array(idx[::-1])
    j = np.array(list(consecutive))
    x, y, _ = relative(X, Y, T, idx[j], idx[j + 1])
    residual = np.hypot(x - [consecutive[i][0] for i in j], y - [consecutive[i][1] for i in j])
    edge = int(np.sum(np.abs(idx - place) == WINDOW))
    return idx, residual, edge


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__.strip().splitlines()[-1])
    poses_path, relations, out = argv
    rows = read_relations(relations)
    scans = partslam_module().load_scan_source(poses_path).scans
    if len(scans) < 2:
        sys.exit(f"{poses_path}: fewer than two scans")
    times = np.array([s.timestamp for s in scans])
    poses = np.array([tuple(s.T_world_laser) for s in scans], dtype=float)
    stamps = np.array(sorted({r[0] for r, _, _ in rows} | {r[1] for r, _, _ in rows}))
    at = {s: j for j, s in enumerate(stamps)}
    consecutive = {}
    for (t1, t2, x, y, _, _, _, yaw), _, _ in rows:
        a, b = at[t1], at[t2]
        if b == a + 1:
            consecutive.setdefault(a, (x, y, yaw))  # the first of several between the same stamps
        elif a == b + 1:  # the same relation the other way round
            c, s = math.cos(yaw), math.sin(yaw)
            consecutive.setdefault(b, (-(c * x + s * y), s * x - c * y, -yaw))
    if not consecutive:
        sys.exit(f"{relations}: no relation between consecutive timestamps to pair them by")
    idx, residual, edge = pair_stamps(stamps, poses, consecutive, f"{relations} against {poses_path}")
    print(f"{len(stamps)} timestamps paired with scans of {poses_path}; {len(residual)} relations between "
          f"consecutive ones fit its poses to {residual.mean():.4f} m (median {np.median(residual):.4f}, max "
          f"{residual.max():.3f}); {edge} at the search window's edge")
    if residual.mean() > MAX_RESIDUAL or edge:
        sys.exit(f"{relations}: not paired with {poses_path} (mean residual {residual.mean():.3f} m, limit "
                 f"{MAX_RESIDUAL}; {edge} pairings at the window's edge): nothing written")
    time_of = dict(zip(stamps, times[idx]))
    write_atomically(out, [f"{time_of[r[0]]:.6f} {time_of[r[1]]:.6f} {' '.join(text)}\n" for r, text, _ in rows])


if __name__ == "__main__":
    main(sys.argv[1:])
