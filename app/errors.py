"""Errors a user can cause. Each carries one line saying what is wrong and what is allowed."""

import re


class NaturaError(Exception):
    """A user-facing error: the CLI prints ``natura: <message>`` and exits with ``exit_code``."""

    exit_code = 2


class ParamError(NaturaError):
    """A parameter name or value that is not allowed."""


class UsageError(NaturaError):
    """A bad command-line argument (scene name, size, output path...)."""


class OutputExistsError(UsageError):
    """Refusing to overwrite an existing file without ``--force``."""


class ShaderCompileError(NaturaError):
    """One or more GLSL errors, already mapped to ``file:line: message``."""

    exit_code = 1

    def __init__(self, errors):
        self.errors = list(errors)
        super().__init__("\n".join(str(e) for e in self.errors))


class NaturaWarning(RuntimeWarning):
    """Something a user should know that does not stop the command (a bake cache that cannot
    be written): the CLI prints it as one ``natura: `` line, without a line of source."""


class GpuUnavailableError(NaturaError):
    """No OpenGL context could be created."""

    exit_code = 3


#: how long a quoted culprit may be in a message (the whole line stays under ~200 characters)
QUOTE_LIMIT = 60
LINE_LIMIT = 200


def quote(value, limit: int = QUOTE_LIMIT) -> str:
    """``repr(str(value))``, cut to ``limit`` characters with an ellipsis in the middle (a
    path keeps its file name): a 100 kB argument is named, never echoed."""
    return _cut(repr(value if isinstance(value, str) else str(value)), limit)


def _cut(text: str, limit: int) -> str:
    head = (limit - 1) // 2
    return text if len(text) <= limit else text[:head] + "…" + text[-(limit - 1 - head):]


def quote_path(path, limit: int = QUOTE_LIMIT) -> str:
    """A path quoted like :func:`quote`, but a long one keeps its whole file name and cuts its
    folders (``'/tmp/…/F/seq-0005.png'``): the name is what a user looks for."""
    text = str(path)
    shown = quote(text, limit)
    if len(shown) <= len(repr(text)) and "…" not in shown:
        return shown
    head, sep, name = text.rpartition("/")
    if not sep or len(repr(name)) + 8 > limit:
        return shown
    room = limit - len(repr(name)) - 3  # the quotes' share is in repr(name); "…/" and a slash
    keep = max(1, room // 2)
    return repr(f"{head[:keep]}…{head[-(room - keep):]}/{name}")


#: a quoted part (as :func:`quote` writes one) longer than QUOTE_LIMIT: its opening quote does
#: not follow a letter and its closing quote is not followed by one, so the text between two
#: quoted parts, or an apostrophe, is never taken for one
_QUOTED = re.compile(r"(?<!\w)(?:'(?:[^'\\\n]|\\.){%d,}'|\"(?:[^\"\\\n]|\\.){%d,}\")(?!\w)"
                     % (QUOTE_LIMIT, QUOTE_LIMIT))


def one_line(message: str, limit: int = LINE_LIMIT) -> str:
    """A message as one line of at most ``limit`` characters: newlines become spaces, long
    quoted parts are cut (:func:`quote`), and a line still too long keeps its start and its
    end (where the "allowed ..." part is)."""
    text = " ".join(str(message).split())
    text = _QUOTED.sub(lambda m: _cut(m.group(0), QUOTE_LIMIT), text)
    if len(text) > limit:
        head = limit * 2 // 5
        text = text[:head] + " … " + text[-(limit - head - 3):]
    return text
