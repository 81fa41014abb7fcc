"""Scans, submaps and the Manhattan angle from Python, the checks of core/maps/submap_test.cc and
manhattan_test.cc on the built-in simulator."""
import math

import numpy as np
import pytest

import partslam

DEG = math.pi / 180


def residual_mod_quarter(a):
    """Signed difference to the nearest multiple of 90 degrees [rad]."""
    q = math.pi / 2
    return a - q * math.floor(a / q + 0.5)


def test_simulated_scans_have_poses_and_finite_points(sim_scans):
    assert len(sim_scans) > 1000
    assert isinstance(sim_scans, partslam.Scans)
    timestamps = [s.timestamp for s in sim_scans]
    assert all(b > a for a, b in zip(timestamps, timestamps[1:]))
    for scan in sim_scans[::50]:
        points = scan.points_laser
        assert points.shape[1] == 2 and 0 < len(points) <= scan.num_beams
        assert np.isfinite(points).all()
        assert np.all(np.hypot(points[:, 0], points[:, 1]) < 30.0)
        np.testing.assert_allclose(scan.points_world(), partslam.transform(scan.T_world_laser, points), atol=1e-12)
        near = scan.points_world(max_range=8.0)
        assert len(near) == np.count_nonzero(np.hypot(points[:, 0], points[:, 1]) <= 8.0)
    assert sim_scans[-1].timestamp == timestamps[-1]


def test_travel_distances_grow_along_the_log(sim_scans):
    s = partslam.travel_distances(sim_scans)
    assert s.shape == (len(sim_scans),) and s[0] == 0.0
    assert np.all(np.diff(s) >= 0)
    step = np.hypot(sim_scans[1].T_world_laser[0] - sim_scans[0].T_world_laser[0],
                    sim_scans[1].T_world_laser[1] - sim_scans[0].T_world_laser[1])
    assert s[1] == pytest.approx(step)


def test_one_submap_per_half_metre_of_travel(sim_scans, sim_submaps):
    travel = partslam.travel_distances(sim_scans)[-1]
    assert len(sim_submaps) == pytest.approx(travel / 0.5, abs=2.0)
    gaps = np.diff([m.travel for m in sim_submaps])
    assert np.all(gaps >= 0.5 - 0.1 - 1e-9) and np.all(gaps <= 0.5 + 0.1 + 1e-9)


def test_submap_points_are_finite_cropped_aligned_and_centred(sim_scans, sim_submaps):
    assert len(sim_submaps) > 100
    s = partslam.travel_distances(sim_scans)
    for k, m in enumerate(sim_submaps):
        points = m.points
        assert len(points) >= 20 and np.isfinite(points).all()
        assert np.all(np.abs(points) < 6.4), f"submap {k} leaves the crop"
        assert 0.0 <= m.alignment_angle < math.pi / 2
        assert partslam.wrap_angle(m.T_world_map[2] + m.alignment_angle) == pytest.approx(0.0, abs=1e-12)
        if k % 10:
            continue
        # Centred: the frame is the centroid of the window's points, one per 0.1 m cell, recomputed here.
        window = [j for j in range(m.anchor_scan, len(sim_scans)) if s[j] < m.travel + 2.0]
        world = np.vstack([sim_scans[j].points_world(max_range=8.0) for j in window])
        cells, inverse = np.unique(np.floor(world / 0.1).astype(np.int64), axis=0, return_inverse=True)
        sums = np.zeros((len(cells), 2))
        np.add.at(sums, inverse.ravel(), world)
        means = sums / np.bincount(inverse.ravel())[:, None]
        assert len(m.scan_timestamps) == len(window)
        np.testing.assert_allclose(m.T_world_map[:2], means.mean(axis=0), atol=1e-6)


def test_a_local_map_is_the_stored_submap_over_the_same_scans(sim_scans, sim_submaps):
    s = partslam.travel_distances(sim_scans)
    m = sim_submaps[20]
    local = partslam.build_local_map(sim_scans, s[m.anchor_scan], m.travel + 2.0)
    assert local.anchor_scan == m.anchor_scan
    np.testing.assert_array_equal(local.scan_timestamps, m.scan_timestamps)
    np.testing.assert_array_equal(local.points, m.points)
    assert local.T_world_map == m.T_world_map
    with pytest.raises(ValueError, match="local map"):
        partslam.build_local_map(sim_scans, 5.0, 4.0)
    with pytest.raises(ValueError, match="no scan"):
        partslam.build_local_map(sim_scans, 1e6, 1e6 + 2)
    with pytest.raises(ValueError, match="fewer than 100000 points"):
        partslam.build_local_map(sim_scans, 0.0, 2.0, partslam.SubmapConfig(min_points=100000))


