"""Render-farm jobs for existing schedulers: a gdof command line with a frame
range becomes an Open Job Description job template (openjd) or an OpenCue
job (opencue), one task per frame or per chunk of frames.

Pure Python: no extension module is needed, so a submission machine only
needs this package. `python -m gdof.farm` (or `gdof-submit`) is the command
line; FarmJob is the description every backend reads, so a wrangler adds a
scheduler (Deadline, Tractor, ...) as one more function of a FarmJob
(docs/farm.md).
"""

from .job import FarmJob, chunk_ranges, parse_frames  # noqa: F401

__all__ = ["FarmJob", "chunk_ranges", "parse_frames"]
