"""Method 3 from Python against the CLI on the same inputs: equal bit for bit."""

import numpy as np
import pytest
from conftest import SOURCE, images_equal, run_cli

import gdof

TWO_PLANES = SOURCE / "examples/scene/two_planes.json"
SPHERE = SOURCE / "examples/scene/sphere_of_focus.json"


def test_defocus_equals_cli_diffuse(cli, scene, tmp_path):
    flat, _ = scene
    run_cli(cli, flat, "--blurfield", TWO_PLANES, "--diffuse", "-o", tmp_path / "cli.exr")
    out = gdof.defocus(gdof.read_image(str(flat)), gdof.BlurField.read(str(TWO_PLANES)))
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
    # Something was blurred: the result is not the input's colour.
    src = gdof.read_image(str(flat))[0]
    assert not np.array_equal(out[0].channel("R"), src.channel("R"))


def test_defocus_deep_with_flags_equals_cli(cli, scene, tmp_path):
    _, deep = scene
    run_cli(cli, deep, "--blurfield", SPHERE, "--solver", "explicit", "--layers", "4", "--pyramid", "off",
            "--diffuse", "-o", tmp_path / "cli.exr")
    stats = gdof.DefocusStats()
    out = gdof.defocus(gdof.read_image(str(deep)), gdof.BlurField.read(str(SPHERE)), solver="explicit", layers=4,
                       pyramid=False, stats=stats)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
    assert stats.layers == 4 and stats.layers_explicit >= 1 and stats.layers_pyramid == 0


def test_bokeh_options_object_equals_cli(cli, scene, tmp_path):
    flat, _ = scene
    run_cli(cli, flat, "--blurfield", TWO_PLANES, "--aperture", "polygon:6:15,roundness=0.2", "--bokeh",
            "-o", tmp_path / "cli.exr")
    options = gdof.DefocusOptions()
    options.filter = "bokeh"
    options.aperture = "polygon:6:15,roundness=0.2"
    out = gdof.defocus(gdof.read_image(str(flat)), gdof.BlurField.read(str(TWO_PLANES)), options=options)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")


def test_thin_lens_default_and_lens_keywords_equal_cli(cli, scene, tmp_path):
    flat, _ = scene
    run_cli(cli, flat, "--f-number", "1.4", "--focus-distance", "5", "--diffuse", "-o", tmp_path / "cli.exr")
    out = gdof.defocus(gdof.read_image(str(flat)), f_number=1.4, focus_distance=5)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")


def test_progress_is_called_and_its_exception_stops_the_work(scene):
    flat, _ = scene
    seen = []
    gdof.defocus(gdof.read_image(str(flat)), gdof.BlurField.read(str(TWO_PLANES)), progress=seen.append)
    assert seen and all(0.0 <= f <= 1.0 for f in seen)

    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop()

    with pytest.raises(Stop):
        gdof.defocus(gdof.read_image(str(flat)), gdof.BlurField.read(str(TWO_PLANES)), progress=stop)


def test_unknown_keyword_is_a_type_error(scene):
    with pytest.raises(TypeError, match="unknown keyword 'solvr'"):
        gdof.defocus(gdof.read_image(str(scene[0])), solvr="adi")
