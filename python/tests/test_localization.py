"""Building maps, point files and global localisation from Python: the checks of core/maps/grid_map_test.cc,
io/formats/map_server_test.cc and core/matching/localizer_test.cc on the built-in simulator."""
import math

import numpy as np
import pytest

import partslam


def test_grid_map_of_the_simulator_round_trips_through_map_server_files(sim_scans, tmp_path):
    grid = partslam.build_grid_map(sim_scans)
    cells = grid.cells
    assert cells.shape == (grid.height, grid.width)
    assert (cells == int(partslam.CellState.OCCUPIED)).sum() > 500
    assert (cells == int(partslam.CellState.FREE)).sum() > (cells == int(partslam.CellState.OCCUPIED)).sum()
    partslam.write_map_yaml(str(tmp_path / "b.yaml"), grid)
    back = partslam.read_map_yaml(str(tmp_path / "b.yaml"))
    np.testing.assert_array_equal(back.cells, cells)
    assert back.origin == pytest.approx(grid.origin)
    points = partslam.occupied_points(back)
    assert points.shape == ((cells == 2).sum(), 2)


def test_a_stretch_of_the_log_is_found_in_its_own_map(sim_scans):
    localizer = partslam.Localizer(partslam.build_grid_map(sim_scans))
    local = partslam.build_local_map(sim_scans, 30.0, 32.0)
    found = localizer.locate(local.points, local.origins)
    truth = local.T_world_map
    assert math.hypot(found.T_map_query[0] - truth[0], found.T_map_query[1] - truth[1]) < 0.1
    assert abs(partslam.wrap_angle(found.T_map_query[2] - truth[2])) < 1 * math.pi / 180
    assert found.confidence == pytest.approx(found.score - found.elsewhere_score)
    assert found.calibrated and 0 < found.probability <= 1
    assert found.confident == (found.confidence >= 0.2 and found.probability >= 0.025)
    assert not localizer.locate(local.points).calibrated  # bare points
    assert found.candidates >= 2


def test_a_stretch_by_travel_or_by_time_is_the_local_map_match_and_locate_build(sim_scans):
    by_travel = partslam.find_log_stretch(sim_scans, partslam.StretchSpec(from_m=30.0, to_m=32.0))
    assert by_travel.stretch and by_travel.log_scans == len(sim_scans)
    first = sim_scans[by_travel.first]
    by_time = partslam.find_log_stretch(sim_scans, partslam.StretchSpec(at_time=first.timestamp), window=2.0)
    assert (by_time.first, by_time.end) == (by_travel.first, by_travel.end)
    local = partslam.stretch_local_map(by_travel)
    assert local.travel == 30.0
    np.testing.assert_array_equal(local.points, partslam.build_local_map(sim_scans, 30.0, 32.0).points)
    matched = partslam.find_log_stretch(sim_scans, partslam.StretchSpec(from_m=30.0, to_m=32.0),
                                        scan_match=partslam.FrontEndConfig())
    assert matched.end - matched.first == by_travel.end - by_travel.first
    assert matched.matched_scans == len(matched.scans) < len(sim_scans)
    with pytest.raises(partslam.InputError, match="give one stretch of the log"):
        partslam.StretchSpec(from_m=1.0, to_m=2.0, at_m=3.0).validate()
    with pytest.raises(partslam.InputError, match="no scan between"):
        partslam.find_log_stretch(sim_scans, partslam.StretchSpec(at_m=1e6))


def test_point_files_and_local_maps_from_points(tmp_path):
    (tmp_path / "p.csv").write_text("x,y\n" + "".join(f"{0.05 * k},{math.sin(k)}\n" for k in range(200)))
    points = partslam.read_points(str(tmp_path / "p.csv"))
    assert points.shape == (200, 2)
    local = partslam.local_map_from_points(points)
    assert len(local.points) >= 20
    (tmp_path / "bad.csv").write_text("1,2\nnan,3\n")
    with pytest.raises(partslam.InputError, match="bad.csv:2"):
        partslam.read_points(str(tmp_path / "bad.csv"))
    with pytest.raises(ValueError, match="no occupied cell"):
        partslam.Localizer(np.zeros((0, 2)))


