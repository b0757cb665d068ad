"""The effect interface: one package per effect, owning its GL resources, parameters and passes.

What an effect declares (``name``, ``programs``, ``python_params()``, ``stages``, ``produces`` /
``consumes``, ``update``, ``draw`` or ``passes``, ``bench_passes``) is docs/architecture.md's
"Effects" section. GL resources are created lazily through ``self.gpu`` under the effect's
name, so a scene without the effect allocates nothing of it. An effect never imports or names
another effect: what it needs from others comes through the frame's slots.
"""

from __future__ import annotations

import copy
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, ClassVar

from ..errors import NaturaError, UsageError
from ..frame import Stage
from ..gpu.cache import Keyed
from ..gpu.programs import ProgramSpec
from ..gpu.shaders import (
    PreprocessError,
    ShaderError,
    ShaderLibrary,
    SourceError,
    _stamp,  # the stamp the library's live reload compares
    read_source,
)
from ..params import Joint, Param, ParamSet, parse_glsl_annotations, with_joints

if TYPE_CHECKING:
    from ..frame import FrameContext
    from ..gpu.context import Caps
    from ..gpu.device import Gpu
    from ..gpu.targets import RenderTarget


#: :meth:`Effect.glsl_params` memoised: (class, …, shader root) → (stamps, stage files, params);
#: the most recently used entries (a test making many shader roots does not grow it unbounded)
_GLSL_PARAMS: OrderedDict[tuple, tuple[dict, list, list]] = OrderedDict()
_GLSL_PARAMS_KEPT = 256


@dataclass
class Pass:
    """A named piece of a frame's work and the stage it runs in."""

    name: str
    run: Callable[[], None]
    stage: Stage = Stage.OPAQUE


