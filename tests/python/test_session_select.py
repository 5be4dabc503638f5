"""telerehab.session reads chosen channels over a window of session time through the file's
summary (issue 47): exactly the whole read's values sliced by t_s, the same without a summary,
columns handed to numpy without a copy; and telerehab.session.info lists what a file holds
from its summary."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader

import telerehab

BIN = os.environ.get("TELEREHAB_BIN", str(Path(__file__).resolve().parents[2] / "target" / "debug" / "telerehab"))


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    path = tmp_path_factory.mktemp("select") / "session.mcap"
    subprocess.run(
        [BIN, "run", "--sim", "--headless", "--duration", "10", "--seed", "8", "--speed", "max",
         "--exercise", "sine-road", "--record", str(path)],
        check=True,
        capture_output=True,
    )
    return path


def without_summary(recording: Path, out: Path) -> Path:
    """The recording with its footer saying it has no summary, as a writer without one leaves
    it (the summary start, the footer's first field, set to 0)."""
    data = bytearray(recording.read_bytes())
    footer = len(data) - 37
    assert data[footer] == 0x02  # the footer record's opcode
    data[footer + 9 : footer + 17] = bytes(8)
    out.write_bytes(bytes(data))
    return out


def assert_same_columns(got, want, what):
    assert list(got) == list(want), what
    for name, column in want.items():
        # (A label column's str width is its longest label's, which a window may change.)
        assert got[name].dtype.kind == column.dtype.kind, f"{what} {name}"
        assert got[name].shape == column.shape, f"{what} {name}"
        if column.dtype.kind == "f":
            assert np.array_equal(got[name], column, equal_nan=True), f"{what} {name}"
        else:
            assert np.array_equal(got[name], column), f"{what} {name}"


CHOSEN = ["/wheel", "/vehicle", "/raw/imu", "/arm", "/score"]


@pytest.mark.parametrize("start_s,end_s", [(3.2345, 7.5), (0.0, 1.0), (9.5, 60.0), (4.0, 4.0)])
def test_a_window_of_chosen_channels_is_the_whole_read_sliced_by_session_time(recording, start_s, end_s):
    whole = telerehab.session.read(recording)
    part = telerehab.session.read(recording, channels=CHOSEN, start_s=start_s, end_s=end_s)
    assert sorted(part.channels) == sorted(CHOSEN)
    assert part.metadata == whole.metadata
    for topic in CHOSEN:
        t_s = whole.channels[topic]["t_s"]
        keep = (t_s >= start_s) & (t_s < end_s)
        if topic == "/score" and not keep.any():
            assert part.channels[topic] == {} and part.messages[topic] == []
            continue
        want = {name: column[keep] for name, column in whole.channels[topic].items()}
        assert_same_columns(part.channels[topic], want, f"{topic} over [{start_s}, {end_s})")
        assert part.units[topic] == whole.units[topic]


def test_without_a_summary_a_selection_reads_the_same_front_to_back(recording, tmp_path):
    bare = without_summary(recording, tmp_path / "bare.mcap")
    window = dict(channels=["/wheel", "/score"], start_s=2.5, end_s=6.25)
    indexed = telerehab.session.read(recording, **window)
    walked = telerehab.session.read(bare, **window)
    for topic in window["channels"]:
        assert_same_columns(walked.channels[topic], indexed.channels[topic], topic)
    assert telerehab.session.info(bare).channels == telerehab.session.info(recording).channels


def test_the_info_lists_channels_message_counts_and_spans_from_the_summary(recording):
    info = telerehab.session.info(recording)
    whole = telerehab.session.read(recording)
    assert info.indexed and info.metadata == whole.metadata
    # Counted again by the mcap package, message by message.
    counts, first, last = {}, {}, {}
    with open(recording, "rb") as f:
        for _, channel, message in make_reader(f).iter_messages(log_time_order=False):
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            first.setdefault(channel.topic, message.log_time)
            last[channel.topic] = message.log_time
    assert {t: c.messages for t, c in info.channels.items() if c.messages} == counts
    zero = min(first.values())
    for topic, c in info.channels.items():
        if c.messages:
            assert c.first_s == pytest.approx((first[topic] - zero) * 1e-9, abs=1e-9), topic
            assert c.last_s == pytest.approx((last[topic] - zero) * 1e-9, abs=1e-9), topic
    wheel = info.channels["/wheel"]
    assert wheel.readable and wheel.schema == "telerehab.WheelBlock" and wheel.encoding == "protobuf"
    assert wheel.first_s == whole.channels["/wheel"]["t_s"][0]
    assert 0 <= whole.channels["/wheel"]["t_s"][-1] - wheel.last_s < 1.0  # a block's span
    assert info.channels["/score"].encoding == "json"
    assert not info.channels["/arm/scene"].readable
    assert info.end_s >= wheel.last_s and info.chunks >= 10  # a chunk a second


def test_a_channel_the_file_lacks_or_a_window_ending_before_it_starts_is_named(recording):
    with pytest.raises(KeyError, match=r"/nope.*/wheel"):
        telerehab.session.read(recording, channels=["/wheel", "/nope"])
    with pytest.raises(ValueError, match="start_s 5 s is after end_s 2 s"):
        telerehab.session.read(recording, channels=["/wheel"], start_s=5.0, end_s=2.0)
    with pytest.raises(ValueError, match="start_s is NaN"):
        telerehab.session.read(recording, start_s=float("nan"))
    with pytest.raises(TypeError, match="list of topics"):
        telerehab.session.read(recording, channels="/wheel")
    with pytest.raises(FileNotFoundError):
        telerehab.session.info(recording.parent / "missing.mcap")


def test_the_columns_are_handed_to_numpy_without_a_copy(recording):
    part = telerehab.session.read(recording, channels=["/wheel", "/arm"], start_s=1.0, end_s=2.0)
    for column in (part.channels["/wheel"]["angle_rad"], part.channels["/wheel"]["tick"]):
        # numpy's view of the Vec the Rust reader filled, not a copy of it.
        assert not column.flags.owndata and type(column.base).__name__ == "PySliceContainer"
    assert len(part.channels["/wheel"]["t_s"]) == 1000  # one second at 1 kHz
