"""A real CARMEN log degraded the way another robot's sensors would be (scripts/slam-stress.sh): the same run, its
truth (the relations file, by timestamp) unchanged.
Usage: /usr/bin/python3 scripts/log_variants.py IN.clf[.gz] OUT.clf.gz VARIANT
  VARIANT: half-beams     every second beam kept (0.5-degree lasers become 1-degree ones, 1-degree ones 2-degree)
           half-rate      every second scan dropped (twice the motion between scans; the odometry messages kept)
           odometry-scale the wheel odometry's increments rescaled: translations x 0.92, turns x 1.10 (a robot
                          whose wheels and gauge are miscalibrated), the laser's mount on the robot kept
           short-range    returns beyond 8 m dropped (a short-range laser)
           sparse         half of the returns dropped, chosen at random with a fixed seed (glass, black surfaces,
                          open space)
           odometry-curve the wheel odometry turns 0.01 rad more per metre travelled (one wheel 0.5 % larger than
                          the other on a 0.5 m gauge: straight corridors drawn as arcs), the laser's mount kept
           range-noise    N(0, 0.03 m) added to every return nearer than 40 m, with a fixed seed (a cheaper laser
                          than these logs' SICKs, e.g. a Hokuyo URG's +-3 cm; no-return codes left as they are)
           laser-lag      each scan posed by the odometry of 0.1 s before it (a laser whose stamps lag the
                          odometry's: the pose is wrong while the robot turns), interpolated in the log's FLASER poses
           moved-K        (K = 1..9) the whole run moved rigidly: every pose (laser, odometry, ODOM) turned by
                          0.61 K rad and shifted by (3.7 K, -2.3 K) m. Nothing a relation measures changes: slam's
                          answers on these are its resolution (scripts/slam-resolution.sh)
Only FLASER and ODOM messages are read; a log with other laser messages is refused."""
import bisect
import gzip
import math
import os
import random
import sys

VARIANTS = ("half-beams", "half-rate", "odometry-scale", "short-range", "sparse", "odometry-curve", "laser-lag",
            "range-noise") + tuple(
    f"moved-{k}" for k in range(1, 10))
NO_RETURN = "81.91"
TRANSLATION_SCALE, TURN_SCALE = 0.92, 1.10
CURVE = 0.01  # [rad per metre]
SHORT_RANGE = 8.0
LAG = 0.1  # [s]
RANGE_NOISE, NOISY_BELOW = 0.03, 40.0  # [m]


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


class RescaledOdometry:
    """Integrates the log's odometry increments, each expressed in the previous pose's frame, rescaled
    (translation_scale, turn_scale) and bent (curve [rad] more turn per metre of the increment's translation)."""

    def __init__(self, translation_scale=1.0, turn_scale=1.0, curve=0.0):
        self.raw = None
        self.pose = None
        self.translation_scale, self.turn_scale, self.curve = translation_scale, turn_scale, curve

    def __call__(self, x, y, theta):
        if self.raw is None:
            self.raw, self.pose = (x, y, theta), [x, y, theta]
            return tuple(self.pose)
        px, py, pt = self.raw
        c, s = math.cos(pt), math.sin(pt)
        dx, dy = c * (x - px) + s * (y - py), -s * (x - px) + c * (y - py)
        dt = self.turn_scale * wrap(theta - pt) + self.curve * math.hypot(dx, dy)
        dx, dy = self.translation_scale * dx, self.translation_scale * dy
        c, s = math.cos(self.pose[2]), math.sin(self.pose[2])
        self.pose = [self.pose[0] + c * dx - s * dy, self.pose[1] + s * dx + c * dy, wrap(self.pose[2] + dt)]
        self.raw = (x, y, theta)
        return tuple(self.pose)


def rescaled_flaser(rest, odometry):
    """FLASER's laser pose (x y theta) and odometry pose: the odometry rescaled, the laser kept on its mount."""
    return reposed_flaser(rest, odometry(*(float(v) for v in rest[3:6])))


def reposed_flaser(rest, pose):
    """FLASER's laser pose (x y theta) and odometry pose: the odometry replaced by pose, the laser kept on its
    mount."""
    lx, ly, lt, ox, oy, ot = (float(v) for v in rest[:6])
    c, s = math.cos(ot), math.sin(ot)
    mount = (c * (lx - ox) + s * (ly - oy), -s * (lx - ox) + c * (ly - oy), lt - ot)
    nx, ny, nt = pose
    c, s = math.cos(nt), math.sin(nt)
    laser = (nx + c * mount[0] - s * mount[1], ny + s * mount[0] + c * mount[1], wrap(nt + mount[2]))
    return ["%.6f" % v for v in laser + (nx, ny, nt)] + rest[6:]


