"""Parts from Python: the codec's known bit layout and round trips (core/parts/part_codec_test.cc), the descriptor
matcher's hand-computed scores (descriptor_matcher_test.cc), CPD on a map cut from the dictionary
(cpd_test.cc), and the whole chain dictionary -> CPD -> top K -> codec -> hMM / iMM ranking on the simulator."""
import math

import numpy as np
import pytest

import partslam


def lattice_codec():
    return partslam.CodecConfig(dictionary_extent=(-20.0, 30.8, -10.0, 15.4))  # steps 0.4 m and 0.2 m


def make_part(keypoint, rotation, origin, score=0.5):
    return partslam.Part(keypoint_box=keypoint, descriptor_box=partslam.place_rotated_box(keypoint, rotation, origin),
                         appearance_score=score, rotation=rotation)


def test_bit_budget():
    c = lattice_codec()
    assert partslam.bits_per_part(c) == 44  # the paper's 42 + 2 rotation bits
    assert [partslam.packed_bits(k, c) for k in range(1, 6)] == [44 * k for k in range(1, 6)]
    c.rotation_bits = 0
    assert partslam.bits_per_part(c) == 42
    assert partslam.origin_step(lattice_codec()) == pytest.approx((0.4, 0.2))


def test_known_bit_layout():
    # x cells [1, 3) -> fields 1, 2; y cells [0, 128) -> 0, 127; origin lattice (2, 5); rotation 3.
    p = make_part((-6.3, -6.1, -6.4, 6.4), 3, (-20.0 + 2 * 0.4, -10.0 + 5 * 0.2))
    packed = partslam.encode([p], lattice_codec())
    assert packed.bits == 44 and len(packed.data) == 6
    expected = 1 | (2 << 7) | (0 << 14) | (127 << 21) | (2 << 28) | (5 << 35) | (3 << 42)
    assert int.from_bytes(packed.data, "little") == expected


def test_exact_round_trip_on_the_lattice():
    c = lattice_codec()
    parts = [make_part((-6.4, 6.4, -6.4, 6.4), 0, (-20.0, -10.0)),
             make_part((1.2, 3.5, -2.0, 0.1), 1, (-20.0 + 100 * 0.4, -10.0 + 3 * 0.2)),
             make_part((6.3, 6.4, -6.4, -6.3), 2, (30.8, 15.4)),
             make_part((-0.5, 0.5, 2.0, 2.6), 3, (-20.0 + 50 * 0.4, -10.0 + 64 * 0.2))]
    back = partslam.decode(partslam.encode(parts, c), c)
    assert len(back) == len(parts)
    for a, b in zip(parts, back):
        assert b.rotation == a.rotation
        assert b.keypoint_box == pytest.approx(a.keypoint_box, abs=1e-9)
        assert b.descriptor_box == pytest.approx(a.descriptor_box, abs=1e-9)
        assert b.appearance_score == c.score_max  # not stored with score_bits = 0


def test_random_round_trip_within_quantisation():
    c = lattice_codec()
    c.score_bits = 5
    step = partslam.origin_step(c)
    rng = np.random.default_rng(7)
    for trial in range(100):
        parts = []
        for _ in range(1 + trial % 5):
            x0, y0 = rng.uniform(-6.4, 5.6, 2)
            keypoint = (x0, min(6.4, x0 + 0.2 + 6 * rng.random()), y0, min(6.4, y0 + 0.2 + 6 * rng.random()))
            origin = (-20.0 + 50.8 * rng.random(), -10.0 + 25.4 * rng.random())
            parts.append(make_part(keypoint, int(rng.integers(4)), origin, rng.random()))
        packed = partslam.encode(parts, c)
        assert packed.bits == 49 * len(parts)  # 44 + 5 score bits
        # The blob survives a trip through Python bytes.
        back = partslam.decode(partslam.PackedDescriptor(bytes(packed.data), packed.bits), c)
        for a, b in zip(parts, back):
            assert b.rotation == a.rotation
            assert b.keypoint_box == pytest.approx(a.keypoint_box, abs=0.05 + 1e-9)
            assert b.descriptor_box[0] == pytest.approx(a.descriptor_box[0], abs=step[0] / 2 + 1e-9)
            assert b.descriptor_box[2] == pytest.approx(a.descriptor_box[2], abs=step[1] / 2 + 1e-9)
            assert b.appearance_score == pytest.approx(a.appearance_score, abs=0.5 / 31 + 1e-9)


def test_encoding_errors_name_the_part():
    c = lattice_codec()
    with pytest.raises(ValueError, match="part 1"):
        partslam.encode([make_part((0, 1, 0, 1), 0, (0, 0)), make_part((0, 9, 0, 1), 0, (0, 0))], c)
    with pytest.raises(ValueError):
        partslam.decode(partslam.PackedDescriptor(b"\x00\x00", 12), c)
    with pytest.raises(ValueError, match="dictionary_extent"):
        partslam.CodecConfig().validate()


