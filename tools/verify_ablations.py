#!/usr/bin/env python3
"""Measurements on the rows of build/verify_features (docs/NOTES.md, "Four more levers measured on the rows" and
"Pose ambiguity"): where the product's model fails, four levers tried against it, and how well a map's runner-up
pose flags a wrong answered pose (VerifiedDmm::runner_up, pose_ambiguous).

Usage: verify_ablations.py --tuning A.csv ... --validation B.csv ...
(the rows of `build/verify_features LOG OUT.csv 200 100 1 2`, as for tools/fit_verification.py).

- failures: per set, why R@1 fails (the relevant map's answered pose right, its right pose among its candidates
  but not answered, no right candidate) and how far the winning map lies from the query;
- selector: a listwise model fitted over the relevant pairs' candidate poses only, to pick each map's pose;
- extra terms: log point counts and the pair's pose ambiguity beside the twelve terms;
- second pose: each map scored by its best pose's probability minus alpha times its second-best pose's;
- pose ambiguity: over the relevant pairs, the share of wrong and of right answered poses whose runner-up pose
  (the most probable other candidate) reaches a share of the answer's probability;
- hubness: the score minus lambda times the stored map's mean score against the other tasks' queries where it is
  not relevant (an upper bound: it reads the evaluation's ground truth).
The product's model is read from src/core/matching/verification.cc.
"""
import argparse
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fit_verification as fv  # noqa: E402


def product_weights():
    src = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src", "core", "matching",
                            "verification.cc")).read()
    intercept = float(re.search(r"kIntercept = ([-0-9.e]+)", src).group(1))
    body = re.search(r"kWeights = \{([^}]*)\}", src).group(1)
    return np.array([intercept] + [float(v) for v in body.split(",") if v.strip()])


def name(path):
    return os.path.basename(path).replace(".csv", "")


def r1_of(a, score, rows=None):
    """R@1 with each pair answered by `rows` (one row per pair; default: its highest score)."""
    keep = fv.pair_max(a, score) if rows is None else rows
    tasks = a["task"][keep].astype(int)
    wins = [a["relevant"][keep[tasks == t]][np.argmax(score[keep[tasks == t]])] == 1 for t in np.unique(tasks)]
    return float(np.mean(wins))


