"""dMM and ranking from Python: the known-answer checks of core/matching/dmm_test.cc and ranking_test.cc, on
submaps of the built-in simulator moved by known poses."""
import concurrent.futures
import math

import numpy as np
import pytest

import partslam

DEG = math.pi / 180


def angle_error(a, b):
    return abs(partslam.wrap_angle(a - b))


def small_config(**fields):
    """A small window so the exhaustive reference stays fast (dmm_test.cc)."""
    return partslam.DmmConfig(linear_window=2.5, angular_window=2.0 * DEG, **fields)


def test_recovers_an_exact_cell_shift(sim_submaps):
    map_points = sim_submaps[40].points
    T_map_query = (1.2, -0.7, math.pi / 2)
    query_points = partslam.transform(partslam.inverse(T_map_query), map_points)
    config = small_config(dilation=0, angular_step=1.0 * DEG)
    r = partslam.match_dmm(partslam.prepare_query(query_points, config), partslam.prepare_map(map_points, config))
    assert r.inlier_fraction >= 0.97  # cell-boundary rounding may lose a few points
    assert abs(r.T_map_query[0] - 1.2) <= 0.1 + 1e-9
    assert abs(r.T_map_query[1] + 0.7) <= 0.1 + 1e-9
    assert angle_error(r.T_map_query[2], math.pi / 2) < 1e-9


def test_pose_within_one_cell_and_one_step_of_known_offsets(sim_submaps):
    # dmm_test.cc, PoseWithinOneCellAndOneStepOfTruth, on copies of simulated submaps: the query is the map moved
    # by a known pose and re-centred on its centroid (as a submap is). An exact copy fits a plateau of poses
    # perfectly under the default one-cell dilation (ties keep the first found), so the target is not dilated.
    rng = np.random.default_rng(21)
    config = partslam.DmmConfig(dilation=0)
    for p in range(12):
        map_points = sim_submaps[int(rng.integers(len(sim_submaps)))].points
        T_map_moved = (rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5),
                       int(rng.integers(4)) * math.pi / 2 + rng.uniform(-2.5, 2.5) * DEG)
        moved = partslam.transform(partslam.inverse(T_map_moved), map_points)
        c = partslam.centroid(moved)
        truth = partslam.compose(T_map_moved, (c[0], c[1], 0.0))
        query = partslam.prepare_query(moved - c, config)
        r = partslam.match_dmm(query, partslam.prepare_map(map_points, config))
        assert r.inlier_fraction > 0.5, f"pair {p}"
        assert angle_error(r.T_map_query[2], truth[2]) <= query.angular_step + 1e-9, f"pair {p}"
        assert abs(r.T_map_query[0] - truth[0]) <= config.resolution + 1e-9, f"pair {p}"
        assert abs(r.T_map_query[1] - truth[1]) <= config.resolution + 1e-9, f"pair {p}"


def test_relevant_simulated_pairs_come_out_near_their_true_relative_pose(sim_scans):
    # dmm_test.cc, SimulatedPairs: the full 30 m range, a submap every 2 m; pairs of maps whose centres lie within
    # 2 m after more than 20 m of travel, ground truth from the simulator's exact poses.
    maps = partslam.build_submaps(sim_scans, partslam.SubmapConfig(spacing=2.0, max_range=30.0))
    centres = np.array([m.T_world_map[:2] for m in maps])
    travel = np.array([m.travel for m in maps])
    near = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1)) <= 2.0
    far_along = np.abs(travel[:, None] - travel[None, :]) > 20.0
    pairs = np.argwhere(near & far_along)
    assert len(pairs) >= 50
    config = partslam.DmmConfig()
    rng = np.random.default_rng(3)
    within_one = within_two = 0
    n = 40
    for q, g in pairs[rng.integers(len(pairs), size=n)]:
        query = partslam.prepare_query(maps[q].points, config)
        r = partslam.match_dmm(query, partslam.prepare_map(maps[g].points, config))
        truth = partslam.compose(partslam.inverse(maps[g].T_world_map), maps[q].T_world_map)
        cells = max(abs(r.T_map_query[0] - truth[0]), abs(r.T_map_query[1] - truth[1])) / config.resolution
        steps = angle_error(r.T_map_query[2], truth[2]) / query.angular_step
        within_one += cells <= 1 + 1e-9 and steps <= 1 + 1e-9
        within_two += cells <= 2 + 1e-9 and steps <= 2 + 1e-9
    assert within_one >= n * 8 // 10, f"{within_one} of {n}"
    assert within_two >= n * 9 // 10, f"{within_two} of {n}"


