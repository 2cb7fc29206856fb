"""OpenCue for a FarmJob (opencue-pyoutline): an outline with one shell layer
over the frame range, chunked, whose command gets each chunk's first and
last frame from OpenCue's #FRAME_START# / #FRAME_END# tokens; the
environment is the job's (set before every frame), the output patterns the
layer's outputs. serialize() gives the job spec (XML) without a Cuebot;
launch() submits it to one.
"""

from __future__ import annotations

import shlex

from .job import FarmJob


def _outline_modules():
    try:
        import outline
        import outline.modules.shell
    except ImportError as e:  # pragma: no cover - depends on the install
        raise ImportError("gdof.farm.opencue needs opencue-pyoutline (pip install opencue-pyoutline)") from e
    return outline


def build(job: FarmJob, show: str = "gdof", shot: str = "gdof", user: str = "gdof"):
    """The outline.Outline of the job (one layer, range and chunk set)."""
    outline = _outline_modules()
    ol = outline.Outline(job.name, show=show, shot=shot, user=user)
    for key, value in job.env.items():
        ol.set_env(key, value, pre=True)
    command = job.task_command("#FRAME_START#-#FRAME_END#")
    layer = outline.modules.shell.Shell(
        "gdof", command=[shlex.quote(a) if "#FRAME_" not in a else a for a in command],
        range=job.frames.replace(" ", ""), chunk=job.chunk)
    for k, out in enumerate(job.outputs()):
        layer.add_output(f"output{k}", out)
    ol.add_layer(layer)
    return ol


def serialize(job: FarmJob, **kwargs) -> str:
    """The OpenCue job spec (XML) of the job, made without a Cuebot."""
    outline = _outline_modules()
    from outline.cuerun import OutlineLauncher

    return OutlineLauncher(build(job, **kwargs)).serialize(use_pycuerun=False)


def launch(job: FarmJob, **kwargs):  # pragma: no cover - needs a Cuebot
    """Submits the job to the Cuebot that opencue's configuration names."""
    outline = _outline_modules()
    return outline.cuerun.launch(build(job, **kwargs), use_pycuerun=False)
