"""Blur fields from dicts, JSON text and files agree; the thin lens matches
its formula; cameras resolve from an image's attributes."""

import json

import numpy as np
import pytest
from conftest import SOURCE

import gdof

SPEC = {"blurfield": {"kind": "focal_planes", "depths": [2.9, 12.6], "max_blur": 10, "slope": 6,
                      "interpolation": "smooth"}}


@pytest.fixture
def camera():
    return gdof.Camera.look_at((0, 1, 0), (0, 1, 10), focal_length_mm=35, display_window=(0, 0, 320, 180))


def points(n=200):
    rng = np.random.default_rng(11)
    p = rng.uniform([-3, -2, 0.5], [3, 4, 40], (n, 3))
    return p


def test_dict_json_text_and_file_agree(camera, tmp_path):
    path = tmp_path / "f.json"
    path.write_text(json.dumps(SPEC))
    a = gdof.BlurField.parse(SPEC).evaluate(camera, points())
    b = gdof.BlurField.parse(json.dumps(SPEC)).evaluate(camera, points())
    c = gdof.BlurField.read(str(path)).evaluate(camera, points())
    assert a.dtype == np.float32 and a.shape == (200,)
    assert np.array_equal(a, b) and np.array_equal(a, c)
    assert 0 < a.max() <= 10 and a.min() >= 0


def test_example_file_reads(camera):
    f = gdof.BlurField.read(str(SOURCE / "examples/scene/two_planes.json"))
    assert f.describe().startswith("focal_planes") and f.depth_only


def test_thin_lens_field_matches_the_formula(camera):
    lens = gdof.ThinLens(focal_length_mm=50, f_number=2.0, focus_distance=3.0, sensor_width_mm=36,
                         image_width_px=320)
    field = gdof.BlurField.from_thin_lens(lens)
    cam = gdof.Camera.look_at((0, 0, 0), (0, 0, -1), focal_length_mm=50, display_window=(0, 0, 320, 180))
    for depth in [1.0, 2.0, 3.0, 7.5, 40.0]:
        f, n, s = 50.0, 2.0, 3000.0
        z = depth * 1000.0
        c = (f / n) * f * abs(z - s) / (z * (s - f))  # sensor CoC diameter, mm
        expected = c / 2 * 320 / 36
        got = field.evaluate(cam, [(0.0, 0.0, -depth)])[0]
        assert got == pytest.approx(expected, rel=1e-5), depth


def test_camera_from_the_example_scene(scene):
    img = gdof.read_image(str(scene[0]))[0]
    cam = gdof.resolve_camera(img.metadata, img.display_window)
    assert cam.lens.complete and cam.display_window == img.display_window
    p = np.array([cam.unproject(40.5, 30.5, 6.0)])
    px = cam.project(p)[0]
    assert px == pytest.approx([40.5, 30.5, 6.0], rel=1e-9)
    override = gdof.resolve_camera(img.metadata, img.display_window, f_number=11.0)
    assert override.lens.f_number == 11.0


def test_bad_field_names_the_key():
    with pytest.raises(gdof.Error, match=r"blurfield\.depths"):
        gdof.BlurField.parse({"blurfield": {"kind": "focal_planes", "depths": "x", "max_blur": 3}})