def test_branch_and_bound_equals_exhaustive(sim_submaps):
    rng = np.random.default_rng(11)
    for p in range(6):
        a = int(rng.integers(len(sim_submaps)))
        b = a if p % 2 == 0 else int(rng.integers(len(sim_submaps)))  # the same place, then any other map
        truth = (rng.uniform(-1, 1), rng.uniform(-1, 1), int(rng.integers(4)) * math.pi / 2)
        config = small_config(dilation=p % 3)
        query = partslam.prepare_query(partslam.transform(partslam.inverse(truth), sim_submaps[a].points), config)
        target = partslam.prepare_map(sim_submaps[b].points, config)
        bnb = partslam.match_dmm(query, target)
        reference = partslam.match_exhaustive(query, target)
        assert bnb.inliers == reference.inliers, f"pair {p}"
        assert bnb.candidates_scored < reference.candidates_scored


def test_match_dmm_on_points_prepares_both_with_the_config(sim_submaps):
    points = sim_submaps[7].points
    config = partslam.DmmConfig(dilation=0)
    direct = partslam.match_dmm(points, points, config)
    prepared = partslam.match_dmm(partslam.prepare_query(points, config), partslam.prepare_map(points, config))
    assert direct.inliers == prepared.inliers == len(points)
    assert direct.T_map_query == prepared.T_map_query
    assert direct.T_map_query == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)


def test_empty_query_scores_zero_and_bad_input_raises():
    config = small_config()
    target = partslam.prepare_map([[0.0, 0.0], [1.0, 0.0]], config)
    assert partslam.match_dmm(partslam.prepare_query(np.empty((0, 2)), config), target).inliers == 0
    assert partslam.match_dmm(partslam.prepare_query([[0.0, 0.0]], config), target).inlier_fraction == 1.0
    with pytest.raises(ValueError, match="not finite"):
        partslam.prepare_query(np.array([[np.nan, 0.0]]), config)
    with pytest.raises(ValueError, match="shape"):
        partslam.prepare_map(np.array([]), config)
    with pytest.raises(ValueError, match="prepared at"):
        partslam.match_dmm(partslam.prepare_query([[0.0, 0.0]], small_config(resolution=0.05)), target)
    with pytest.raises(ValueError, match="3000 x 5 m"):
        partslam.prepare_map([[0.0, 0.0], [3000.0, 5.0]])
    with pytest.raises(ValueError, match="angular_window"):
        partslam.DmmConfig(angular_window=1.0).validate()


def test_matching_or_ranking_nothing_raises_instead_of_scoring_zero(sim_submaps):
    points = sim_submaps[0].points
    with pytest.raises(partslam.InputError, match="query_points is empty"):
        partslam.match_dmm(np.empty((0, 2)), points)
    with pytest.raises(partslam.InputError, match="map_points is empty"):
        partslam.match_dmm(points, np.empty((0, 2)))
    for method in ("dmm", "succinct"):
        with pytest.raises(partslam.InputError, match="no stored maps to rank"):
            partslam.rank(method, points, [])
    with pytest.raises(partslam.InputError, match="no stored maps to rank"):
        partslam.Ranker("dmm").rank(points)


