"""Bad ``natura`` invocations for the fuzz suite (tests/cli/test_fuzz_cli.py), and the checks
each answer must pass.

:func:`make_fixtures` lays out the odd inputs (a folder, a named pipe, Latin-1 and binary files,
an unreadable file, deep nesting, huge integers, dangling links...) in a folder of their own;
:func:`generate` draws, from a seed, invocations that are each bad in one way, over every
subcommand; :func:`judge` says what is wrong with one answer (empty list: it is right).

A bad invocation must: exit 2, print nothing on stdout and exactly one stderr line of at most
200 characters that starts with ``natura: `` (once) and says what is ``allowed``, write no
file, modify no file, and finish in time.
"""

from __future__ import annotations

import os
import random
import stat
from pathlib import Path

LIMIT = 200
#: a case that takes longer than this (seconds) is a hang
CASE_TIMEOUT = 20.0
DEFAULT_SEED = 20240611

SMALL = ["--size", "16x16"]
BIG = "7" * 100_000  # a 100 kB argument


def seed_from_env() -> int:
    text = os.environ.get("NATURA_FUZZ_SEED", "")
    return int(text) if text.strip() else DEFAULT_SEED


def is_root() -> bool:
    return hasattr(os, "geteuid") and os.geteuid() == 0


# ---- fixtures ------------------------------------------------------------------------------

def make_fixtures(root: Path) -> dict[str, str]:
    """Odd files in ``root``; returns name → absolute path."""
    root.mkdir(parents=True, exist_ok=True)
    fx: dict[str, str] = {}

    def put(name: str, data: bytes) -> None:
        (root / name).write_bytes(data)
        fx[name] = str(root / name)

    (root / "folder.toml").mkdir()
    fx["folder"] = str(root / "folder.toml")
    (root / "empty-dir").mkdir()
    fx["empty_dir"] = str(root / "empty-dir")
    os.mkfifo(root / "pipe.toml")
    fx["fifo"] = str(root / "pipe.toml")
    put("latin1.toml", "[sky]\nsun_size = 0.1 # café\n".encode("latin-1"))
    put("binary.toml", bytes(range(256)) * 8)
    put("deep.toml", b"a = " + b"[" * 5000 + b"]" * 5000 + b"\n")
    put("deep_table.toml", b"[sky]\nsun_size = " + b"[" * 3000 + b"1" + b"]" * 3000 + b"\n")
    put("huge_int.toml", b"[sky]\nsun_size = " + b"9" * 400 + b"\n")
    put("huge_int2.toml", b"[sky]\nsun_size = 999999999999999999999999999999999999\n")
    put("nan.toml", b"[sky]\nsun_size = nan\n")
    put("inf.toml", b"[sky]\nsun_size = -inf\n")
    put("not_table.toml", b"sun_size = 0.1\n")
    put("bad_key.toml", b"[sky]\nsun_sise = 0.1\n")
    put("bad_type.toml", b"[sky]\nsun_size = \"big\"\n")
    put("date.toml", b"[sky]\nsun_size = 1979-05-27\n")
    put("nested.toml", b"[sky.sun_size]\nx = 1\n")
    put("list.toml", b"[sky]\nsun_size = [1, 2, 3]\n")
    put("invalid.toml", b"[sky\nsun_size = = 1\n")
    put("long_line.toml", b"[sky]\nsun_size = \"" + b"x" * 200_000 + b"\"\n")
    put("big.toml", b"# " + b"x" * 2_000_000 + b"\n")
    put("nul.toml", b"[sky]\x00\nsun_size = 0.1\n")
    put("bom_bad.toml", b"\xff\xfe[\x00s\x00k\x00y\x00]\x00")
    put("plain.txt", b"just a file\n")
    unreadable = root / "unreadable.toml"
    unreadable.write_bytes(b"[sky]\nsun_size = 0.1\n")
    unreadable.chmod(0)
    # root reads anything: a file that fails to read even for root stands in for it
    fx["unreadable"] = "/proc/self/mem" if is_root() else str(unreadable)
    os.symlink(root / "no-such-target", root / "dangling")
    fx["dangling"] = str(root / "dangling")
    os.symlink(root / "loop-b", root / "loop-a")
    os.symlink(root / "loop-a", root / "loop-b")
    fx["loop"] = str(root / "loop-a")
    # a folder the user cannot create files in (as root: /proc, which refuses even root)
    locked = root / "locked"
    locked.mkdir()
    (locked / "keep.txt").write_bytes(b"keep")
    locked.chmod(0o500)
    fx["locked"] = "/proc" if is_root() else str(locked)
    fx["root"] = str(root)
    return fx