def failures(paths, w):
    print("| set | R@1 | relevant pose right, another map wins | right pose not answered | no right candidate |"
          " winner < 3 m | 3-6 m | 6-15 m | > 15 m | winner overlaps more at the truth |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for path in paths:
        a = fv.load(path)
        p = fv.predict(w, fv.features(a))
        lab = fv.labels(a)
        keep = fv.pair_max(a, p)
        tasks = a["task"][keep].astype(int)
        n = wins = pose_right = not_chosen = 0
        dist = []
        more = 0
        for t in np.unique(tasks):
            k = keep[tasks == t]
            rel = k[a["relevant"][k] == 1][0]
            top = k[np.argmax(p[k])]
            n += 1
            if top == rel:
                wins += 1
                continue
            any_right = lab[(a["task"] == t) & (a["relevant"] == 1)].any()
            pose_right += lab[rel] > 0
            not_chosen += (lab[rel] == 0) and any_right
            dist.append(a["dist"][top])
            more += a["t_qo"][top] > a["t_qo"][rel]
        d = np.array(dist)
        print("| %s | %.3f | %d | %d | %d | %d | %d | %d | %d | %d |" % (
            name(path), wins / n, pose_right, not_chosen, n - wins - pose_right - not_chosen, (d < 3).sum(),
            ((d >= 3) & (d < 6)).sum(), ((d >= 6) & (d < 15)).sum(), (d >= 15).sum(), more))


def selector(tuning, validation, w):
    sets = [fv.load(p) for p in tuning]
    rel = [a[a["relevant"] == 1] for a in sets]
    ws = fv.fit_listwise(rel, [fv.features(a) for a in rel], iterations=1500)
    for split, paths in (("tuning", tuning), ("validation", validation)):
        figures = []
        for path in paths:
            a = fv.load(path)
            x = fv.features(a)
            p, s = fv.predict(w, x), ws[0] + x @ ws[1:]
            lab = fv.labels(a)
            by_model, by_selector = fv.pair_max(a, p), fv.pair_max(a, s)
            figures.append((lab[by_model[a["relevant"][by_model] == 1]].mean(),
                            lab[by_selector[a["relevant"][by_selector] == 1]].mean(),
                            r1_of(a, p), r1_of(a, p, by_selector)))
        print("%s means: relevant pose right, model %.3f / selector %.3f; R@1 at the model's poses %.3f / at the "
              "selector's %.3f" % (split, *np.mean(figures, axis=0)))


def extra_terms(a):
    key = a["task"].astype(np.int64) * 1000003 + a["map"].astype(np.int64)
    _, inv, count = np.unique(key, return_inverse=True, return_counts=True)
    best = np.zeros(count.size)
    np.maximum.at(best, inv, a["inliers"])
    second = np.zeros(count.size)
    np.maximum.at(second, inv, np.where(a["k"] == 1, a["inliers"], 0))
    return {"counts": [np.log(a["nq"]) / 6, np.log(a["nm"]) / 6],
            "ambiguity": [count[inv] / 4.0, second[inv] / np.maximum(best[inv], 1)]}


def with_extra(a, groups):
    x = fv.features(a)
    if not groups:
        return x
    terms = extra_terms(a)
    e = np.stack([v for g in groups for v in terms[g]], axis=1)
    base = np.stack([a["r_" + f] for f in fv.FEATURES], axis=1)
    i, j = np.triu_indices(e.shape[1])
    return np.hstack([x, e, e[:, i] * e[:, j], (e[:, :, None] * base[:, None, :]).reshape(len(a), -1)])


def extra(tuning, validation):
    for groups in ([], ["counts"], ["ambiguity"], ["counts", "ambiguity"]):
        sets = [fv.load(p) for p in tuning]
        w = fv.fit_listwise(sets, [with_extra(a, groups) for a in sets], iterations=1500)
        out = []
        for paths in (tuning, validation):
            figures = []
            for path in paths:
                a = fv.load(path)
                figures.append(fv.rank_figures(a, w[0] + with_extra(a, groups) @ w[1:]))
            out += list(np.mean(figures, axis=0))
        print("%-22s tuning ANR %.2f R@1 %.3f | validation ANR %.2f R@1 %.3f" % (
            " + ".join(groups) or "the twelve terms", *out))


def r1_sweep(tuning, validation, w, knob, values, scores):
    """R@1 split means of rankings scores(a, z, value) -> (score, rows) over `values` of a knob (z: the model's
    logit per row)."""
    for split, paths in (("tuning", tuning), ("validation", validation)):
        figures = []
        for path in paths:
            a = fv.load(path)
            z = w[0] + fv.features(a) @ w[1:]
            figures.append([r1_of(*scores(a, z, v)) for v in values])
        print("%s R@1 means: %s" % (split, ", ".join("%s %.2f %.3f" % (knob, v, r)
                                                     for v, r in zip(values, np.mean(figures, axis=0)))))


def second_pose(a, z, alpha):
    key = a["task"].astype(np.int64) * 1000003 + a["map"].astype(np.int64)
    order = np.lexsort((-z, key))
    k, zs = key[order], z[order]
    first = np.nonzero(np.r_[True, k[1:] != k[:-1]])[0]  # each pair's best pose, then its others
    after = np.minimum(first + 1, len(k) - 1)
    has_second = (first + 1 < len(k)) & (k[after] == k[first])
    p1 = 1 / (1 + np.exp(-zs[first]))
    p2 = np.where(has_second, 1 / (1 + np.exp(-zs[after])), 0.0)
    rows = order[first]
    score = np.zeros(len(a))
    score[rows] = np.log(np.maximum(p1 - alpha * p2, 1e-12))
    return a, score, rows


def hubness(a, z, lam):
    keep = fv.pair_max(a, z)
    a, z = a[keep], z[keep]
    maps, rel = a["map"].astype(int), a["relevant"] == 1
    total, count = np.zeros(maps.max() + 1), np.zeros(maps.max() + 1)
    np.add.at(total, maps[~rel], z[~rel])
    np.add.at(count, maps[~rel], 1)
    # leave the pair's own task out
    others = count[maps] - (~rel)
    mu = np.where(others > 0, (total[maps] - np.where(rel, 0, z)) / np.maximum(others, 1), np.median(z))
    return a, z - lam * mu, np.arange(len(a))


def pose_ambiguity(tuning, validation, w, shares=tuple(np.round(np.arange(0.2, 0.71, 0.05), 2)), false_alarms=0.15):
    """The flag's share (kAmbiguousPoseShare) is the smallest that flags at most `false_alarms` of the tuning
    split's right answered poses."""
    chosen = None
    for split, paths in (("tuning", tuning), ("validation", validation)):
        right, wrong = [], []  # runner-up / answer probability of the relevant pairs, by answered pose
        for path in paths:
            a = fv.load(path)
            p = fv.predict(w, fv.features(a))
            lab = fv.labels(a)
            rel = np.nonzero(a["relevant"] == 1)[0]
            for t in np.unique(a["task"][rel]):
                rows = rel[a["task"][rel] == t]
                order = rows[np.argsort(-p[rows], kind="stable")]
                ratio = p[order[1]] / p[order[0]] if len(order) > 1 else 0.0
                (right if lab[order[0]] > 0 else wrong).append(ratio)
        right, wrong = np.array(right), np.array(wrong)
        auc = np.mean([(x > right).mean() + 0.5 * (x == right).mean() for x in wrong])
        if chosen is None:
            chosen = min(s for s in shares if (right >= s).mean() <= false_alarms)
        print("%s: %d right and %d wrong answered poses, AUC %.3f; flagged at share" % (
            split, len(right), len(wrong), auc))
        for s in shares:
            print("  %.2f: wrong %.3f, right %.3f%s" % (s, (wrong >= s).mean(), (right >= s).mean(),
                                                       "  (chosen on tuning)" if s == chosen else ""))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tuning", nargs="+", required=True)
    ap.add_argument("--validation", nargs="+", required=True)
    o = ap.parse_args()
    w = product_weights()
    print("## Failures of the product's model\n")
    failures(o.tuning + o.validation, w)
    print("\n## A pose selector of its own\n")
    selector(o.tuning, o.validation, w)
    print("\n## Extra terms\n")
    extra(o.tuning, o.validation)
    print("\n## The second pose's probability subtracted\n")
    r1_sweep(o.tuning, o.validation, w, "alpha", (0.0, 0.25, 0.5, 1.0), second_pose)
    print("\n## Pose ambiguity: the runner-up pose flags a wrong answered pose\n")
    pose_ambiguity(o.tuning, o.validation, w)
    print("\n## Hubness correction (upper bound: reads the ground truth)\n")
    r1_sweep(o.tuning, o.validation, w, "lambda", (0.0, 0.25, 0.5, 1.0), hubness)


if __name__ == "__main__":
    main()
