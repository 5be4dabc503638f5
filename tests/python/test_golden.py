"""Every recording format this product has written opens in Python: the golden recordings in
tests/golden/ (see its README) read through telerehab.session.read with their channels,
units and measures, as a recording of this build does."""

from pathlib import Path

import numpy as np
import pytest

import telerehab

GOLDEN = Path(__file__).resolve().parents[1] / "golden"


@pytest.mark.parametrize("name", ["v1-json-regimen.mcap", "v2-compact.mcap", "v3-raw-inputs.mcap"])
def test_a_golden_recording_reads_with_its_channels_and_units(name):
    s = telerehab.session.read(GOLDEN / name)
    wheel = s.channels["/wheel"]
    assert len(wheel["t_s"]) >= 900, name
    assert np.all(np.diff(wheel["t_s"]) > 0), name
    assert np.all(np.abs(wheel["commanded_nm"]) <= wheel["ceiling_nm"] + 1e-12), name
    assert "N·m" in s.units["/wheel"]["commanded_nm"], name
    assert s.metadata["seed"] == "7", name
    assert "format_version" not in s.metadata, "formats 1–3 carry no version"
    assert s.metrics, f"{name}: the session's measures"
