"""Tests of scripts/bag_relations.py (the benchmark's relations carried onto a re-timed recording of the same run) on
two small CARMEN logs written here: the run as logged, and the same scans re-timed and listed partly out of order, as
intel's benchmark bag lists them (ctest bag_relations.pairs_scans_by_their_ranges; it needs the `partslam` module on
PYTHONPATH or in build/python). Usage: /usr/bin/python3 scripts/bag_relations_test.py"""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bag_relations.py")
SCANS = 40
# Where the re-timed recording lists each scan of the log: runs of scans out of order, up to 3 places away.
ORDER = list(range(SCANS))
ORDER[5], ORDER[6] = 6, 5
ORDER[10:14] = [12, 10, 13, 11]
ORDER[20:25] = [24, 23, 22, 21, 20]


def log_time(i):
    return 100.0 + 0.5 * i


def flaser(i, t, longer=0.0):
    """Scan i of the run: 8 beams whose lengths differ from every other scan's (the first `longer` [m] longer), the
    robot 0.5 m further each scan."""
    ranges = [1.0 + 0.37 * k + 0.011 * i + (longer if k == 0 else 0.0) for k in range(8)]
    pose = (0.5 * i, 0.0, 0.0)
    fields = ["FLASER", str(len(ranges))] + ["%.3f" % r for r in ranges]
    fields += ["%.6f" % v for v in pose + pose] + ["%.6f" % t, "host", "%.6f" % t]
    return " ".join(fields)


def write(path, lines):
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


class BagRelations(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        self.log, self.other, self.relations = (os.path.join(d, n) for n in ("run.clf", "other.clf", "run.relations"))
        self.out = os.path.join(d, "other.relations")
        write(self.log, [flaser(i, log_time(i)) for i in range(SCANS)])
        # The other recording: slot k holds the log's scan ORDER[k], stamped at its own clock.
        self.other_time = {ORDER[k]: 1e9 + 0.1 * k for k in range(SCANS)}
        write(self.other, [flaser(ORDER[k], 1e9 + 0.1 * k) for k in range(SCANS)])
        self.pairs = [(i, i + 1) for i in range(SCANS - 1)] + [(3, 22), (11, 30)]
        write(self.relations, ["%.6f %.6f 0.5 0 0 0 0 0.01" % (log_time(a), log_time(b)) for a, b in self.pairs])

    def tearDown(self):
        self.dir.cleanup()

    def run_script(self, other=None):
        return subprocess.run([sys.executable, SCRIPT, self.log, other or self.other, self.relations, self.out],
                              capture_output=True, text=True)

    def test_each_relation_names_the_scans_that_hold_the_same_ranges(self):
        r = self.run_script()
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(self.out) as f:
            lines = [line.split() for line in f]
        self.assertEqual(len(lines), len(self.pairs))
        for (a, b), v in zip(self.pairs, lines):
            self.assertAlmostEqual(float(v[0]), self.other_time[a], places=4)
            self.assertAlmostEqual(float(v[1]), self.other_time[b], places=4)
            self.assertEqual(v[2:], ["0.5", "0", "0", "0", "0", "0.01"])
        # Paired by their order, 15 of the 41 relations would name other scans.
        moved = sum(self.other_time[a] != 1e9 + 0.1 * a or self.other_time[b] != 1e9 + 0.1 * b for a, b in self.pairs)
        self.assertEqual(moved, 15)

    def test_a_scan_without_its_twin_is_named_and_nothing_is_written(self):
        changed = os.path.join(self.dir.name, "changed.clf")
        write(changed, [flaser(ORDER[k], 1e9 + 0.1 * k, 0.005 if k == 7 else 0.0) for k in range(SCANS)])
        r = self.run_script(changed)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("changed.clf: scan 7 has no scan of", r.stderr)
        self.assertFalse(os.path.exists(self.out))

    def test_recordings_of_different_lengths_are_refused(self):
        shorter = os.path.join(self.dir.name, "shorter.clf")
        write(shorter, [flaser(ORDER[k], 1e9 + 0.1 * k) for k in range(SCANS - 1)])
        r = self.run_script(shorter)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("holds 40 scans", r.stderr)
        self.assertIn("shorter.clf 39: they cannot be paired", r.stderr)
        self.assertFalse(os.path.exists(self.out))


if __name__ == "__main__":
    unittest.main()
