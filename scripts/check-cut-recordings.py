#!/usr/bin/env python3
"""Cuts every log and bag of ../shared/data at N random points (seed 24) and reads each cut with the partslam
Python module: the scans read must be the first ones of the whole file (same stamps and points, in order), and a
warning must say the recording was cut short (unless the cut lost nothing, e.g. inside an MCAP's summary).
For a CARMEN log the scans read must also be every scan whose line lies whole in the text before the cut (the
cut line itself may still parse, e.g. a cut in its last field: then nothing was lost and no warning is needed).
Prints one line per file: cuts, bad cuts, the share of the whole file's scans the cuts read. A one-off check of the issue's floor over all the shared data (the ctest suite cuts a sample of them).

    PYTHONPATH=build/python /usr/bin/python3 scripts/check-cut-recordings.py [SHARED_DATA] [N]
"""
import gzip
import pathlib
import random
import sys
import tempfile
import warnings
import zlib

import partslam

shared = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parents[2] / "shared" / "data")
cuts = int(sys.argv[2]) if len(sys.argv) > 2 else 20
files = sorted(shared.glob("*/*.log.gz")) + sorted(shared.glob("*/*.clf.gz")) + sorted(shared.glob("corrected/*.gz"))
files += sorted(shared.glob("bags/*.bag")) + sorted(shared.glob("bags/*.mcap"))
files = sorted(set(files))
rng = random.Random(24)
failures = 0
warnings.simplefilter("ignore")  # the warnings are checked from .warnings
with tempfile.TemporaryDirectory() as tmp:
    for path in files:
        whole = partslam.load_scan_source(str(path))
        stamps = [s.timestamp for s in whole.scans]
        sizes = [len(s.points_laser) for s in whole.scans]
        data = path.read_bytes()
        # A gzip log is cut in its text (as a logger killed mid-write leaves it) and compressed again, and also cut
        # as a compressed stream (a .gz whose end is lost).
        text = gzip.decompress(data) if path.suffix == ".gz" else None
        shares, bad = [], 0
        for k in range(cuts):
            if text is not None and k % 2 == 0:
                n = rng.randrange(len(text) // 20, len(text))
                blob, name = gzip.compress(text[:n]), "cut.log.gz"
            else:
                n = rng.randrange(len(data) // 20, len(data))
                blob, name = data[:n], "cut" + "".join(path.suffixes[-2:] if path.suffix == ".gz" else [path.suffix])
            cut = pathlib.Path(tmp) / name
            cut.write_bytes(blob)
            try:
                got = partslam.load_scan_source(str(cut))
            except partslam.InputError as e:
                print(f"  {path.name} cut at {n}: {e}")
                bad += 1
                continue
            m = len(got.scans)
            prefix = [s.timestamp for s in got.scans] == stamps[:m] and [len(s.points_laser) for s in got.scans] == sizes[:m]
            warned = any("cut short" in w or "ends mid-record" in w or "ends at byte" in w for w in got.warnings)
            lost = m < len(stamps) and not warned
            if text is not None:  # the text before the cut: every whole scan line in it must be read
                before = zlib.decompressobj(16 + zlib.MAX_WBITS).decompress(blob)
                whole_lines = before[: before.rfind(b"\n") + 1]
                expected = sum(1 for line in whole_lines.split(b"\n") if line.startswith((b"FLASER", b"ROBOTLASER1")))
                lost = m < expected or (m > expected + 1)
            if not prefix or lost:
                print(f"  {path.name} cut at {n}: prefix {prefix}, {m} scans, warnings {got.warnings}")
                bad += 1
            shares.append(m / len(stamps))
        failures += bad
        print(f"{path.relative_to(shared)}: {cuts} cuts, {bad} bad; scans read {min(shares, default=0):.2f} .. "
              f"{max(shares, default=0):.2f} of {len(stamps)}", flush=True)
print("all cuts read their whole records before the cut" if failures == 0 else f"{failures} bad cuts")
sys.exit(1 if failures else 0)
