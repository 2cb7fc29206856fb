"""Ctrl-C during a long defocus: the work stops and KeyboardInterrupt is
raised within a second. The interrupt comes from a timer thread, which runs
only because the GIL is released while the library works."""

import _thread
import signal
import threading
import time

import numpy as np
import pytest

import gdof


def long_input():
    """A 1536 x 1536 plate with depth from 0.5 to 50, under a wide-open lens:
    blurs of hundreds of pixels solved at full resolution by the explicit
    solver, about ten seconds of work on two cores (1024 x 1024 took 4 s)."""
    h = w = 1536
    pixels = np.zeros((5, h, w), np.float32)
    pixels[0:4] = 1.0
    pixels[4] = np.linspace(0.5, 50.0, h, dtype=np.float32)[:, None]
    return gdof.Image.from_array(pixels, ["R", "G", "B", "A", "Z"])


def interrupted_after(send, delay=0.3):
    img = long_input()
    sent = []

    def fire():
        sent.append(time.monotonic())
        send()

    timer = threading.Timer(delay, fire)
    timer.start()
    start = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            gdof.defocus(img, solver="explicit", pyramid=False, layers=8, focal_length_mm=50, f_number=0.7,
                             focus_distance=1.0)
    finally:
        timer.cancel()
    end = time.monotonic()
    assert sent, "the call returned before the interrupt was sent"
    return end - sent[0], end - start


def test_interrupt_main_stops_a_long_defocus():
    latency, total = interrupted_after(_thread.interrupt_main)
    assert latency < 1.0, f"KeyboardInterrupt {latency:.2f} s after the interrupt"


def test_sigint_stops_a_long_defocus():
    main = threading.main_thread().ident
    latency, total = interrupted_after(lambda: signal.pthread_kill(main, signal.SIGINT))
    assert latency < 1.0, f"KeyboardInterrupt {latency:.2f} s after SIGINT"
    # The module still works afterwards.
    small = gdof.Image.from_array(np.ones((4, 8, 8), np.float32), ["R", "G", "B", "A"])
    assert small.pixels.sum() == 4 * 64
