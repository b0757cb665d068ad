"""Render a list of scene jobs (name, scene, --set values, optionally a camera) on this
process's context and save each as the 8-bit sRGB image ``natura render`` would write
(``python -m tests.helpers.parity OUT JOBS.json WxH``).

The GL 4.1 parity test runs it twice, once as is and once under Mesa's caps
(:data:`GL41_ENV`), and compares the images job by job. Besides the images, ``OUT/run.json``
holds the context's description, each job's refusal (a one-line error instead of an image)
and every program the jobs compiled, so the test can check that no variant is built that
``natura shaders check`` does not know.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

#: a GL 4.1 core context as macOS gives one: version and GLSL capped, and the extensions that
#: bring 4.2+ features to an older context removed (Mesa still offers them on a capped context;
#: Apple's driver does not)
GL41_ENV = {
    "MESA_GL_VERSION_OVERRIDE": "4.1",
    "MESA_GLSL_VERSION_OVERRIDE": "410",
    "MESA_EXTENSION_OVERRIDE": " ".join(f"-GL_ARB_{e}" for e in (
        "compute_shader", "shader_image_load_store", "shader_storage_buffer_object",
        "multi_draw_indirect", "base_instance", "shading_language_420pack",
        "explicit_uniform_location", "clip_control", "pipeline_statistics_query")),
}


def main(argv: list[str]) -> int:
    import numpy as np

    from app.errors import NaturaError
    from app.gpu.context import create_headless_context, describe_context
    from app.imageio import to_srgb8
    from app.runtime import open_session, parse_size, render_frames, scene_params
    from app.sim.camera import Camera

    out, jobs_file, size_text = Path(argv[0]), Path(argv[1]), argv[2]
    size = parse_size(size_text)
    jobs = json.loads(jobs_file.read_text())
    out.mkdir(parents=True, exist_ok=True)
    run: dict = {"context": None, "refused": {}, "programs": []}
    programs: set = set()
    # one context for every job, as the window's picker switches scenes on one: a context of
    # its own per job (context, blitter and program loads again each time) was half the run
    ctx = create_headless_context()
    for name, scene, sets, *camera in jobs:
        try:
            params = scene_params(scene, sets=sets)
            view = None
            if camera:
                x, y, z, yaw, pitch = camera[0]
                view = Camera(position=(x, y, z), yaw=yaw, pitch=pitch)
            session = open_session(scene, params, ctx=ctx, camera=view)
        except NaturaError as exc:
            run["refused"][name] = str(exc)
            continue
        try:
            run["context"] = run["context"] or describe_context(session.gpu.ctx)
            try:
                image = next(render_frames(session, size))
            except NaturaError as exc:
                run["refused"][name] = str(exc)
                continue
            np.save(out / f"{name}.npy",
                    to_srgb8(image[..., :3], session.scene.exposure(), params["output.tonemap"]))
            programs.update(session.gpu.shaders._programs)
        finally:
            session.release()
    run["programs"] = sorted([name, list(map(list, defines)), list(map(list, stages))]
                             for name, defines, stages in programs)
    (out / "run.json").write_text(json.dumps(run, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
