"""The station's MCAP recordings open in the Python `mcap` reader (what Foxglove-era tooling uses)."""

import json
import os
import subprocess
from collections import Counter
from pathlib import Path

from mcap.reader import make_reader

BIN = os.environ.get("TELEREHAB_BIN", str(Path(__file__).resolve().parents[2] / "target" / "debug" / "telerehab"))


def test_recording_opens_in_python_mcap_with_json_schemas(tmp_path):
    path = tmp_path / "session.mcap"
    subprocess.run(
        [BIN, "run", "--sim", "--headless", "--duration", "2", "--seed", "3", "--speed", "max", "--record", str(path)],
        check=True,
        capture_output=True,
    )
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None
        encodings = {ch.topic: (ch.message_encoding, summary.schemas[ch.schema_id].encoding) for ch in summary.channels.values()}
        assert encodings == {t: ("json", "jsonschema") for t in ("/wheel", "/vehicle", "/score", "/assist", "/timing", "/arm", "/arm_calibration", "/metrics")}
        counts = Counter()
        last_t = {}
        for schema, channel, message in reader.iter_messages():
            body = json.loads(message.data)
            counts[channel.topic] += 1
            assert body["t_s"] >= last_t.get(channel.topic, -1.0)
            last_t[channel.topic] = body["t_s"]
            if channel.topic == "/wheel":
                assert abs(body["commanded_nm"]) <= 1.87
    assert counts["/wheel"] == counts["/vehicle"] == counts["/timing"] == 2101
    assert counts["/score"] == 21
    meta = {m.name: m.metadata for m in make_reader(open(path, "rb")).iter_metadata()}
    assert meta["session"]["seed"] == "3"
