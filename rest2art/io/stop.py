"""A stop asked for by a signal, remembered as well as raised.

SIGTERM and SIGINT raise an exception in the main thread, so that temporaries and CoACD
workers go on the way out. Raising alone is not enough: libraries the pipeline calls catch
``BaseException`` (trimesh guards its optional imports and several conversions that way), so a
signal that lands inside one of them can be swallowed and the run goes on, or fails later with
an unrelated error. The handler therefore also records the stop; an output is never committed
after one, and the command line reports the stop whatever the run did afterwards.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager

_STOP: list[int] = []
"""Signal numbers received while :func:`stop_on_signals` was active (the first one counts)."""


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C."""


def _on_signal(signum, frame):
    _STOP.append(signum)
    if signum == signal.SIGTERM:
        raise Terminated()
    raise KeyboardInterrupt()


def stopped() -> int | None:
    """The signal number of a stop asked for since :func:`stop_on_signals` began, or None."""
    return _STOP[0] if _STOP else None


def raise_if_stopped() -> None:
    """Raise the stop again (``Terminated`` or ``KeyboardInterrupt``) if one was asked for and
    swallowed: call it before committing an output."""
    if _STOP:
        raise Terminated() if _STOP[0] == signal.SIGTERM else KeyboardInterrupt()


@contextmanager
def stop_on_signals():
    """Within the block, SIGTERM and SIGINT are recorded and raised in the main thread (no-op
    elsewhere: only the main thread may set handlers). Previous handlers come back on leaving."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _STOP.clear()
    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGTERM, signal.SIGINT)}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
