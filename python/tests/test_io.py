"""Logs from Python (io/carmen_log_test.cc): a tiny CARMEN log with known answers, the simulator as a scan
source, a log round trip in a temporary folder, and errors that name the file and line."""
import gzip
import math

import numpy as np
import pytest

import partslam

# FLASER: 4 beams at -90, -45, 0, 45 deg (kCarmen: pi/4); 81.91 = no return, 0 = invalid.
TINY_LOG = ("# CARMEN Logfile\n"
            "PARAM robot_front_laser_max 81.9 nohost 0\n"
            "FLASER 4 1.0 2.0 81.91 0 0.5 1.0 1.5707963267948966 0.4 0.9 1.5 100.25 host 100.3\n"
            "ODOM 0.4 0.9 1.5 0.1 0.2 0.3 100.2 host 100.2\n")


@pytest.mark.parametrize("gz", [False, True])
def test_tiny_log_known_answers(tmp_path, gz):
    path = tmp_path / ("tiny.log.gz" if gz else "tiny.log")
    path.write_bytes(gzip.compress(TINY_LOG.encode()) if gz else TINY_LOG.encode())
    log = partslam.read_carmen_log(path)
    assert len(log.scans) == 1 and log.stats.flaser == 1 and log.stats.odom == 1
    assert log.stats.skipped == {"PARAM": 1}
    scan = log.scans[0]
    assert scan.timestamp == 100.25 and scan.num_beams == 4
    assert scan.T_world_laser == pytest.approx((0.5, 1.0, math.pi / 2))
    assert scan.T_world_odom == pytest.approx((0.4, 0.9, 1.5))
    np.testing.assert_allclose(scan.points_laser, [[0.0, -1.0], [math.sqrt(2), -math.sqrt(2)]], atol=1e-9)
    assert log.odometry[0].T_world_odom == pytest.approx((0.4, 0.9, 1.5))
    assert log.odometry[0].tv == 0.1
    source = partslam.load_scan_source(str(path))
    assert source.name == "tiny" and len(source.scans) == 1


def test_malformed_and_missing_logs_raise_value_error_naming_file_and_line(tmp_path):
    bad = tmp_path / "bad.clf"
    bad.write_text("ODOM 0 0 0 0 0 0 1.0 host 1.0\nFLASER 4 1 2 nan 4 0 0 0 0 0 0 1.0 h 1.0\n")
    with pytest.raises(ValueError, match=r"bad.clf:2: FLASER range\[2\]: not a finite number 'nan'"):
        partslam.read_carmen_log(bad)
    with pytest.raises(partslam.InputError, match="bad.clf:2"):
        partslam.load_scan_source(str(bad))
    missing = tmp_path / "missing.log.gz"
    with pytest.raises(ValueError, match=r"missing\.log\.gz: cannot open"):
        partslam.load_scan_source(str(missing))
    with pytest.raises(ValueError, match="max_usable_range"):
        partslam.read_carmen_log(bad, partslam.LogReadOptions(max_usable_range=-1.0))


def test_simulator_source_is_seeded():
    assert partslam.is_simulator_spec("sim:7") and not partslam.is_simulator_spec("simulator.log")
    a, b, c = (partslam.load_scan_source(s) for s in ("sim", "sim:1", "sim:2"))
    assert a.name == b.name == "sim-1" and c.name == "sim-2" and a.source == "sim"
    assert len(a.scans) == len(b.scans)
    np.testing.assert_array_equal(a.scans[100].points_laser, b.scans[100].points_laser)
    assert a.scans[100].T_world_laser == b.scans[100].T_world_laser
    assert len(a.scans) != len(c.scans) or a.scans[100].T_world_laser != c.scans[100].T_world_laser
    with pytest.raises(ValueError, match="seed must be an integer"):
        partslam.load_scan_source("sim:x")


def test_written_log_reads_back_to_a_tenth_of_a_millimetre(tmp_path, sim_scans):
    scans = partslam.Scans([sim_scans[i] for i in range(0, 300, 3)])
    path = tmp_path / "sim.log.gz"
    partslam.write_carmen_log(path, scans, header="written by test_io.py")
    back = partslam.read_carmen_log(path)
    assert len(back.scans) == len(scans) and back.stats.flaser == len(scans)
    for a, b in zip(scans, back.scans):
        assert b.timestamp == pytest.approx(a.timestamp, abs=1e-6)
        assert b.T_world_laser == pytest.approx(a.T_world_laser, abs=1e-6)
        np.testing.assert_allclose(b.points_laser, a.points_laser, atol=1e-4)
    with pytest.raises(ValueError, match="no beams"):
        partslam.write_carmen_log(tmp_path / "empty.log", [partslam.Scan(timestamp=1.0)])
