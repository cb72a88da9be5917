"""keylo.open: the frames of any source as numpy arrays, without copies."""

import numpy as np

import keylo


def test_an_ouster_capture_reads_as_read_only_views(ouster_pcap):
    frames = list(keylo.open(ouster_pcap))
    assert len(frames) == 3
    f = frames[0]
    assert (f.rows, f.cols) == (128, 1024)
    assert f.range.shape == f.signal.shape == f.valid.shape == (128, 1024)
    assert f.xyz.shape == (128, 1024, 3) and f.xyz.dtype == np.float32
    assert f.valid.dtype == np.bool_ and f.valid.any()
    assert f.column_times.shape == (1024,)
    assert f.points is None  # organised: use xyz and valid
    # The same memory each time (a view of the frame, not a copy), and read-only.
    assert np.shares_memory(f.range, f.range)
    assert not f.range.flags.writeable
    # Each row fired at its own column offset: its times are the column times, shifted.
    t = f.pixel_times
    assert t.shape == (128, 1024) and t.dtype == np.float64
    for row in t:
        assert np.isin(row, f.column_times).all()
        shift = int(np.argmax(f.column_times == row[0]))
        np.testing.assert_array_equal(row, np.roll(f.column_times, -shift))
    assert not np.array_equal(t[0], t[-1])
    # Range is the norm of the point (to the sensor's precision) where valid.
    r = np.linalg.norm(f.xyz[f.valid], axis=1)
    assert np.allclose(r, f.range[f.valid], atol=0.05)


def test_an_unorganised_source_has_every_point(sim_bins):
    frames = list(keylo.open(sim_bins, max_frames=3))
    assert len(frames) == 3
    f = frames[0]
    raw = np.fromfile(sorted(sim_bins.glob("**/*.bin"))[0], dtype=np.float32).reshape(-1, 4)
    assert f.points.shape == (len(raw), 3)
    np.testing.assert_array_equal(f.points, raw[:, :3].astype(np.float64))


def test_the_simulator_gives_frames_and_ground_truth():
    reader = keylo.open(kind="sim", scene="lab", frames=4, sensor="os1-64", columns=512)
    frames = list(reader)
    stamps, poses = reader.ground_truth()
    assert len(frames) == 4 and poses.shape == (4, 4, 4) and stamps.shape == (4,)
    assert frames[0].rows == 64 and frames[0].cols == 512


def test_sim_returns_frames_and_ground_truth():
    frames, stamps, poses = keylo.sim("corridor", 3, sensor="os1-64", columns=512)
    assert len(frames) == 3 and poses.shape == (3, 4, 4)
    # The pose of each frame refers to a time within its sweep (the simulator's: its end).
    sweep_start = np.array([f.timestamp for f in frames])
    assert np.all((stamps >= sweep_start) & (stamps - sweep_start < 0.1))
