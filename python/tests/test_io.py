"""Logs and the map database from Python (io/logs/carmen_log_test.cc, map_database_test.cc): a tiny CARMEN log with
known answers, the simulator as a scan source, log and database round trips in a temporary folder, errors that
name the file and line, and databases shared with the CLI in both directions."""
import gzip
import math
import subprocess

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
    assert source.T_base_laser is None  # one scan cannot tell a laser's mount


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


def test_cut_and_damaged_logs_warn_or_skip_with_skip_damaged(tmp_path):
    lines = [f"FLASER 4 1 2 3 4 {0.1 * i} 0 0 {0.1 * i} 0 0 {i} host {i}\n" for i in range(10)]
    cut = tmp_path / "cut.log"
    cut.write_text("".join(lines)[:-20])
    log = partslam.read_carmen_log(cut)
    assert len(log.scans) == 9 and log.stats.cut_short
    assert len(log.warnings) == 1 and "cut.log: the file ends mid-record after byte" in log.warnings[0]
    with pytest.warns(UserWarning, match="cut.log: the file ends mid-record"):
        assert partslam.load_scan_source(str(cut)).warnings == log.warnings
    damaged = tmp_path / "damaged.log"
    damaged.write_text("".join(lines[:4]) + "FLASER 4 1 x\n" + "".join(lines[4:]))
    with pytest.raises(ValueError, match=r"damaged.log:5: FLASER"):
        partslam.read_carmen_log(damaged)
    log = partslam.read_carmen_log(damaged, partslam.LogReadOptions(skip_damaged=True))
    assert len(log.scans) == 10 and log.stats.damaged == 1
    assert "skipped 1 damaged line(s)" in log.warnings[0]


def test_a_binary_file_read_as_a_log_raises_with_the_readers_message(tmp_path):
    # A PNG's bytes are not UTF-8: the message quoting them used to be dropped (InputError() with no text).
    png = tmp_path / "a.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe binary\n")
    with pytest.raises(partslam.InputError) as error:
        partslam.load_scan_source(str(png))
    message = str(error.value)
    assert message.startswith(str(png) + ":1: ")
    assert "CARMEN" in message


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


def test_submaps_dictionary_and_descriptors_round_trip_through_the_database(tmp_path, sim_scans, sim_submaps):
    path = tmp_path / "maps.db"
    config = partslam.SubmapConfig(window_length=2.0, spacing=0.5)
    spec = partslam.DatasetSpec(name="sim-1", source="sim", config=config)
    dictionary = partslam.build_dictionary("sim-2", partslam.load_scan_source("sim:2").scans)
    with pytest.raises(ValueError, match="no such file"):
        partslam.MapDatabase(path)
    db = partslam.MapDatabase(path, partslam.MapDatabase.Mode.CREATE)
    dataset_id = db.store_dataset(spec, sim_submaps)
    db.add_dictionary(dictionary)
    del db

    db = partslam.MapDatabase(path, partslam.MapDatabase.Mode.READ_WRITE)
    info = db.find_dataset("sim-1")
    assert info.id == dataset_id and info.submap_count == len(sim_submaps)
    assert info.spec.kind == partslam.DatasetKind.SUBMAPS and info.spec.config.window_length == 2.0
    assert db.find_dataset("nope") is None
    loaded = db.load_submaps(dataset_id)
    ids = db.map_ids(dataset_id)
    assert [m.id for m in loaded] == ids and len(loaded) == len(sim_submaps)
    for a, b in zip(sim_submaps, loaded):
        assert b.T_world_map == a.T_world_map and b.travel == a.travel and b.anchor_scan == a.anchor_scan
        np.testing.assert_array_equal(b.scan_timestamps, a.scan_timestamps)
        np.testing.assert_array_equal(b.points, a.points.astype(np.float32).astype(np.float64))  # float32 blobs
    assert db.locate(ids[3]).index == 3 and db.locate(ids[3]).dataset_name == "sim-1"
    np.testing.assert_array_equal(db.load_submap(ids[3]).points, loaded[3].points)
    stored_dictionary = partslam.resolve_dictionary(db)
    assert stored_dictionary.name == "sim-2"
    np.testing.assert_allclose(stored_dictionary.points, dictionary.points, atol=1e-5)

    # Descriptors as `partslam describe` stores them: CPD parts, top K, packed under the set's codec.
    maps = loaded[::25]
    prepared = partslam.prepare_dictionary(stored_dictionary.points)
    parts = [r.parts for r in partslam.discover_parts_many([m.points for m in maps], [m.id for m in maps], prepared)]
    codec = partslam.descriptor_codec_config(stored_dictionary.points, 3)
    records = [partslam.DescriptorRecord(m.id, partslam.encode(partslam.select_top_parts(p, 3), codec))
               for m, p in zip(maps, parts)]
    db.put_descriptors("sim-2", 3, codec, records)
    assert db.descriptor_codec("sim-2", 3).dictionary_extent == codec.dictionary_extent
    assert db.descriptor_codec("sim-2", 4) is None
    assert db.get_descriptor(maps[1].id, "sim-2", 3).data == records[1].descriptor.data
    decoded = partslam.load_descriptor_set(db, "sim-2", 3)
    assert sorted(decoded) == [m.id for m in maps]
    for m, r in zip(maps, records):
        expected = partslam.decode(r.descriptor, codec)
        assert [(x.keypoint_box, x.descriptor_box, x.rotation) for x in decoded[m.id]] == \
            [(x.keypoint_box, x.descriptor_box, x.rotation) for x in expected]
    assert partslam.load_descriptor(db, "sim-2", 3, ids[1]) is None
    summary = db.summary()
    assert summary.schema_version == 4 and summary.counts_kept and summary.submap_count == len(sim_submaps)
    assert [(s.dictionary, s.k, s.count) for s in summary.descriptor_sets] == [("sim-2", 3, len(maps))]
    db.check_integrity()


