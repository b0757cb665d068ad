"""One mechanism for every tunable.

A :class:`Param` gives a tunable its name (``effect.name``), default, range, step, unit,
one-line doc and the thesis section it comes from. From it come the ImGui widgets
(``app.ui.panel``), validation, TOML presets and ``--set name=value``.

Parameters are declared in Python (``Param(...)``) or by annotating a uniform in GLSL::

    uniform float uSunSize; // @param 0.05 [0, 1] step=0.005 §1.7 sun disk size

which becomes ``<effect>.sun_size`` (a leading ``u`` prefix is dropped and camelCase becomes
snake_case). See :func:`parse_glsl_annotations` for the full grammar.
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime
import difflib
import math
import os
import re
import reprlib
import stat
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, Mapping

from .errors import ParamError, one_line, quote

#: the largest preset file read (a preset is a few kB; /dev/zero or a huge file is refused)
PRESET_LIMIT = 1 << 20
_PRESET_ALLOWED = "allowed a UTF-8 TOML file of at most 1 MB"

_SHOW = reprlib.Repr()
_SHOW.maxstring = 50
_SHOW.maxother = 50
_SHOW.maxlevel = 3
_SHOW.maxlist = _SHOW.maxtuple = _SHOW.maxdict = 6


def _plain(value: Any, depth: int = 0) -> str:
    """``value`` as a user writes it: numbers as numbers (numpy's too), a sequence as
    comma-separated items (the ``--set`` form), a date or time in ISO form (a TOML preset may
    hold one); anything else by its reprlib repr."""
    np = sys.modules.get("numpy")  # a numpy value exists only where numpy is loaded
    if np is not None and isinstance(value, (np.generic, np.ndarray)):
        value = value.tolist() if value.size <= 6 else value
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        text = repr(value)
        return text if len(text) <= 12 else f"{value:.6g}"
    if isinstance(value, int):
        return _SHOW.repr(value)
    if isinstance(value, (datetime.date, datetime.time)):
        return value.isoformat()
    if isinstance(value, (list, tuple)) and depth < 2:
        items = [_plain(v, depth + 1) for v in value[:6]]
        text = ",".join(items) + (",…" if len(value) > 6 else "")
        return f"[{text}]" if depth else text
    return _SHOW.repr(value)


def show(value: Any) -> str:
    """A value as a user writes it, short, for messages: numbers, comma-separated sequences,
    ISO dates; long strings, deep or long lists, huge integers are cut, and nothing here
    raises."""
    if isinstance(value, str):
        return quote(value)
    try:
        return quote(_plain(value)).strip("'\"")
    except Exception:  # noqa: BLE001 — e.g. an int too long to print
        return f"<a {type(value).__name__}>"


KINDS = ("float", "int", "bool", "vec3", "vec4", "color", "choice")
#: number of components of each vector kind
COMPONENTS = {"vec3": 3, "vec4": 4, "color": 3}
_WORDS = {3: "three", 4: "four"}


def _fmt(x: float) -> str:
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:g}"


@dataclass
class Inspector:
    """A material inspector an effect offers the window's panel (``Effect.panel_items``), like
    the toon-village thesis's custom inspectors (spec/003 Fig. 130): ``popups`` — a button per
    title opening that popup with the widgets of those parameters (names of the effect's
    parameters) — and ``textures`` — the generated maps shown as thumbnails (label → a texture
    object the window's renderer can draw)."""

    title: str
    popups: dict[str, list[str]] = field(default_factory=dict)
    textures: dict[str, Any] = field(default_factory=dict)
    #: the parameter set the popups edit (None: the scene's own)
    params: "ParamSet | None" = None


@dataclass(frozen=True, eq=False)
class Joint:
    """A rule between parameters that each one's range cannot say (``bake_shape.cells_g <
    cells_b < cells_a``): ``text`` is how a user reads it, ``holds`` says whether the values of
    ``names`` (in that order) keep it. Every :class:`Param` it ties carries it in ``joint``, so
    ``natura params`` and the panel show it beside that parameter's range; a scene's values are
    checked against it after the defaults, the preset and every ``--set`` are in
    (:meth:`ParamSet.check_joint`), and the panel refuses a change that would break it."""

    names: tuple[str, ...]
    text: str
    holds: Callable[..., bool]

    def broken_by(self, values: Mapping[str, Any]) -> str | None:
        """None when ``values`` keep the rule, else why not ("" when the rule's own text is
        all there is to say; a check that knows more says it by raising ParamError)."""
        try:
            return None if self.holds(*(values[n] for n in self.names)) else ""
        except ParamError as exc:
            return str(exc)


@dataclass
class Param:
    """A tunable: everything the UI, the CLI, presets and validation need to know."""

    name: str
    default: Any
    lo: float | None = None
    hi: float | None = None
    doc: str = ""
    kind: str = "float"
    step: float | None = None
    unit: str = ""
    section: str = ""
    uniform: str | None = None
    choices: tuple[str, ...] = ()
    source: str = "python"  # "python" or the GLSL file that declared it
    srgb: bool = False  # a colour given as display (sRGB) values rather than linear ones
    #: the rules that tie it to other parameters (shown beside its range)
    joint: tuple[Joint, ...] = ()

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"{self.name}: unknown kind {self.kind!r}")
        if self.step is None:
            if self.kind == "int":
                self.step = 1
            elif self.lo is not None and self.hi is not None:
                self.step = (self.hi - self.lo) / 100.0
            else:
                self.step = 0.01
        self.default = self.validate(self.default)

    @property
    def group(self) -> str:
        return self.name.split(".", 1)[0]

    @property
    def short(self) -> str:
        return self.name.split(".", 1)[-1]

    def joint_text(self) -> str:
        """Its rules with other parameters, as shown beside the range ("" when none)."""
        return "; ".join(j.text for j in self.joint)

    def written(self, value: Any) -> str:
        """``value`` as ``natura params`` prints it (a word where the number stands for one)."""
        return repr(value)

    def allowed(self) -> str:
        """What is allowed, as a phrase for error messages."""
        if self.kind == "bool":
            return "true or false"
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        rng = (f"[{_fmt(self.lo)}, {_fmt(self.hi)}]" if self.lo is not None and self.hi is not None
               else "any finite value")
        if self.kind in COMPONENTS:
            return f"{_WORDS[COMPONENTS[self.kind]]} comma-separated numbers, each in {rng}"
        if self.kind == "int":
            return f"an integer in {rng}"
        return f"a number in {rng}"

    def _bad(self, value, why: str) -> ParamError:
        return ParamError(f"{self.name}={show(value)} {why}: allowed {self.allowed()}")

    def _scalar(self, value, original) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            if not isinstance(value, str):
                raise self._bad(original, "is not a number")
            try:
                value = float(value.strip())
            except ValueError:
                raise self._bad(original, "is not a number") from None
        try:
            value = float(value)
        except OverflowError:  # an integer beyond any float (a TOML preset may hold one)
            raise self._bad(original, "is not finite") from None
        if not math.isfinite(value):
            raise self._bad(original, "is not finite")
        if self.lo is not None and value < self.lo - 1e-12:
            raise self._bad(original, "is out of range")
        if self.hi is not None and value > self.hi + 1e-12:
            raise self._bad(original, "is out of range")
        return value

    def validate(self, value: Any) -> Any:
        """Return ``value`` converted to this parameter's type, or raise :class:`ParamError`
        (and nothing else, whatever ``value`` is)."""
        try:
            return self._validate(value)
        except ParamError:
            raise
        except (ValueError, TypeError, OverflowError, RecursionError, AttributeError):
            raise self._bad(value, "is not a valid value") from None

    def _validate(self, value: Any) -> Any:
        original = value
        if self.kind == "bool":
            if isinstance(value, bool):
                return value
            if isinstance(value, (list, tuple, dict)):
                raise self._bad(original, "is not a boolean")
            text = str(value).strip().lower()
            if text in ("1", "true", "yes", "on"):
                return True
            if text in ("0", "false", "no", "off"):
                return False
            raise self._bad(original, "is not a boolean")
        if self.kind == "choice":
            if not isinstance(value, str):
                raise self._bad(original, "is not a choice")
            text = value.strip()
            if text not in self.choices:
                raise self._bad(original, "is not a choice")
            return text
        if self.kind in COMPONENTS:
            n = COMPONENTS[self.kind]
            if isinstance(value, str):
                text = value.strip().strip("()[]")
                if text.startswith("#") and len(text) == 7 and self.kind == "color":
                    try:
                        value = [int(text[i : i + 2], 16) / 255.0 for i in (1, 3, 5)]
                    except ValueError:
                        raise self._bad(original, "is not a colour") from None
                else:
                    value = [v for v in re.split(r"[,\s]+", text) if v]
            if not isinstance(value, (list, tuple)):
                raise self._bad(original, f"is not {_WORDS[n]} numbers")
            items = list(value)
            if len(items) != n:
                raise self._bad(original, f"is not {_WORDS[n]} numbers")
            return tuple(self._scalar(v, original) for v in items)
        number = self._scalar(value, original)
        if self.kind == "int":
            if abs(number - round(number)) > 1e-9:
                raise self._bad(original, "is not an integer")
            return int(round(number))
        return number


def non_zero(name: str, what: str = "vector") -> Joint:
    """The rule that a direction parameter is not the zero vector (it is normalised)."""
    return Joint((name,), f"{name} not the zero {what}",
                 lambda v: math.fsum(float(x) * float(x) for x in v) > 1e-18)


def with_joints(params: Iterable[Param], joints: Iterable[Joint]) -> list[Param]:
    """``params`` with each rule of ``joints`` added to every parameter it ties (copies where
    one is added; the others as they are)."""
    joints = list(joints)
    out = []
    for p in params:
        mine = tuple(j for j in joints if p.name in j.names and j not in p.joint)
        out.append(dataclasses.replace(p, joint=p.joint + mine) if mine else p)
    return out


class ParamSet:
    """The parameters of one scene and their current values.

    ``version(group)`` increases whenever a value in that group changes, so effects can redo
    work (a cubemap, a lookup table) only when something they depend on changed.
    """

    def __init__(self, params: Iterable[Param] = ()):
        self._params: dict[str, Param] = {}
        self._values: dict[str, Any] = {}
        self._versions: dict[str, int] = {}
        self._aliases: dict[str, str] = {}
        for p in params:
            self.add(p)

    def alias(self, former: str, group: str) -> None:
        """Accept ``former.x`` for ``group.x`` everywhere a name is given (``--set``, presets,
        lookups): the former name of a renamed group keeps old presets and scripts working."""
        self._aliases[former] = group

    def add(self, param: Param, replace: bool = False) -> None:
        """Declare a parameter. A re-declaration (e.g. after a shader reload) keeps the value
        when it is still valid."""
        old = self._params.get(param.name)
        if old is not None and not replace and old.source == param.source == "python":
            raise ValueError(f"parameter {param.name} declared twice")
        if old is not None and old.joint and not param.joint:  # a shader reload keeps its rules
            param.joint = old.joint
        self._params[param.name] = param
        if param.name in self._values:
            with contextlib.suppress(ParamError):  # an invalid value falls back to the default
                self._values[param.name] = param.validate(self._values[param.name])
                return
        self._values[param.name] = param.default
        self._bump(param.group)

    def remove(self, name: str) -> None:
        if name in self._params:
            group = self._params.pop(name).group
            self._values.pop(name, None)
            self._bump(group)

    def __contains__(self, name: str) -> bool:
        return name in self._params or self._unalias(name) in self._params

    def _unalias(self, name: str) -> str:
        group, dot, rest = name.partition(".")
        return f"{self._aliases[group]}.{rest}" if dot and group in self._aliases else name

    def __iter__(self):
        return iter(self._params.values())

    def __len__(self):
        return len(self._params)

    def resolve(self, name: str) -> str:
        """The full name for ``name``; a name without a group (``material``) is accepted when
        exactly one parameter of the scene has that short name."""
        if name in self._params:
            return name
        if self._unalias(name) in self._params:
            return self._unalias(name)
        if "." not in name:
            matches = [p.name for p in self._params.values() if p.short == name]
            if len(matches) == 1:
                return matches[0]
            if len(matches) > 1:
                raise ParamError(one_line(f"parameter {quote(name)} is ambiguous: allowed "
                                          + ", ".join(sorted(matches))))
        raise _unknown_name(name, list(self._params.values()))

    def spec(self, name: str) -> Param:
        return self._params[self.resolve(name)]

    def groups(self) -> dict[str, list[Param]]:
        out: dict[str, list[Param]] = {}
        for p in self._params.values():
            out.setdefault(p.group, []).append(p)
        return out

    def __getitem__(self, name: str) -> Any:
        return self._values[self.resolve(name)]

    def get(self, name: str, default: Any = None) -> Any:
        return self._values.get(name, default)

    def set(self, name: str, value: Any) -> Any:
        param = self.spec(name)
        value = param.validate(value)
        if self._values.get(param.name) != value:
            self._values[param.name] = value
            self._bump(param.group)
        return value

    def set_many(self, values: Mapping[str, Any]) -> None:
        """:meth:`set` each of ``values``, in order."""
        for name, value in values.items():
            self.set(name, value)

    @contextlib.contextmanager
    def kept(self, names: Iterable[str] | None = None) -> Iterator[dict[str, Any]]:
        """For a ``with`` block: the values of ``names`` (every parameter when None), yielded,
        and set back after the block whatever it changed."""
        saved = self.values() if names is None else {n: self[n] for n in names}
        try:
            yield saved
        finally:
            self.set_many(saved)

    def joints(self) -> list[Joint]:
        """The rules between this set's parameters (each once; a rule naming a parameter the
        scene does not have is left out)."""
        return _rules_among(self._params)

    def check_joint(self, changed: Iterable[str] | None = None,
                    values: Mapping[str, Any] | None = None) -> None:
        """Raise :class:`ParamError` (one line: the values and the rule) when a rule between
        parameters is broken — every rule, or those tying a name in ``changed``; ``values``
        stands in for some current values (a change not made yet)."""
        current = {**self._values, **(values or {})}
        names = None if changed is None else {self.resolve(n) for n in changed}
        for j in self.joints():
            if names is None or not names.isdisjoint(j.names):
                _check_rule(j, current)

    def try_set(self, name: str, value: Any) -> Any:
        """:meth:`set`, refused (ParamError, nothing changed) when the new value breaks a rule
        it shares with other parameters (the panel's one change at a time)."""
        param = self.spec(name)
        value = param.validate(value)
        self.check_joint([param.name], {param.name: value})
        return self.set(param.name, value)

    def set_from_string(self, assignment: str) -> None:
        """Apply ``name=value`` as given to ``--set``."""
        if "=" not in assignment:
            raise ParamError(f"--set {quote(assignment)} is not name=value: "
                             "allowed e.g. sky.sun_size=0.1")
        name, _, value = assignment.partition("=")
        self.set(name.strip(), value.strip())

    def reset(self, name: str | None = None) -> None:
        for p in [self.spec(name)] if name else list(self._params.values()):
            self.set(p.name, p.default)

    def values(self, group: str | None = None) -> dict[str, Any]:
        return {k: v for k, v in self._values.items() if group is None or k.split(".")[0] == group}

    def version(self, group: str) -> int:
        return self._versions.get(group, 0)

    def _bump(self, group: str) -> None:
        self._versions[group] = self._versions.get(group, 0) + 1

    def load_preset(self, path: Path) -> None:
        """Apply a TOML preset: one table per group, ``[sky] sun_size = 0.05``. Any problem
        with the file (missing, a folder, a pipe or device, unreadable, too large, not UTF-8,
        not TOML, nested too deeply, a value out of range) is one :class:`ParamError` line."""
        name = quote(str(path), 40)
        for group, table in read_preset(path).items():
            if not isinstance(table, dict):
                raise ParamError(f"preset {name}: {quote(group, 30)} must be a table like "
                                 f"[{quote(group, 30)[1:-1]}]: allowed one table per group")
            for key, value in table.items():
                try:
                    self.set(f"{group}.{key}", value)
                except ParamError as exc:
                    raise ParamError(one_line(f"preset {name}: {exc}")) from None

    def preset_text(self, title: str = "") -> str:
        """The current values as a TOML preset (every parameter, grouped)."""
        return _preset_toml(self.groups(), self._values, title)


def _rules_among(params: Mapping[str, Param]) -> list[Joint]:
    """The rules between ``params`` (each once, in declaration order; a rule naming a
    parameter not in ``params`` is left out)."""
    seen: dict[int, Joint] = {}
    for p in params.values():
        for j in p.joint:
            if id(j) not in seen and all(n in params for n in j.names):
                seen[id(j)] = j
    return list(seen.values())


def _check_rule(j: Joint, current: Mapping[str, Any]) -> None:
    """Raise :class:`ParamError` (one line: the values and the rule) when ``current`` breaks
    the rule ``j``."""
    why = j.broken_by(current)
    if why is not None:
        shown = ", ".join(f"{n}={show(current[n])}" for n in j.names)
        raise ParamError(one_line(f"{why or shown}: allowed {j.text}"))


def _preset_toml(groups: Mapping[str, list[Param]], values: Mapping[str, Any],
                 title: str = "") -> str:
    """``values`` as a TOML preset: a title comment, then one table per group."""
    lines = [f"# Natura preset{(' — ' + title) if title else ''}"]
    for group, params in groups.items():
        lines.append(f"\n[{group}]")
        for p in params:
            lines.append(f"{p.short} = {_toml_value(values[p.name])}")
    return "\n".join(lines) + "\n"


def _unknown_name(name: str, params: list[Param]) -> ParamError:
    """One line: every allowed name when they fit, else the closest ones (or the groups)
    and where the full list is."""
    group = name.split(".", 1)[0]
    same = [p.name for p in params if p.group == group]
    pool = sorted(same or [p.name for p in params])
    head = f"unknown parameter {quote(name)}: allowed "
    if len(head) + len(", ".join(pool)) <= 190:
        return ParamError(head + ", ".join(pool))
    close = difflib.get_close_matches(name[:200], pool, n=3, cutoff=0.6)
    groups = sorted({p.group for p in params})
    shown = ", ".join(close) if close else "names in " + ", ".join(groups)
    return ParamError(one_line(f"{head}{shown}, … (all: natura params SCENE)"))


def read_preset(path: Path) -> dict[str, Any]:
    """A preset file's TOML, or one :class:`ParamError` line: the file as
    :func:`read_preset_text` takes it, valid TOML, not nested too deeply, every value
    readable. Its top-level entries are checked to be tables as they are applied."""
    name = quote(str(path), 40)
    text = read_preset_text(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParamError(one_line(f"preset {name} is not valid TOML ({str(exc)[:70]}): "
                                  f"{_PRESET_ALLOWED}")) from None
    except RecursionError:
        raise ParamError(f"preset {name} nests too deeply: {_PRESET_ALLOWED}") from None
    except (ValueError, OverflowError, MemoryError) as exc:  # e.g. an int of 5000 digits
        raise ParamError(one_line(f"preset {name} holds a value Python cannot read "
                                  f"({type(exc).__name__}): {_PRESET_ALLOWED}")) from None
    return data


def read_preset_text(path: str | os.PathLike) -> str:
    """The text of a preset file, or :class:`ParamError`: the file must be a regular file
    (checked before opening, so a named pipe cannot block), readable, at most
    :data:`PRESET_LIMIT` bytes, and UTF-8."""
    name = quote(str(path))

    def refuse(why: str) -> ParamError:
        return ParamError(f"preset {name} {why}: {_PRESET_ALLOWED}")

    try:
        p = Path(path).expanduser()
    except RuntimeError:  # ~nosuchuser
        raise refuse("names an unknown user's home folder") from None
    try:
        st = p.stat()
    except (FileNotFoundError, NotADirectoryError):
        raise refuse("does not exist") from None
    except OSError as exc:  # a link loop, a name too long...
        raise refuse(f"cannot be opened ({exc.strerror or type(exc).__name__})") from None
    except ValueError:  # a NUL byte in the name
        raise refuse("is not a valid file name") from None
    if stat.S_ISDIR(st.st_mode):
        raise refuse("is a folder")
    if not stat.S_ISREG(st.st_mode):
        raise refuse("is not a regular file (a pipe, socket or device)")
    if st.st_size > PRESET_LIMIT:
        raise refuse(f"is {st.st_size} bytes")
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    try:
        fd = os.open(p, flags)
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):  # swapped since the check
                raise refuse("is not a regular file (a pipe, socket or device)")
            data = f.read(PRESET_LIMIT + 1)
    except PermissionError:
        raise refuse("is not readable (permission denied)") from None
    except OSError as exc:
        raise refuse(f"cannot be read ({exc.strerror or type(exc).__name__})") from None
    if len(data) > PRESET_LIMIT:
        raise refuse("is larger than 1 MB")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise refuse(f"is not UTF-8 (byte {exc.start})") from None


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (tuple, list)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return '"' + str(v).replace("\\", "\\\\").replace('"', '\\"') + '"'


_ANNOTATION = re.compile(
    r"^\s*uniform\s+(?P<type>float|int|bool|vec3|vec4)\s+(?P<name>\w+)\s*;\s*//\s*@param\s+(?P<rest>.*)$"
)
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_DEFAULT = re.compile(
    rf"^(?P<default>\(\s*{_NUMBER}(?:\s*,\s*{_NUMBER}){{2,3}}\s*\)|{_NUMBER}|true|false)\s*"
)
_RANGE = re.compile(rf"^\[\s*(?P<lo>{_NUMBER})\s*,\s*(?P<hi>{_NUMBER})\s*\]\s*")
_OPTION = re.compile(r"^(?P<key>step|unit)=(?P<value>\S+)\s*|^(?P<color>color)\b\s*"
                     r"|^(?P<section>§\S+)\s*")


def param_name_from_uniform(uniform: str) -> str:
    """``uSunSize`` → ``sun_size``; ``u_sun_size`` → ``sun_size``; ``fogDensity`` →
    ``fog_density``."""
    name = uniform
    if re.match(r"^u[A-Z_]", name):
        name = name[1:].lstrip("_")
    name = re.sub(r"(?<=[a-z0-9])([A-Z])", r"_\1", name)
    return name.lower()


def parse_glsl_annotations(text: str, group: str, source: str = "",
                           spec_doc: str = "",
                           problems: list[tuple[int, str]] | None = None) -> list[Param]:
    """Parameters declared by ``// @param`` comments on uniforms.

    Grammar (after ``@param``)::

        DEFAULT [LO, HI] [step=S] [unit=U] [color] [§SECTION] doc

    The doc may go on over the comment-only lines right below whose ``//`` stands in the
    annotation's column (so that a shader's lines stay within 100 columns).

    DEFAULT is a number, ``true``/``false`` (bool uniforms) or ``(a, b, c)`` (vec3). The range
    is required except for bools. ``color`` marks a vec3 as a colour (colour-picker widget).
    A malformed annotation raises :class:`ParamError` naming the file and line; with a
    ``problems`` list it is skipped instead and ``(line, message)`` appended there (a live
    reload keeps the parameter's last good declaration). Lines are counted as the compiler
    counts them (only ``\\n`` ends one).
    """
    out = []
    lines = text.split("\n")
    for lineno, line in enumerate(lines, 1):
        if "@param" in line:
            line += _continued(line, lines[lineno:])
        try:
            param = _annotation(line, group, source, spec_doc)
        except ParamError as exc:
            if problems is None:
                raise ParamError(f"{source}:{lineno}: {exc}") from None
            problems.append((lineno, str(exc)))
            continue
        if param is not None:
            out.append(param)
    return out


def _continued(line: str, below: list[str]) -> str:
    """The doc text an annotation continues on the comment-only lines right below it whose
    ``//`` stands in the annotation's column (each prefixed with a space; "" if none)."""
    col = line.find("//")
    out = ""
    for nxt in below:
        if col < 0 or nxt.find("//") != col or nxt[:col].strip():
            break
        out += " " + nxt[col + 2:].strip()
    return out


_SUPPORTED = re.compile(r"^\s*uniform\s+(?:float|int|bool|vec3|vec4)\s+\w+\s*;\s*//\s*@param\s*$")


def _annotation(line: str, group: str, source: str, spec_doc: str) -> Param | None:
    """The parameter one line declares (``None`` if it declares none); :class:`ParamError`
    (without the file and line) for a malformed annotation."""
    m = _ANNOTATION.match(line)
    if not m:
        if _SUPPORTED.match(line):
            raise ParamError("@param needs a default first: "
                             "allowed a number, true/false or (a, b, c)")
        if "@param" in line and re.match(r"^\s*uniform\b", line):
            raise ParamError("@param on an unsupported uniform: "
                             "allowed float, int, bool, vec3, vec4")
        return None
    gtype, uname, rest = m["type"], m["name"], m["rest"].strip()
    d = _DEFAULT.match(rest)
    if not d:
        raise ParamError("@param needs a default first: "
                         "allowed a number, true/false or (a, b, c)")
    default_text = d["default"]
    rest = rest[d.end():]
    lo = hi = None
    r = _RANGE.match(rest)
    if r:
        lo, hi = float(r["lo"]), float(r["hi"])
        rest = rest[r.end():]
    elif gtype != "bool":
        raise ParamError("@param needs a range [lo, hi] after the default")
    opts: dict[str, Any] = {}
    while True:
        o = _OPTION.match(rest)
        if not o:
            break
        if o["key"]:
            opts[o["key"]] = o["value"]
        elif o["color"]:
            opts["color"] = True
        else:
            opts["section"] = o["section"]
        rest = rest[o.end():]
    kind = gtype
    if kind == "vec3" and opts.get("color"):
        kind = "color"
    default: Any
    if kind in COMPONENTS:
        default = default_text.strip("()")
    elif kind == "bool":
        default = default_text
    elif default_text.startswith("(") or default_text in ("true", "false"):
        raise ParamError(f"default {default_text} does not suit a {gtype} uniform: "
                         "allowed a number")
    else:
        default = float(default_text)
    step = None
    if "step" in opts:
        if not re.fullmatch(_NUMBER, opts["step"]):
            raise ParamError(f"step={opts['step']} is not a number: allowed e.g. step=0.01")
        step = float(opts["step"])
    section = opts.get("section", "")
    if section and spec_doc:
        section = f"{spec_doc} {section}"
    try:
        return Param(
            name=f"{group}.{param_name_from_uniform(uname)}",
            default=default,
            lo=lo,
            hi=hi,
            doc=rest.strip(),
            kind=kind,
            step=step,
            unit=opts.get("unit", ""),
            section=section,
            uniform=uname,
            source=source or "glsl",
        )
    except (ParamError, ValueError, TypeError) as exc:
        raise ParamError(f"default {exc}") from None
