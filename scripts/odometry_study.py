"""What a raw log's wheel odometry could add to slam's poses, judged by the log's relations (docs/NOTES.md, "The
bench's resolution, and where aces's error is"). A study, not a stage of slam: it reads slam's corrected log.
Usage: /usr/bin/python3 scripts/odometry_study.py CORRECTED.log RAW.clf[.gz] RELATIONS
  CORRECTED.log  `partslam slam RAW --out DIR`'s DIR/corrected.log (its FLASER poses, the raw log's timestamps)
  RAW            the raw log (its FLASER poses are the odometry's)
  RELATIONS      the Freiburg relations file of the run
Prints:
  1. the mean relation error by the relations' time span (< 2 s, 2-20 s, longer), slam's and the odometry's;
  2. the odometry's timing: each matched step (slam's pose to the next, in the robot's frame) regressed on the
     odometry's steps i-1, i and i+1 (one in step with the scans gives about 0, 1, 0; half a scan ahead, about
     0.5, 0.5, 0);
  3. a smoother of slam's positions with those calibrated odometry steps (per axis, a chain least squares: each
     position held to slam's by the matches' noise, each step to the odometry's by its noise; the noise levels from
     the residual of 2.: the matches' white noise makes consecutive residuals anti-correlated, -cov1 = sigma_e^2,
     and the rest of their variance is the odometry's) and its relation error: the translation of a fusion that
     estimates its own weights, not slam's output."""
import bisect
import gzip
import math
import sys

import numpy as np


def flaser_poses(path):
    """(timestamp, (x, y, theta)) of every FLASER line, in the file's order."""
    out = []
    with (gzip.open(path, "rt") if path.endswith(".gz") else open(path)) as f:
        for line in f:
            if not line.startswith("FLASER"):
                continue
            v = line.split()
            n = int(v[1])
            out.append((float(v[8 + n]), tuple(float(x) for x in v[2 + n:5 + n])))
    return out


def relative(a, b):
    """b in a's frame: (x, y, theta)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2])))


def nearest(times, poses, t):
    i = bisect.bisect_left(times, t)
    j = min(range(max(0, i - 1), min(len(times), i + 1)), key=lambda k: abs(times[k] - t))
    return poses[j]


def relations(path):
    with open(path) as f:
        return [(float(v[0]), float(v[1]), float(v[2]), float(v[3])) for v in (l.split() for l in f) if len(v) >= 8]


def errors_by_span(times, poses, rels):
    spans = {"< 2 s": [], "2-20 s": [], "longer": []}
    for t1, t2, x, y in rels:
        r = relative(nearest(times, poses, t1), nearest(times, poses, t2))
        e = math.hypot(r[0] - x, r[1] - y)
        spans["< 2 s" if t2 - t1 < 2 else "2-20 s" if t2 - t1 < 20 else "longer"].append(e)
    return spans


def chain_smooth(positions, steps, w_pose, w_step):
    """argmin sum w_pose (p_i - positions_i)^2 + sum w_step (p_i - p_(i-1) - steps_i)^2 (Thomas algorithm)."""
    n = len(positions)
    diag = np.full(n, w_pose)
    diag[1:] += w_step
    diag[:-1] += w_step
    rhs = w_pose * positions
    rhs[1:] += w_step * steps
    rhs[:-1] -= w_step * steps
    c, d = np.zeros(n), np.zeros(n)
    c[0], d[0] = -w_step / diag[0], rhs[0] / diag[0]
    for i in range(1, n):
        den = diag[i] + w_step * c[i - 1]
        c[i] = -w_step / den
        d[i] = (rhs[i] + w_step * d[i - 1]) / den
    x = np.zeros(n)
    x[-1] = d[-1]
    for i in range(n - 2, -1, -1):
        x[i] = d[i] - c[i] * x[i + 1]
    return x


def main(corrected, raw, rel_path):
    slam = flaser_poses(corrected)
    odometry = dict((round(t, 6), p) for t, p in flaser_poses(raw))
    times = [t for t, _ in slam]
    missing = [t for t in times if round(t, 6) not in odometry]
    if missing:
        sys.exit(f"{raw}: no FLASER line at {missing[0]:.6f} s, a scan of {corrected}: not the same run")
    M = np.array([p for _, p in slam])
    O = np.array([odometry[round(t, 6)] for t in times])
    rels = relations(rel_path)
    print("1. relation error by span [m] (count): slam | odometry")
    s_err = errors_by_span(times, [tuple(p) for p in M], rels)
    o_err = errors_by_span(times, [tuple(p) for p in O], rels)
    for k in s_err:
        if s_err[k]:
            print(f"   {k:7s} {np.mean(s_err[k]):.4f} | {np.mean(o_err[k]):.4f} ({len(s_err[k])})")
    m = np.array([relative(M[i - 1], M[i]) for i in range(1, len(M))])
    o = np.array([relative(O[i - 1], O[i]) for i in range(1, len(O))])
    calibrated = o.copy()
    print("2. matched step ~ odometry steps i-1, i, i+1 (coefficients):")
    for k, name in enumerate(("forward", "sideways", "turn")):
        X = np.stack([o[:-2, k], o[1:-1, k], o[2:, k]], 1)
        coef = np.linalg.lstsq(X, m[1:-1, k], rcond=None)[0]
        calibrated[1:-1, k] = X @ coef
        print(f"   {name:8s} {coef[0]:+.2f} {coef[1]:+.2f} {coef[2]:+.2f}")
    res = m[1:-1, :2] - calibrated[1:-1, :2]
    var = np.mean(np.sum(res ** 2, 1)) / 2
    cov1 = np.mean(np.sum(res[1:] * res[:-1], 1)) / 2
    sigma_e2 = max(-cov1, 1e-10)
    q = max(var - 2 * sigma_e2, 1e-10)
    world = np.zeros((len(o), 2))
    for i in range(len(o)):
        c, s = math.cos(M[i][2]), math.sin(M[i][2])
        world[i] = (c * calibrated[i][0] - s * calibrated[i][1], s * calibrated[i][0] + c * calibrated[i][1])
    smoothed = M.copy()
    for ax in (0, 1):
        smoothed[:, ax] = chain_smooth(M[:, ax], world[:, ax], 1 / sigma_e2, 1 / q)
    f_err = errors_by_span(times, [tuple(p) for p in smoothed], rels)
    all_s = np.mean([e for v in s_err.values() for e in v])
    all_f = np.mean([e for v in f_err.values() for e in v])
    print(f"3. matches' noise {math.sqrt(sigma_e2):.4f} m, odometry step's {math.sqrt(q):.4f} m; relation error "
          f"slam {all_s:.5f} -> smoothed {all_f:.5f} m (under 2 s {np.mean(s_err['< 2 s']):.4f} -> "
          f"{np.mean(f_err['< 2 s']):.4f})")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