#: files every case's working folder starts with (the no-clobber cases aim at them)
TAKEN = {
    "taken.png": b"my picture",
    "taken.exr": b"my exr",
    "taken.json": b"{\"mine\": true}\n",
    "taken-0002.png": b"frame two, mine",
    "r.png": b"my chart",  # the chart beside r.json
    "natura-sky-0001.png": b"my earlier headless picture",
}


def make_workdir(folder: Path) -> None:
    folder.mkdir(parents=True)
    for name, data in TAKEN.items():
        (folder / name).write_bytes(data)
    (folder / "sub.png").mkdir()  # a folder with an image name
    (folder / "a-file").write_bytes(b"a file, not a folder")


# ---- the cases -----------------------------------------------------------------------------

def _bad_values(fx: dict[str, str]) -> dict[str, list[str]]:
    return {
        "--size": ["", " ", "0x0", "0x16", "16x0", "-1x16", "16", "x", "axb", "16x", "x16",
                   "16x16x16", "1e3x16", "99999x16", "16384x16385", "nanxnan", "16,16",
                   BIG, BIG + "x16", "16x" + BIG],
        "--time": ["", "nan", "inf", "-inf", "-1", "24.5", "1e400", "abc", BIG, "0x10"],
        "--camera": ["", " ", ",", ",,,", "1,2", "1,2,3,4,5,6,7", "nan,0,0", "0,inf,0",
                     "0,2,0,nan", "0,2,0,0,100", "0,2,0,0,-91", "0,2,0,0,0,0", "0,2,0,0,0,171",
                     "0,2,0,0,0,1e9", "a,b,c", "1e400,0,0", BIG, ",".join(["1"] * 50_000)],
        "--yaw": ["nan", "inf", "-inf", "1e400", "x", "", BIG],
        "--pitch": ["nan", "91", "-90.5", "inf", "x", "", BIG],
        "--fov": ["0", "0.5", "171", "nan", "-inf", "x", "", BIG],
        "--set": ["", "=", "=1", "sky.sun_size", "sky.sun_size=", "sky.sun_size=nan",
                  "sky.sun_size=inf", "sky.sun_size=1e999", "sky.sun_size=5", "sky.sun_size=x",
                  "sky.sun_sise=0.1", "nosuch.thing=1", "sun=0.1", "sky.sun_size=" + BIG,
                  BIG + "=1", "sky.sun_size=" + "9" * 5000, "time.hour=25",
                  "sky.sun_size=0x10", "sky.sun_size=1,2,3", "output.tonemap=nope"],
        "--preset": [fx[k] for k in (
            "folder", "fifo", "latin1.toml", "binary.toml", "deep.toml", "deep_table.toml",
            "huge_int.toml", "huge_int2.toml", "nan.toml", "inf.toml", "not_table.toml",
            "bad_key.toml", "bad_type.toml", "date.toml", "nested.toml", "list.toml",
            "invalid.toml", "long_line.toml", "big.toml", "nul.toml", "bom_bad.toml",
            "unreadable", "dangling", "loop")]
        + ["/dev/zero", "/dev/null", "missing.toml", "", "~nosuchuser/x.toml",
           "a-file/x.toml", "p" * 300 + ".toml", fx["plain.txt"] + "/x.toml", BIG],
        "--shaders": [fx["folder"].replace("folder.toml", "nope"), fx["plain.txt"], fx["fifo"],
                      "/dev/null", "/dev/zero", fx["dangling"], fx["loop"],
                      "~nosuchuser/glsl", "s" * 300, BIG, "a-file/glsl"],
        "--out": ["", ".", "..", "x", "x.jpg", "x.PNG.txt", "sub.png", "taken.png", "taken.exr",
                  "no/such/folder/x.png", "~nosuchuser/x.png", "a-file/x.png",
                  fx["locked"] + "/x.png", "/dev/null", "m" * 252 + ".png", "m" * 300 + ".png",
                  BIG + ".png", "/"],
        "--frames": ["0", "-1", "-1000000", "1000000000000", "100001", "1e3", "x", "", "1.5",
                     BIG],
        "--fps": ["0", "-1", "nan", "inf", "-inf", "1e-320", "1e400", "1001", "x", "", "0.0001",
                  BIG],
    }


