"""Tests of scripts/log_variants.py on a small CARMEN log written here (the stress bench's inputs; ctest
log_variants.degrades_as_documented). Usage: /usr/bin/python3 scripts/log_variants_test.py"""
import gzip
import math
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "log_variants.py")


def flaser(ranges, pose, t):
    """A FLASER message with the laser 0.1 m ahead of the robot on its axis."""
    x, y, theta = pose
    laser = (x + 0.1 * math.cos(theta), y + 0.1 * math.sin(theta), theta)
    fields = ["FLASER", str(len(ranges))] + ["%.2f" % r for r in ranges]
    fields += ["%.6f" % v for v in laser + pose] + ["%.6f" % t, "host", "%.6f" % t]
    return " ".join(fields)


def straight_log(steps=11, speed=1.0, dt=0.5):
    """The robot drives along x at speed [m/s], a scan of 4 beams (2, 5, 9, 81.91 m) and an ODOM message each dt."""
    lines = ["# a straight drive"]
    for i in range(steps):
        t, pose = 100.0 + i * dt, (i * speed * dt, 0.0, 0.0)
        lines.append("ODOM %.6f 0 0 0 0 0 %.6f host %.6f" % (pose[0], t, t))
        lines.append(flaser([2.0, 5.0, 9.0, 81.91], pose, t + 0.01))
    return "\n".join(lines) + "\n"


def turning_log(steps=11, rate=0.4, dt=0.5):
    """The robot turns on the spot at rate [rad/s]."""
    lines = []
    for i in range(steps):
        t = 100.0 + i * dt
        lines.append(flaser([3.0, 3.0], (0.0, 0.0, i * rate * dt), t))
    return "\n".join(lines) + "\n"


def read_flaser(path, plain=False):
    """Per FLASER message: (ranges, laser pose, odometry pose); plain: an uncompressed file."""
    out = []
    with (open(path) if plain else gzip.open(path, "rt")) as f:
        for line in f:
            v = line.split()
            if v[0] != "FLASER":
                continue
            n = int(v[1])
            rest = [float(x) for x in v[2 + n:2 + n + 6]]
            out.append(([float(r) for r in v[2:2 + n]], tuple(rest[:3]), tuple(rest[3:6])))
    return out


