#!/usr/bin/python3
"""Score an MRPT pf-localization run (made by scripts/mrpt-pf-localization.sh) against truth.

usage: mrpt_pf_score.py --corrected LOG-corrected.log.gz --first K --stdout pf.stdout
                        [--exec-times exec_times.txt] --log NAME --wall SECONDS --status STATUS
                        [--map first_visit.yaml] [--tol-xy 0.3] [--tol-deg 3] [--stay-m 10]
                        [--per-step out.tsv] [--extra JSON]
       mrpt_pf_score.py --summarise runs.jsonl [--sanity sanity.json --sanity-steps steps.tsv]

Rawlog entry j (the j-th action + sensory frame) is scan K + j of the twin, i.e. the (K+j)-th
FLASER line of the corrected log, whose laser pose is the truth (the twin's laser sensor pose
relative to the robot is zero, so MRPT's robot pose is the laser pose).
pf-localization prints one 'PDF estimation: (x,y,phi deg)' line per rawlog entry: the first is
the initial (uniform) PDF at entry 0 (the app does not run the filter on entry 0), then one
after each filter step ('Step j. Executing ParticleFilter ...'), i.e. the posterior mean
(weighted particle mean) after entry j.

converged: the travel (metres along the true path from scan K) of the first step from which
every step is within tol-xy / tol-deg for at least stay-m metres of further travel (the log
must go on for those metres). later_within: share of the steps from that step to the end
(inclusive) within tolerance. --map: also the share of steps whose true position is on a free
cell of the map (map_server yaml + binary PGM). Prints one JSON line.

--summarise: one JSON line per log from the per-run lines: run 1's figures, "repeats" (the
main figures of every run) and, with --sanity, "tracking_from_truth" (the run initialised at
the true pose: travel until the first step out of tolerance, share within).
"""
import argparse, gzip, json, math, re, statistics


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def read_truth(fn):
    op = gzip.open if fn.endswith('.gz') else open
    poses = []
    with op(fn, 'rt', errors='replace') as f:
        for ln in f:
            t = ln.split()
            if not t or t[0] != 'FLASER':
                continue
            n = int(t[1])
            poses.append((float(t[n + 2]), float(t[n + 3]), float(t[n + 4])))
    return poses


PDF_RE = re.compile(r'PDF estimation: \(([-+0-9.eE]+),([-+0-9.eE]+),([-+0-9.eE]+)deg\)')


