"""A warm start for the ``natura`` commands the tests run (``tests.helpers.cli.run``).

Each ``natura`` process spends ~0.11 s of CPU importing numpy, moderngl, PIL and Natura before
it parses its arguments, and ~0.35 s more where it draws a chart (matplotlib); the suite starts
a few hundred of them. A server per test process imports those modules once and forks a child
for each command. The child is a process of its own (its pid, GL context, memory and exit
status), given what the console script's process would have: the arguments, the folder, the
umask, the environment and the three standard streams (files here, pipes there: both are
block-buffered and not a terminal). It then runs ``app.cli.main`` as the console script does
and leaves through the interpreter's normal exit (atexit handlers, flushing).

A forked child keeps whatever its modules read when they were imported. So ``run`` forks only
where the command's environment is the server's own; a test that changes the environment
(``env=`` or monkeypatch) gets a real process. The README's examples, the console-script fuzz
cases and the tests of limits, signals and the umask start real processes themselves.
``NATURA_TEST_FORK=0`` makes every ``run`` start a real process.
"""

from __future__ import annotations

import atexit
import contextlib
import gc
import importlib
import io
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
from typing import NoReturn

#: imported once by the server: what most commands import before they parse their arguments,
#: and the chart library of the benches (with the backend the benches choose)
PRELOAD = ("numpy", "PIL.Image", "PIL.PngImagePlugin", "moderngl", "app.cli", "app.runtime",
           "app.imageio", "app.scenes", "app.bench", "app.teach.exercise", "matplotlib.pyplot")
#: the switch that turns the server off (any value but "0" leaves it on)
SWITCH = "NATURA_TEST_FORK"
#: the largest request: the arguments, the folder and the environment as JSON
_MAX_MESSAGE = 1 << 20


def _serve(sock: socket.socket) -> bool:
    """Answer requests until the tests' process closes its end (False); return True in each
    child, set up to run its command."""
    while True:
        msg, fds, _flags, _addr = socket.recv_fds(sock, _MAX_MESSAGE, 3)
        if not msg:
            return False
        req = json.loads(msg)
        pid = os.fork()
        if pid == 0:
            sock.close()
            for target, fd in enumerate(fds):
                os.dup2(fd, target)
                os.close(fd)
            os.chdir(req["cwd"])
            os.umask(req["umask"])
            os.environ.clear()
            os.environ.update(req["env"])
            sys.argv = list(req["argv"])
            sys.path[0] = os.path.dirname(sys.argv[0])  # as for the console script
            return True
        for fd in fds:
            os.close(fd)
        sock.send(json.dumps({"pid": pid}).encode())
        _, status = os.waitpid(pid, 0)
        sock.send(json.dumps({"returncode": os.waitstatus_to_exitcode(status)}).encode())


def _server_main() -> int:
    sock = socket.socket(fileno=int(sys.argv[1]))
    import matplotlib

    matplotlib.use("Agg")  # what the benches choose before they draw
    for name in PRELOAD:
        importlib.import_module(name)
    if threading.active_count() != 1:  # a fork copies only the thread that calls it
        raise SystemExit(f"forkserver: {threading.active_count()} threads after the imports")
    sys.stdout.flush()
    sys.stderr.flush()
    # the collector of a child would otherwise walk (and so copy) every page the imports made
    gc.freeze()
    if not _serve(sock):
        return 0
    _leave(_command())


def _command() -> int:
    """The console script's ``raise SystemExit(main())``: its exit status, an uncaught
    exception's traceback on stderr and status 1, as the interpreter gives them."""
    from app.cli import main

    try:
        return main()
    except SystemExit as e:
        if e.code is None or isinstance(e.code, int):
            return e.code or 0
        print(e.code, file=sys.stderr)
        return 1
    except BaseException:
        sys.excepthook(*sys.exc_info())
        return 1


def _leave(code: int) -> NoReturn:
    """The interpreter's exit as a program sees it (the other threads joined, the atexit
    handlers, the standard streams flushed: status 120 where stdout cannot take the rest),
    without tearing down the modules the child shares with the server."""
    for t in threading.enumerate():
        if t is not threading.main_thread() and not t.daemon:
            t.join()
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            code = 120
    os._exit(code & 0xFF)


class Server:
    """One server process, started with the environment ``env``; ``run`` forks a command."""

    def __init__(self, env: dict[str, str], cwd: str):
        self.env = env
        self._sock, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        self._proc = subprocess.Popen(
            [sys.executable, "-m", "tests.helpers.forkserver", str(theirs.fileno())], env=env,
            cwd=cwd, pass_fds=[theirs.fileno()], stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL)  # its children get their own; it prints nothing
        theirs.close()

    def close(self) -> None:
        self._sock.close()
        self._proc.wait(timeout=30)

    def run(self, argv: list[str], cwd: str, env: dict[str, str], timeout: float
            ) -> subprocess.CompletedProcess:
        """``argv`` (the console script first) in ``cwd`` with ``env``, as ``subprocess.run``
        with ``capture_output=True, text=True`` would give it."""
        umask = os.umask(0)
        os.umask(umask)
        req = json.dumps({"argv": argv, "cwd": str(cwd), "umask": umask, "env": env})
        with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
            socket.send_fds(self._sock, [req.encode()], [0, out.fileno(), err.fileno()])
            pid = self._reply()["pid"]
            self._sock.settimeout(timeout)
            try:
                reply = self._reply()
            except TimeoutError:
                with contextlib.suppress(ProcessLookupError):  # it ended meanwhile
                    os.kill(pid, signal.SIGKILL)
                self._sock.settimeout(None)
                self._reply()
                raise subprocess.TimeoutExpired(argv, timeout, _text(out), _text(err)) from None
            finally:
                self._sock.settimeout(None)
            return subprocess.CompletedProcess(argv, reply["returncode"], _text(out), _text(err))

    def _reply(self) -> dict:
        msg = self._sock.recv(_MAX_MESSAGE)
        if not msg:
            raise RuntimeError("forkserver: the server has exited (its stderr is above)")
        return json.loads(msg)


def _text(f) -> str:
    """A captured stream as ``subprocess.run(text=True)`` decodes it: the locale's encoding,
    universal newlines."""
    f.seek(0)
    return io.TextIOWrapper(io.BytesIO(f.read())).read()


_server: Server | None = None
#: set by pytest for each test, and read by nothing when a module is imported
_PER_TEST = ("PYTEST_CURRENT_TEST",)


def _import_view(env: dict[str, str]) -> dict[str, str]:
    """The environment as the modules saw it when the server imported them."""
    return {k: v for k, v in env.items() if k not in _PER_TEST}


def run(argv: list[str], cwd, env: dict[str, str], timeout: float
        ) -> subprocess.CompletedProcess | None:
    """``argv`` through this process's server, or None where it must be a real process (the
    switch is off, or ``env`` is not the server's)."""
    global _server
    if os.environ.get(SWITCH) == "0":
        return None
    if not os.path.isdir(cwd):
        return None  # subprocess.run's own error
    if _server is None:
        from app import PROJECT_ROOT

        _server = Server(env, str(PROJECT_ROOT))
        atexit.register(_server.close)
    if _import_view(env) != _import_view(_server.env):
        return None
    return _server.run(argv, str(cwd), env, timeout)


if __name__ == "__main__":
    raise SystemExit(_server_main())