def _bench_values(fx: dict[str, str]) -> dict[str, list[str]]:
    return {
        "--warmup": ["-5", "-1", "1001", "x", "", "1.5", "1e9", BIG],
        "--repeat": ["0", "-1", "10001", "x", "", "2.5", "99999999999999999999", BIG],
        "--budget": ["0", "-0", "0.0", "-1", "-1e-9", "nan", "-nan", "inf", "-inf", "1e400",
                     "100000.5", "1e6", "x", "", " ", "1ms", "16,7", BIG],
        "--sizes": ["", " ", ",", ",,", "0x0", "16x16,0x0", "axb", "16x16,x", "16", "-1x-1",
                    "99999x16", BIG, ",".join(["16x16"] * 20_000)],
        "--out": ["", "r.txt", "r.JSONX", "taken.json", "r.json", "sub.png", "no/such/r.json",
                  "~nosuchuser/r.json", fx["locked"] + "/r.json", "/dev/null",
                  "j" * 251 + ".json", "j" * 300 + ".json", BIG + ".json", "a-file/r.json"],
    }


def _fixed_cases(fx: dict[str, str]) -> list[list[str]]:
    """Invocations bad as a whole (not one bad value)."""
    return [
        ["bogus"], ["bogus", "sky"], ["Render", "sky"], [BIG], [""],
        ["render"], ["render", ""], ["render", "atlantis"], ["render", BIG],
        ["render", "sky", "extra", "--out", "o.png"], ["render", "../sky"], ["render", "sky\n"],
        ["render", "sky", "--bogus"], ["render", "sky", "--size"], ["render", "sky", "--out"],
        ["render", "sky", "--set"], ["render", "sky", "--frames"], ["render", "sky", "-x"],
        ["render", "sky", "--" + BIG], ["render", "sky", "--force=1"],
        ["window", "atlantis"], ["window", "sky", "extra"], ["window", "--bogus"],
        ["window", "sky", "--frames", "0"], ["window", "sky", "--frames", "-3"],
        ["window", "sky", "--frames", "1000000000000"], ["window", "sky", "--frames", "x"],
        ["--frames", "0"], ["--bogus"], ["--size", ""], ["--size", "0x0"], ["--camera", ""],
        ["--time", "99"], ["--preset", fx["fifo"]], ["--preset", "/dev/zero"],
        ["scenes", "extra"], ["scenes", "--bogus"], ["scenes", "sky"],
        ["params"], ["params", "atlantis"], ["params", "sky", "extra"], ["params", "sky", "x", "y"],
        ["params", "sky", "--bogus"], ["params", "sky", "--set", "sky.sun_size=1"],
        ["params", "sky", "--shaders"], ["params", ""], ["params", BIG],
        ["shaders"], ["shaders", "bogus"], ["shaders", "check", "extra"],
        ["shaders", "check", "--bogus"], ["shaders", "copy"], ["shaders", "copy", "a", "b"],
        ["shaders", "copy", ""], ["shaders", "copy", "."], ["shaders", "copy", "a-file"],
        ["shaders", "copy", "sub.png"], ["shaders", "copy", fx["dangling"]],
        ["shaders", "copy", fx["loop"]], ["shaders", "copy", fx["locked"] + "/copy"],
        ["shaders", "copy", "no/such/parent/copy"], ["shaders", "copy", "~nosuchuser/copy"],
        ["shaders", "copy", "d" * 300], ["shaders", "copy", BIG], ["shaders", "copy", "/dev/null"],
        ["shaders", "copy", "a-file/copy"], ["shaders", "copy", "/"],
        ["bench"], ["bench", "atlantis"], ["bench", "sky", "extra"], ["bench", "sky", "--bogus"],
        ["bench", "materials", *SMALL, "--out", "r.json"],  # its chart r.png exists
        ["bench", "materials", *SMALL, "--out", "taken.json"],
        ["bench", "sky", "--repeat", "0", "--warmup", "-5"],
        ["--version", "extra"],
        ["doctor", "extra"], ["doctor", "--bogus"], ["doctor", "sky"],
        ["compare"], ["compare", "atlantis"], ["compare", "sky"],
        ["compare", "sky", "--a", "nosuch=1"], ["compare", "sky", "--b", "sky.sun_size=5"],
        ["compare", "sky", "--a", "sky.sun_size=0.1", "--rounds", "0"],
        ["compare", "sky", "--a", "sky.sun_size=0.1", "--wipe", "2"],
        ["report"], ["report", "atlantis"], ["report", "planet", "--methods", "nosuch"],
        ["report", "sky", "--methods", "lut"], ["report", "planet", "--out", "a-file"],
        ["explain"], ["explain", "nosuch"], ["explain", "spec/003", "eq.", "999"],
        ["explain", "spec/003", "§2.9", "--bogus"], ["explain", "spec/9999", "§1"],
        ["exercise"], ["exercise", "nosuch"], ["exercise", "start", "nosuch", "new-dir"],
        ["exercise", "start", "schlick-fresnel"], ["exercise", "check", "a-file"],
        ["render", "sky", *SMALL, "--error-budget", "0.1"],
        ["render", "planet", *SMALL, "--quality", "auto"],
        ["render", "planet", *SMALL, "--quality", "auto", "--error-budget", "-1"],
        ["render", "planet", *SMALL, "--quality", "auto", "--ms-budget", "nan"],
        ["render", "planet", *SMALL, "--quality", "best"],
    ]