def main(src, dst, variant):
    if variant not in VARIANTS:
        sys.exit(f"log_variants: unknown variant {variant!r} (one of {', '.join(VARIANTS)})")
    part = dst + ".part"
    try:
        try:
            degrade(src, part, variant)
        except (OSError, EOFError, UnicodeDecodeError) as e:
            sys.exit(f"log_variants: {src}: cannot read it or write {dst} ({e})")
        os.replace(part, dst)
    finally:  # any failure, an error exit too: no half-written output left behind
        if os.path.exists(part):
            os.remove(part)


def moved(pose, k):
    """pose (x, y, theta) after the rigid move of variant moved-k."""
    a = 0.61 * k
    c, s = math.cos(a), math.sin(a)
    return (3.7 * k + c * pose[0] - s * pose[1], -2.3 * k + s * pose[0] + c * pose[1], wrap(a + pose[2]))


def pose_at(poses, times, t):
    """The odometry pose at time t, linear between the two FLASER poses around it (the first or last outside);
    times: the poses' timestamps. A lag looks back only, so the poses read so far are enough."""
    i = bisect.bisect_right(times, t)
    if i == 0:
        return poses[0][1]
    if i == len(poses):
        return poses[-1][1]
    (t0, a), (t1, b) = poses[i - 1], poses[i]
    u = (t - t0) / (t1 - t0) if t1 > t0 else 0.0
    return (a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]), wrap(a[2] + u * wrap(b[2] - a[2])))


def degrade(src, part, variant):
    rng = random.Random(7)
    odometry = (RescaledOdometry(TRANSLATION_SCALE, TURN_SCALE) if variant == "odometry-scale"
                else RescaledOdometry(curve=CURVE))
    opener = gzip.open if src.endswith(".gz") else open
    lagged, lagged_times = [], []  # laser-lag: the FLASER poses so far and their timestamps (CARMEN's ipc_timestamp)
    scans = 0
    move = int(variant.split("-")[1]) if variant.startswith("moved-") else 0
    with opener(src, "rt") as lines, gzip.open(part, "wt") as out:
        for number, line in enumerate(lines, 1):
            f = line.split()
            if f and f[0] in ("ROBOTLASER1", "ROBOTLASER2", "RAWLASER1", "RAWLASER2"):
                sys.exit(f"log_variants: {src}:{number}: {f[0]} messages are not handled (FLASER and ODOM only)")
            if not f or f[0] not in ("FLASER", "ODOM"):
                out.write(line)
                continue
            try:
                if f[0] == "ODOM":
                    if variant in ("odometry-scale", "odometry-curve"):
                        f[1:4] = ["%.6f" % v for v in odometry(*(float(v) for v in f[1:4]))]
                    elif move:
                        f[1:4] = ["%.6f" % v for v in moved(tuple(float(v) for v in f[1:4]), move)]
                    out.write(" ".join(f) + "\n")
                    continue
                n = int(f[1])
                ranges, rest = f[2:2 + n], f[2 + n:]
                if len(ranges) != n or len(rest) < 6:
                    raise ValueError(f"{n} ranges and a pose announced, {len(f) - 2} fields follow")
                scans += 1
                if variant == "half-rate" and scans % 2 == 0:
                    continue
                if variant == "half-beams":
                    ranges = ranges[::2]
                elif variant == "short-range":
                    ranges = [r if float(r) < SHORT_RANGE else NO_RETURN for r in ranges]
                elif variant == "sparse":
                    ranges = [r if rng.random() < 0.5 else NO_RETURN for r in ranges]
                elif variant == "range-noise":
                    ranges = ["%.3f" % max(0.0, float(r) + rng.gauss(0.0, RANGE_NOISE)) if 0 < float(r) < NOISY_BELOW
                              else r for r in ranges]
                elif variant in ("odometry-scale", "odometry-curve"):
                    rest = rescaled_flaser(rest, odometry)
                elif move:
                    poses = moved(tuple(float(v) for v in rest[:3]), move) + moved(
                        tuple(float(v) for v in rest[3:6]), move)
                    rest = ["%.6f" % v for v in poses] + rest[6:]
                elif variant == "laser-lag":
                    if len(rest) < 9:
                        raise ValueError(f"{n} ranges announced, no timestamp after the poses")
                    lagged.append((float(rest[6]), tuple(float(v) for v in rest[3:6])))
                    lagged_times.append(lagged[-1][0])
                    rest = reposed_flaser(rest, pose_at(lagged, lagged_times, lagged[-1][0] - LAG))
            except ValueError as e:
                sys.exit(f"log_variants: {src}:{number}: a malformed {f[0]} message ({e})")
            out.write(" ".join(["FLASER", str(len(ranges))] + ranges + rest) + "\n")
    if scans == 0:
        sys.exit(f"log_variants: {src}: no FLASER message")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__.strip().splitlines()[1])
    main(*sys.argv[1:])