def test_submaps_from_a_python_list_of_scans(sim_scans):
    first = [sim_scans[i] for i in range(200)]
    from_list = partslam.build_submaps(first)
    from_scans = partslam.build_submaps(partslam.Scans(first))
    assert len(from_list) == len(from_scans) > 0
    for a, b in zip(from_list, from_scans):
        np.testing.assert_array_equal(a.points, b.points)


def test_scans_built_in_python():
    # A square room seen from its centre by four scans turning on the spot: the submap holds its walls.
    beams = np.linspace(-math.pi / 2, math.pi / 2, 181)
    scans = []
    for k in range(40):
        theta = k * 0.2
        x, y = 0.05 * k, 0.0
        directions = np.stack([np.cos(beams + theta), np.sin(beams + theta)], axis=1)
        with np.errstate(divide="ignore"):  # beams along an axis never reach the other pair of walls
            ranges = np.min((3.0 - np.sign(directions) * [x, y]) / np.abs(directions), axis=1)
        scans.append(partslam.Scan(timestamp=0.1 * k, T_world_laser=(x, y, theta), T_world_odom=(x, y, theta),
                                   points_laser=ranges[:, None] * np.stack([np.cos(beams), np.sin(beams)], axis=1),
                                   num_beams=181))
    maps = partslam.build_submaps(scans, partslam.SubmapConfig(window_length=1.5, spacing=0.5))
    assert len(maps) >= 1
    world = partslam.transform(maps[0].T_world_map, maps[0].points)
    # Every point lies on the walls |x| = 3 or |y| = 3 (cell means: within half a cell diagonal).
    assert np.all(np.abs(np.max(np.abs(world), axis=1) - 3.0) < 0.08)


def test_bad_submap_config_names_the_field(sim_scans):
    with pytest.raises(ValueError, match="window_length"):
        partslam.build_submaps(sim_scans, partslam.SubmapConfig(window_length=0.0))
    with pytest.raises(ValueError, match="min_points"):
        partslam.SubmapConfig(min_points=0).validate()
    with pytest.raises(TypeError, match="unexpected keyword argument 'windw'"):
        partslam.SubmapConfig(windw=3.0)


def test_configs_print_in_their_keyword_form():
    config = partslam.SubmapConfig(window_length=3.0, align=False)
    text = repr(config)
    assert text.startswith("SubmapConfig(window_length=3.0, spacing=0.5, ") and "align=False" in text
    again = eval(text, vars(partslam))  # noqa: S307 - the repr of our own config
    assert (again.window_length, again.spacing, again.align) == (3.0, 0.5, False)
    assert repr(partslam.DmmConfig(dilation=0)).startswith("DmmConfig(resolution=0.1, ")


def test_manhattan_angle_of_an_axis_aligned_rectangle():
    i = np.arange(50)
    points = np.vstack([np.stack([0.1 * i, np.full(50, 0.05)], 1), np.stack([0.1 * i, np.full(50, 3.05)], 1),
                        np.stack([np.full(50, 0.05), 0.06 * i], 1), np.stack([np.full(50, 5.05), 0.06 * i], 1)])
    assert residual_mod_quarter(partslam.manhattan_angle(points)) == pytest.approx(0.0, abs=0.1 * DEG)
    a = partslam.manhattan_angle(partslam.transform((0.0, 0.0, 25.0 * DEG), points))
    assert 0.0 <= a < math.pi / 2
    assert residual_mod_quarter(a + 25.0 * DEG) == pytest.approx(0.0, abs=0.1 * DEG)


def test_manhattan_angle_undoes_known_turns_of_simulated_submaps(sim_scans):
    maps = partslam.build_submaps(sim_scans, partslam.SubmapConfig(align=False))
    checked = 0
    for m in maps[::37]:
        for degrees in (0.4, 17.0, 45.0, 62.5, -20.0, 135.0):
            a = partslam.manhattan_angle(partslam.transform((0.0, 0.0, degrees * DEG), m.points))
            assert 0.0 <= a < math.pi / 2
            assert abs(residual_mod_quarter(a + degrees * DEG)) < 1.0 * DEG
            checked += 1
    assert checked > 40