def test_match_many_equals_one_by_one_for_any_threads_and_top_k_drops_only_losers(sim_submaps):
    config = partslam.DmmConfig()
    query = partslam.prepare_query(sim_submaps[100].points, config)
    maps = [partslam.prepare_map(m.points, config) for m in sim_submaps[::12]]
    serial = partslam.match_dmm_many(query, maps)
    parallel = partslam.match_dmm_many(query, maps, threads=2)
    assert len(serial) == len(maps)
    for m, (s, p) in enumerate(zip(serial, parallel)):
        assert s.exact
        assert s.inliers == p.inliers == partslam.match_dmm(query, maps[m]).inliers
        assert s.T_map_query == p.T_map_query
    scores = sorted((r.inliers for r in serial), reverse=True)
    top = partslam.match_dmm_many(query, maps, top_k=3)
    assert sum(r.exact and serial[m].inliers >= scores[2] for m, r in enumerate(top)) >= 3
    for m, r in enumerate(top):
        if r.exact:
            assert r.inliers == serial[m].inliers
        else:
            assert r.inliers == 0 and serial[m].inliers <= scores[2]


def test_dmm_ranks_a_subset_and_threads_do_not_change_it(sim_submaps):
    ranker = partslam.Ranker("dmm:eq1")
    ranker.prepare([m.points for m in sim_submaps], threads=2)
    assert len(ranker) == len(sim_submaps) and ranker.bits_per_map > 0
    candidates = [3, 10, 0, 25, 40]
    query = sim_submaps[0].points
    one = ranker.rank(query, candidates=candidates, threads=1)
    two = ranker.rank(query, candidates=candidates, threads=2)
    np.testing.assert_array_equal(one.scores, two.scores)
    assert one.scores[2] == len(query)  # the query itself matches all its points
    assert one.order[0] == 2
    assert np.hypot(*one.direct[2].T_map_query[:2]) <= 0.15  # within a dilated cell
    top = ranker.rank(query, candidates=candidates, top_k=1)
    assert top.scores[2] == one.scores[2]
    with pytest.raises(ValueError, match="candidate 9999 is not a prepared map"):
        ranker.rank(query, candidates=[9999])


def test_rank_scores_are_the_dmm_inliers_and_the_same_map_comes_first(sim_submaps):
    stored = [m.points for m in sim_submaps[::8]]
    query_index = 5
    ranking = partslam.rank("dmm:eq1", stored[query_index], stored, threads=2)
    assert ranking.order[0] == query_index
    search = partslam.RankingConfig().dmm  # the ranking's search: 8 rotation families, not DmmConfig's 4
    assert search.canonical_turns == 8
    prepared = [partslam.prepare_map(p, search) for p in stored]
    many = partslam.match_dmm_many(partslam.prepare_query(stored[query_index], search), prepared)
    np.testing.assert_array_equal(ranking.scores, [r.inliers for r in many])
    assert [r.T_map_query for r in ranking.direct] == [r.T_map_query for r in many]


@pytest.mark.parametrize("method", ["grid", "sc"])
def test_descriptor_baselines_find_a_map_identical_to_the_query(sim_submaps, method):
    stored = [m.points for m in sim_submaps[::8]]
    ranking = partslam.rank(method, stored[9], stored)
    assert ranking.scores.shape == (len(stored),) and np.isfinite(ranking.scores).all()
    assert ranking.order[0] == 9


def test_rerank_puts_the_shortlist_first_ordered_by_dmm(sim_submaps):
    # A first stage without parts: every stored map scores 0, so the shortlist is the first R candidates.
    points = [m.points for m in sim_submaps]
    parts = [[] for _ in sim_submaps]
    rerank = partslam.Ranker("rerank:3:hmm:3")
    rerank.prepare(points, parts)
    dmm = partslam.Ranker("dmm")
    dmm.prepare(points)
    candidates = [5, 0, 7, 9, 11]
    r = rerank.rank(points[0], [], candidates=candidates)
    d = dmm.rank(points[0], candidates=candidates)
    assert len(r.shortlist_scores) == len(candidates)
    for j in range(len(candidates)):
        assert (r.direct[j] is not None) == (j < 3)
        if j < 3:
            assert r.scores[j] > r.scores[3]
            assert r.direct[j].inliers == d.direct[j].inliers and r.scores[j] == d.scores[j]
    assert r.scores[1] > r.scores[0]  # the query itself beats every other shortlisted map


