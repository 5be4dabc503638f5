"""A recorded session (the station's MCAP file) as numpy columns, with the units of every field.

>>> s = telerehab.session.read("session.mcap")            # doctest: +SKIP
>>> s.channels["/wheel"]["angle_rad"]                      # one float64 array per field
>>> telerehab.session.info("session.mcap").channels        # what it holds, from its summary
>>> w = telerehab.session.read("session.mcap", channels=["/wheel"], start_s=600.0, end_s=1200.0)
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
``/raw/wheel``, ``/raw/imu``) are recorded in compact blocks (protobuf messages of one
delta-coded, quantised column per field, the quantum of each field stated in the file). They
are decoded by the station's own reader (the Rust crate ``record``, in the native module): the
file is streamed once, chunk by chunk, with the GIL released, straight into the numpy columns,
so a read holds little more than the columns it returns. A read of chosen ``channels`` over a
window ``[start_s, end_s)`` of session time goes through the file's summary (MCAP's chunk and
message indexes): it decompresses only the chunks holding those channels' messages in the
window and decodes only those messages, so ten minutes of one channel of an hour's recording
read in a fraction of a second; the columns are those of the whole read, sliced by ``t_s``.
A file without a summary is read front to back instead, with the same result. The low-rate
channels are JSON.
``/arm/scene`` is the arm as a Foxglove 3-D scene (``foxglove.SceneUpdate``), for Foxglove,
and is not read here.
"""

from __future__ import annotations

import importlib
import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from telerehab import _native

__all__ = ["ChannelInfo", "Info", "Session", "info", "read"]

Column = npt.NDArray[Any]