def _base(command: str) -> list[str]:
    """An invocation that is fine as it is (one bad value is then put into it)."""
    return {
        "render": ["render", "sky", *SMALL, "--out", "o.png"],
        "window": ["window", "sky", *SMALL],
        "natura": [*SMALL],
        "bench": ["bench", "sky", *SMALL, "--repeat", "1", "--warmup", "0", "--no-sweep",
                  "--out", "b.json"],
        "params": ["params", "sky"],
        "check": ["shaders", "check"],
    }[command]


def generate(seed: int, fx: dict[str, str], n_random: int = 260) -> list[list[str]]:
    """Bad invocations: the fixed ones, every bad value once in a random subcommand that takes
    it, then ``n_random`` random draws (one or two bad values each)."""
    rng = random.Random(seed)
    values = _bad_values(fx)
    bench = _bench_values(fx)
    takes = {  # the options each command accepts
        "render": ["--size", "--time", "--camera", "--yaw", "--pitch", "--fov", "--set",
                   "--preset", "--shaders", "--out", "--frames", "--fps"],
        "window": ["--size", "--time", "--camera", "--yaw", "--pitch", "--fov", "--set",
                   "--preset", "--shaders", "--frames"],
        "natura": ["--size", "--time", "--camera", "--yaw", "--pitch", "--fov", "--set",
                   "--preset", "--shaders"],
        "bench": ["--size", "--time", "--camera", "--set", "--preset", "--shaders", "--warmup",
                  "--repeat", "--sizes", "--out", "--budget"],
        "params": ["--shaders"],
        "check": ["--shaders"],
    }

    def pool(command: str, option: str) -> list[str]:
        if command == "bench" and option in bench:
            return bench[option]
        return values[option]

    def put(argv: list[str], option: str, value: str) -> list[str]:
        out = list(argv)
        if option in out:  # replace the good value
            out[out.index(option) + 1] = value
        else:
            out += [option, value]
        return out

    cases = [list(c) for c in _fixed_cases(fx)]
    for option in sorted(set(values) | set(bench)):
        for value in sorted(set(values.get(option, [])) | set(bench.get(option, []))):
            commands = [c for c in takes if option in takes[c]
                        and value in pool(c, option)]
            command = rng.choice(commands)
            cases.append(put(_base(command), option, value))
    for _ in range(n_random):
        command = rng.choice(sorted(takes))
        argv = _base(command)
        for option in rng.sample(takes[command], k=min(len(takes[command]), rng.choice((1, 2)))):
            argv = put(argv, option, rng.choice(pool(command, option)))
        if rng.random() < 0.2 and command in ("render", "bench") and not any(
                a.startswith("/dev/") for a in argv):  # no --force at a device, ever
            argv.append("--force")  # force never makes a bad value good
        cases.append(argv)
    # '--force' with only a taken name would be a good invocation: drop those
    return [c for c in cases if not _good(c)]


