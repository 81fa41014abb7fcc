#!/usr/bin/env python3
"""Fits the same-place probability of core/matching/verification.cc and checks it (docs/NOTES.md, "Verifying a
match").

Input: the CSV rows of build/verify_features (one per (query, stored map, candidate pose) of the evaluation's
tasks). The model is logistic in the match terms at the refined pose; a row is positive when the map is the
task's relevant one and the refined pose is within 0.5 m / 0.2 rad of the truth. Its weights are fitted to rank
each task's positive rows first (a conditional logit over the task's rows: --objective listwise, kept) or to
predict each row's label (pointwise, the first model), then Platt-scaled on each pair's best pose so that the
answer's probability is calibrated. Fitted on the tuning sets only; the validation sets report the expected
calibration error (ECE, 10 equal-width bins over every pair) and the recall@1 / ANR of ranking by it, beside
Eq. 1 and the oracle (the true overlap at the true pose).

Usage: fit_verification.py --tuning A.csv B.csv ... --validation C.csv ... [--plot docs/reliability.png]
                           [--objective listwise|pointwise] [--features qo,mo,...] [--no-quadratic]
                           [--fit-on tuning|validation] [--bare]
--bare reports the model (fitted as ever) on rows whose free shares are zeroed, as maps without laser origins
give them. The defaults fit the product's model: the twelve terms and every product of two of them (--no-quadratic: the
terms alone); --fit-on validation fits on the validation sets themselves, an upper bound of what a model of
these terms can rank there, not a model to ship (docs/NOTES.md).
Prints the coefficients as C++ for verification.cc and a Markdown table.
"""
import argparse
import numpy as np

FEATURES = ["qo", "mo", "qf", "mf", "qs", "ms", "qfit", "mfit", "qc", "mc", "qcfit", "mcfit"]
QUADRATIC = True


