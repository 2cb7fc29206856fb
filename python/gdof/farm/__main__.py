"""gdof-submit / python -m gdof.farm: a gdof command line over a frame range
as an Open Job Description template and/or an OpenCue job spec.

    gdof-submit --frames 1001-1100 --chunk 10 --openjd job.json --opencue job.xml \\
        --env OCIO=/show/ocio/config.ocio -- \\
        gdof in.####.exr --blurfield field.json --diffuse -o out/defocus.####.exr
"""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional

from .job import FarmJob


def main(argv: Optional[List[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--" not in argv:
        print("gdof-submit: error: give the gdof command line after --", file=sys.stderr)
        return 2
    split = argv.index("--")
    ours, command = argv[:split], argv[split + 1:]
    p = argparse.ArgumentParser(prog="gdof-submit", description=__doc__.split("\n\n")[0])
    p.add_argument("--frames", required=True, help="the frame range, as gdof --frames reads it (1001-1100, 1-10x2)")
    p.add_argument("--chunk", type=int, default=1, help="frames per task (default 1)")
    p.add_argument("--name", default="gdof", help="the job's name")
    p.add_argument("--env", action="append", default=[], metavar="NAME=VALUE", help="environment of every task")
    p.add_argument("--openjd", metavar="FILE", help="write an Open Job Description template (JSON)")
    p.add_argument("--opencue", metavar="FILE", help="write an OpenCue job spec (XML; needs opencue-pyoutline)")
    p.add_argument("--show", default="gdof", help="OpenCue show")
    p.add_argument("--shot", default="gdof", help="OpenCue shot")
    p.add_argument("--user", default="gdof", help="OpenCue user")
    a = p.parse_args(ours)
    env = {}
    for item in a.env:
        if "=" not in item:
            p.error(f"--env: expected NAME=VALUE, got '{item}'")
        k, v = item.split("=", 1)
        env[k] = v
    if not a.openjd and not a.opencue:
        p.error("nothing to write: give --openjd FILE and/or --opencue FILE")
    try:
        job = FarmJob(command=command, frames=a.frames, chunk=a.chunk, env=env, name=a.name)
    except ValueError as e:
        print(f"gdof-submit: error: {e}", file=sys.stderr)
        return 2
    if a.openjd:
        from . import openjd

        openjd.write(job, a.openjd)
    if a.opencue:
        from . import opencue

        spec = opencue.serialize(job, show=a.show, shot=a.shot, user=a.user)
        with open(a.opencue, "w", encoding="utf-8") as f:
            f.write(spec)
    print(f"gdof-submit: {len(job.chunks)} tasks over frames {a.frames}"
          + (f", template {a.openjd}" if a.openjd else "") + (f", OpenCue spec {a.opencue}" if a.opencue else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
