"""Tests of scripts/retimed_relations.py (a relations file carried onto a re-timed recording of the same run, paired by
the recording's poses when the log the relations name is not at hand) on a run written here: a path of straight
stretches and turns, logged at uneven intervals (0.2 to 0.8 s), re-timed at 0.1 s a scan with poses off by 1 cm, and relations
every 3 to 5 scans (ctest retimed_relations.pairs_stamps_by_the_poses; it needs the `partslam` module on PYTHONPATH
or in build/python). Usage: /usr/bin/python3 scripts/retimed_relations_test.py"""
import math
import os
import random
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "retimed_relations.py")
SCANS = 400


def run_of_scans(seed):
    """True poses and log times of the run: 0.12 m a scan, turning 8 degrees a scan on a third of them."""
    rng = random.Random(seed)
    poses, times = [(0.0, 0.0, 0.0)], [100.0]
    for i in range(1, SCANS):
        x, y, th = poses[-1]
        th += math.radians(8.0) if (i // 20) % 3 == 2 else 0.0
        poses.append((x + 0.12 * math.cos(th), y + 0.12 * math.sin(th), th))
        times.append(times[-1] + rng.uniform(0.2, 0.8))
    return poses, times


def flaser(pose, t):
    fields = ["FLASER", "4"] + ["1.000"] * 4 + ["%.6f" % v for v in pose + pose] + ["%.6f" % t, "host", "%.6f" % t]
    return " ".join(fields)


def relation(a, b):
    """The true relative pose of b in a's frame."""
    (xa, ya, ta), (xb, yb, tb) = a, b
    c, s = math.cos(ta), math.sin(ta)
    return (c * (xb - xa) + s * (yb - ya), -s * (xb - xa) + c * (yb - ya), math.atan2(math.sin(tb - ta), math.cos(tb - ta)))


def write(path, lines):
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


class RetimedRelations(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        self.poses_log, self.relations, self.out = (os.path.join(d, n) for n in ("poses.clf", "run.relations", "out"))
        self.truth, self.log_time = run_of_scans(1)
        rng = random.Random(2)
        write(self.poses_log, [flaser((x + rng.gauss(0, 0.01), y + rng.gauss(0, 0.01), th), 1e9 + 0.1 * i)
                               for i, (x, y, th) in enumerate(self.truth)])
        sampled = [0]
        while sampled[-1] + 5 < SCANS:
            sampled.append(sampled[-1] + rng.choice((3, 4, 5)))
        self.pairs = list(zip(sampled, sampled[1:])) + [(sampled[2], sampled[60]), (sampled[10], sampled[70])]
        lines = []
        for k, (a, b) in enumerate(self.pairs):
            if k % 7 == 3:  # some written the other way round
                a, b = b, a
            x, y, th = relation(self.truth[a], self.truth[b])
            lines.append("%.6f %.6f %.6f %.6f 0 0 0 %.6f" % (self.log_time[a], self.log_time[b], x, y, th))
        write(self.relations, lines)
        self.lines = lines

    def tearDown(self):
        self.dir.cleanup()

    def run_script(self, poses=None, relations=None):
        return subprocess.run([sys.executable, SCRIPT, poses or self.poses_log, relations or self.relations, self.out],
                              capture_output=True, text=True)

    def test_each_stamp_is_paired_with_the_scan_it_names(self):
        r = self.run_script()
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(self.out) as f:
            got = [line.split() for line in f]
        self.assertEqual(len(got), len(self.lines))
        for line, v in zip(self.lines, got):
            ia = min(range(SCANS), key=lambda i: abs(self.log_time[i] - float(line.split()[0])))
            ib = min(range(SCANS), key=lambda i: abs(self.log_time[i] - float(line.split()[1])))
            self.assertAlmostEqual(float(v[0]), 1e9 + 0.1 * ia, places=4, msg=line)
            self.assertAlmostEqual(float(v[1]), 1e9 + 0.1 * ib, places=4, msg=line)
            self.assertEqual(v[2:], line.split()[2:])
        self.assertIn("; 0 at the search window's edge", r.stdout)

    def test_poses_of_another_run_are_refused_and_nothing_is_written(self):
        other = os.path.join(self.dir.name, "other.clf")
        poses, _ = run_of_scans(1)
        write(other, [flaser((2.0 * x, 2.0 * y, th), 1e9 + 0.1 * i) for i, (x, y, th) in enumerate(poses)])
        r = self.run_script(poses=other)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("not paired with", r.stderr)
        self.assertIn("nothing written", r.stderr)
        self.assertFalse(os.path.exists(self.out))
        self.assertFalse(os.path.exists(self.out + ".tmp"))

    def test_an_output_that_cannot_be_written_is_named(self):
        self.out = os.path.join(self.dir.name, "no such folder", "out")
        r = self.run_script()
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("no such folder/out: cannot write it", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_a_malformed_relation_is_named_with_its_line(self):
        bad = os.path.join(self.dir.name, "bad.relations")
        write(bad, self.lines[:4] + ["1.0 2.0 0.5 nan 0 0 0 0"] + self.lines[4:])
        r = self.run_script(relations=bad)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("bad.relations:5: expected", r.stderr)
        self.assertFalse(os.path.exists(self.out))


if __name__ == "__main__":
    unittest.main()