def test_a_map_frame_point_file_names_its_frame_and_gives_the_world_files_local_map(tmp_path, cli):
    import subprocess
    db = tmp_path / "m.db"
    subprocess.run([cli, "submaps", "sim:1", "--db", str(db)], check=True, capture_output=True)
    for frame in ("map", "world"):
        subprocess.run([cli, "export", str(db), "--map", "20", "--frame", frame, "--out", str(tmp_path / f"{frame}.csv")],
                       check=True, capture_output=True)
    points, T_world_points, origins = partslam.read_point_file(str(tmp_path / "map.csv"))
    world, none, world_origins = partslam.read_point_file(str(tmp_path / "world.csv"))
    assert none is None and T_world_points is not None
    np.testing.assert_allclose(partslam.transform(T_world_points, points), world, atol=1e-5)
    # the stored map's laser origins travel with it, in the file's frame
    assert len(origins) > 0 and len(origins) == len(world_origins)
    np.testing.assert_allclose(partslam.transform(T_world_points, origins), world_origins, atol=1e-5)
    from_map = partslam.local_map_from_points(partslam.transform(T_world_points, points),
                                              origins=partslam.transform(T_world_points, origins))
    from_world = partslam.local_map_from_points(world, origins=world_origins)
    assert len(from_map.points) == len(from_world.points)
    np.testing.assert_allclose(from_map.origins, from_world.origins, atol=1e-4)


def test_a_wing_built_at_another_angle_is_searched_too():
    def wall(a, b):
        t = np.linspace(0.0, 1.0, int(np.hypot(b[0] - a[0], b[1] - a[1]) / 0.05) + 1)[:, None]
        return np.asarray(a) + t * (np.asarray(b) - np.asarray(a))

    walls = []
    for k in range(6):
        walls += [wall((0.0, 2.0 * k + 0.3), (20.0, 2.0 * k + 0.3)), wall((4.0 * k + 0.3, 0.0), (4.0 * k + 0.3, 10.0))]
    c, s = math.cos(math.radians(20)), math.sin(math.radians(20))
    turn = np.array([[c, -s], [s, c]])
    for k in range(4):
        walls += [wall((0.0, 2.0 * k), (12.0, 2.0 * k)) @ turn.T + (30.0, 0.0),
                  wall((3.0 * k, 0.0), (3.0 * k, 6.0)) @ turn.T + (30.0, 0.0)]
    points = np.concatenate(walls)
    localizer = partslam.Localizer(points)
    assert len(localizer.wing_directions) == 1
    assert math.degrees(localizer.wing_directions[0] - localizer.alignment_angle) % 90 == pytest.approx(20, abs=1)
    config = partslam.LocalizerConfig()
    config.wall_direction_share = 0
    assert partslam.Localizer(points, config).wing_directions == []


def test_the_tracker_follows_the_log_through_its_map(sim_scans):
    localizer = partslam.Localizer(partslam.build_grid_map(sim_scans))
    starts = localizer.hypotheses(*_local(sim_scans, 30.0), count=4)
    assert 1 <= len(starts) <= 4
    assert starts[0].probability >= starts[-1].probability
    tracker = partslam.Tracker(localizer, partslam.TrackerConfig(hypotheses=8))
    statuses = []
    for s in range(10, 60, 2):
        local = partslam.build_local_map(sim_scans, float(s), s + 2.0)
        step = tracker.step(local.points, local.origins, local.T_world_map)
        statuses.append(step.status)
        if step.status == "localised":
            truth = local.T_world_map
            assert math.hypot(step.pose.T_map_query[0] - truth[0], step.pose.T_map_query[1] - truth[1]) < 0.3
            assert step.pose.share >= 0.5 and step.hypotheses
    assert "localised" in statuses[:5] and "lost" not in statuses
    with pytest.raises(partslam.InputError, match="declare_share"):
        partslam.TrackerConfig(declare_share=0.1).validate()


def _local(scans, at):
    local = partslam.build_local_map(scans, at, at + 2.0)
    return local.points, local.origins
