"""A recorded session (the station's MCAP file) as numpy columns, with the units of every field.

>>> s = telerehab.session.read("session.mcap")            # doctest: +SKIP
>>> s.channels["/wheel"]["angle_rad"]                      # one float64 array per field
>>> s.units["/wheel"]["commanded_nm"]                      # 'Torque commanded to the motor …, N·m.'
>>> s.metrics["sparc_median"], len(s.movements)            # the session's movement measures
>>> s.frame("/wheel")                                      # a pandas DataFrame, if pandas is installed

Channels (one per MCAP topic): ``/wheel``, ``/assist``, ``/timing`` every haptic tick (1 kHz);
``/vehicle`` every tick on the road; ``/arm`` every tick with arm sensing; ``/score`` every
100 ms; ``/arm_calibration`` and ``/metrics`` once at the end; the raw inputs the station's
pure code consumed, ``/raw/wheel`` every tick (the wheel's reading and its timestamp, the body
clock, pause and stop, the arm tracker's events) and ``/raw/imu`` every IMU sample (``sensor``,
``device_t_ns``, gyro rad/s, specific force m/s²), exactly as consumed, so ``telerehab replay``
re-runs a session from them. Every sample carries ``tick``
(haptic tick since the start) and ``t_s`` (session time, s). Units are in the field names
(``_rad``, ``_nm``, ``_m_s``, ``_us``, …) and, in full, in :attr:`Session.units`, read from the
file itself, so they cannot drift from what the station wrote.

The high-rate channels (``/wheel``, ``/vehicle``, ``/assist``, ``/timing``, ``/arm``,
``/raw/wheel``, ``/raw/imu``) are
recorded in compact blocks: protobuf messages (descriptor in the file) of one column per field
over 100 samples, numbers as differences of whole quanta (1 µrad, 1 µN·m, 1 µm, …, stated per
field in the channel's ``telerehab.columns`` metadata). They are decoded here with the
``protobuf`` package and numpy; the low-rate channels are JSON. ``/arm/scene`` is the arm as a
Foxglove 3-D scene (``foxglove.SceneUpdate``), for Foxglove, and is not read here.

Pure Python over the ``mcap`` reader: the file is read once, message by message.
"""

from __future__ import annotations

import importlib
import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional, Union

import numpy as np
import numpy.typing as npt

__all__ = ["Session", "read"]

Column = npt.NDArray[Any]


@dataclass(frozen=True)
class Session:
    """One recorded session.

    ``channels[topic][field]``: a numpy array per field, one row per message in time order:
    float64 for numbers (NaN where a message left an optional field out), int64 for integers,
    bool for flags, str for names; a field holding lists (``shoulder_m``) is a 2-D array.
    ``units[topic][field]``: the field's description from the file, unit included.
    ``metadata``: the ``session`` metadata record (exercise, seed, patient, loop rate, the
    configuration and regimen as TOML text). ``messages``: the low-rate (JSON) channels'
    messages as dictionaries.
    """

    path: str
    metadata: Dict[str, str]
    channels: Dict[str, Dict[str, Column]]
    units: Dict[str, Dict[str, str]]
    messages: Dict[str, List[Dict[str, Any]]] = field(repr=False)

    @property
    def metrics(self) -> Dict[str, float]:
        """The session's movement measures (``/metrics``), name → value, the unit in the name
        (``sparc_median``, ``wheel_rom_deg``, ``active_s``, …); empty if the session did not end
        in order (a killed session recovered with ``telerehab recover``)."""
        end = self.messages.get("/metrics", [])
        return {str(k): float(v) for k, v in end[-1]["measures"].items()} if end else {}

    @property
    def movements(self) -> List[Dict[str, Any]]:
        """The wheel's movements found at the end of the session (``/metrics``): ``start_s``,
        ``duration_s``, ``peak_speed_rad_s``, ``n_peaks`` and, where defined, ``sparc`` and
        ``ldlj``."""
        end = self.messages.get("/metrics", [])
        return list(end[-1]["movements"]) if end else []

    @property
    def arm_calibration(self) -> Optional[Dict[str, Any]]:
        """The arm calibrated from the session (``/arm_calibration``), or ``None``."""
        end = self.messages.get("/arm_calibration", [])
        return dict(end[-1]) if end else None

    def frame(self, topic: str) -> Any:
        """The channel ``topic`` as a pandas DataFrame indexed by ``t_s`` (2-D fields left out).

        Raises ``ImportError`` without pandas (``pip install pandas``) and ``KeyError`` naming
        the topics present for an unknown one.
        """
        # Optional (numpy columns serve without it), so imported here and untyped.
        pd: Any = importlib.import_module("pandas")
        columns = self._channel(topic)
        flat = {k: v for k, v in columns.items() if v.ndim == 1}
        return pd.DataFrame(flat).set_index("t_s")

    def _channel(self, topic: str) -> Dict[str, Column]:
        try:
            return self.channels[topic]
        except KeyError:
            raise KeyError(f"no channel {topic!r} in {self.path}; it has {sorted(self.channels)}") from None


