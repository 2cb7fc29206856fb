"""Photographed focus sweeps from Python (gdof.align_sweep,
gdof.depth_from_focus) against the CLI's --depth-from-focus on the same
frames: equal bit for bit; a known shift found; errors as gdof.Error."""

import numpy as np
import pytest
from conftest import images_equal, run_cli

import gdof


def box_blur(a, r):
    """A (2 r + 1)^2 box mean with edges repeated (r = 0: a copy)."""
    if r == 0:
        return a.copy()
    p = np.pad(a, r, mode="edge")
    c = p.cumsum(0).cumsum(1)
    c = np.pad(c, ((1, 0), (1, 0)))
    k = 2 * r + 1
    return (c[k:, k:] - c[:-k, k:] - c[k:, :-k] + c[:-k, :-k]) / (k * k)


def make_sweep(n=5, w=120, h=80, seed=3):
    """n frames of a textured left half sharp at frame 2 and a right half
    sharp at frame n - 1, the blur growing by one box step per frame away."""
    rng = np.random.default_rng(seed)
    texture = rng.random((h, w)).astype(np.float32) * 0.5 + 0.25
    frames = []
    for k in range(n):
        left, right = box_blur(texture, abs(k - 1)), box_blur(texture, abs(k - (n - 1)))
        grey = np.where(np.arange(w)[None, :] < w // 2, left, right).astype(np.float32)
        pixels = np.stack([grey, grey * 0.9, grey * 0.8])
        frames.append(gdof.Image.from_array(np.ascontiguousarray(pixels), ["R", "G", "B"]))
    return frames


def test_depth_from_focus_equals_cli(cli, tmp_path):
    frames = make_sweep()
    for k, f in enumerate(frames):
        gdof.write_image(str(tmp_path / f"f.{k + 1:04d}.exr"), f)
    run_cli(cli, "--depth-from-focus", tmp_path / "f.####.exr", "-o", tmp_path / "cli.exr")
    plate, stats = gdof.depth_from_focus(frames)
    gdof.write_image(str(tmp_path / "py.exr"), plate)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
    assert stats.pixels == 120 * 80
    # The left half is sharpest in frame 2, the right in frame 5 (the index from 1).
    index = plate.channel("focus.index")
    assert abs(np.median(index[20:60, 10:50]) - 2.0) < 0.3
    assert abs(np.median(index[20:60, 70:110]) - 5.0) < 0.3
    # With focus distances the depth is theirs.
    plate_m, _ = gdof.depth_from_focus(frames, [1.0, 1.5, 2.0, 3.0, 4.0])
    assert abs(np.median(plate_m.channel("Z")[20:60, 10:50]) - 1.5) < 0.2


def test_align_sweep_finds_a_shift():
    frames = make_sweep(3)
    # Frame 3 moved 2 px right and 1 px down (np.roll: content at x lands at x + 2).
    moved = np.roll(frames[2].pixels, (1, 2), axis=(1, 2))
    frames[2] = gdof.Image.from_array(np.ascontiguousarray(moved), ["R", "G", "B"])
    aligned, alignment = gdof.align_sweep(frames)
    assert alignment.reference == 1
    m = alignment.maps[2]
    x, y = m.apply(60.0, 40.0)
    assert abs(x - 62.0) < 0.1 and abs(y - 41.0) < 0.1, (x, y)
    assert abs(m.scale - 1.0) < 1e-3
    assert len(aligned) == 3


def test_bad_sweeps_raise_gdof_error():
    frames = make_sweep(3)
    with pytest.raises(gdof.Error, match="at least 2 frames"):
        gdof.align_sweep(frames[:1])
    with pytest.raises(gdof.Error, match="rise or fall"):
        gdof.depth_from_focus(frames, [1.0, 3.0, 2.0])
    with pytest.raises(gdof.Error, match="min_peak_ratio"):
        gdof.depth_from_focus(frames, min_peak_ratio=0.5)