class LogVariants(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def run_variant(self, text, variant, name="in.clf"):
        src, dst = os.path.join(self.dir.name, name), os.path.join(self.dir.name, "out.clf.gz")
        with open(src, "w") as f:
            f.write(text)
        p = subprocess.run([sys.executable, SCRIPT, src, dst, variant], capture_output=True, text=True)
        return p, dst

    def test_odometry_curve_turns_a_straight_drive_by_its_rate(self):
        p, out = self.run_variant(straight_log(), "odometry-curve")
        self.assertEqual(p.returncode, 0, p.stderr)
        scans = read_flaser(out)
        self.assertEqual(len(scans), 11)
        _, laser, odom = scans[-1]
        # 5 m driven (plus the 0.01 s between each ODOM and its scan, the same in both): 0.05 rad of turn.
        self.assertAlmostEqual(odom[2], 0.01 * 5.0, delta=1e-4)
        self.assertAlmostEqual(odom[1], 5.0 * 0.05 / 2, delta=0.02)  # bent: an arc's height, 5 m at 0.01 rad/m
        # The laser stays on its mount: 0.1 m ahead along the bent heading.
        self.assertAlmostEqual(laser[0] - odom[0], 0.1 * math.cos(odom[2]), delta=2e-6)
        self.assertAlmostEqual(laser[1] - odom[1], 0.1 * math.sin(odom[2]), delta=2e-6)
        self.assertEqual(scans[-1][0], [2.0, 5.0, 9.0, 81.91])

    def test_laser_lag_poses_each_scan_where_the_robot_was_before(self):
        p, out = self.run_variant(turning_log(), "laser-lag")
        self.assertEqual(p.returncode, 0, p.stderr)
        scans = read_flaser(out)
        self.assertAlmostEqual(scans[0][2][2], 0.0, delta=1e-6)  # nothing before the first scan: its own pose
        for i in range(1, len(scans)):
            self.assertAlmostEqual(scans[i][2][2], 0.4 * (i * 0.5 - 0.1), delta=1e-5)
            self.assertAlmostEqual(scans[i][1][2], scans[i][2][2], delta=1e-5)

    def test_moved_keeps_every_relative_pose_and_moves_every_pose(self):
        p, out = self.run_variant(turning_log().replace("FLASER", "ODOM 0 0 0 0 0 0 0 host 0\nFLASER", 1)
                                  + straight_log(), "moved-2")
        self.assertEqual(p.returncode, 0, p.stderr)
        before = read_flaser(os.path.join(self.dir.name, "in.clf"), plain=True)
        after = read_flaser(out)
        self.assertEqual(len(after), len(before))

        def relative(a, b):
            c, s = math.cos(a[2]), math.sin(a[2])
            dx, dy = b[0] - a[0], b[1] - a[1]
            return c * dx + s * dy, -s * dx + c * dy, math.remainder(b[2] - a[2], 2 * math.pi)

        for (r0, l0, o0), (r1, l1, o1) in zip(before, after):
            self.assertEqual(r0, r1)
            self.assertNotAlmostEqual(o1[0], o0[0], delta=1.0)  # moved: 7.4 m along x, turned 1.22 rad
            for got, want in zip(relative(o1, l1), relative(o0, l0)):  # the laser on its mount
                self.assertAlmostEqual(got, want, delta=2e-6)
            for got, want in zip(relative(after[0][2], o1), relative(before[0][2], o0)):  # the run's shape
                self.assertAlmostEqual(got, want, delta=2e-5)
        with gzip.open(out, "rt") as f:
            odom = [line.split() for line in f if line.startswith("ODOM")]
        self.assertAlmostEqual(float(odom[0][1]), 7.4, delta=1e-6)  # the origin, moved by (3.7 K, -2.3 K)
        self.assertAlmostEqual(float(odom[0][2]), -4.6, delta=1e-6)
        self.assertAlmostEqual(float(odom[0][3]), 1.22, delta=1e-6)

    def test_short_range_drops_far_returns_only(self):
        p, out = self.run_variant(straight_log(), "short-range")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(read_flaser(out)[3][0], [2.0, 5.0, 81.91, 81.91])

    def test_range_noise_moves_near_returns_by_centimetres_and_keeps_no_return_codes(self):
        p, out = self.run_variant(straight_log(steps=200), "range-noise")
        self.assertEqual(p.returncode, 0, p.stderr)
        scans = read_flaser(out)
        self.assertEqual(len(scans), 200)
        errors = [r - true for ranges, _, _ in scans for r, true in zip(ranges[:3], (2.0, 5.0, 9.0))]
        mean = sum(errors) / len(errors)
        std = math.sqrt(sum((e - mean) ** 2 for e in errors) / len(errors))
        self.assertLess(abs(mean), 0.005)
        self.assertAlmostEqual(std, 0.03, delta=0.004)
        self.assertTrue(all(ranges[3] == 81.91 for ranges, _, _ in scans))  # the no-return code untouched
        recorded = read_flaser(os.path.join(self.dir.name, "in.clf"), plain=True)
        self.assertEqual([s[1:] for s in scans], [s[1:] for s in recorded])  # the poses as recorded

    def test_a_malformed_message_is_named_and_leaves_no_output(self):
        text = straight_log().replace("FLASER 4 2.00 5.00 9.00 81.91 0.600000", "FLASER 4 2.00 5.00", 1)
        self.assertNotEqual(text, straight_log())
        p, out = self.run_variant(text, "laser-lag")
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("in.clf:", p.stderr)
        self.assertIn("malformed FLASER", p.stderr)
        self.assertFalse(os.path.exists(out))
        self.assertFalse(os.path.exists(out + ".part"))

    def test_an_unknown_variant_is_refused(self):
        p, out = self.run_variant(straight_log(), "upside-down")
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("unknown variant", p.stderr)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
