"""A real SMTP server for tests: aiosmtpd on 127.0.0.1:PORT; each message it takes is written
to DIR as N.eml, its envelope recipients first as an `X-Envelope-To:` line. Prints `ready`
once listening; stops when its standard input closes (or it is killed).

    python3 tests/smtp_sink.py PORT DIR
"""

import itertools
import pathlib
import sys

from aiosmtpd.controller import Controller


class Sink:
    def __init__(self, out):
        self.out = out
        self.numbers = itertools.count()

    async def handle_DATA(self, server, session, envelope):
        path = self.out / f"{next(self.numbers)}.eml"
        part = path.with_suffix(".part")
        head = ("X-Envelope-To: " + ", ".join(envelope.rcpt_tos) + "\r\n").encode()
        part.write_bytes(head + envelope.original_content)
        part.rename(path)  # whole messages only: a reader never sees half of one
        return "250 Message accepted for delivery"


def main():
    port, out = int(sys.argv[1]), pathlib.Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    controller = Controller(Sink(out), hostname="127.0.0.1", port=port)
    controller.start()
    print("ready", flush=True)
    try:
        sys.stdin.read()
    finally:
        controller.stop()


if __name__ == "__main__":
    main()
