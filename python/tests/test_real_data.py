"""The module on a real log (fr079, corrected), as io/testing/real_data_test.cc and dmm_real_data_test.cc check
it; skipped when the shared data folder is absent ($PARTSLAM_SHARED_DATA, else ../shared/data). Every core check
also runs on the simulator in the other test files."""
import math

import numpy as np
import pytest

import partslam
from conftest import shared_data

FR079 = shared_data() / "fr079" / "fr079-corrected.log.gz"
pytestmark = pytest.mark.skipif(not FR079.exists(), reason=f"{FR079} is absent (set PARTSLAM_SHARED_DATA)")


@pytest.fixture(scope="module")
def fr079():
    return partslam.read_carmen_log(FR079)


def test_fr079_scan_and_odometry_counts(fr079):
    # Counted independently with zcat | awk (io/testing/real_data_test.cc).
    assert len(fr079.scans) == 4791
    assert len(fr079.odometry) == 9725
    assert partslam.load_scan_source(str(FR079)).name == "fr079-corrected"


def test_fr079_submaps_recover_a_known_offset(fr079):
    maps = partslam.build_submaps(fr079.scans, partslam.SubmapConfig(spacing=5.0))
    assert len(maps) > 50
    config = partslam.DmmConfig()
    T_map_query = (1.3, -0.8, -math.pi / 2 + 1.7 * math.pi / 180)
    for m in maps[3::len(maps) // 6]:
        assert np.isfinite(m.points).all() and np.all(np.abs(m.points) < 6.4)
        query = partslam.prepare_query(partslam.transform(partslam.inverse(T_map_query), m.points), config)
        r = partslam.match_dmm(query, partslam.prepare_map(m.points, config))
        assert r.inlier_fraction > 0.9
        assert abs(r.T_map_query[0] - T_map_query[0]) <= config.resolution + 1e-9
        assert abs(r.T_map_query[1] - T_map_query[1]) <= config.resolution + 1e-9
        assert abs(partslam.wrap_angle(r.T_map_query[2] - T_map_query[2])) <= query.angular_step + 1e-9
