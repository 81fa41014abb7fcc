#!/bin/bash
# mrpt-pf-localization.sh - run MRPT's pf-localization (Debian mrpt-apps 2.5.x, Monte Carlo
# localisation with global initialisation) as a peer of our tracker: same building map (the
# first visit of the corrected log, exported by build/tracking_check) and the same drifted
# odometry (the "mild" twin), localising every scan after the map's scans.
# Prints one JSON line per log on stdout; progress goes to stderr.
#
# usage: scripts/mrpt-pf-localization.sh [LOG ...]      LOG in: intel fr079 (default: both)
# env:   WORK=build/mrpt-pf  DATA=../shared/data  TIMEOUT=1200  REPS=3  SANITY=1
#        REPS:   pf-localization seeds its RNG from the clock (no seed option), so it is run REPS
#                times; the JSON line's main figures are run 1's, "repeats" lists every run.
#        SANITY: 1 = also run it once initialised at the true pose of scan K (+-0.3 m, +-5 deg)
#                to check the map/rawlog frames ("tracking_from_truth").
# Needs build/tracking_check (the project's build). About 8 minutes on 2 cores (nice -n 15).
#
# Pipeline per log:
#  1. build/tracking_check LOG-corrected.log.gz noise=mild max_starts=1 twin_out=... writes the
#     first-visit map (ROS map_server .yaml + .pgm) and the drifted twin (CARMEN FLASER lines:
#     real scans, laser pose = odometry pose = corrected pose corrupted by 1 % scale and
#     0.3 deg/m). Its "map of scans [0, K)" gives K, the first scan to localise.
#  2. The twin is cut to FLASER lines K.. (pf-localization never sees the mapped part) and
#     converted as in scripts/mrpt-peers.sh: PARAM laser_front_laser_resolution = 180/n deg,
#     carmen2rawlog, then obs2sf (Actions/SensoryFrame rawlog, scan timestamps restored, MRPT's
#     default Gaussian odometry motion model). Rawlog entry j = scan K + j.
#  3. pgm2gridmap turns the map_server map into a serialized COccupancyGridMap2D (.gridmap, one
#     of the two map formats pf-localization reads): x_min/y_min = the map_server origin
#     (lower-left corner), PGM row 0 = top row, occupied -> p(free) 0, free -> 1, unknown -> 0.5;
#     its likelihood/insertion options are loaded from the ini (a .gridmap carries its own).
#  4. pf-localization with a copy of the shipped localization_demo.ini (2D, LF_Thrun likelihood,
#     KLD 150..40000 particles, 40000 initial); changed: map_file, rawlog_file, logOutput_dir,
#     3D display/scene output off, and init_PDF_mode=0 (uniform over the free cells) over the
#     whole map's bounds (global localisation, no initial pose).
#  5. scripts/mrpt_pf_score.py: per step the posterior mean ('PDF estimation' in the app's
#     output) vs the corrected log's laser pose of the same scan; travel to convergence
#     (within 0.3 m / 3 deg and staying so for >= 10 m of travel), share of later steps within,
#     wall time, time per step.
set -u
cd "$(dirname "$0")/.."
DATA=${DATA:-../shared/data}
WORK=${WORK:-build/mrpt-pf}
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)
TIMEOUT=${TIMEOUT:-1200}
REPS=${REPS:-3}
SANITY=${SANITY:-1}
NICE=(nice -n 15)
PY=/usr/bin/python3
PF_INI=/usr/share/mrpt/config_files/pf-localization/localization_demo.ini
SCORE=scripts/mrpt_pf_score.py
TC=build/tracking_check
LOGS=("$@"); [ ${#LOGS[@]} -eq 0 ] && LOGS=(intel fr079)
mkdir -p "$WORK/tools"
log() { echo "[mrpt-pf] $*" >&2; }

# ---- prerequisites -------------------------------------------------------------------------
need=()
command -v pf-localization >/dev/null && command -v carmen2rawlog >/dev/null || need+=(mrpt-apps)
[ -d /usr/include/mrpt/obs ] || need+=(libmrpt-obs-dev)
[ -d /usr/include/mrpt/maps ] || need+=(libmrpt-maps-dev)
command -v g++ >/dev/null || need+=(g++)
if [ ${#need[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ]; then log "installing ${need[*]}"; apt-get install -y "${need[@]}" >&2 || exit 1
  else log "missing packages: ${need[*]} (apt-get install them)"; exit 1; fi
fi
[ -f "$PF_INI" ] || { log "shipped ini $PF_INI not found"; exit 1; }
[ -x "$TC" ] || { log "$TC not built (build the project first)"; exit 1; }
[ -f "$SCORE" ] || { log "$SCORE missing"; exit 1; }

# ---- helper sources (written by this script) -----------------------------------------------
cp "scripts/mrpt/obs2sf.cpp" "$WORK/tools/obs2sf.cpp"  # the helper's source
cp "scripts/mrpt/pgm2gridmap.cpp" "$WORK/tools/pgm2gridmap.cpp"  # the helper's source
INC=$(for d in /usr/include/mrpt/*/include; do printf -- '-I%s ' "$d"; done)
if [ ! -x "$WORK/tools/obs2sf" ] || [ "$WORK/tools/obs2sf.cpp" -nt "$WORK/tools/obs2sf" ]; then
  log "building obs2sf"
  "${NICE[@]}" g++ -O2 -std=c++17 $INC "$WORK/tools/obs2sf.cpp" -o "$WORK/tools/obs2sf" -lmrpt-obs \
      -lmrpt-poses -lmrpt-io -lmrpt-serialization -lmrpt-system -lmrpt-core -lmrpt-math -lmrpt-rtti \
      -lmrpt-containers >&2 || { log "obs2sf build failed"; exit 1; }
fi
if [ ! -x "$WORK/tools/pgm2gridmap" ] || [ "$WORK/tools/pgm2gridmap.cpp" -nt "$WORK/tools/pgm2gridmap" ]; then
  log "building pgm2gridmap"
  "${NICE[@]}" g++ -O2 -std=c++17 $INC "$WORK/tools/pgm2gridmap.cpp" -o "$WORK/tools/pgm2gridmap" \
      -lmrpt-maps -lmrpt-obs -lmrpt-config -lmrpt-io -lmrpt-serialization -lmrpt-system -lmrpt-core >&2 \
    || { log "pgm2gridmap build failed"; exit 1; }
fi

# ---- ini copy: io paths, no 3D display/scenes, initial PDF box -----------------------------
# make_ini rawlog map outprefix ini mode xmin xmax ymin ymax [yawmin yawmax]
make_ini() {
  local yaw=""
  [ $# -ge 11 ] && yaw="\\ninit_PDF_min_yaw_deg=${10}\\ninit_PDF_max_yaw_deg=${11}"
  sed -e "s|^map_file=.*|map_file=$2|" \
      -e "s|^rawlog_file=.*|rawlog_file=$1|" \
      -e "s|^logOutput_dir=.*|logOutput_dir=$3|" \
      -e 's|^3DSceneFrequency=.*|3DSceneFrequency=-1|' \
      -e 's|^SHOW_PROGRESS_3D_REAL_TIME *=.*|SHOW_PROGRESS_3D_REAL_TIME = false|' \
      -e "s|^init_PDF_mode=.*|init_PDF_mode=$5|" \
      -e "s|^init_PDF_min_x=.*|init_PDF_min_x=$6|" -e "s|^init_PDF_max_x=.*|init_PDF_max_x=$7|" \
      -e "s|^init_PDF_min_y=.*|init_PDF_min_y=$8|" -e "s|^init_PDF_max_y=.*|init_PDF_max_y=$9$yaw|" \
      "$PF_INI" > "$4"
}

# run_pf ini outprefix stdout  -> sets WALL, STATUS
run_pf() {
  rm -rf "$2"_[0-9]* "$2"_SUMMARY.txt
  local t0 t1 rc
  t0=$(date +%s.%N)
  timeout "$TIMEOUT" "${NICE[@]}" pf-localization "$1" < /dev/null > "$3" 2>&1
  rc=$?
  t1=$(date +%s.%N)
  WALL=$($PY -c "print(round($t1-$t0, 2))")
  if [ $rc -eq 124 ]; then STATUS="timeout after ${TIMEOUT} s"
  elif [ $rc -ne 0 ]; then
    STATUS="failed rc=$rc: $(grep -v '^\s*$' "$3" | tail -3 | tr '\n' ' ' | cut -c1-300 | tr '"\\' "' ")"
  elif ! grep -q 'PDF estimation' "$3"; then STATUS="no estimates in output"
  else STATUS=ok; fi
}

for L in "${LOGS[@]}"; do
  COR="$DATA/$L/$L-corrected.log.gz"
  [ -f "$COR" ] || { log "$L: $COR not found"; continue; }
  D="$WORK/$L"; mkdir -p "$D"
  # 1. map + drifted twin
  "${NICE[@]}" "$TC" "$COR" "$D" noise=mild max_starts=1 twin_out="$D/twin_mild.clf" > "$D/tracking_check.out" 2>&1 \
    || { log "$L: tracking_check failed: $(tail -2 "$D/tracking_check.out")"; continue; }
  K=$(sed -n 's/.*map of scans \[0, \([0-9]*\)).*/\1/p' "$D/tracking_check.out" | head -1)
  [ -n "$K" ] && [ -s "$D/first_visit.yaml" ] && [ -s "$D/twin_mild.clf" ] \
    || { log "$L: tracking_check gave no K / map / twin"; continue; }
  # 2. cut twin (scans K..), PARAM lines, convert
  read -r N MAXR <<< "$(awk '$1=="FLASER"{n=$2; if(!b) b=n; for(i=3;i<=n+2;i++) if($i>m) m=$i} END{print b, m}' "$D/twin_mild.clf")"
  {
    echo "PARAM laser_front_laser_resolution $($PY -c "print('%.9f' % (180.0/$N))") nohost 0"
    $PY -c "import sys; sys.exit(0 if $MAXR < 80 else 1)" && echo "PARAM robot_front_laser_max $MAXR nohost 0"
    awk -v K="$K" '$1=="FLASER"{if(k++>=K) print}' "$D/twin_mild.clf"
  } > "$D/cut.clf"
  awk '$1=="FLASER"{n=$2; print $(n+9)}' "$D/cut.clf" > "$D/cut.times"
  NSC=$(wc -l < "$D/cut.times")
  rm -f "$D/cut.obs.rawlog" "$D/cut.sf.rawlog"
  "${NICE[@]}" carmen2rawlog -q -w -i "$D/cut.clf" -o "$D/cut.obs.rawlog" > "$D/carmen2rawlog.txt" 2>&1 \
    || { log "$L: carmen2rawlog failed"; continue; }
  "${NICE[@]}" "$WORK/tools/obs2sf" "$D/cut.obs.rawlog" "$D/cut.times" "$D/cut.sf.rawlog" 2> "$D/obs2sf.txt" \
    || { cat "$D/obs2sf.txt" >&2; log "$L: obs2sf failed"; continue; }
  rm -f "$D/cut.obs.rawlog" "$D/cut.obs.gt.txt"
  log "$L: K=$K, $NSC scans to localise; $(tr '\n' ' ' < "$D/obs2sf.txt")"
  # 3. map
  GRID="$D/first_visit.gridmap"
  read -r XMIN XMAX YMIN YMAX RES NFREE NOCC <<< "$("$WORK/tools/pgm2gridmap" "$D/first_visit.yaml" "$PF_INI" "$GRID")"
  [ -n "${NOCC:-}" ] || { log "$L: pgm2gridmap failed"; continue; }
  log "$L: gridmap x [$XMIN, $XMAX] y [$YMIN, $YMAX] res $RES, $NFREE free / $NOCC occupied cells"
  # 4.+5. global localisation runs
  : > "$D/runs.jsonl"
  for r in $(seq 1 "$REPS"); do
    make_ini "$D/cut.sf.rawlog" "$GRID" "$D/pf_r$r" "$D/pf_r$r.ini" 0 "$XMIN" "$XMAX" "$YMIN" "$YMAX"
    log "$L: pf-localization run $r/$REPS (timeout ${TIMEOUT}s)"
    run_pf "$D/pf_r$r.ini" "$D/pf_r$r" "$D/pf_r$r.stdout"
    ET=$(ls "$D"/pf_r${r}_000_*/exec_times.txt 2>/dev/null | head -1)
    $PY "$SCORE" --corrected "$COR" --first "$K" --stdout "$D/pf_r$r.stdout" ${ET:+--exec-times "$ET"} \
        --log "$L" --wall "$WALL" --status "$STATUS" --map "$D/first_visit.yaml" --per-step "$D/pf_r$r.steps.tsv" \
        --extra "{\"run\": $r}" >> "$D/runs.jsonl"
    log "$L: run $r: $(tail -1 "$D/runs.jsonl")"
    rm -rf "$D"/pf_r${r}_000_*/particles
  done
  SAN=()
  if [ "$SANITY" = 1 ]; then
    read -r TX TY TT <<< "$(zcat -f "$COR" | awk -v K="$K" '$1=="FLASER"{if(k++==K){n=$2; print $(n+3), $(n+4), $(n+5); exit}}')"
    B=($($PY -c "import math; x,y,t=$TX,$TY,math.degrees($TT); print(x-.3, x+.3, y-.3, y+.3, t-5, t+5)"))
    make_ini "$D/cut.sf.rawlog" "$GRID" "$D/pf_truth" "$D/pf_truth.ini" 1 "${B[@]}"
    log "$L: sanity run from the true pose of scan $K"
    run_pf "$D/pf_truth.ini" "$D/pf_truth" "$D/pf_truth.stdout"
    $PY "$SCORE" --corrected "$COR" --first "$K" --stdout "$D/pf_truth.stdout" --log "$L" --wall "$WALL" \
        --status "$STATUS" --per-step "$D/pf_truth.steps.tsv" > "$D/sanity.json"
    rm -rf "$D"/pf_truth_000_*/particles
    SAN=(--sanity "$D/sanity.json" --sanity-steps "$D/pf_truth.steps.tsv")
  fi
  $PY "$SCORE" --summarise "$D/runs.jsonl" "${SAN[@]}"
done
