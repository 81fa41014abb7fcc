#!/usr/bin/env bash
# Test-time only (make test, the ctest fixture Ros2Bags): writes ROS 2 bags from the ROS 1 bags of
# ../shared/data/bags with tests/ros2/convert.js, whose libraries come from the npm registry (pinned in
# package-lock.json), so the project's ROS 2 reader is checked on files written by an independent implementation.
#   tests/ros2/make-test-bags.sh BAGS_DIR OUT_DIR
# Writes into OUT_DIR: fr079.zstd.mcap (little-endian CDR), intel.zstd.mcap (big endian), aces.plain.mcap
# (uncompressed chunks), fr079.be.db3 (big endian), intel.rosbag2/ (a folder with metadata.yaml), aces.db3.
# Files newer than this script, convert.js and their bag are kept.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bags="$1"
out="$2"
mkdir -p "$out/npm"
if ! cmp -s "$here/package-lock.json" "$out/npm/package-lock.json" || [ ! -d "$out/npm/node_modules" ]; then
  cp "$here/package.json" "$here/package-lock.json" "$out/npm/"
  (cd "$out/npm" && npm ci --no-audit --no-fund --loglevel=error)
fi
cp "$here/convert.js" "$out/npm/convert.js"  # beside node_modules, where node resolves its requires
convert() {  # BAG OUT FORMAT [options]
  local bag="$bags/$1.clf2bag.bag" target="$out/$2"
  if [ -e "$target" ] && [ "$target" -nt "$bag" ] && [ "$target" -nt "$here/convert.js" ] &&
     [ "$target" -nt "$0" ]; then
    return
  fi
  rm -rf "$target"
  node "$out/npm/convert.js" "$bag" "$target.partial" "${@:3}"
  mv "$target.partial" "$target"
}
convert fr079 fr079.zstd.mcap mcap --compression zstd
convert intel intel.zstd.mcap mcap --compression zstd --endian be
convert aces aces.plain.mcap mcap --compression none
convert fr079 fr079.be.db3 db3 --endian be
convert intel intel.rosbag2 folder
convert aces aces.db3 db3