def load(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def bare(a):
    """The rows as maps of bare points would give them (no laser origins, so no free space): free shares 0, seen
    shares equal to the occupied ones; the other terms do not read free space."""
    b = a.copy()
    for side in ("q", "m"):
        b["r_%sf" % side] = 0
        b["r_%ss" % side] = b["r_%so" % side]
    return b


def features(a, prefix="r_", names=None):
    x = np.stack([a[prefix + n] for n in (names or FEATURES)], axis=1)
    if not QUADRATIC:
        return x
    i, j = np.triu_indices(x.shape[1])
    return np.hstack([x, x[:, i] * x[:, j]])


def labels(a):
    return ((a["relevant"] == 1) & (a["r_dt"] < 0.5) & (a["r_da"] < 0.2)).astype(float)


def fit_logistic(x, y, l2=1e-7, iterations=50):
    """Newton's method (IRLS) with an L2 penalty on the weights (not the intercept)."""
    X = np.hstack([np.ones((len(x), 1)), x])
    w = np.zeros(X.shape[1])
    reg = l2 * len(x) * np.eye(X.shape[1])
    reg[0, 0] = 0
    for _ in range(iterations):
        p = 1 / (1 + np.exp(-X @ w))
        g = X.T @ (p - y) + reg @ w
        H = (X * (p * (1 - p))[:, None]).T @ X + reg
        step = np.linalg.solve(H, g)
        w -= step
        if np.abs(step).max() < 1e-9:
            break
    return w


def fit_listwise(sets, xs, l2=1e-4, iterations=600, rate=0.05):
    """The weights that rank each task's right answer first: a conditional logit over every candidate pose of
    every map of a task (softmax across the task), maximising the probability mass on the positive rows (the
    relevant map within tolerance). Tasks with no positive row carry no information and are left out. Adam on
    standardised features, from zero, a fixed number of steps: deterministic. Returns (weights, no intercept)."""
    x = np.vstack(xs)
    mu, sd = x.mean(0), x.std(0) + 1e-9
    groups, ys, offset = [], [], 0
    for a in sets:
        t = a["task"].astype(np.int64)
        groups.append(t + offset)
        offset += int(t.max()) + 1
        ys.append(labels(a) > 0)
    g, y = np.concatenate(groups), np.concatenate(ys)
    has = np.zeros(offset, bool)
    has[g[y]] = True
    keep = has[g]
    x, g, y = (x[keep] - mu) / sd, g[keep], y[keep]
    w, m1, m2 = np.zeros(x.shape[1]), np.zeros(x.shape[1]), np.zeros(x.shape[1])
    for i in range(iterations):
        s = x @ w
        top = np.full(offset, -np.inf)
        np.maximum.at(top, g, s)
        e = np.exp(s - top[g])
        z_all, z_pos = np.zeros(offset), np.zeros(offset)
        np.add.at(z_all, g, e)
        np.add.at(z_pos, g, e * y)
        grad = x.T @ (e / z_all[g] - np.where(y, e / np.maximum(z_pos[g], 1e-300), 0)) / has.sum() + l2 * w
        m1 = 0.9 * m1 + 0.1 * grad
        m2 = 0.999 * m2 + 0.001 * grad * grad
        w -= rate * (m1 / (1 - 0.9 ** (i + 1))) / (np.sqrt(m2 / (1 - 0.999 ** (i + 1))) + 1e-8)
    return np.concatenate([[-(w / sd) @ mu], w / sd])


def predict(w, x):
    return 1 / (1 + np.exp(-(w[0] + x @ w[1:])))


def ece(p, y, bins=10):
    edges = np.linspace(0, 1, bins + 1)
    idx = np.clip(np.digitize(p, edges) - 1, 0, bins - 1)
    e = 0.0
    rows = []
    for b in range(bins):
        m = idx == b
        if m.any():
            e += m.mean() * abs(p[m].mean() - y[m].mean())
            rows.append((p[m].mean(), y[m].mean(), int(m.sum())))
    return e, rows


def pair_max(a, score):
    """The best score over each pair's candidate poses (rows of the same task and map), one row per pair."""
    key = a["task"].astype(np.int64) * 1000003 + a["map"].astype(np.int64)
    order = np.lexsort((-score, key))
    first = np.ones(len(order), bool)
    first[1:] = key[order][1:] != key[order][:-1]
    return order[first]


def rank_figures(a, score):
    keep = pair_max(a, score)
    a, score = a[keep], score[keep]
    tasks = a["task"].astype(int)
    ranks = []
    for t in np.unique(tasks):
        m = tasks == t
        s = score[m]
        rel = a["relevant"][m] == 1
        sr = s[rel][0]
        ranks.append(((1 + (s > sr).sum() + ((s == sr).sum() - 1) / 2), m.sum()))
    r = np.array(ranks)
    return 100 * np.mean(r[:, 0] / r[:, 1]), np.mean(r[:, 0] <= 1.0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tuning", nargs="+", required=True)
    ap.add_argument("--validation", nargs="+", required=True)
    ap.add_argument("--plot")
    ap.add_argument("--objective", choices=["listwise", "pointwise"], default="listwise",
                    help="listwise: the relevant map's right pose first in its task (kept); pointwise: a "
                    "logistic regression of each row's label (the first model)")
    ap.add_argument("--features", default=",".join(FEATURES), help="comma-separated terms (ablations)")
    ap.add_argument("--quadratic", action=argparse.BooleanOptionalAction, default=True,
                    help="every product of two terms too (the product's model)")
    ap.add_argument("--fit-on", choices=["tuning", "validation"], default="tuning",
                    help="validation: fit on the validation sets, a bound on what these terms can rank there")
    ap.add_argument("--iterations", type=int, default=1500, help="steps of the listwise fit")
    ap.add_argument("--bare", action="store_true",
                    help="report the fitted model on the rows as bare points would give them (no free space)")
    o = ap.parse_args()
    global QUADRATIC
    FEATURES[:] = o.features.split(",")
    QUADRATIC = o.quadratic
    names = ("tuning", "validation")
    if o.fit_on == "validation":
        o.tuning, o.validation, names = o.validation, o.tuning, names[::-1]
    tuning = [load(p) for p in o.tuning]
    xs = [features(a) for a in tuning]
    if o.objective == "listwise":
        w = fit_listwise(tuning, xs, iterations=o.iterations)
    else:
        w = fit_logistic(np.vstack(xs), np.concatenate([labels(a) for a in tuning]))
    # Platt scaling on what the ranker reports: each pair's best pose (the maximum over its poses), so that the
    # probability of the pose it answers with is calibrated (a monotone map: the ranking does not change).
    z, yz = [], []
    for a in tuning:
        f = features(a)
        lin = w[0] + f @ w[1:]
        keep = pair_max(a, lin)
        z.append(lin[keep])
        yz.append(labels(a)[keep])
    ab = fit_logistic(np.concatenate(z)[:, None], np.concatenate(yz))
    w = np.concatenate([[ab[0] + ab[1] * w[0]], ab[1] * w[1:]])
    print("// fitted by tools/fit_verification.py on", " ".join(p.split("/")[-1] for p in o.tuning))
    print("constexpr double kIntercept = %.6g;" % w[0])
    print("constexpr double kWeights[] = {%s};  // %s%s" % (", ".join("%.6g" % v for v in w[1:]), ", ".join(FEATURES),
          ", then the products of terms i <= j in row order" if QUADRATIC else ""))
    print()
    print("| set | split | ANR Eq. 1 | ANR verified | ANR oracle | R@1 Eq. 1 | R@1 verified | R@1 oracle | ECE |")
    print("|---|---|---|---|---|---|---|---|---|")
    all_p, all_y = [], []
    means = []
    for fitted, split, paths, sets in ((True, names[0], o.tuning, tuning), (False, names[1], o.validation, None)):
        sets = sets or [load(p) for p in paths]
        figures = []
        for path, a in zip(paths, sets):
            a = bare(a) if o.bare else a
            p = predict(w, features(a))
            keep = pair_max(a, p)  # the pose each pair answers with
            e, _ = ece(p[keep], labels(a)[keep])
            eq1 = rank_figures(a, a["inliers"])
            ver = rank_figures(a, p)
            ora = rank_figures(a, a["t_qo"])
            print("| %s | %s | %.1f | %.1f | %.1f | %.2f | %.2f | %.2f | %.3f |" % (
                path.split("/")[-1].replace(".csv", ""), split, eq1[0], ver[0], ora[0], eq1[1], ver[1], ora[1], e))
            figures.append(ver)
            if not fitted:
                all_p.append(p[keep])
                all_y.append(labels(a)[keep])
        means.append("%s mean: ANR %.2f, R@1 %.3f" % (split, *np.mean(figures, axis=0)))
    print("\n" + "; ".join(means))
    p, yv = np.concatenate(all_p), np.concatenate(all_y)
    e, rows = ece(p, yv)
    print("%s (not fitted on), all pairs: ECE %.4f over %d pairs" % (names[1], e, len(p)))
    for mp, fy, n in rows:
        print("  predicted %.3f  observed %.3f  pairs %d" % (mp, fy, n))
    if o.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(4, 4))
        ax.plot([0, 1], [0, 1], "k:", lw=1)
        ax.plot([r[0] for r in rows], [r[1] for r in rows], "o-")
        ax.set_xlabel("predicted probability")
        ax.set_ylabel("observed share of same place")
        ax.set_title("validation ECE %.3f" % e)
        fig.tight_layout()
        fig.savefig(o.plot, dpi=100)


if __name__ == "__main__":
    main()
