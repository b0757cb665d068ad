"""Errors a user can cause. Each carries one line saying what is wrong and what is allowed."""


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


class GpuUnavailableError(NaturaError):
    """No OpenGL context could be created."""

    exit_code = 3