def test_concurrent_ranking_from_python_threads_gives_the_serial_answer(sim_submaps):
    ranker = partslam.Ranker("dmm")
    ranker.prepare([m.points for m in sim_submaps[::4]])
    queries = [m.points for m in sim_submaps[1::40]]
    serial = [ranker.rank(q).scores for q in queries]
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        threaded = list(pool.map(lambda q: ranker.rank(q).scores, queries))
    for a, b in zip(serial, threaded):
        np.testing.assert_array_equal(a, b)


def test_method_specs_and_their_errors():
    names = [name for name, _ in partslam.methods()]
    assert {"dmm", "succinct", "rerank", "imm", "hmm", "grid", "sc"} <= set(names)
    spec = partslam.parse_method_spec("rerank:20")
    assert spec.name == "rerank" and spec.spec == "rerank:20:succinct" and spec.needs_points and spec.gives_pose
    assert not spec.shardable
    assert partslam.parse_method_spec("hmm:3").needs_parts
    with pytest.raises(ValueError, match="nope"):
        partslam.Ranker("nope")
    with pytest.raises(ValueError, match="has no parts"):
        partslam.rank("hmm:3", [[0.0, 0.0]], [[[0.0, 0.0]]])
    with pytest.raises(ValueError, match="2 point sets but 1 part lists"):
        partslam.Ranker("dmm").prepare([[[0.0, 0.0]], [[1.0, 1.0]]], [[]])
    assert partslam.ranking_order([1.0, 3.0, 1.0, 2.0]) == [1, 3, 0, 2]


def test_dmm_gives_its_same_place_probability_and_reads_free_space_from_laser_origins(sim_submaps):
    # The verified dMM's probability reaches Python with its runner-up pose; with the maps' laser origins their
    # free space contradicts other places (a beam passing through the query's walls), without them it cannot.
    query, stored = sim_submaps[250], sim_submaps[:200]
    points = [m.points for m in stored]
    bare = partslam.rank("dmm", query.points, points, threads=2)
    seen = partslam.rank("dmm", query.points, points, threads=2, query_origins=query.origins,
                         map_origins=[m.origins for m in stored])
    centre = np.array(query.T_world_map[:2])
    distance = [np.linalg.norm(np.array(m.T_world_map[:2]) - centre) for m in stored]
    far = [i for i, d in enumerate(distance) if d > 10.0]
    assert len(far) > 20
    assert distance[seen.order[0]] < 1.5  # the simulated robot passed here before
    for r in (bare, seen):
        np.testing.assert_array_equal(r.scores, r.probability)  # dmm ranks by the probability
        assert all(0.0 <= p <= 1.0 for p in r.probability)
        assert len(r.runner_up) == len(r.pose_ambiguous) == len(points)
        for p, q, a in zip(r.probability, r.runner_up, r.pose_ambiguous):
            assert a == partslam.pose_ambiguous(p, q)
    assert seen.probability[seen.order[0]] > 0.5 > max(seen.probability[i] for i in far)
    assert np.mean([seen.probability[i] for i in far]) < 0.75 * np.mean([bare.probability[i] for i in far])
    share = partslam.AMBIGUOUS_POSE_SHARE
    assert partslam.pose_ambiguous(0.8, share * 0.8) and not partslam.pose_ambiguous(0.8, share * 0.8 - 1e-3)
    eq1 = partslam.rank("dmm:eq1", query.points, points[:10])
    assert eq1.probability == [] and eq1.runner_up == [] and eq1.pose_ambiguous == []


def test_laser_origins_must_match_the_maps_they_belong_to(sim_submaps):
    ranker = partslam.Ranker("dmm")
    with pytest.raises(partslam.InputError, match="2 origin sets but 3 point sets"):
        ranker.prepare([m.points for m in sim_submaps[:3]], origins=[m.origins for m in sim_submaps[:2]])
    ranker.prepare([m.points for m in sim_submaps[:3]], origins=[m.origins for m in sim_submaps[:3]])
    with pytest.raises(partslam.InputError, match="query_origins given without query_points"):
        ranker.rank(query_origins=sim_submaps[0].origins)
    assert len(ranker.rank(sim_submaps[0].points, query_origins=sim_submaps[0].origins).probability) == 3