def _good(argv: list[str]) -> bool:
    """Draws that are not bad invocations: a base invocation whose only change is ``--force``
    with a taken name (overwriting is what --force is for), or ``--out r.json`` on the base
    bench (it runs with --no-sweep: no chart is written, so the r.png beside it is safe)."""
    rest = [a for a in argv if a != "--force"]
    for command in ("render", "bench"):
        base = _base(command)
        if len(rest) != len(base) or "--out" not in rest:
            continue
        i = rest.index("--out")
        same = rest[:i + 1] == base[:i + 1] and rest[i + 2:] == base[i + 2:]
        if same and rest[i + 1] in ("taken.png", "taken.exr", "taken.json") and "--force" in argv:
            return True
        if same and command == "bench" and rest[i + 1] == "r.json":
            return True
    return False


# ---- judging -------------------------------------------------------------------------------

def snapshot(folder: Path) -> dict[str, bytes | str]:
    """Relative path → content (regular files: the bytes themselves, compared whole — a
    fixture folder of ~2.3 MB reads and compares in a fifth of the time SHA-256 takes to hash
    it, and no two contents can collide) or kind, for every entry under ``folder`` (links not
    followed)."""
    out: dict[str, bytes | str] = {}

    def walk(where: str, prefix: str) -> None:
        with os.scandir(where) as entries:
            for entry in entries:
                rel = prefix + entry.name
                st = entry.stat(follow_symlinks=False)
                if stat.S_ISREG(st.st_mode):
                    try:
                        with open(entry.path, "rb") as f:
                            out[rel] = f.read()
                    except PermissionError:
                        out[rel] = f"unreadable {st.st_size} {st.st_mtime_ns}"
                else:
                    out[rel] = f"kind {stat.S_IFMT(st.st_mode)}"
                    if stat.S_ISDIR(st.st_mode):
                        try:
                            walk(entry.path, rel + os.sep)
                        except PermissionError:  # as os.walk: an unlistable folder's entries
                            pass                 # are not seen

    walk(os.fspath(folder), "")
    return out


def judge(rc: int | None, stdout: str, stderr: str, before: dict[str, bytes | str],
          after: dict[str, bytes | str]) -> list[str]:
    """The problems of one answer, by category: hang, crash, exit0, exit, stdout, lines, long,
    prefix, allowed, clobbered, temp_left, written."""
    problems = []
    if rc is None:
        return ["hang"]
    if "Traceback" in stderr or rc == 70 or rc < 0:
        problems.append("crash")
    elif rc == 0:
        problems.append("exit0")
    elif rc != 2:
        problems.append(f"exit{rc}")
    if stdout.strip():
        problems.append("stdout")
    lines = [line for line in stderr.splitlines() if line.strip()]
    if len(lines) != 1 or len(stderr.strip().splitlines()) != 1:
        problems.append("lines")
    if lines:
        line = lines[0]
        if len(line) > LIMIT:
            problems.append("long")
        if not line.startswith("natura: ") or line.startswith("natura: natura"):
            problems.append("prefix")
        if "allowed" not in line:
            problems.append("allowed")
    for rel, digest in before.items():
        if after.get(rel) != digest:
            problems.append("clobbered")
            break
    new = [rel for rel in after if rel not in before]
    if any(Path(rel).name.startswith(".") for rel in new):
        problems.append("temp_left")
    if any(not Path(rel).name.startswith(".") for rel in new):
        problems.append("written")
    return problems


def shorten(argv: list[str], width: int = 60) -> str:
    """An invocation as one short line for reports."""
    parts = [a if len(a) <= width else a[:20] + f"…({len(a)} chars)" for a in argv]
    return "natura " + " ".join(repr(p) if (not p or " " in p or "\n" in p) else p
                                for p in parts)
