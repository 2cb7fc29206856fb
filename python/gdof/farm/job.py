"""FarmJob: what a farm needs to know about a gdof run over a frame range.

The gdof command line is written for one run with frame patterns in its
file names (in.####.exr ... -o out.####.exr); each task runs it with
`--frames FIRST-LAST` for its chunk, which gdof expands itself.
"""

from __future__ import annotations

import os
import re
import shlex
from dataclasses import dataclass, field
from typing import Dict, List, Sequence

_RANGE = re.compile(r"^(-?\d+)(?:-(-?\d+)(?:x(\d+))?)?$")


def parse_frames(spec: str) -> List[int]:
    """Frames of a range as gdof --frames reads it: '1001-1100', '1-10x2',
    '1,3,7-9', '10-1' (backwards). Raises ValueError naming the bad part."""
    frames: List[int] = []
    for part in spec.split(","):
        m = _RANGE.match(part.strip())
        if not m:
            raise ValueError(f"frames: cannot read '{part}' in '{spec}' (expected e.g. 1001-1100, 1-10x2, 1,3,7-9)")
        first = int(m.group(1))
        last = int(m.group(2)) if m.group(2) is not None else first
        step = int(m.group(3)) if m.group(3) else 1
        if step < 1:
            raise ValueError(f"frames: the step of '{part}' must be at least 1")
        direction = 1 if last >= first else -1
        frames.extend(range(first, last + direction, direction * step))
    if not frames:
        raise ValueError(f"frames: '{spec}' has no frame")
    return frames


def chunk_ranges(frames: Sequence[int], chunk: int) -> List[str]:
    """The frames cut into chunks of at most `chunk` consecutive entries, each
    written as gdof --frames reads it ('1001-1010', or '1001' alone; a chunk
    whose frames are not consecutive is a list, '1,3,5')."""
    if chunk < 1:
        raise ValueError(f"chunk: must be at least 1, got {chunk}")
    out = []
    for i in range(0, len(frames), chunk):
        part = list(frames[i:i + chunk])
        step = part[1] - part[0] if len(part) > 1 else 1
        if len(part) == 1:
            out.append(str(part[0]))
        elif step == 1 and all(b - a == 1 for a, b in zip(part, part[1:])):
            out.append(f"{part[0]}-{part[-1]}")
        else:
            out.append(",".join(str(f) for f in part))
    return out


@dataclass
class FarmJob:
    """A gdof command line run over frames on a farm.

    command: the whole command line, the program first (['gdof', 'in.####.exr',
    '--diffuse', '-o', 'out.####.exr']); frames: a range as for --frames;
    chunk: frames per task; env: variables every task gets (OCIO, ...);
    name: the job's name."""

    command: List[str]
    frames: str
    chunk: int = 1
    env: Dict[str, str] = field(default_factory=dict)
    name: str = "gdof"

    def __post_init__(self) -> None:
        if not self.command:
            raise ValueError("command: empty; give the gdof command line, the program first")
        if "--frames" in self.command:
            raise ValueError("command: has its own --frames; give the range as the job's frames")
        if not self.outputs():
            raise ValueError("command: writes nothing (no -o)")
        self.frame_list = parse_frames(self.frames)
        self.chunks = chunk_ranges(self.frame_list, self.chunk)

    def outputs(self) -> List[str]:
        """The -o file names (with their frame patterns), as given."""
        return [self.command[i + 1] for i, a in enumerate(self.command[:-1]) if a == "-o"]

    def output_folders(self) -> List[str]:
        """The absolute folders the outputs go to (the farm creates or syncs them)."""
        seen: List[str] = []
        for o in self.outputs():
            d = os.path.dirname(os.path.abspath(o))
            if d not in seen:
                seen.append(d)
        return seen

    def task_command(self, frames: str) -> List[str]:
        """The command one task runs for its chunk."""
        return [self.command[0], "--frames", frames] + list(self.command[1:])

    def shell_command(self, frames: str) -> str:
        return " ".join(shlex.quote(a) for a in self.task_command(frames))