def read_map(yaml):
    """map_server map -> (free(x, y) function)."""
    import os
    meta = {}
    for ln in open(yaml):
        if ':' in ln:
            k, v = ln.split(':', 1)
            meta[k.strip()] = v.strip().strip('"\'')
    res = float(meta['resolution'])
    ox, oy = [float(v) for v in meta['origin'].strip('[]').split(',')[:2]]
    img = meta['image']
    if not img.startswith('/'):
        img = os.path.join(os.path.dirname(yaml), img)
    data = open(img, 'rb').read()
    toks, pos = [], 0
    while len(toks) < 4:  # P5 header with comments
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b'#':
            pos = data.index(b'\n', pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        toks.append(data[pos:end])
        pos = end
    W, H, maxv = int(toks[1]), int(toks[2]), int(toks[3])
    px = data[pos + 1:pos + 1 + W * H]
    neg = int(meta.get('negate', '0'))
    free_th = float(meta.get('free_thresh', '0.196'))

    def free(x, y):
        c, r = int(math.floor((x - ox) / res)), int(math.floor((y - oy) / res))
        if not (0 <= c < W and 0 <= r < H):
            return False
        v = px[(H - 1 - r) * W + c] / maxv
        p = v if neg else 1.0 - v
        return p < free_th
    return free


def summarise(a):
    runs = [json.loads(l) for l in open(a.summarise) if l.strip()]
    if not runs:
        print(json.dumps({'status': 'no runs'}))
        return
    out = dict(runs[0])
    out.pop('run', None)
    out['runs'] = len(runs)
    keys = ('run', 'status', 'converged', 'converge_travel_m', 'later_within', 'all_within', 'wall_s')
    out['repeats'] = [{k: r.get(k) for k in keys} for r in runs]
    if a.sanity:
        try:
            s = json.loads(open(a.sanity).read())
            t = {'status': s.get('status'), 'all_within': s.get('all_within')}
            rows = [l.rstrip('\n').split('\t') for l in open(a.sanity_steps)][1:]
            bad = next((r for r in rows if r[11] == '0'), None)
            t['within_until_travel_m'] = float(bad[2]) if bad else (float(rows[-1][2]) if rows else None)
            out['tracking_from_truth'] = t
        except (OSError, ValueError, IndexError) as e:
            out['tracking_from_truth'] = {'status': 'unreadable: %s' % e}
    print(json.dumps(out))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--summarise')
    ap.add_argument('--sanity')
    ap.add_argument('--sanity-steps')
    ap.add_argument('--map')
    ap.add_argument('--corrected')
    ap.add_argument('--first', type=int)
    ap.add_argument('--stdout')
    ap.add_argument('--exec-times')
    ap.add_argument('--log')
    ap.add_argument('--wall', type=float)
    ap.add_argument('--status', default='ok')
    ap.add_argument('--tol-xy', type=float, default=0.3)
    ap.add_argument('--tol-deg', type=float, default=3.0)
    ap.add_argument('--stay-m', type=float, default=10.0)
    ap.add_argument('--per-step')
    ap.add_argument('--extra', default='{}', help='JSON object merged into the output')
    a = ap.parse_args()
    if a.summarise:
        summarise(a)
        return
    if a.corrected is None or a.first is None or a.stdout is None:
        ap.error('--corrected, --first and --stdout are required')

    K = a.first
    truth = read_truth(a.corrected)[K:]
    out = {'log': a.log, 'peer': 'mrpt-pf-localization', 'status': a.status,
           'first_localised_scan': K, 'scans_to_localise': len(truth)}
    out.update(json.loads(a.extra))
    est = []
    try:
        with open(a.stdout, errors='replace') as f:
            for ln in f:
                m = PDF_RE.search(ln)
                if m:
                    est.append((float(m.group(1)), float(m.group(2)), math.radians(float(m.group(3)))))
    except OSError:
        pass
    out['steps_estimated'] = len(est)
    if len(est) > len(truth):
        out['status'] = 'more estimates (%d) than scans (%d)' % (len(est), len(truth))
        est = []
    n = len(est)
    # travel along the true path from scan K
    travel = [0.0]
    for i in range(1, len(truth)):
        travel.append(travel[-1] + math.hypot(truth[i][0] - truth[i - 1][0], truth[i][1] - truth[i - 1][1]))
    out['true_path_m'] = round(travel[-1], 1) if truth else 0.0
    if a.map and truth:
        free = read_map(a.map)
        out['truth_on_free_map_cells'] = round(sum(free(p[0], p[1]) for p in truth) / len(truth), 4)
    exy = [math.hypot(est[i][0] - truth[i][0], est[i][1] - truth[i][1]) for i in range(n)]
    eth = [abs(math.degrees(wrap(est[i][2] - truth[i][2]))) for i in range(n)]
    ok = [exy[i] <= a.tol_xy and eth[i] <= a.tol_deg for i in range(n)]
    conv = None
    # bad[i]: index of the first not-ok step at or after i (n if none)
    nxt_bad = [n] * (n + 1)
    for i in range(n - 1, -1, -1):
        nxt_bad[i] = i if not ok[i] else nxt_bad[i + 1]
    for i in range(n):
        if not ok[i]:
            continue
        end = travel[nxt_bad[i] - 1]  # travel of the last ok step of this run
        if end - travel[i] >= a.stay_m:
            conv = i
            break
    if conv is None:
        out['converged'] = False
        out['converge_travel_m'] = None
        out['later_within'] = None
    else:
        out['converged'] = True
        out['converge_step'] = conv
        out['converge_travel_m'] = round(travel[conv], 2)
        later = ok[conv:]
        out['later_within'] = round(sum(later) / len(later), 4)
        out['later_steps'] = len(later)
        out['later_median_err_m'] = round(statistics.median(exy[conv:]), 3)
        out['later_median_err_deg'] = round(statistics.median(eth[conv:]), 2)
    out['all_within'] = round(sum(ok) / n, 4) if n else None
    if n:
        out['final_err_m'] = round(exy[-1], 3)
        out['final_err_deg'] = round(eth[-1], 2)
    out['wall_s'] = a.wall
    if a.wall is not None and n:
        out['wall_per_step_ms'] = round(1000.0 * a.wall / n, 2)
    if a.exec_times:
        try:
            ts = [float(v) for v in open(a.exec_times).read().split()]
            if ts:
                out['pf_step_mean_ms'] = round(1000.0 * sum(ts) / len(ts), 2)
                out['pf_step_median_ms'] = round(1000.0 * statistics.median(ts), 2)
        except (OSError, ValueError):
            pass
    if n and n < len(truth) and out['status'] == 'ok':
        out['status'] = 'incomplete: %d of %d steps' % (n, len(truth))
    if a.per_step and n:
        with open(a.per_step, 'w') as f:
            f.write('step\tscan\ttravel_m\ttrue_x\ttrue_y\ttrue_th\test_x\test_y\test_th\terr_m\terr_deg\tok\n')
            for i in range(n):
                f.write('%d\t%d\t%.3f\t%.3f\t%.3f\t%.4f\t%.3f\t%.3f\t%.4f\t%.3f\t%.2f\t%d\n' % (
                    i, K + i, travel[i], *truth[i], *est[i], exy[i], eth[i], ok[i]))
    print(json.dumps(out))


if __name__ == '__main__':
    main()