def part_at(descriptor_box, score=1.0):
    return partslam.Part(descriptor_box=descriptor_box,
                         keypoint_box=(0, descriptor_box[1] - descriptor_box[0], 0, descriptor_box[3] - descriptor_box[2]),
                         appearance_score=score)


def test_region_similarity_known_answers():
    a = (0, 2, 0, 2)
    assert partslam.region_similarity(a, a) == 1.0
    assert partslam.region_similarity(a, (5, 7, 0, 2)) == 0.0
    assert partslam.region_similarity(a, (1, 3, 0, 2)) == 0.5
    assert partslam.region_similarity((0, 4, 0, 4), (1, 2, 1, 2)) == 0.25
    assert partslam.region_similarity(a, (0, 2, 0, 1)) == pytest.approx(1 / math.sqrt(2))


def test_match_score_known_answers_for_the_three_matchers():
    query = [part_at((0, 2, 0, 2), 0.5), part_at((10, 12, 0, 2), 0.8), part_at((20, 21, 0, 1), 1.0)]
    stored = [part_at((1, 3, 0, 2)), part_at((10, 12, 0, 2)), part_at((20, 22, 0, 2)), part_at((0, 2, 0, 1))]
    r = 1 / math.sqrt(2)
    M = partslam.Matcher
    assert partslam.match_score(query, stored, M.MAX_MAX) == pytest.approx(1.0)
    assert partslam.match_score(query, stored, M.SUM_MAX) == pytest.approx(r + 1.0 + 0.5)
    assert partslam.match_score(query, stored, M.SUM_MAX_WEIGHTED) == pytest.approx(0.5 * r + 0.8 + 0.5)
    assert partslam.match_score(stored, query, M.SUM_MAX) == pytest.approx(0.5 + 1.0 + 0.5 + r)
    assert partslam.match_score([], stored, M.SUM_MAX) == 0.0
    assert partslam.matcher_from_string("smw") == M.SUM_MAX_WEIGHTED
    with pytest.raises(ValueError, match="best"):
        partslam.matcher_from_string("best")


def test_origin_gate():
    stored = partslam.Part(keypoint_box=(-1, 1, -1, 1), descriptor_box=(9, 11, 19, 21))
    near = partslam.Part(keypoint_box=(-0.5, 1.5, -1, 1), descriptor_box=(9, 11, 19, 21))  # frame 0.5 m off
    far = partslam.Part(keypoint_box=(3, 5, -1, 1), descriptor_box=(9, 11, 19, 21))  # frame 4 m off
    assert partslam.dictionary_origin(stored) == pytest.approx((10, 20))
    assert partslam.dictionary_origin(near) == pytest.approx((9.5, 20))
    M = partslam.Matcher
    assert partslam.match_score([near, far], [stored], M.SUM_MAX) == 2.0
    assert partslam.match_score([near, far], [stored], M.SUM_MAX, origin_gate=2.0) == 1.0
    assert not partslam.passes_origin_gate(far, stored, 3.9)
    assert partslam.passes_origin_gate(far, stored, 4.0)


def rooms(rng, n, half):
    """Outlines of n random rectangles (walls every 0.1 m) within +-half: a Manhattan scene with many corners."""
    points = []
    for _ in range(n):
        x0, y0 = rng.integers(int(-half * 10), int(half * 10) - 60, 2)
        w, h = rng.integers(20, 60, 2)
        i, j = np.arange(w), np.arange(h + 1)
        points += [np.stack([x0 + i, np.full(w, y0)], 1), np.stack([x0 + i, np.full(w, y0 + h)], 1),
                   np.stack([np.full(h + 1, x0), y0 + j], 1), np.stack([np.full(h + 1, x0 + w), y0 + j], 1)]
    return 0.1 * np.vstack(points).astype(np.float64)


def scatter(rng, n, half):
    """Points on cell centres without any symmetry, so a crop fits the dictionary at exactly one place."""
    return 0.1 * rng.integers(int(-half * 10), int(half * 10) + 1, (n, 2)) + 0.05


def test_find_corners_puts_the_corner_of_an_l_first():
    i = np.arange(41)
    l_shape = np.vstack([np.stack([1.0 + 0.1 * i, np.full(41, 2.0)], 1), np.stack([np.full(40, 1.0), 2.1 + 0.1 * i[:40]], 1)])
    config = partslam.CpdConfig()
    corners = partslam.find_corners(l_shape, config)
    assert len(corners) > 0
    assert np.hypot(*(corners[0] - [1.0, 2.0])) < config.corner_radius / 2


