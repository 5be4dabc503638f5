"""telerehab.session reads a recorded session into numpy columns with the units of its schemas,
and its movement measures (the station's /metrics channel)."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

import telerehab

BIN = os.environ.get("TELEREHAB_BIN", str(Path(__file__).resolve().parents[2] / "target" / "debug" / "telerehab"))


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    path = tmp_path_factory.mktemp("session") / "session.mcap"
    subprocess.run(
        [BIN, "run", "--sim", "--headless", "--duration", "6", "--seed", "5", "--speed", "max",
         "--exercise", "dial-sine", "--record", str(path)],
        check=True,
        capture_output=True,
    )
    return path


def test_every_channel_is_read_as_columns_of_one_row_per_sample(recording):
    s = telerehab.session.read(recording)
    counts = {}
    decoders = DecoderFactory()
    with open(recording, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            if channel.topic == "/arm/scene":
                continue  # for Foxglove's 3-D panel
            n = 1
            if channel.message_encoding == "protobuf":  # a block of samples
                n = len(decoders.decoder_for("protobuf", schema)(message.data).tick)
            counts[channel.topic] = counts.get(channel.topic, 0) + n
    assert {t: len(c["t_s"]) for t, c in s.channels.items()} == counts
    wheel = s.channels["/wheel"]
    assert wheel["angle_rad"].dtype == np.float64
    assert wheel["tick"].dtype == np.uint64  # Rust's u64
    assert wheel["clipped"].dtype == np.bool_
    assert np.all(np.diff(wheel["t_s"]) > 0)
    assert np.all(np.abs(wheel["commanded_nm"]) <= wheel["ceiling_nm"] + 1e-12)
    assert s.metadata["seed"] == "5" and s.metadata["exercise"] == "dial-sine"


def test_units_come_from_the_schemas_in_the_file(recording):
    s = telerehab.session.read(recording)
    assert "N·m" in s.units["/wheel"]["commanded_nm"]
    assert "rad" in s.units["/wheel"]["angle_rad"]
    assert set(s.units["/wheel"]) >= set(s.channels["/wheel"])


def test_the_sessions_measures_and_movements_are_there(recording):
    s = telerehab.session.read(recording)
    m = s.metrics
    assert m["movements"] == len(s.movements) >= 2
    assert 6.0 <= m["session_s"] < 6.5  # 6 s of exercise and the torque's fade-out
    # The measures agree with the same Rust code run from Python on the recorded wheel angle,
    # at the station's 100 Hz (block means of 10 ticks).
    angle = s.channels["/wheel"]["angle_rad"]
    blocks = angle[: len(angle) // 10 * 10].reshape(-1, 10).mean(axis=1)
    again = telerehab.metrics.session_measures(blocks, 100.0)
    assert len(again["movements"]) == m["movements"]
    # Smoothness over the discrete movements alone (issue 42): a dial sine tracked throughout
    # may have none, and then no SPARC.
    discrete = [mv for mv in again["movements"] if mv["discrete"]]
    assert m["discrete_movements"] == len(discrete)
    scored = [mv["sparc"] for mv in discrete if mv["sparc"] is not None]
    if scored:
        assert abs(np.median(scored) - m["sparc_median"]) < 1e-9
    else:
        assert "sparc_median" not in m
    assert all(mv["sparc"] is None for mv in again["movements"] if not mv["discrete"])


def test_not_a_recording_is_a_value_error_naming_the_file(tmp_path):
    bad = tmp_path / "notes.mcap"
    bad.write_bytes(b"this is not an mcap file at all")
    with pytest.raises(ValueError, match="notes.mcap"):
        telerehab.session.read(bad)
    with pytest.raises(FileNotFoundError):
        telerehab.session.read(tmp_path / "missing.mcap")


def test_a_recording_cut_short_is_a_value_error_that_says_to_recover_it(recording, tmp_path):
    cut = tmp_path / "killed.mcap"
    cut.write_bytes(recording.read_bytes()[: recording.stat().st_size // 2])
    with pytest.raises(ValueError, match=r"killed\.mcap .*telerehab recover"):
        telerehab.session.read(cut)


def test_a_channel_is_a_pandas_frame_indexed_by_session_time(recording):
    s = telerehab.session.read(recording)
    frame = s.frame("/wheel")
    assert frame.index.name == "t_s"
    assert len(frame) == len(s.channels["/wheel"]["t_s"])
    assert np.array_equal(frame["angle_rad"].to_numpy(), s.channels["/wheel"]["angle_rad"])
    with pytest.raises(KeyError, match="/wheel"):
        s.frame("/nope")


def test_the_raw_inputs_are_columns_with_units_and_hold_what_the_station_consumed(recording):
    s = telerehab.session.read(recording)
    wheel, raw, imu, arm = (s.channels[t] for t in ("/wheel", "/raw/wheel", "/raw/imu", "/arm"))
    # /raw/wheel: one row a tick, the reading as the wheel gave it and the body clock.
    assert np.array_equal(raw["tick"], wheel["tick"])
    assert set(raw["read"]) == {"ok"}
    assert raw["now_ns"].dtype == np.uint64 and np.all(np.diff(raw["now_ns"]) == 1_000_000)
    assert "rad" in s.units["/raw/wheel"]["angle_rad"]
    assert np.array_equal(raw["angle_rad"], wheel["angle_rad"])  # no fault: the reading is the angle
    assert not raw["paused"].any()
    # The tracker is stepped except on ticks the simulated arm cannot reach the rim.
    assert 0.5 < raw["arm_stepped"].mean()
    # /raw/imu: every sample of both simulated IMUs, SI units after the device edge.
    assert set(imu["sensor"]) == {0, 1}
    assert "rad/s" in s.units["/raw/imu"]["gyro_x_rad_s"]
    assert "m/s²" in s.units["/raw/imu"]["acc_z_m_s2"]
    assert imu["device_t_ns"].dtype == np.uint64
    g = np.sqrt(imu["acc_x_m_s2"] ** 2 + imu["acc_y_m_s2"] ** 2 + imu["acc_z_m_s2"] ** 2)
    assert 9.0 < np.median(g) < 10.6  # gravity plus the arm's motion, m/s²
    # Exactly what the arm tracker consumed: the upper-arm gyro it reports on /arm, bit for bit.
    upper = imu["sensor"] == 0
    assert upper.sum() == raw["arm_stepped"].sum()  # a fresh sample every tick it was stepped
    at = np.searchsorted(arm["tick"], imu["tick"][upper])
    # (/arm records it on its own grid of 1 µrad/s, which holds /raw/imu's 100 µrad/s one.)
    assert np.allclose(arm["upper_gyro_x_rad_s"][at], imu["gyro_x_rad_s"][upper], rtol=0, atol=1e-12)
    assert np.allclose(imu["gyro_x_rad_s"] / 1e-4, np.round(imu["gyro_x_rad_s"] / 1e-4), rtol=0, atol=1e-6)


def test_the_native_read_releases_the_gil(recording):
    # Another thread stamps the time every 0.5 ms: it can only while it holds the GIL. With the
    # GIL held through a read, no more than a stamp or two (a switch before the call starts)
    # could fall within a read (more only while the OS holds the reader back); released, some
    # 20 do.
    import threading
    import time

    from telerehab import _native

    stamps = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            stamps.append(time.perf_counter())
            stop.wait(0.0005)

    th = threading.Thread(target=ticker)
    th.start()
    windows = []
    try:
        for _ in range(20):
            t0 = time.perf_counter()
            _native.session_read(str(recording))
            windows.append((t0, time.perf_counter()))
    finally:
        stop.set()
        th.join()
    inside = [sum(t0 < t < t1 for t in stamps) for t0, t1 in windows]
    assert sorted(inside)[len(inside) // 2] >= 5, inside  # the median read


def test_each_exercises_results_and_the_end_reason_are_read(recording):
    s = telerehab.session.read(recording)
    assert s.end_reason == "complete"
    assert len(s.exercises) == 1, s.exercises
    e = s.exercises[0]
    assert (e["index"], e["kind"], e["name"]) == (0, "dial-sine", "Dial sine")
    assert abs(e["active_s"] - 6.0) < 0.01 and e["prescribed_s"] == 6.0
    scores = e["scores"]
    assert scores["dial_mean_abs_error_deg"] > 0 and scores["dial_rms_error_deg"] >= scores["dial_mean_abs_error_deg"]
    assert "rms_lateral_m" not in scores
    # One exercise: its movements are the session's.
    assert scores["movements"] == s.metrics["movements"]
