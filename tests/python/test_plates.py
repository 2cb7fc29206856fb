"""Live-action plates from Python against the CLI: focus_at= is --focus-at,
probe() is --probe, Image.attach_depth is --depth FILE."""

import math
import re

import numpy as np
import pytest
from conftest import SOURCE, images_equal, run_cli

import gdof

THIN_LENS = SOURCE / "examples/blurfields/thin_lens.json"


def test_focus_at_equals_cli(cli, scene, tmp_path):
    flat, _ = scene
    # The thin lens of the scene's camera, and a blur field refocused there.
    run_cli(cli, flat, "--f-number", "1.4", "--focus-at", "100,60", "--diffuse", "-o", tmp_path / "cli.exr")
    out = gdof.defocus(gdof.read_image(str(flat)), f_number=1.4, focus_at=(100, 60))
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
    run_cli(cli, flat, "--blurfield", THIN_LENS, "--focus-at", "100,60", "--diffuse", "-o", tmp_path / "cli2.exr")
    out = gdof.defocus(gdof.read_image(str(flat)), gdof.BlurField.read(str(THIN_LENS)), focus_at=(100, 60))
    gdof.write_image(str(tmp_path / "py2.exr"), out)
    assert images_equal(tmp_path / "cli2.exr", tmp_path / "py2.exr")
    # Focusing elsewhere changes the picture: the keyword is not ignored.
    other = gdof.defocus(gdof.read_image(str(flat)), f_number=1.4, focus_at=(5, 5))
    assert not np.array_equal(other[0].channel("R"), gdof.read_image(str(tmp_path / "py.exr"))[0].channel("R"))
    with pytest.raises(gdof.Error, match="focus_at"):
        gdof.defocus(gdof.read_image(str(flat)), focus_at=(1, 2, 3))


def probe_numbers(text):
    """depth, world (x, y, z), blur from a --probe line."""
    m = re.search(r"depth (\S+), world \((\S+), (\S+), (\S+)\), blur (\S+) px", text)
    assert m, text
    return [float(v) for v in m.groups()]


def test_probe_equals_cli_and_needs_no_lens(cli, scene):
    flat, _ = scene
    line = run_cli(cli, flat, "--f-number", "1.4", "--probe", "100,60").stdout
    p = gdof.probe(gdof.read_image(str(flat)), 100, 60, f_number=1.4)
    depth, wx, wy, wz, blur = probe_numbers(line)
    assert p.x == 100 and p.y == 60
    assert p.depth == pytest.approx(depth, rel=1e-5)
    assert p.position == pytest.approx((wx, wy, wz), rel=1e-5, abs=1e-6)
    assert p.blur_px == pytest.approx(blur, rel=1e-5, abs=1e-6)
    assert p.blur_px > 0.1  # the scene's camera at f/1.4 blurs there
    # A plate with no camera at all: the depth alone; a focal length adds
    # the world position, which is the depth along +z at the centre.
    z = np.full((90, 160), 4.0, dtype=np.float32)
    rgbaz = np.stack([np.full_like(z, 0.5)] * 3 + [np.ones_like(z), z])
    plate = gdof.Image.from_array(rgbaz, ["R", "G", "B", "A", "Z"])
    bare = gdof.probe(plate, 80, 45)
    assert bare.depth == pytest.approx(4.0)
    assert all(math.isnan(v) for v in bare.position) and math.isnan(bare.blur_px)
    focal = gdof.probe(plate, 80, 45, focal_length_mm=35, sensor_width_mm=36)
    assert focal.position[2] == pytest.approx(4.0) and abs(focal.position[0]) < 0.05
    assert math.isnan(focal.blur_px)
    with pytest.raises(gdof.Error, match="depth channel 'Q'"):
        gdof.probe(plate, 80, 45, depth_channel="Q")