def read(path: Union[str, "os.PathLike[str]"]) -> Session:
    """Read the station's recording at ``path`` (MCAP, JSON channels).

    Raises ``FileNotFoundError`` for a missing file and ``ValueError`` naming the path for a
    file that is not a finished telerehab recording (run ``telerehab recover`` on one a killed
    session left behind).
    """
    from mcap.exceptions import McapError
    from mcap.reader import make_reader

    from google.protobuf.message import DecodeError

    path = os.fspath(path)
    messages: Dict[str, List[Dict[str, Any]]] = {}
    blocks: Dict[str, _Blocks] = {}
    units: Dict[str, Dict[str, str]] = {}
    metadata: Dict[str, str] = {}
    with open(path, "rb") as f:
        try:
            reader = make_reader(f)
            for schema, channel, message in reader.iter_messages(log_time_order=False):
                if schema is None or channel.topic == "/arm/scene":
                    continue
                if channel.message_encoding == "protobuf":
                    if channel.topic not in blocks:
                        blocks[channel.topic] = _Blocks(schema.name, schema.data, channel.metadata)
                        units[channel.topic] = blocks[channel.topic].units()
                    blocks[channel.topic].add(message.data)
                    continue
                if channel.topic not in units:
                    units[channel.topic] = _descriptions(schema.data)
                messages.setdefault(channel.topic, []).append(json.loads(message.data))
            for m in reader.iter_metadata():
                if m.name == "session":
                    metadata = dict(m.metadata)
        except (McapError, DecodeError, json.JSONDecodeError, UnicodeDecodeError, AssertionError, KeyError) as e:
            raise ValueError(f"{path} is not a readable telerehab recording: {e!r}") from None
    if not metadata:
        raise ValueError(f"{path} has no 'session' metadata record: not a telerehab recording")
    channels = {topic: _columns(rows) for topic, rows in messages.items()}
    channels.update({topic: b.columns() for topic, b in blocks.items()})
    return Session(path=path, metadata=metadata, channels=channels, units=units, messages=messages)


# The integers a block reserves (``record::blocks`` in the station).
_ABSENT = np.iinfo(np.int64).min
_NAN = _ABSENT + 1
_NEG_INF = _ABSENT + 2
_POS_INF = np.iinfo(np.int64).max


class _Blocks:
    """One high-rate channel's block messages, decoded into columns."""

    def __init__(self, name: str, descriptor_set: bytes, channel_metadata: Mapping[str, str]) -> None:
        from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

        pool = descriptor_pool.DescriptorPool()
        for file in descriptor_pb2.FileDescriptorSet.FromString(descriptor_set).file:
            pool.Add(file)
        self._cls = message_factory.GetMessageClass(pool.FindMessageTypeByName(name))
        self._columns: List[Dict[str, Any]] = json.loads(channel_metadata["telerehab.columns"])
        self._parts: Dict[str, List[Column]] = {c["name"]: [] for c in self._columns}

    def units(self) -> Dict[str, str]:
        out = {c["name"]: str(c["description"]) for c in self._columns if c["name"] != "t_ns"}
        out["t_s"] = "Session time, s."
        return out

    def add(self, data: bytes) -> None:
        msg = self._cls.FromString(data)
        for c in self._columns:
            values = getattr(msg, c["name"])
            width = int(c["elements"])
            if c["type"] in ("float", "int"):
                # Differences from the previous sample's value of the same element, wrapping.
                q = np.array(values, dtype=np.int64).reshape(-1, width)
                with np.errstate(over="ignore"):
                    q = np.cumsum(q, axis=0, dtype=np.int64)
                col: Column = q if c["type"] == "int" else _unquantise(q, float(c["quantum"]))
            elif c["type"] == "bool":
                col = np.array(values, dtype=bool).reshape(-1, width)
            else:
                col = np.array(list(values), dtype=str).reshape(-1, width)
            self._parts[c["name"]].append(col if width > 1 else col[:, 0])

    def columns(self) -> Dict[str, Column]:
        out: Dict[str, Column] = {}
        for name, parts in self._parts.items():
            col = np.concatenate(parts) if parts else np.array([])
            if name == "t_ns":
                out["t_s"] = col.astype(np.float64) * 1e-9
            else:
                out[name] = col
        return out


def _unquantise(q: Column, quantum: float) -> Column:
    x = q.astype(np.float64) * quantum
    x[(q == _ABSENT) | (q == _NAN)] = np.nan
    x[q == _POS_INF] = np.inf
    x[q == _NEG_INF] = -np.inf
    return x


def _descriptions(schema: bytes) -> Dict[str, str]:
    """Field name → description of a JSON schema's top-level properties."""
    try:
        props: Mapping[str, Any] = json.loads(schema).get("properties", {})
    except (json.JSONDecodeError, UnicodeDecodeError, AttributeError):
        return {}
    return {name: str(p.get("description", "")) for name, p in props.items() if isinstance(p, dict)}


def _columns(rows: List[Dict[str, Any]]) -> Dict[str, Column]:
    """One numpy array per field of ``rows`` (field order of first appearance)."""
    names: Dict[str, None] = {}
    for r in rows:
        for k in r:
            names.setdefault(k, None)
    return {name: _column([r.get(name) for r in rows]) for name in names}


def _column(values: List[Any]) -> Column:
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present) and len(present) == len(values):
        return np.array(values, dtype=bool)
    if present and all(isinstance(v, int) and not isinstance(v, bool) for v in present) and len(present) == len(values):
        return np.array(values, dtype=np.int64)
    if present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
        return np.array([np.nan if v is None else float(v) for v in values], dtype=np.float64)
    if present and all(isinstance(v, list) for v in present):
        try:
            return np.array(values, dtype=np.float64)
        except (TypeError, ValueError):
            pass
    if present and all(isinstance(v, str) for v in present):
        return np.array(["" if v is None else v for v in values], dtype=str)
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out
