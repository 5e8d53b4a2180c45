"""Native simulator output kept out of stdout and out of the working directory.

PyBullet prints from C straight to file descriptor 1 (where it glues onto a command's result
line) and its build time to descriptor 2 when it is first imported (a stray line in a --quiet
run's log), and MuJoCo writes ``MUJOCO_LOG.TXT`` into the working directory when it warns.
Inside :func:`captured`, descriptors 1 and 2 go to a temporary file and the working directory is
a temporary folder (one a killed run left is removed by the next); on leaving, both are restored
and what they caught is handed back.
"""

from __future__ import annotations

import ctypes
import os
import sys
from contextlib import contextmanager
from dataclasses import dataclass

from rest2art.io.atomic import scratch_folder

KEEP_CHARS = 4000
"""Captured output kept per block (its end: the last lines say what went wrong)."""


@dataclass
class NativeOutput:
    """What native code wrote while captured."""

    text: str = ""
    """stdout, stderr and any MuJoCo log, its last ``KEEP_CHARS`` characters."""
    chars: int = 0
    """How many characters were written in all."""


def _flush_c_stdio() -> None:
    """fflush(NULL): C stdio buffers what it prints to a pipe; flush before switching back."""
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass


@contextmanager
def captured():
    """Run the block with fds 1 and 2 in a temporary file and a temporary working directory;
    yields a :class:`NativeOutput` filled on exit. Paths used inside must be absolute."""
    out = NativeOutput()
    sys.stdout.flush()
    sys.stderr.flush()
    _flush_c_stdio()
    cwd = os.getcwd()
    saved = {fd: os.dup(fd) for fd in (1, 2)}
    with scratch_folder("rest2art-native") as folder, open(folder / "output.txt", "w+b") as sink:
        for fd in saved:
            os.dup2(sink.fileno(), fd)
        os.chdir(folder)
        try:
            yield out
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            _flush_c_stdio()
            for fd, copy in saved.items():
                os.dup2(copy, fd)
                os.close(copy)
            os.chdir(cwd)
            sink.seek(0)
            text = sink.read().decode(errors="replace")
            for log in sorted(folder.glob("*.TXT")):
                text += f"\n[{log.name}]\n" + log.read_text(errors="replace")
            out.chars = len(text.strip())
            out.text = text.strip()[-KEEP_CHARS:]
