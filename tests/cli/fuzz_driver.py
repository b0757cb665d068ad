"""Run many ``natura`` invocations in one interpreter (the fuzz suite's batch driver).

    python -m tests.cli.fuzz_driver CASES.json RESULTS.jsonl

CASES.json: ``{"fixtures": DIR, "cases": [{"argv": [...], "cwd": DIR}, ...], "start": N}``.
Each case calls :func:`app.cli.main` with a fresh argv in its own working folder, with stdout
and stderr captured, a timer for hangs and a bound on memory; one JSON line per case goes to
RESULTS.jsonl (flushed before the next case starts, so a case that kills the interpreter is
known: the test starts a new driver after it).
"""

from __future__ import annotations

import io
import json
import os
import resource
import signal
import sys
import time
from pathlib import Path

from tests.cli.fuzz_cases import CASE_TIMEOUT, judge, snapshot

MEMORY_LIMIT = 4 << 30  # bytes of address space: /dev/zero read whole fails fast, not the host


class Hang(BaseException):
    """Raised by the timer: not an Exception, so no ``except Exception`` swallows it."""


class _Buffer(io.StringIO):
    def close(self) -> None:  # the CLI closes stderr on a broken pipe: keep what it wrote
        pass


def _alarm(signum, frame):
    raise Hang()


def run_case(argv: list[str], cwd: Path) -> tuple[int | None, str, str, float]:
    from app.cli import main

    out, err = _Buffer(), _Buffer()
    saved = sys.stdout, sys.stderr, os.getcwd()
    os.chdir(cwd)
    sys.stdout, sys.stderr = out, err
    rc: int | None
    t0 = time.monotonic()
    signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, CASE_TIMEOUT)
    try:
        try:
            rc = main(list(argv))
        except SystemExit as exc:  # argparse's --help/--version, or a handler's exit
            rc = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except Hang:
            rc = None
        except BaseException as exc:  # noqa: BLE001 — anything main let through is a crash
            import traceback

            err.write("Traceback (escaped main)\n" + "".join(
                traceback.format_exception_only(type(exc), exc)))
            rc = 70
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        sys.stdout, sys.stderr = saved[0], saved[1]
        os.chdir(saved[2])
    return rc, out.getvalue(), err.getvalue(), time.monotonic() - t0


def main() -> int:
    spec = json.loads(Path(sys.argv[1]).read_text())
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    fixtures = Path(spec["fixtures"])
    # the fixtures after one case are the fixtures before the next (nothing else runs between
    # them): one snapshot of them per case, and a change that lands between two cases is still
    # seen, by the next one
    fx_now = None
    with open(sys.argv[2], "a", encoding="utf-8") as results:
        for i, case in enumerate(spec["cases"]):
            if i < spec.get("start", 0):
                continue
            cwd = Path(case["cwd"])
            if fx_now is None:
                fx_now = {f"fx/{k}": v for k, v in snapshot(fixtures).items()}
            before = {**fx_now, **snapshot(cwd)}
            results.write(json.dumps({"i": i, "started": True}) + "\n")
            results.flush()
            rc, out, err, seconds = run_case(case["argv"], cwd)
            fx_now = {f"fx/{k}": v for k, v in snapshot(fixtures).items()}
            after = {**fx_now, **snapshot(cwd)}
            problems = judge(rc, out, err, before, after)
            results.write(json.dumps({"i": i, "rc": rc, "problems": problems,
                                      "stderr": err[:400], "stdout": out[:200],
                                      "seconds": round(seconds, 3)}) + "\n")
            results.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
