"""The interpreter lock is released while Rust works, and Ctrl-C raises KeyboardInterrupt within a fraction of
a second."""

from __future__ import annotations

import _thread
import os
import signal
import threading
import time

import pytest

import granular
from conftest import EDMD_2D

LONG = EDMD_2D.replace("count = 300", "count = 3000").replace("radius = 0.005", "radius = 0.002").replace(
    "radius = 0.01", "radius = 0.004"
)


def _calibrated_step(sim: granular.Simulation, seconds: float) -> float:
    """A time to advance to that takes about ``seconds`` of wall time (the machine may be busy)."""
    start = time.perf_counter()
    sim.advance(sim.time + 0.02)
    rate = 0.02 / max(time.perf_counter() - start, 1e-6)
    return sim.time + seconds * rate


def test_other_threads_run_during_advance() -> None:
    sim = granular.Simulation(granular.Scenario.from_toml(LONG))
    until = _calibrated_step(sim, 0.5)
    counter = [0]
    done = threading.Event()

    def count() -> None:
        while not done.is_set():
            counter[0] += 1

    worker = threading.Thread(target=count)
    worker.start()
    try:
        start = time.perf_counter()
        sim.advance(until)
        elapsed = time.perf_counter() - start
        during = counter[0]
    finally:
        done.set()
        worker.join()
    assert elapsed > 0.1, "the step is too short to show anything"
    # A Python thread that held no lock would count millions per second; with the lock held by
    # a Rust loop it would get a few switch intervals at most.
    assert during > 100_000 * elapsed, (during, elapsed)


def test_advance_in_a_thread_while_python_works() -> None:
    sim = granular.Simulation(granular.Scenario.from_toml(LONG))
    until = _calibrated_step(sim, 0.3)
    t = threading.Thread(target=sim.advance, args=(until,))
    t.start()
    spins = 0
    while t.is_alive():
        spins += 1
    t.join()
    assert sim.time == until
    assert spins > 10_000


def _interrupt_during(call, delay: float, how: str) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """Calls ``call()`` and interrupts it after ``delay`` seconds; returns (when it raised, when interrupted)."""
    fired = [0.0]

    def fire() -> None:
        fired[0] = time.perf_counter()
        if how == "signal":
            os.kill(os.getpid(), signal.SIGINT)
        else:
            _thread.interrupt_main()

    # A process started in the background by a shell without job control inherits SIGINT
    # ignored, and then Python installs no handler: neither the signal nor interrupt_main()
    # would reach it and the call would never end. Install Python's own handler for the test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(delay, fire)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
        raised = time.perf_counter()
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    return raised, fired[0]


@pytest.mark.parametrize("how", ["signal", "interrupt_main"])
def test_ctrl_c_interrupts_advance(how: str) -> None:
    sim = granular.Simulation(granular.Scenario.from_toml(LONG))
    raised, fired = _interrupt_during(lambda: sim.advance(1e9), 0.3, how)
    assert raised - fired < 0.25, f"KeyboardInterrupt came {raised - fired:.3f} s after the interrupt"
    # The simulation is consistent and goes on.
    t = sim.time
    assert 0.0 < t < 1e9
    sim.advance(t + 0.01)
    assert sim.time == t + 0.01


def test_ctrl_c_interrupts_run(tmp_path) -> None:  # type: ignore[no-untyped-def]
    sc = granular.Scenario.from_toml(LONG)
    # Far beyond the interruption, within the pre-flight limits on collisions and outputs.
    sc.update({"stop.collisions_per_particle": 1e5, "stop.wall_seconds": 100.0})
    sim = granular.Simulation(sc)
    raised, fired = _interrupt_during(sim.run, 0.3, "signal")
    assert raised - fired < 0.25
    sim2 = granular.Simulation(sc)
    raised, fired = _interrupt_during(lambda: sim2.run(out=tmp_path / "run"), 0.5, "signal")
    assert raised - fired < 0.5
    assert (tmp_path / "run" / "timeseries.csv").exists()
