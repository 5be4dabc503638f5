"""What a recording's channels cost: the file rewritten by one writer (zstd chunks of 1 MiB, as
the station writes) with every channel, without the raw inputs (/raw/*), and without each of a
few channels, in MB per hour of session. Both sides go through the same writer, so the
difference is what those channels add.

    python3 scripts/raw_inputs_size.py session.mcap SECONDS
"""

import io
import sys

from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer


def rewritten_bytes(path: str, keep) -> int:
    """Bytes of `path` rewritten with the channels whose topic `keep` accepts."""
    out = io.BytesIO()
    w = Writer(out, chunk_size=1024 * 1024, compression=CompressionType.ZSTD)
    w.start(profile="", library="raw_inputs_size")
    schemas, channels = {}, {}
    with open(path, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            if not keep(channel.topic):
                continue
            if schema.id not in schemas:
                schemas[schema.id] = w.register_schema(schema.name, schema.encoding, schema.data)
            if channel.id not in channels:
                channels[channel.id] = w.register_channel(
                    channel.topic, channel.message_encoding, schemas[schema.id], channel.metadata
                )
            w.add_message(
                channels[channel.id], message.log_time, message.data, message.publish_time, message.sequence
            )
    w.finish()
    return len(out.getvalue())


def main() -> None:
    path, seconds = sys.argv[1], float(sys.argv[2])
    mb_h = 3600.0 / seconds / 1e6
    every = rewritten_bytes(path, lambda t: True)
    without = rewritten_bytes(path, lambda t: not t.startswith("/raw/"))
    print(f"{path}: {every * mb_h:.0f} MB/h, without /raw/* {without * mb_h:.0f} MB/h: "
          f"the raw inputs add {(every - without) * mb_h:.0f} MB/h ({100 * (every - without) / without:.1f} %)")
    for topic in ("/raw/wheel", "/raw/imu", "/wheel", "/arm"):
        n = rewritten_bytes(path, lambda t, topic=topic: t != topic)
        print(f"  {topic}: {(every - n) * mb_h:.0f} MB/h")


if __name__ == "__main__":
    main()
