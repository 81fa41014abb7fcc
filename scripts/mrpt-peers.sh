#!/bin/bash
# mrpt-peers.sh - run MRPT's classic 2D SLAM peers (Debian mrpt-apps 2.5.x: rbpf-slam with its
# shipped ICP-based config, icp-slam with icp-slam_demo_classic.ini) on the raw CARMEN logs and
# score them with the Freiburg SLAM benchmark relation error (Kuemmerle et al. 2009) + wall time.
# Prints one JSON line per (log, peer) on stdout; progress goes to stderr.
#
# usage: scripts/mrpt-peers.sh [LOG ...]      LOG in: mit-csail fr079 intel aces fr101 (default: all)
# env:   WORK=build/mrpt-peers  TIMEOUT=900  SEED=1  PEERS="rbpf-slam icp-slam"  DATA=../shared/data
# (make slam-bench runs it and keeps its lines in docs/results/mrpt_peers.jsonl; about 20 minutes on 2 cores)
#
# Pipeline per log:
#  1. gunzip the .clf.gz into $WORK and prepend CARMEN PARAM lines for carmen2rawlog:
#     laser_front_laser_resolution = 180/n deg (carmen2rawlog assumes 0.5 deg => a 90 deg aperture
#     for the 180-beam intel/aces logs; MRPT spaces n beams by aperture/(n-1), so 180/n makes the
#     aperture exactly 180 deg), and, when a log has no 81.9 "no return" value (aces saturates at
#     50.0), robot_front_laser_max = that saturation value so those readings become invalid.
#  2. carmen2rawlog -> observation-only rawlog. Its timestamps are broken in MRPT 2.5.8
#     (base + 1e-6*t microseconds: all scans get the same time) and rbpf-slam segfaults on
#     observation-only rawlogs, so the small helper obs2sf (built here against libmrpt-obs)
#     rewrites it as an Actions/SensoryFrame rawlog: per FLASER scan one CActionRobotMovement2D
#     (odometry increment, MRPT default motion model) + one CSensoryFrame{scan}, with the scan's
#     FLASER ipc_timestamp restored. Step k of the apps == k-th FLASER line.
#  3. run each peer (nice -n 10, one at a time, timeout $TIMEOUT s) on a modified copy of the shipped ini.
#  4. evaluate: step k's pose (log_estimated_path.txt) is scan k's pose; relations are matched to
#     scans by FLASER ipc_timestamp (nearest within 1 ms). E = T_rel^-1 (T_1^-1 T_2).
#     carmen2rawlog sets the laser's sensorPose = FLASER laser pose (-) odom pose, which is zero for
#     mit-csail/fr079/intel/aces (checked and printed), so robot pose == laser pose there.
set -u
cd "$(dirname "$0")/.."
DATA=${DATA:-../shared/data}
WORK=${WORK:-build/mrpt-peers}
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)
TIMEOUT=${TIMEOUT:-900}
SEED=${SEED:-1}
PEERS=${PEERS:-"rbpf-slam icp-slam"}
PY=/usr/bin/python3
RBPF_INI=/usr/share/mrpt/config_files/rbpf-slam/gridmapping_RBPF_ICPbased_intel.ini
ICP_INI=/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini
declare -A CLF=([mit-csail]=csail/mit-csail.clf.gz [fr079]=fr079/fr079.clf.gz [intel]=intel/intel.clf.gz
                [aces]=aces/aces.clf.gz [fr101]=fr101/fr101.clf.gz)
declare -A REL=([mit-csail]=csail/mit-csail.relations [fr079]=fr079/fr079.relations
                [intel]=intel/intel.relations [aces]=aces/aces.relations)
