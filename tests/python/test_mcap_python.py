"""The station's MCAP recordings open in the Python `mcap` reader and decode with Foxglove's own
protobuf decoder (`mcap-protobuf-support`, what Foxglove-family tooling uses): the high-rate
channels as protobuf blocks, the arm as a `foxglove.SceneUpdate`, the low-rate ones as JSON."""

import json
import os
import subprocess
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

import telerehab

BIN = os.environ.get("TELEREHAB_BIN", str(Path(__file__).resolve().parents[2] / "target" / "debug" / "telerehab"))

BLOCKS = ("/wheel", "/vehicle", "/assist", "/timing", "/arm", "/raw/wheel", "/raw/imu")


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    path = tmp_path_factory.mktemp("mcap") / "session.mcap"
    subprocess.run(
        [BIN, "run", "--sim", "--headless", "--duration", "2", "--seed", "3", "--speed", "max", "--record", str(path)],
        check=True,
        capture_output=True,
    )
    return path


def test_every_channel_has_the_encoding_its_rate_calls_for(recording):
    with open(recording, "rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    encodings = {ch.topic: (ch.message_encoding, summary.schemas[ch.schema_id].encoding) for ch in summary.channels.values()}
    assert encodings == {
        **{t: ("protobuf", "protobuf") for t in BLOCKS},
        "/arm/scene": ("protobuf", "protobuf"),
        **{t: ("json", "jsonschema") for t in ("/score", "/arm_calibration", "/metrics")},
    }
    names = {ch.topic: summary.schemas[ch.schema_id].name for ch in summary.channels.values()}
    assert names["/wheel"] == "telerehab.WheelBlock" and names["/arm/scene"] == "foxglove.SceneUpdate"


def test_foxglove_s_protobuf_decoder_reads_every_message(recording):
    decoders = DecoderFactory()
    counts = Counter()
    ticks = Counter()
    with open(recording, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            if channel.message_encoding == "json":
                body = json.loads(message.data)
                counts[channel.topic] += 1
                continue
            decoded = decoders.decoder_for(channel.message_encoding, schema)(message.data)
            counts[channel.topic] += 1
            if channel.topic == "/arm/scene":
                arm = next(e for e in decoded.entities if e.id == "arm")
                shoulder, elbow, grip = arm.lines[0].points
                # Nominal segment lengths (0.30 m, 0.33 m) between the drawn joints.
                assert abs(np.linalg.norm([elbow.x - shoulder.x, elbow.y - shoulder.y, elbow.z - shoulder.z]) - 0.30) < 1e-9
                assert abs(np.linalg.norm([grip.x - elbow.x, grip.y - elbow.y, grip.z - elbow.z]) - 0.33) < 1e-9
            else:
                ticks[channel.topic] += len(decoded.tick)
    # 2 s and the fade-out after (as long as the torque at the end takes to reach zero).
    n = ticks["/wheel"]
    assert ticks["/vehicle"] == ticks["/timing"] == n and 2100 <= n <= 2110
    assert counts["/wheel"] == (n + 99) // 100  # blocks of at most 100 ticks, cut at each 1 s flush
    assert counts["/score"] == (n - 1) // 100
    # 20 Hz from the first tick (the simulated arm is tracked from the start).
    assert counts["/arm/scene"] == (n - 1) // 50 + 1
    meta = {m.name: m.metadata for m in make_reader(open(recording, "rb")).iter_metadata()}
    assert meta["session"]["seed"] == "3"


def test_block_columns_decode_to_the_recorded_samples(recording):
    s = telerehab.session.read(recording)
    wheel = s.channels["/wheel"]
    assert np.array_equal(wheel["tick"], np.arange(len(wheel["tick"]))) and len(wheel["tick"]) >= 2100
    assert np.all(np.abs(wheel["commanded_nm"]) <= wheel["ceiling_nm"] + 1e-12)
    # Floats are whole numbers of their quantum (1 µrad for an angle).
    micro = wheel["angle_rad"] * 1e6
    assert np.max(np.abs(micro - np.round(micro))) < 1e-6
    assert s.channels["/arm"]["upper_orientation_wxyz"].shape[1] == 4


def _foxglove_columns(recording):
    """Every block channel's columns decoded by Foxglove's protobuf decoder and numpy, from the
    block encoding as the file declares it (``telerehab.columns``): the differences of each
    element summed (wrapping), a float's quanta scaled, the reserved integers as NaN and ±∞.
    Independent of the Rust reader: another MCAP reader, another protobuf decoder."""
    absent, nan, neg_inf, pos_inf = -(2**63), -(2**63) + 1, -(2**63) + 2, 2**63 - 1
    decoders = DecoderFactory()
    parts, json_messages = {}, {}
    with open(recording, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages(log_time_order=False):
            if channel.message_encoding == "json":
                json_messages.setdefault(channel.topic, []).append(json.loads(message.data))
                continue
            if "telerehab.columns" not in channel.metadata:
                continue  # the Foxglove scene
            block = decoders.decoder_for("protobuf", schema)(message.data)
            for c in json.loads(channel.metadata["telerehab.columns"]):
                values = list(getattr(block, c["name"]))
                if c["type"] in ("float", "int"):
                    q = np.array(values, dtype=np.int64).reshape(-1, c["elements"])
                    with np.errstate(over="ignore"):
                        q = np.cumsum(q, axis=0, dtype=np.int64)
                    if c["name"] == "t_ns":
                        col = q.astype(np.uint64).astype(np.float64) * 1e-9
                    elif c["type"] == "int":
                        col = q.astype(np.uint64)
                    else:
                        col = q.astype(np.float64) * c["quantum"]
                        col[(q == absent) | (q == nan)] = np.nan
                        col[q == pos_inf], col[q == neg_inf] = np.inf, -np.inf
                else:
                    col = np.array(values, dtype=bool if c["type"] == "bool" else str).reshape(-1, c["elements"])
                name = "t_s" if c["name"] == "t_ns" else c["name"]
                parts.setdefault(channel.topic, {}).setdefault(name, []).append(col if c["elements"] > 1 else col[:, 0])
    blocks = {t: {n: np.concatenate(p) for n, p in cols.items()} for t, cols in parts.items()}
    return blocks, json_messages


def test_every_column_read_through_rust_equals_foxglove_s_decoder_value_for_value(recording):
    s = telerehab.session.read(recording)
    blocks, json_messages = _foxglove_columns(recording)
    assert set(blocks) == set(BLOCKS)
    compared = 0
    for topic, columns in blocks.items():
        assert list(s.channels[topic]) == list(columns), topic  # every field, in the file's order
        for name, expected in columns.items():
            got = s.channels[topic][name]
            assert got.dtype == expected.dtype and got.shape == expected.shape, (topic, name)
            # Identical values (NaN where NaN), not merely close ones.
            assert np.array_equal(got, expected, equal_nan=got.dtype == np.float64), (topic, name)
            compared += got.size
    assert compared > 100_000
    assert s.messages == json_messages
    assert s.channels["/raw/wheel"]["read"].dtype.kind == "U"