def test_probe_gives_the_parts_the_defocus_splits(cli, tmp_path):
    # A bar's anti-aliased right edge (0.4 bar, 0.6 wall) with a renderer's
    # filtered Z. Focused on the bar the defocus splits it: probe() gives its
    # parts as --probe prints them; focused on the wall it stays whole.
    h, w, share = 48, 64, 0.4
    xx = np.mgrid[0:h, 0:w][1]
    bar, edge = (xx >= 20) & (xx < 30), xx == 30
    red = np.where(bar, 1.0, np.where(edge, share + (1 - share) * 0.3, 0.3))
    grey = np.where(bar, 0.0, np.where(edge, (1 - share) * 0.3, 0.3))
    z = np.where(bar, 2.0, np.where(edge, share * 2.0 + (1 - share) * 5.0, 5.0))
    plate = gdof.Image.from_array(np.stack([red, grey, grey, np.ones_like(z), z]).astype(np.float32),
                                  ["R", "G", "B", "A", "Z"])
    gdof.write_image(str(tmp_path / "edge.exr"), plate)
    lens = dict(focal_length_mm=35, sensor_width_mm=36, f_number=0.1)
    p = gdof.probe(plate, 30, 20, focus_distance=2, **lens)
    line = run_cli(cli, tmp_path / "edge.exr", "--focal-length-mm", "35", "--sensor-width-mm", "36", "--f-number",
                   "0.1", "--focus-distance", "2", "--probe", "30,20").stdout
    m = re.search(r"split silhouette pixel: (\S+) foreground at depth (\S+) \(blur (\S+) px\), "
                  r"the rest at depth (\S+) \(blur (\S+) px\)", line)
    assert m, line
    assert p.mixed
    assert [p.fg_share, p.fg_depth, p.fg_blur_px, p.bg_depth, p.bg_blur_px] == pytest.approx(
        [float(v) for v in m.groups()], rel=1e-5, abs=1e-6)
    assert p.fg_share == pytest.approx(share, abs=0.05) and p.bg_blur_px > 3 * p.fg_blur_px + 0.5
    whole = gdof.probe(plate, 30, 20, focus_distance=5, **lens)
    assert not whole.mixed and math.isnan(whole.fg_share) and math.isnan(whole.bg_blur_px)


def test_attach_depth_equals_cli_depth_file(cli, tmp_path):
    # An RGBA plate and a depth map of its own (uint16-like counts in a
    # float EXR), attached: the same result as the CLI's --depth.
    h, w = 48, 64
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    rgba = np.stack([0.2 + 0.1 * ((xx // 4 + yy // 4) % 3), np.full_like(xx, 0.3), np.full_like(xx, 0.4),
                     np.ones_like(xx)]).astype(np.float32)
    depth = np.where((xx >= 20) & (xx < 30), 2.0, 5.0).astype(np.float32)[None]
    gdof.write_image(str(tmp_path / "rgba.exr"), gdof.Image.from_array(rgba, ["R", "G", "B", "A"]))
    gdof.write_image(str(tmp_path / "depth.exr"), gdof.Image.from_array(depth, ["Y"]))
    lens = ["--focal-length-mm", "35", "--sensor-width-mm", "36", "--f-number", "1", "--focus-distance", "5"]
    run_cli(cli, tmp_path / "rgba.exr", "--depth", tmp_path / "depth.exr", *lens, "--diffuse", "-o", tmp_path / "cli.exr")
    plate = gdof.read_image(str(tmp_path / "rgba.exr"))[0]
    plate.attach_depth(gdof.read_image(str(tmp_path / "depth.exr"))[0])
    assert "Z" in plate.channel_names
    out = gdof.defocus(plate, focal_length_mm=35, sensor_width_mm=36, f_number=1, focus_distance=5)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
    small = gdof.Image.from_array(depth[:, :10, :10].copy(), ["Y"])
    with pytest.raises(gdof.Error, match="10x10"):
        plate.attach_depth(small)


def test_lens_at_frame_equals_cli_lens_table(cli, scene, tmp_path):
    # A focus pull keyed at frames 1 and 3: frame 2's lens from Python's
    # lens_at_frame, splatted into defocus(), equals the CLI's sequence frame.
    flat, _ = scene
    (tmp_path / "in.0002.exr").write_bytes(flat.read_bytes())
    (tmp_path / "lens.csv").write_text("frame,focus_distance,f_number\n1,2,1.4\n3,6,2.8\n")
    run_cli(cli, "--frames", "2", tmp_path / "in.####.exr", "--lens-table", tmp_path / "lens.csv", "--diffuse",
            "-o", tmp_path / "cli.####.exr")
    lens = gdof.lens_at_frame(str(tmp_path / "lens.csv"), 2)
    assert lens == pytest.approx({"focus_distance": 3.0, "f_number": 2.1})
    out = gdof.defocus(gdof.read_image(str(flat)), **lens)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.0002.exr", tmp_path / "py.exr")
    with pytest.raises(gdof.Error, match="missing.csv"):
        gdof.lens_at_frame(str(tmp_path / "missing.csv"), 2)