@dataclass(frozen=True)
class Session:
    """One recorded session.

    ``channels[topic][field]``: a numpy array per field, one row per message in time order:
    float64 for numbers (NaN where a message left an optional field out), uint64 for integers
    (every integer the station records is unsigned, as in Rust), bool for flags, str for names; a field holding lists (``shoulder_m``) is a 2-D array.
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
    def exercises(self) -> List[Dict[str, Any]]:
        """Each exercise's own results (``/metrics``), in course order: ``index``, ``kind``,
        ``name`` (the patient's), ``prescribed_s``, ``active_s`` and ``scores`` (name → value, the
        unit in the name: ``rms_lateral_m``, ``dial_mean_abs_error_deg``, ``sparc_median``, …);
        empty for a recording made before they were recorded."""
        end = self.messages.get("/metrics", [])
        return list(end[-1].get("exercises", [])) if end else []

    @property
    def end_reason(self) -> str:
        """How the session ended (``/metrics``), as its ``Bye`` said: ``complete``, ``ended early
        by the patient (…)``, ``wheel unplugged``, …; empty when not recorded."""
        end = self.messages.get("/metrics", [])
        return str(end[-1].get("end_reason", "")) if end else ""

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


def read(
    path: Union[str, "os.PathLike[str]"],
    *,
    channels: Optional[Sequence[str]] = None,
    start_s: Optional[float] = None,
    end_s: Optional[float] = None,
) -> Session:
    """Read the station's recording at ``path`` (MCAP), or part of it.

    ``channels``: the topics to read (``["/wheel", "/score"]``; default: every channel).
    ``start_s``, ``end_s``: the window of session time to read, ``start_s <= t_s < end_s``
    (default: from the start, to the end). With any of them, only the chunks of the file holding
    the chosen channels' messages in the window are decompressed (through the file's summary),
    and the columns are the whole read's, sliced by ``t_s``; every chosen channel is in
    :attr:`Session.channels`, with empty columns when it has no sample in the window (a
    low-rate channel then has none). :func:`info` lists the channels and their spans first.

    Raises ``FileNotFoundError`` for a missing file, ``KeyError`` naming a channel the file does
    not have (and those it has), ``ValueError`` for a window ending before it starts or a time
    that is NaN, and ``ValueError`` naming the path for a file that is not a finished telerehab
    recording (run ``telerehab recover`` on one a killed session left behind).
    """
    path = os.fspath(path)
    if isinstance(channels, str):
        raise TypeError(f"channels is a list of topics, e.g. [{channels!r}], not a string")
    chosen = None if channels is None else [str(c) for c in channels]
    metadata, blocks, block_units, json_channels = _native.session_read(
        path,
        chosen,
        None if start_s is None else float(start_s),
        None if end_s is None else float(end_s),
    )
    # A channel the file declares but holds no message of (/vehicle off the road) is left out,
    # unless it was chosen.
    channels_read: Dict[str, Dict[str, Column]] = {
        topic: {name: _text(c) for name, c in cols.items()}
        for topic, cols in blocks.items()
        if len(cols["t_s"]) or chosen is not None
    }
    units = {topic: block_units[topic] for topic in channels_read}
    messages: Dict[str, List[Dict[str, Any]]] = {}
    for topic, (schema, raw) in json_channels.items():
        if not raw and chosen is None:
            continue
        try:
            messages[topic] = [json.loads(m) for m in raw]
        except (json.JSONDecodeError, UnicodeDecodeError) as e:
            raise ValueError(f"{path} is not a readable telerehab recording: {topic}: {e}") from None
        channels_read[topic] = _columns(messages[topic])
        units[topic] = _descriptions(schema)
    return Session(path=path, metadata=metadata, channels=channels_read, units=units, messages=messages)


@dataclass(frozen=True)
class ChannelInfo:
    """One channel of a recording, from its summary (see :func:`info`).

    ``encoding``: ``protobuf`` (blocks of samples, and the Foxglove scene) or ``json``.
    ``schema``: its schema's name (``telerehab.Wheel``). ``readable``: whether :func:`read`
    reads it. ``messages``: its MCAP messages (a block holds up to 100 samples). ``first_s``,
    ``last_s``: the stamps of its first and last messages, s of session time (``None`` for a
    channel without messages); a block is stamped with its first sample, so its samples run
    up to a block's span (at most a second) past ``last_s``.
    """

    topic: str
    encoding: str
    schema: str
    readable: bool
    messages: int
    first_s: Optional[float]
    last_s: Optional[float]


@dataclass(frozen=True)
class Info:
    """What a recording holds (see :func:`info`): its ``session`` metadata record, its channels
    by topic, its chunks, and whether this came from its summary (``indexed``) or a walk over a
    file without one."""

    path: str
    metadata: Dict[str, str]
    channels: Dict[str, ChannelInfo]
    chunks: int
    indexed: bool

    @property
    def end_s(self) -> float:
        """The stamp of the last message of any channel, s of session time (0 when empty)."""
        return max((c.last_s for c in self.channels.values() if c.last_s is not None), default=0.0)


def info(path: Union[str, "os.PathLike[str]"]) -> Info:
    """What the recording at ``path`` holds, read from its summary without decompressing its
    data (a file without a summary, cut short or recovered, is walked instead): its channels,
    their message counts and the session times of their first and last messages (session time
    0 is the earliest message stamp: the session's first tick), and its metadata.

    Raises as :func:`read` does for a missing file or one that is not a recording.
    """
    path = os.fspath(path)
    metadata, chunks, indexed, channels = _native.session_info(path)
    by_topic = {c[0]: ChannelInfo(*c) for c in channels}
    return Info(path=path, metadata=metadata, channels=by_topic, chunks=chunks, indexed=indexed)


def _text(column: Union[Column, "tuple[npt.NDArray[np.uint32], List[str]]"]) -> Column:
    """A column as numpy: an enum label column arrives as codes into its distinct labels."""
    if isinstance(column, tuple):
        codes, labels = column
        return np.asarray(labels, dtype=str)[codes] if labels else np.full(codes.shape, "", dtype=str)
    return column


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
    if (
        present
        and all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in present)
        and len(present) == len(values)
    ):
        return np.array(values, dtype=np.uint64)
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