LOGS=("$@"); [ ${#LOGS[@]} -eq 0 ] && LOGS=(mit-csail fr079 intel aces fr101)
mkdir -p "$WORK/tools"
log() { echo "[mrpt-peers] $*" >&2; }

# ---- prerequisites -------------------------------------------------------------------------
need=()
command -v rbpf-slam >/dev/null && command -v icp-slam >/dev/null && command -v carmen2rawlog >/dev/null || need+=(mrpt-apps)
[ -d /usr/include/mrpt/obs ] || need+=(libmrpt-obs-dev)
command -v g++ >/dev/null || need+=(g++)
if [ ${#need[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ]; then log "installing ${need[*]}"; apt-get install -y "${need[@]}" >&2 || exit 1
  else log "missing packages: ${need[*]} (apt-get install them)"; exit 1; fi
fi
[ -f "$RBPF_INI" ] && [ -f "$ICP_INI" ] || { log "shipped ini files not found"; exit 1; }

# ---- helper sources (written by this script) -----------------------------------------------
cp "scripts/mrpt/obs2sf.cpp" "$WORK/tools/obs2sf.cpp"  # the helper's source
cat > "$WORK/tools/eval_relations.py" <<'PY_EOF'
#!/usr/bin/python3
"""Relation error (Kuemmerle et al. 2009) of an MRPT app trajectory.

usage: eval_relations.py --times T --relations R --path log_estimated_path.txt
                         [--ml most_likely_path.txt --stdout app.out --odo log_odometry_path.txt]
                         --log NAME --peer NAME --wall SECONDS --status STATUS

--path: MRPT app 'log_estimated_path.txt' (one line per rawlog step = per scan):
        rbpf-slam: step x y z yaw pitch roll timestamp ; icp-slam: timestamp x y phi (maybe)
--ml:   rbpf-slam 'most_likely_path.txt' (x y yaw, one entry per particle-filter update,
        plus the prior as entry 0); which step each update belongs to is read from the app's
        stdout ('New pose=' lines between 'STEP k' markers); poses of steps without an
        update are the last update composed with the odometry increment since then.
Prints one JSON line.
"""
import argparse, bisect, json, math, re, sys


def comp(a, b):
    x, y, t = a
    c, s = math.cos(t), math.sin(t)
    return (x + c * b[0] - s * b[1], y + s * b[0] + c * b[1], t + b[2])


def inv(a):
    x, y, t = a
    c, s = math.cos(t), math.sin(t)
    return (-c * x - s * y, s * x - c * y, -t)


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def read_floats(fn):
    rows = []
    with open(fn) as f:
        for ln in f:
            ln = ln.strip()
            if not ln or ln[0] in '%#':
                continue
            try:
                rows.append([float(v) for v in ln.split()])
            except ValueError:
                pass
    return rows


def mean_std(v):
    if not v:
        return None, None
    m = sum(v) / len(v)
    return m, math.sqrt(sum((x - m) ** 2 for x in v) / len(v))


def relation_error(rel, times, poses):
    def near(t):
        i = bisect.bisect_left(times, t)
        best = None
        for c in (i - 1, i):
            if 0 <= c < len(times) and abs(times[c] - t) <= 1e-3:
                if best is None or abs(times[c] - t) < abs(times[best] - t):
                    best = c
        return best
    et, er = [], []
    for r in rel:
        k1, k2 = near(r[0]), near(r[1])
        if k1 is None or k2 is None:
            continue
        est = comp(inv(poses[k1]), poses[k2])   # T_1^-1 * T_2
        gt = (r[2], r[3], r[7])                  # (x, y, yaw) of the relation
        e = comp(inv(gt), est)                   # E = T_rel^-1 * (T_1^-1 * T_2)
        et.append(math.hypot(e[0], e[1]))
        er.append(abs(wrap(e[2])) * 180.0 / math.pi)
    mt, st = mean_std(et)
    mr, sr = mean_std(er)
    r4 = lambda v, n: round(v, n) if v is not None else None
    return {'matched': len(et), 'trans_mean_m': r4(mt, 4), 'trans_std_m': r4(st, 4),
            'rot_mean_deg': r4(mr, 3), 'rot_std_deg': r4(sr, 3)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--times', required=True)
    ap.add_argument('--relations')
    ap.add_argument('--path')
    ap.add_argument('--ml')
    ap.add_argument('--stdout')
    ap.add_argument('--odo')
    ap.add_argument('--log', required=True)
    ap.add_argument('--peer', required=True)
    ap.add_argument('--variant', default='')
    ap.add_argument('--wall', type=float)
    ap.add_argument('--status', default='ok')
    a = ap.parse_args()

    out = {'log': a.log, 'peer': a.peer}
    if a.variant:
        out['trajectory'] = a.variant
    out['status'] = a.status
    out['wall_s'] = a.wall
    times = [r[0] for r in read_floats(a.times)]
    out['scans'] = len(times)

    poses = None  # per scan index
    mlposes = None
    odoposes = None
    if a.status == 'ok' and a.path:
        rows = read_floats(a.path)
        if len(rows) != len(times):
            out['status'] = 'path has %d steps for %d scans' % (len(rows), len(times))
        else:
            if len(rows[0]) >= 8:  # rbpf-slam: step x y z yaw pitch roll t
                steps = [(r[1], r[2], r[4]) for r in rows]
                ts = [r[7] for r in rows]
                # the path's timestamps are the restored FLASER ipc_timestamps: check step k == scan k
                out['step_time_mismatch'] = sum(
                    1 for k in range(len(ts)) if abs(ts[k] - times[k]) > 1e-3)
            else:  # icp-slam: step x y phi (no timestamp): check the step numbering
                steps = [(r[1], r[2], r[3]) for r in rows]
                out['step_index_mismatch'] = sum(1 for k, r in enumerate(rows) if int(r[0]) != k)
            poses = steps
            if a.ml:
                ml = [tuple(r[:3]) for r in read_floats(a.ml)]
                odo = [(r[1], r[2], r[4]) for r in read_floats(a.odo)]
                loc = []  # per step: True if a PF update happened in that step
                n_upd = 0
                with open(a.stdout, errors='replace') as f:
                    for ln in f:
                        if 'New pose=' in ln:
                            n_upd += 1
                        m = re.search(r'-- STEP (\d+) --', ln)
                        if m:
                            loc.append(n_upd > 0)
                            n_upd = 0
                if len(loc) != len(times) or sum(loc) + 1 != len(ml) or len(odo) != len(times):
                    out['most_likely_particle'] = 'mapping failed (steps %d, updates %d, ml %d, odo %d)' % (
                        len(loc), sum(loc), len(ml), len(odo))
                else:
                    mlposes, j, jstep = [], 0, None
                    for k in range(len(times)):
                        if loc[k]:
                            j += 1
                            jstep = k
                        if jstep is None:
                            mlposes.append(ml[0])
                        else:
                            d = comp(inv(odo[jstep]), odo[k])
                            mlposes.append(comp(ml[j], d))
    if a.odo and a.status == 'ok':
        rows = read_floats(a.odo)
        if len(rows) == len(times):
            odoposes = [(r[1], r[2], r[4]) if len(r) >= 7 else (r[1], r[2], r[3]) for r in rows]
    if not a.relations:
        out['relations'] = 'no relations'
    elif poses is not None:
        rel = read_floats(a.relations)
        out['relations'] = len(rel)
        out.update(relation_error(rel, times, poses))
        if mlposes is not None:
            out['most_likely_particle'] = relation_error(rel, times, mlposes)
        if odoposes is not None:
            out['raw_odometry'] = relation_error(rel, times, odoposes)
    print(json.dumps(out))


if __name__ == '__main__':
    main()
PY_EOF
if [ ! -x "$WORK/tools/obs2sf" ] || [ "$WORK/tools/obs2sf.cpp" -nt "$WORK/tools/obs2sf" ]; then
  log "building obs2sf"
  INC=$(for d in /usr/include/mrpt/*/include; do printf -- '-I%s ' "$d"; done)
  g++ -O2 -std=c++17 $INC "$WORK/tools/obs2sf.cpp" -o "$WORK/tools/obs2sf" -lmrpt-obs -lmrpt-poses \
      -lmrpt-io -lmrpt-serialization -lmrpt-system -lmrpt-core -lmrpt-math -lmrpt-rtti -lmrpt-containers >&2 \
    || { log "obs2sf build failed"; exit 1; }
fi

# ---- ini copies: input/output set, GUI/3D/image output off, fixed seed ---------------------
make_rbpf_ini() {  # rawlog outdir ini
  sed -e "s|^rawlog_file=.*|rawlog_file=$1|" \
      -e "s|^logOutput_dir=.*|logOutput_dir=$2|" \
      -e 's|^SAVE_MAP_IMAGES=1|SAVE_MAP_IMAGES=0|' \
      -e 's|^SAVE_3D_SCENE=1|SAVE_3D_SCENE=0|' \
      -e 's|^SHOW_PROGRESS_IN_WINDOW=1|SHOW_PROGRESS_IN_WINDOW=0|' \
      -e "s|^\(SHOW_PROGRESS_IN_WINDOW=0\)|\1\nRANDOM_SEED=$SEED|" "$RBPF_INI" > "$3"
}
make_icp_ini() {  # rawlog outdir ini
  sed -e "s|^rawlog_file=.*|rawlog_file=$1|" \
      -e "s|^logOutput_dir=.*|logOutput_dir=$2|" \
      -e 's|^LOG_FREQUENCY=50|LOG_FREQUENCY=0|' \
      -e 's|^SAVE_3D_SCENE=1|SAVE_3D_SCENE=0|' \
      -e 's|^SHOW_PROGRESS_3D_REAL_TIME=1|SHOW_PROGRESS_3D_REAL_TIME=0|' "$ICP_INI" > "$3"
}

for L in "${LOGS[@]}"; do
  [ -n "${CLF[$L]:-}" ] || { log "unknown log $L"; continue; }
  D="$WORK/$L"; mkdir -p "$D"
  # 1. uncompressed log + PARAM lines
  if [ ! -s "$D/$L.in.clf" ]; then
    zcat "$DATA/${CLF[$L]}" > "$D/$L.clf" || { log "cannot read $DATA/${CLF[$L]}"; continue; }
    read -r N MAXR <<< "$(awk '$1=="FLASER"{n=$2; if(!b) b=n; for(i=3;i<=n+2;i++) if($i>m) m=$i} END{print b, m}' "$D/$L.clf")"
    {
      echo "PARAM laser_front_laser_resolution $($PY -c "print('%.9f' % (180.0/$N))") nohost 0"
      $PY -c "import sys; sys.exit(0 if $MAXR < 80 else 1)" && echo "PARAM robot_front_laser_max $MAXR nohost 0"
      cat "$D/$L.clf"
    } > "$D/$L.in.clf.tmp" && mv "$D/$L.in.clf.tmp" "$D/$L.in.clf"
    # FLASER ipc_timestamp = the field after the 6 pose values
    awk '$1=="FLASER"{n=$2; print $(n+9)}' "$D/$L.clf" > "$D/$L.times"
    rm -f "$D/$L.clf"
  fi
  # 2. convert
  if [ ! -s "$D/$L.sf.rawlog" ]; then
    log "$L: $(grep -m3 '^PARAM' "$D/$L.in.clf" | grep -E 'laser_front_laser_resolution|robot_front_laser_max' | tr '\n' ';')"
    carmen2rawlog -q -w -i "$D/$L.in.clf" -o "$D/$L.obs.rawlog" >/dev/null 2>&1 || { log "$L: carmen2rawlog failed"; continue; }
    "$WORK/tools/obs2sf" "$D/$L.obs.rawlog" "$D/$L.times" "$D/$L.sf.rawlog.tmp" 2> "$D/obs2sf.txt" \
      && mv "$D/$L.sf.rawlog.tmp" "$D/$L.sf.rawlog" || { cat "$D/obs2sf.txt" >&2; log "$L: obs2sf failed"; continue; }
    rm -f "$D/$L.obs.rawlog" "$D/$L.obs.gt.txt"   # gt.txt: carmen2rawlog copies the FLASER odometry there
  fi
  log "$L: $(tr '\n' ' ' < "$D/obs2sf.txt")"
  RELARG=(); [ -n "${REL[$L]:-}" ] && RELARG=(--relations "$DATA/${REL[$L]}")
  # 3. run peers, one at a time
  for P in $PEERS; do
    OUT="$D/$P"; INI="$D/$P.ini"; rm -rf "$OUT"
    case $P in
      rbpf-slam) make_rbpf_ini "$D/$L.sf.rawlog" "$OUT" "$INI" ;;
      icp-slam)  make_icp_ini  "$D/$L.sf.rawlog" "$OUT" "$INI" ;;
      *) log "unknown peer $P"; continue ;;
    esac
    log "$L: running $P (timeout ${TIMEOUT}s)"
    t0=$(date +%s.%N)
    timeout "$TIMEOUT" nice -n 10 "$P" "$INI" < /dev/null > "$D/$P.stdout" 2>&1
    rc=$?
    t1=$(date +%s.%N)
    WALL=$($PY -c "print(round($t1-$t0, 2))")
    if [ $rc -eq 124 ]; then STATUS="timeout after ${TIMEOUT} s"
    elif [ $rc -ne 0 ]; then STATUS="failed rc=$rc: $(grep -v '^\s*$' "$D/$P.stdout" | tail -1 | cut -c1-160 | tr '"\\' "' ")"
    elif [ ! -s "$OUT/log_estimated_path.txt" ]; then STATUS="no log_estimated_path.txt"
    else STATUS=ok; fi
    EXTRA=()
    [ "$P" = rbpf-slam ] && EXTRA=(--ml "$OUT/most_likely_path.txt" --stdout "$D/$P.stdout")
    $PY "$WORK/tools/eval_relations.py" --times "$D/$L.times" "${RELARG[@]}" \
        --path "$OUT/log_estimated_path.txt" --odo "$OUT/log_odometry_path.txt" "${EXTRA[@]}" \
        --log "$L" --peer "$P" --wall "$WALL" --status "$STATUS"
    gzip -f "$D/$P.stdout"
  done
done
