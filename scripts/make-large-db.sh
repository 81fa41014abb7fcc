#!/usr/bin/env bash
# Measures a large map database on disk (docs/NOTES.md, "A large database on disk (measured)"): for each N, a new
# database of N synthetic maps with K = 3 descriptors resampled from real ones (build/large_db generate: fr079's
# submaps described against the intel dictionary), then its build time, file size, `partslam info` wall time and
# one query over the whole set (build/large_db query: open + load the set + rank with imm:3, Sum-Max, gate 2 m).
#   cold: the database file evicted from the page cache first (sync, then posix_fadvise DONTNEED on it: its
#         pages are read from the disk again), in a fresh process
#   fresh: a fresh process, the file in the page cache (warm page cache)
#   warm: the same rank again in the same process (median of 20)
# Usage: bash scripts/make-large-db.sh [N ...]   (default 1000000 10000000; about 6 min for both on 2 cores)
# Needs ../shared/data (or $PARTSLAM_SHARED_DATA) and build/partslam, build/large_db. Databases go to
# $LARGE_DB_DIR (default /tmp/bigdb): about 225 bytes per map, 2.3 GB at 10 M; they are kept for reruns of info
# and query, and rebuilt (the build is timed) on every run of the script.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=${PARTSLAM_SHARED_DATA:-../shared/data}
DIR=${LARGE_DB_DIR:-/tmp/bigdb}
BIN=${BUILD_DIR:-build}
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1000000 10000000)
[ -d "$DATA" ] || { echo "make-large-db: $DATA not found (real descriptors are resampled)" >&2; exit 1; }
for tool in partslam large_db; do
  [ -x "$BIN/$tool" ] || { echo "make-large-db: $BIN/$tool missing: cmake --build $BIN --target $tool" >&2; exit 1; }
done
mkdir -p "$DIR"
SOURCE="$DIR/source.db"
if [ ! -f "$SOURCE" ]; then  # the real descriptors: fr079's 845 submaps against the intel dictionary
  "$BIN/partslam" submaps "$DATA/fr079/fr079-corrected.log.gz" --db "$SOURCE" --name fr079 --quiet > /dev/null
  "$BIN/partslam" dictionary "$DATA/intel/intel-corrected.log.gz" --db "$SOURCE" --name intel > /dev/null
  "$BIN/partslam" describe "$SOURCE" --dict intel --k 3 --quiet > /dev/null
fi
/usr/bin/python3 - "$BIN" "$SOURCE" "$DIR" "${sizes[@]}" <<'PY'
import os, re, statistics, subprocess, sys, time
bin_dir, source, out_dir, sizes = sys.argv[1], sys.argv[2], sys.argv[3], [int(n) for n in sys.argv[4:]]

def run(*args):
    t = time.perf_counter()
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return out, time.perf_counter() - t

def evict(path):  # drops the file's (clean) pages from the page cache
    subprocess.run(["sync"], check=True)
    fd = os.open(path, os.O_RDONLY)
    os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
    os.close(fd)

def query(db, load):
    rss = f"{out_dir}/.rss"
    out, wall = run("/usr/bin/time", "-f", "%M", "-o", rss, f"{bin_dir}/large_db", "query", db, "--load", load,
                    "--repeat", "20")
    f = lambda pattern: float(re.search(pattern, out).group(1))
    return {"load": f(r"load ([\d.]+) ms"), "build": f(r"build ([\d.]+) ms"), "rank": f(r"rank ([\d.]+) ms:"),
            "cold": f(r"cold ([\d.]+) ms"), "warm": f(r"median ([\d.]+) ms"), "wall": wall * 1e3,
            "rss_mb": int(open(rss).read().split()[-1]) / 1e3}

rows = []
for n in sizes:
    db = f"{out_dir}/synthetic-{n}.db"
    for suffix in ("", "-journal"):
        if os.path.exists(db + suffix): os.remove(db + suffix)
    out, _ = run(f"{bin_dir}/large_db", "generate", source, "--dict", "intel", "--k", "3", "--maps", str(n),
                 "--out", db)
    print(out.strip(), flush=True)
    build_s = float(re.search(r"build ([\d.]+) s", out).group(1))
    size = os.path.getsize(db)
    evict(db)
    info_out, info_cold = run(f"{bin_dir}/partslam", "info", db)
    info_warm = statistics.median(run(f"{bin_dir}/partslam", "info", db)[1] for _ in range(5))
    print(info_out.strip(), flush=True)
    evict(db)
    cold = query(db, "stream")
    fresh = query(db, "stream")
    fresh_set = query(db, "set")
    rows.append((n, build_s, size, info_cold, info_warm, cold, fresh, fresh_set))
    print(f"N={n}: cold {cold}\n  fresh {fresh}\n  fresh, load set {fresh_set}", flush=True)

print("\n| maps | build [s] | file [MB] | bytes per map | info cold / warm [s] | cold query [s] (load) "
      "| fresh process, warm cache [s] (load) | load_descriptor_set path, fresh [s] (load + build) "
      "| warm query [ms] | peak memory stream / set [MB] |")
print("|---|---|---|---|---|---|---|---|---|---|")
for n, build_s, size, info_cold, info_warm, cold, fresh, fs in rows:
    print(f"| {n:,} | {build_s:.1f} | {size / 1e6:.0f} | {size / n:.0f} | {info_cold:.3f} / {info_warm:.3f} "
          f"| {cold['cold'] / 1e3:.2f} ({cold['load'] / 1e3:.2f}) | {fresh['cold'] / 1e3:.2f} ({fresh['load'] / 1e3:.2f}) "
          f"| {fs['cold'] / 1e3:.2f} ({(fs['load'] + fs['build']) / 1e3:.2f}) | {fresh['warm']:.1f} "
          f"| {fresh['rss_mb']:.0f} / {fs['rss_mb']:.0f} |")
PY
