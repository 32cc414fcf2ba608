"""Where the replicas' time goes under load: py-spy samples each replica from outside while
the load runs (``py-spy record``, 10 samples a second, without pausing it), and each
sample of a busy thread is put to what it was doing: the call whose route function is on
its stack, an event stream, or the HTTP work around them (uvicorn, Starlette, FastAPI).
"""

from __future__ import annotations

import re
import signal
import subprocess
import sys
from collections import Counter
from pathlib import Path

# Samples a second. py-spy's own CPU grows with it and shares the replicas' cores ("anything
# else" in the report): 0.63 of this machine's 2 cores at 100 a second, 0.07 at 10, which
# still gives thousands of samples a run, enough for each share to about a per cent.
RATE = 10
STREAMS = "event streams (reading and sending events, presence)"
AROUND = "HTTP around the calls (uvicorn, middleware, routing, JSON)"
BACKGROUND = "background (sweeper, online keeper, listener)"
OTHER = "other"
# Frames where a thread waits without using the CPU, which py-spy, sampling without pausing
# the process, still reports as busy at times (in a 100-search run, 41 % of its "busy"
# samples ended in one): the event loop's poll for sockets (``Runner.run`` is the deepest
# Python frame), psycopg waiting for PostgreSQL's answer, and an idle worker thread.
# One line of ``py-spy record --format raw``: a collapsed stack, a space, its count.
SAMPLE = re.compile(r"(.+) (\d+)")
WAITS = ("Runner.run (", "Connection.wait (", "Condition.wait (")


class Sampler:
    """``py-spy record`` on each of ``pids`` from :meth:`start` to :meth:`stop`."""

    def __init__(self, pids: list[int], folder: Path, rate: int = RATE) -> None:
        self.rate = rate  # samples a second; 0: not sampled
        self.outputs = [folder / f"py-spy-{pid}.txt" for pid in pids]
        self.pids = pids
        self.running: list[subprocess.Popen[bytes]] = []
        self.problem: str | None = None
        self.shares: Counter[str] = Counter()  # busy samples by what they were doing, waits out
        self.stacks: Counter[str] = Counter()  # busy samples by stack (collapsed, all replicas)
        self.unreadable = 0  # lines of the recordings that were no sample

    def start(self) -> None:
        if not self.rate:
            self.problem = "sampling turned off (a rate of 0)"
            return
        spy = Path(sys.executable).with_name("py-spy")
        for pid, output in zip(self.pids, self.outputs, strict=True):
            command = [str(spy), "record", "--pid", str(pid), "--rate", str(self.rate)]
            command += ["--format", "raw", "--output", str(output), "--nonblocking"]
            self.running.append(
                subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            )

    def stop(self) -> None:
        """Ends the recordings (py-spy writes its samples on SIGINT) and reads them."""
        if not self.running:
            return
        for process in self.running:
            if process.poll() is None:
                process.send_signal(signal.SIGINT)
        for process, output in zip(self.running, self.outputs, strict=True):
            _, error = process.communicate(timeout=60)
            if not output.exists():  # no permission to read the process, say
                said = error.decode(errors="replace").strip().splitlines()
                self.problem = said[-1] if said else f"py-spy exited with {process.returncode}"
        self.read()

    def read(self) -> None:
        """The recordings written: each stack kept, each busy one put to what it did."""
        for output in self.outputs:
            if not output.exists():
                continue
            for line in output.read_text().splitlines():
                sample = SAMPLE.fullmatch(line)
                if sample is None:  # a line cut short as py-spy stopped: no sample in it
                    self.unreadable += 1
                    continue
                stack, count = sample.group(1), int(sample.group(2))
                frames = stack.split(";")
                if not waiting(frames):
                    self.shares[what(frames)] += count
                self.stacks[stack] += count

    def write_stacks(self, path: Path) -> None:
        """Every busy sample's stack, collapsed (``frame;frame;... count``, all replicas
        together): what flame graph tools read."""
        lines = [f"{stack} {count}" for stack, count in self.stacks.most_common()]
        path.write_text("\n".join(lines) + "\n")


def waiting(frames: list[str]) -> bool:
    """Whether a sampled stack is a thread waiting (its deepest frame one of ``WAITS``)."""
    return bool(frames) and frames[-1].strip().startswith(WAITS)


def what(frames: list[str]) -> str:
    """What a sampled stack was doing: ``routes/<module>.py``'s function on it, or else."""
    for frame in frames:
        if "backend/api/routes/" in frame:
            function = frame.strip().split(" (")[0]
            module = frame.split("backend/api/routes/")[1].split(".py")[0]
            return f"`{module}.{function}`" if module != "events" else STREAMS
    text = ";".join(frames)
    if "backend/eventstream/" in text:
        return STREAMS
    if "backend/background.py" in text or "eventstream/listener.py" in text:
        return BACKGROUND
    if any(name in text for name in ("uvicorn/", "starlette/", "fastapi/", "backend/middleware")):
        return AROUND
    return OTHER
