"""The stepper table of simulate_system: event-buffer growth and the "event buffer full" status.

The reference of every test is the same run with the default (never full) event buffer: a run
whose buffer grows must reproduce it exactly, and a run stopped by a full buffer must be a prefix
of it.
"""

from importlib import resources

import numpy as np
import pytest

import rubrotor.engine.shaft_steppers as steppers
import rubrotor.engine.simulate as simulation
from rubrotor.core.integrate import EVENT_BUFFER_FULL, STATUS
from rubrotor.engine.settings import Integrator
from rubrotor.scenario import load_scenario

CASE2 = load_scenario(resources.files("rubrotor") / "scenarios" / "seed_case2.toml")
METHODS = {
    "exponential": Integrator(revolutions=15, dtau=1e-3, save_every=8),
    "adaptive": Integrator(revolutions=15),
    "abm": Integrator(revolutions=3, method="abm", dtau=1e-3, save_every=8),
}


def _run(integ):
    s = CASE2
    return simulation.simulate_system(
        s.shaft, s.speed, integ, s.unbalance, s.contact, s.load, s.damping, progress=False
    )


@pytest.fixture(scope="module")
def references():
    return {name: _run(integ) for name, integ in METHODS.items()}


@pytest.mark.parametrize("name", list(METHODS))
def test_growing_event_buffer_changes_nothing(name, references, monkeypatch):
    """A 2-slot buffer that doubles between chunks gives the default run bit for bit."""
    monkeypatch.setattr(simulation, "EVENT_BUFFER", 2)
    monkeypatch.setattr(steppers, "SHAFT_EVENT_RESERVE", 1)
    ref = references[name]
    r = _run(METHODS[name])
    assert ref.events.size > 2  # the buffer had to grow
    assert r.status == ref.status == "complete"
    np.testing.assert_array_equal(r.events, ref.events)
    np.testing.assert_array_equal(r.channels, ref.channels)
    assert r.stats["contact_events"] == ref.stats["contact_events"] == ref.events.size


@pytest.mark.parametrize("name", list(METHODS))
def test_full_event_buffer_stops_the_run_and_says_so(name, references, monkeypatch):
    """With the buffer capped at 2 events the run stops, says why, and keeps a prefix."""
    monkeypatch.setattr(simulation, "EVENT_BUFFER", 2)
    monkeypatch.setattr(simulation, "EVENT_BUFFER_MAX", 2)
    monkeypatch.setattr(steppers, "SHAFT_EVENT_RESERVE", 1)
    ref = references[name]
    r = _run(METHODS[name])
    assert r.status == "partial" and r.final_state is None
    assert r.message.startswith(STATUS[EVENT_BUFFER_FULL]) and "kept" in r.message
    n = r.channels.shape[1]
    assert 1 < n < ref.channels.shape[1]
    np.testing.assert_array_equal(r.channels, ref.channels[:, :n])
    np.testing.assert_array_equal(r.events, ref.events[: r.events.size])
    assert r.events.size == 2 and r.stats["contact_events"] >= 2


@pytest.mark.parametrize("name", list(METHODS))
def test_chunking_changes_nothing(name, references):
    """Calling the kernel 7 samples at a time reproduces the one-call run, events included
    (the state carried between calls holds everything a step reads)."""
    s = CASE2
    r = simulation.simulate_system(
        s.shaft, s.speed, METHODS[name], s.unbalance, s.contact, s.load, s.damping,
        progress=False, chunk_samples=7,
    )  # fmt: skip
    ref = references[name]
    np.testing.assert_array_equal(r.channels, ref.channels)
    np.testing.assert_array_equal(r.events, ref.events)
    assert r.stats["contact_events"] == ref.stats["contact_events"]