def test_transactions_commit_together_or_not_at_all(tmp_path, sim_submaps):
    db = partslam.MapDatabase(tmp_path / "maps.db", partslam.MapDatabase.Mode.CREATE)
    with pytest.raises(RuntimeError, match="interrupted"):
        with db.transaction():
            dataset_id = db.add_dataset(partslam.DatasetSpec(name="partial", source="p"))
            db.add_submaps(dataset_id, sim_submaps[:3])
            raise RuntimeError("interrupted")
    assert db.datasets() == []
    with db.transaction():
        dataset_id = db.add_dataset(partslam.DatasetSpec(name="kept", source="k"))
        db.add_submaps(dataset_id, sim_submaps[:3])
    assert [d.name for d in db.datasets()] == ["kept"] and db.summary().submap_count == 3
    bad = partslam.Submap(travel=float("nan"), points=sim_submaps[0].points)
    with pytest.raises(ValueError, match="travel must be finite"):
        db.store_dataset(partslam.DatasetSpec(name="bad", source="b"), [sim_submaps[0], bad])
    assert [d.name for d in db.datasets()] == ["kept"]
    with pytest.raises(ValueError, match="already"):
        db.add_dataset(partslam.DatasetSpec(name="kept", source="k"))


def test_read_only_and_foreign_files_are_refused(tmp_path):
    path = tmp_path / "maps.db"
    partslam.MapDatabase(path, partslam.MapDatabase.Mode.CREATE)
    db = partslam.MapDatabase.open(path)
    with pytest.raises(ValueError, match="read-only"):
        db.add_dataset(partslam.DatasetSpec(name="a", source="a.log"))
    garbage = tmp_path / "garbage.db"
    garbage.write_bytes(b"not a database at all" * 100)
    with pytest.raises(ValueError, match="garbage.db"):
        partslam.MapDatabase(garbage)


def test_the_cli_and_python_read_each_others_databases(tmp_path, cli, sim_submaps):
    # The CLI writes the simulator's submaps and a dictionary; Python reads what it would have built itself.
    path = tmp_path / "cli.db"
    subprocess.run([cli, "submaps", "sim", "--db", str(path), "--quiet"], check=True, capture_output=True)
    subprocess.run([cli, "dictionary", "sim:2", "--db", str(path), "--name", "sim-2"], check=True,
                   capture_output=True)
    db = partslam.MapDatabase(path)
    [info] = db.datasets()
    assert info.name == "sim-1" and info.submap_count == len(sim_submaps)
    for a, b in zip(sim_submaps, db.load_submaps(info.id)):
        assert b.T_world_map == a.T_world_map
        np.testing.assert_array_equal(b.points, a.points.astype(np.float32).astype(np.float64))
    built = partslam.build_dictionary("sim-2", partslam.load_scan_source("sim:2").scans)
    np.testing.assert_array_equal(db.load_dictionary("sim-2").points,
                                  built.points.astype(np.float32).astype(np.float64))

    # Python writes a dataset; the CLI lists it and matches one of its maps with dMM.
    mine = tmp_path / "python.db"
    written = partslam.MapDatabase(mine, partslam.MapDatabase.Mode.CREATE)
    dataset_id = written.store_dataset(partslam.DatasetSpec(name="from-python", source="sim"), sim_submaps[::5])
    query = written.map_ids(dataset_id)[4]
    del written
    listing = subprocess.run([cli, "info", str(mine)], check=True, capture_output=True, text=True).stdout
    assert "from-python" in listing
    matched = subprocess.run([cli, "match", str(mine), "--query", str(query), "--method", "dmm", "--top", "1"],
                             check=True, capture_output=True, text=True).stdout
    assert "dMM over" in matched
