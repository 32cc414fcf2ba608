"""How the load benchmark puts py-spy's samples to what the replicas did (benchmarks/spy.py):
a thread caught waiting is no CPU, so it is no share of it."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[2] / "benchmarks"))

import spy

ROUTE = "put_taps (backend/api/routes/taps.py:31)"
LOOP = "Runner.run (asyncio/runners.py:118)"
SOLVE = "solve (shared_solver/solve.py:144)"
PSYCOPG_WAIT = "Connection.wait (psycopg/connection.py:495)"


def test_a_route_on_the_stack_names_the_sample() -> None:
    assert spy.what([LOOP, ROUTE, SOLVE]) == "`taps.put_taps`"
    assert not spy.waiting([LOOP, ROUTE, SOLVE])


def test_a_thread_waiting_at_its_deepest_frame_is_no_cpu_and_a_cut_line_no_sample(
    tmp_path: Path,
) -> None:
    assert spy.waiting([LOOP])
    assert spy.waiting([ROUTE, PSYCOPG_WAIT])
    assert not spy.waiting([PSYCOPG_WAIT, "BaseCursor._send_query_prepared (psycopg/x.py:1)"])

    sampler = spy.Sampler([1], tmp_path)
    cut_short = f"{LOOP};{ROUTE};<lambda> ("  # py-spy stopped while writing it
    lines = [f"{LOOP} 7", f"{ROUTE};{PSYCOPG_WAIT} 5", f"{LOOP};{ROUTE};{SOLVE} 3", cut_short]
    sampler.outputs[0].write_text("\n".join(lines) + "\n")
    sampler.read()
    assert dict(sampler.shares) == {"`taps.put_taps`": 3}
    assert sum(sampler.stacks.values()) == 15  # every stack kept for the flame graph
    assert sampler.unreadable == 1


def test_a_rate_of_zero_samples_nothing_and_says_so(tmp_path: Path) -> None:
    sampler = spy.Sampler([1], tmp_path, rate=0)
    sampler.start()
    sampler.stop()
    assert not sampler.running
    assert not sampler.shares
    assert "turned off" in str(sampler.problem)