class Effect:
    name: ClassVar[str] = ""
    title: ClassVar[str] = ""
    spec: ClassVar[str] = ""  # digest the effect implements, e.g. "spec/000"
    programs: ClassVar[tuple[ProgramSpec, ...]] = ()
    #: groups of parameters the effect owns besides its own name
    extra_groups: ClassVar[tuple[str, ...]] = ()
    #: rules between its parameters that their ranges cannot say (``app.params.Joint``): each
    #: is shown beside the range of every parameter it ties and checked before any work
    joints: ClassVar[tuple[Joint, ...]] = ()
    #: names the effect (and its parameter group) had before a rename; still accepted
    former_names: ClassVar[tuple[str, ...]] = ()
    #: render stages the effect draws in; the first is where draw() runs
    stages: ClassVar[tuple[Stage, ...]] = (Stage.OPAQUE,)
    #: frame slots the effect fills (names of app.frame.SLOTS)
    produces: ClassVar[frozenset[str]] = frozenset()
    #: frame slots the effect reads: slot name → "required" or "optional"
    consumes: ClassVar[dict[str, str]] = {}

    @classmethod
    def python_params(cls) -> list[Param]:
        return []

    @classmethod
    def shader_files(cls, library: ShaderLibrary) -> list[Path]:
        return cls._shader_sources(library)[0]

    @classmethod
    def _shader_sources(cls, library: ShaderLibrary,
                        failures: list[PreprocessError] | None = None
                        ) -> tuple[list[Path], dict[Path, Any], list[dict[str, Path]]]:
        """(every file the programs include, the stamp of each file the preprocessor read or
        looked for, each program's stage files); a stage that cannot be preprocessed (a missing,
        empty or refused include, a file that is not text) is added to ``failures``."""
        files: list[Path] = []
        stamps: dict[Path, Any] = {}
        stage_maps: list[dict[str, Path]] = []
        for spec in cls.programs:
            try:
                stages = library.stage_files(spec.name, **spec.stages())
            except NaturaError:  # a stage file renamed away while the window runs
                stage_maps.append({})
                continue
            stage_maps.append(stages)
            for path in stages.values():
                try:
                    src = library.preprocess(path, dict(spec.defines))
                    files.extend(src.files)
                    stamps.update(src.stamps)
                except PreprocessError as exc:
                    files.extend(exc.files)
                    stamps.update(exc.stamps)
                    if failures is not None:
                        failures.append(exc)
        return list(dict.fromkeys(files)), stamps, stage_maps

    @classmethod
    def _sources_unchanged(cls, library: ShaderLibrary, stamps: dict[Path, Any],
                           stage_maps: list[dict[str, Path]]) -> bool:
        """Whether what :meth:`_shader_sources` found still holds: the same stage files, and
        every file read or looked for with its stamp (content hash included) unchanged."""
        for spec, stages in zip(cls.programs, stage_maps):
            try:
                if library.stage_files(spec.name, **spec.stages()) != stages:
                    return False
            except NaturaError:
                if stages:
                    return False
        return all(_stamp(path) == stamp for path, stamp in stamps.items())

    @classmethod
    def glsl_params(cls, library: ShaderLibrary,
                    problems: list[ShaderError] | None = None) -> list[Param]:
        """Parameters from ``// @param`` annotations in every file the programs include. A
        malformed annotation raises :class:`~app.errors.ParamError` naming its file and line;
        with a ``problems`` list it is skipped and listed there instead, as are files that
        cannot be read as text (the compile reports them).

        Without ``problems``, a stage that cannot be preprocessed (an include missing, empty,
        not a file or refused; a file that is not text) raises :class:`~app.errors.UsageError`
        with its ``file:line``: the files after it are unknown, and so are their parameters (a
        deleted include surfaced as an unknown parameter, and ``natura params`` listed half).

        Without ``problems`` (declaring a scene's parameters) the result is memoised per
        effect class and shader root while every file the preprocessor read or looked for
        keeps its stamp (content hash included) and every program its stage files:
        preprocessing every program of a scene is most of ``scene_params`` (~80 ms a scene),
        paid again by every session a process opens. Each call gets its own copies of the
        :class:`Param` objects."""
        if problems is not None:
            return cls._parse_glsl_params(library, problems)
        key = (cls, cls.name, cls.spec, cls.programs, library.root)
        held = _GLSL_PARAMS.get(key)
        if held is not None and cls._sources_unchanged(library, held[0], held[1]):
            _GLSL_PARAMS.move_to_end(key)
            return [copy.copy(p) for p in held[2]]
        failures: list[PreprocessError] = []
        files, stamps, stage_maps = cls._shader_sources(library, failures)
        if failures:
            raise UsageError(str(failures[0].error))
        params = cls._parse_glsl_params(library, None, files)
        _GLSL_PARAMS[key] = (stamps, stage_maps, [copy.copy(p) for p in params])
        while len(_GLSL_PARAMS) > _GLSL_PARAMS_KEPT:
            _GLSL_PARAMS.popitem(last=False)
        return params

    @classmethod
    def _parse_glsl_params(cls, library: ShaderLibrary, problems: list[ShaderError] | None,
                           files: list[Path] | None = None) -> list[Param]:
        out: dict[str, Param] = {}
        for path in cls.shader_files(library) if files is None else files:
            try:
                text = read_source(path)
            except SourceError:
                continue
            where = library.display(path)
            found: list[tuple[int, str]] | None = [] if problems is not None else None
            for p in parse_glsl_annotations(text, cls.name, where, cls.spec, found):
                out.setdefault(p.name, p)
            if problems is not None and found:
                problems.extend(ShaderError(where, line, f"@param: {message}")
                                for line, message in found)
        return list(out.values())

    @classmethod
    def declare(cls, library: ShaderLibrary) -> list[Param]:
        return with_joints(cls.python_params() + cls.glsl_params(library), cls.joints)

    def __init__(self, gpu: Gpu, params: ParamSet):
        self.gpu = gpu
        self.params = params
        self._keyed: list[Keyed] = []

    def keyed(self, build: Callable, release: Callable | None = None) -> Keyed:
        """A :class:`~app.gpu.cache.Keyed` value of this effect (rebuilt when its key changes),
        forgotten when the effect releases its resources."""
        k = Keyed(build, release)
        self._keyed.append(k)
        return k

    def program(self, spec: ProgramSpec):
        prog = self.gpu.program(self.name, spec)
        if self._on_reload not in prog.on_reload:
            prog.on_reload.append(self._on_reload)
        return prog

    def _on_reload(self, prog) -> None:
        """A reloaded shader may declare new ``@param`` uniforms: give them widgets now. A
        malformed annotation is listed on the program (``file:line``) and the parameter keeps
        its last good declaration; nothing here raises into the reload."""
        problems: list[ShaderError] = []
        for p in self.glsl_params(self.gpu.shaders, problems):
            try:
                self.params.add(p, replace=True)
            except (NaturaError, ValueError, TypeError) as exc:
                problems.append(ShaderError(p.source, 1, f"@param {p.name}: {exc}"))
        for error in problems:
            prog.report(error)

    def apply_params(self, prog) -> None:
        """Push every parameter of this effect that names a uniform. A value the uniform's
        (changed) GLSL type cannot take is converted or skipped and listed by
        :meth:`app.gpu.shaders.Program.set`; nothing raises into the render."""
        for p in self.params:
            if p.uniform and p.group == self.name:
                prog.set(p.uniform, self.params[p.name])

    def update(self, frame: FrameContext, dt: float) -> None:
        """CPU work for this frame; may add to ``frame`` (lights, wind...)."""

    def draw(self, frame: FrameContext, target: RenderTarget) -> None:
        """The pass of a single-pass effect (the default :meth:`passes` runs it)."""
        raise NotImplementedError(f"effect {self.name!r} implements neither passes() nor draw()")

    def passes(self, frame: FrameContext, target: RenderTarget) -> list[Pass]:
        """This frame's passes, each in its stage (default: :meth:`draw` in the first stage)."""
        return [Pass(self.name, lambda: self.draw(frame, target), self.stages[0])]

    def bench_passes(self, frame: FrameContext, target: RenderTarget) -> list[Pass]:
        """What ``natura bench`` times: the frame's passes unless an effect adds more."""
        return self.passes(frame, target)

    def render(self, frame: FrameContext, target: RenderTarget) -> None:
        """Run this effect's passes alone, in order, into ``target`` (linear radiance)."""
        frame.image = frame.image_for(target)
        for p in self.passes(frame, target):
            p.run()

    #: the parameter that chooses the effect's method, and what each of its values teaches
    #: (:meth:`lesson` looks the current value up)
    lesson_param: ClassVar[str | None] = None
    LESSONS: ClassVar[dict] = {}

    @classmethod
    def lesson(cls, params: ParamSet) -> str | None:
        """What the effect's current method teaches, in one or two sentences naming its thesis
        section (the window's panel shows it at the top of the effect's header); None when the
        effect has no methods to choose between. A class method of the parameters alone, so a
        handout or a test can ask without a GL context. By default the line of
        :attr:`LESSONS` for the value of :attr:`lesson_param`."""
        if cls.lesson_param is None or cls.lesson_param not in params:
            return None
        return cls.LESSONS.get(params[cls.lesson_param])

    @classmethod
    def context_paths(cls, caps: Caps, params: ParamSet) -> dict[str, str]:
        """The paths this effect takes on a context with ``caps`` under ``params``, where it
        has a choice (compute shaders or fragment passes, a path picked for a software
        renderer): what it is → which path and why, for ``natura doctor``, the window's panel
        and the GPU report. A class method, so it is asked without building anything."""
        return {}

    def panel_notes(self) -> list[str]:
        """Lines the window's panel shows above this effect's widgets (live figures)."""
        return []

    def panel_items(self) -> list:
        """Objects the window's panel offers editors for besides the parameters (it knows how
        to edit ``app.sim`` types such as the sky's ``Keyframes``)."""
        return []

    def release(self) -> None:
        for k in self._keyed:
            k.clear()
        self.gpu.release_owner(self.name)