@pytest.mark.parametrize("mode", [partslam.CandidateMode.CORNERS, partslam.CandidateMode.PARTITIONS])
def test_parts_of_a_map_cut_from_the_dictionary_point_back_to_where_it_was_cut(mode):
    # The dictionary holds the map shifted by (7.3, -4.1), among other points far away. The scatter is dense enough
    # (6 % of the cells) that no crop, even a thin box around one wall, fits anywhere else.
    rng = np.random.default_rng(1)
    map_points = np.vstack([rooms(rng, 3, 5.0), scatter(rng, 600, 5.0)])
    dictionary = np.vstack([map_points + [7.3, -4.1], scatter(rng, 400, 5.0) + [30.0, 30.0]])
    config = partslam.CpdConfig(candidates=mode, maximality=partslam.MaximalityMode.INLIER_SHARE, t_size=0.0,
                                max_parts=12)
    prepared = partslam.prepare_dictionary(dictionary, config)
    result = partslam.discover_parts(map_points, prepared, config, map_key=5)
    assert len(result.parts) >= 3
    for p in result.parts:
        assert p.appearance_score == 1.0 and p.rotation == 0
        assert np.hypot(*np.subtract(partslam.dictionary_origin(p), (7.3, -4.1))) < 0.2
        assert p.descriptor_box[1] - p.descriptor_box[0] == pytest.approx(p.keypoint_box[1] - p.keypoint_box[0])


def test_cpd_is_deterministic_and_parallel_equals_serial():
    rng = np.random.default_rng(3)
    dictionary = rooms(rng, 12, 15.0)
    maps = [rooms(rng, 3, 6.0) for _ in range(6)]
    keys = [100 + i for i in range(len(maps))]
    config = partslam.CpdConfig(t_size=0.0)
    prepared = partslam.prepare_dictionary(dictionary, config)
    serial = partslam.discover_parts_many(maps, keys, prepared, config, threads=1)
    parallel = partslam.discover_parts_many(maps, keys, prepared, config, threads=2)
    for s, p in zip(serial, parallel):
        assert len(s.parts) > 0 and len(s.parts) == len(p.parts)
        assert [x.descriptor_box for x in s.parts] == [x.descriptor_box for x in p.parts]
        assert [x.appearance_score for x in s.parts] == [x.appearance_score for x in p.parts]
    one = partslam.discover_parts(maps[2], prepared, config, map_key=keys[2])
    assert [x.descriptor_box for x in one.parts] == [x.descriptor_box for x in serial[2].parts]


def test_cpd_refuses_an_empty_dictionary_and_absurd_parameters():
    with pytest.raises(ValueError, match="no points"):
        partslam.prepare_dictionary(np.empty((0, 2)))
    with pytest.raises(ValueError, match="no points"):
        partslam.dictionary_codec_config(np.empty((0, 2)))
    with pytest.raises(ValueError, match="box_sizes"):
        partslam.CpdConfig(box_sizes=[]).validate()
    with pytest.raises(ValueError, match="one key per map"):
        partslam.discover_parts_many([np.zeros((3, 2))], [], partslam.prepare_dictionary(rooms(np.random.default_rng(0), 2, 5.0)))


def test_dictionary_cpd_codec_and_part_ranking_on_the_simulator(sim_submaps):
    # The dictionary is another simulated building (seed 2), as fr079 is for fr101.
    dictionary = partslam.build_dictionary("sim-2", partslam.load_scan_source("sim:2").scans)
    assert dictionary.name == "sim-2" and len(dictionary.points) >= 100
    assert np.isfinite(dictionary.points).all()
    with pytest.raises(ValueError, match=r"only \d+ points \(need 100000"):
        partslam.build_dictionary("tiny", partslam.load_scan_source("sim").scans,
                                  partslam.DictionaryConfig(min_points=100000))

    maps = sim_submaps[::10]
    prepared = partslam.prepare_dictionary(dictionary.points)
    results = partslam.discover_parts_many([m.points for m in maps], [m.id for m in maps], prepared, threads=2)
    parts = [r.parts for r in results]
    assert sum(len(p) > 0 for p in parts) >= len(maps) // 2
    for p in parts:
        assert all(0.0 <= x.appearance_score <= 1.0 for x in p)
        assert [x.appearance_score for x in p] == sorted((x.appearance_score for x in p), reverse=True)

    # K = 3 as a database stores it: the decoded descriptor keeps every part's rotation and boxes to a lattice step.
    codec = partslam.descriptor_codec_config(dictionary.points, 3)
    step = partslam.origin_step(codec)
    for p in parts:
        top = partslam.select_top_parts(p, 3)
        stored = partslam.decode_stored(partslam.encode(top, codec), 3, codec)
        assert len(stored) == len(top)
        for a, b in zip(top, stored):
            assert b.rotation == a.rotation
            assert b.keypoint_box == pytest.approx(a.keypoint_box, abs=0.05 + 1e-9)
            assert b.descriptor_box[0] == pytest.approx(a.descriptor_box[0], abs=step[0] / 2 + 1e-9)

    # hMM and iMM rank through the same entry point; the query's own map scores highest.
    points = [m.points for m in maps]
    q = next(i for i, p in enumerate(parts) if len(p) >= 3)
    for method in ("hmm:3", "imm:3"):
        ranking = partslam.rank(method, points[q], points, query_parts=parts[q], map_parts=parts,
                                config=partslam.RankingConfig(parts=partslam.PartsConfig(codec=codec)))
        assert ranking.scores.shape == (len(maps),)
        assert ranking.scores[q] > 0 and ranking.scores[q] == ranking.scores.max()
