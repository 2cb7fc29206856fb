"""Open Job Description (specification jobtemplate-2023-09) for a FarmJob:
one step whose tasks run gdof on one frame (an INT task parameter over the
range) or one chunk (a STRING task parameter listing the chunks), with the
environment as a job environment's variables and the output folders as
PATH job parameters with dataFlow OUT (what a scheduler syncs back).
`openjd run job.json` runs it locally; AWS Deadline Cloud runs it on a farm.
"""

from __future__ import annotations

import json
import os
import re
from typing import Any, Dict, Optional

from .job import FarmJob

SPECIFICATION = "jobtemplate-2023-09"


def _identifier(text: str, fallback: str) -> str:
    name = re.sub(r"[^A-Za-z0-9_]", "_", text)
    return name if re.match(r"^[A-Za-z_]", name) else fallback


def template(job: FarmJob, template_dir: Optional[str] = None) -> Dict[str, Any]:
    """The job template as a dict (json.dumps it, or yaml). Open Job
    Description resolves a PATH parameter's default against the template's
    folder: with `template_dir` the output folders are defaults relative to
    it; without, they must be given when the job is submitted or run
    (-p OutputDir=...)."""
    per_frame = job.chunk == 1 and len(job.chunks) == len(job.frame_list)
    if per_frame:
        task_param = {"name": "Frame", "type": "INT", "range": [int(f) for f in job.frame_list]}
        frames_arg = "{{Task.Param.Frame}}"
    else:
        task_param = {"name": "Frames", "type": "STRING", "range": list(job.chunks)}
        frames_arg = "{{Task.Param.Frames}}"
    # The folders written to, as job parameters (dataFlow OUT) the command uses.
    params = []
    args = [frames_arg if a == "{frames}" else a for a in job.task_command("{frames}")[1:]]
    for k, folder in enumerate(job.output_folders()):
        pname = f"OutputDir{k}" if k else "OutputDir"
        param = {"name": pname, "type": "PATH", "objectType": "DIRECTORY", "dataFlow": "OUT",
                 "description": "where gdof writes its frames"}
        if template_dir is not None:
            param["default"] = os.path.relpath(folder, os.path.abspath(template_dir))
        params.append(param)
        # Each -o into that folder names it through the parameter, so a
        # scheduler that maps paths (or syncs outputs) sees where they go.
        for i in range(len(args) - 1):
            if args[i] == "-o" and os.path.dirname(os.path.abspath(args[i + 1])) == folder:
                args[i + 1] = "{{Param." + pname + "}}/" + os.path.basename(args[i + 1])
    params.append({"name": "Gdof", "type": "STRING", "default": job.command[0],
                   "description": "the gdof executable on the farm's workers"})
    t: Dict[str, Any] = {
        "specificationVersion": SPECIFICATION,
        "name": job.name,
        "parameterDefinitions": params,
        "steps": [{
            "name": _identifier(job.name, "gdof"),
            "parameterSpace": {"taskParameterDefinitions": [task_param]},
            "script": {"actions": {"onRun": {"command": "{{Param.Gdof}}", "args": args}}},
        }],
    }
    if job.env:
        t["jobEnvironments"] = [{"name": "gdofEnvironment", "variables": dict(job.env)}]
    return t


def write(job: FarmJob, path: str) -> None:
    """Writes the template as JSON (openjd reads .json and .yaml)."""
    with open(path, "w", encoding="utf-8") as f:
        json.dump(template(job, os.path.dirname(os.path.abspath(path))), f, indent=2)
        f.write("\n")
