"""Method 4 (the PSF field, filter="vibrate") from Python against the CLI's
--vibrate on the same inputs: equal bit for bit; PsfField from a file, a dict
and JSON text; a bad field raises gdof.Error naming the key."""

import json

import numpy as np
import pytest
from conftest import SOURCE, images_equal, run_cli

import gdof

TWO_PLANES = SOURCE / "examples/scene/two_planes.json"
SWIRL = SOURCE / "examples/psf_fields/swirl.json"


def test_vibrate_with_a_field_file_equals_cli(cli, scene, tmp_path):
    _, deep = scene
    run_cli(cli, deep, "--blurfield", TWO_PLANES, "--psf-field", SWIRL, "--psf-samples", "32", "--vibrate",
            "-o", tmp_path / "cli.exr")
    stats = gdof.DefocusStats()
    out = gdof.defocus(gdof.read_image(str(deep)), gdof.BlurField.read(str(TWO_PLANES)), filter="vibrate",
                       psf_field=str(SWIRL), psf_samples=32, stats=stats)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
    assert stats.layers_vibrated >= 1
    assert 24 <= stats.vibrate.samples <= 40  # the lattice's count nearest 32
    assert stats.vibrate.max_displacement_px > 0 and stats.vibrate.splats > 0


def test_options_object_with_a_parsed_field_equals_cli(cli, scene, tmp_path):
    flat, deep = scene
    run_cli(cli, flat, "--blurfield", TWO_PLANES, "--psf-field", SWIRL, "--psf-samples", "24", "--vibrate",
            "-o", tmp_path / "cli.exr")
    options = gdof.DefocusOptions()
    options.filter = "vibrate"
    options.psf_field = gdof.PsfField.parse(json.loads(SWIRL.read_text()))
    options.vibrate.samples = 24
    assert options.filter == "vibrate" and options.vibrate.samples == 24
    out = gdof.defocus(gdof.read_image(str(flat)), gdof.BlurField.read(str(TWO_PLANES)), options=options)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
    # The swirl did something the default defocus field does not.
    plain = gdof.defocus(gdof.read_image(str(flat)), gdof.BlurField.read(str(TWO_PLANES)), filter="vibrate",
                         psf_samples=24)
    assert np.abs(out[0].channel("R") - plain[0].channel("R")).max() > 1e-2


def test_field_from_file_dict_and_text_agree():
    from_file = gdof.PsfField.read(str(SWIRL))
    spec = json.loads(SWIRL.read_text())
    for field in (gdof.PsfField.parse(spec), gdof.PsfField.parse(json.dumps(spec))):
        assert field.describe() == from_file.describe()
    assert "swirl" in from_file.describe() and not from_file.moves_depth
    assert gdof.PsfField().describe() == "defocus"
    assert gdof.PsfField.parse({"psf_field": {"kind": "depth", "distance": 1}, "samples": 77}).samples == 77
    assert gdof.PsfField.parse({"psf_field": {"kind": "depth", "distance": 1}}).moves_depth


def test_bad_field_raises_the_library_error_naming_the_key(scene, tmp_path):
    bad = {"psf_field": {"kind": "sum", "children": [{"kind": "defocus"}, {"kind": "swirl", "strenght": 2}]}}
    with pytest.raises(gdof.Error, match=r"psf_field\.children\[1\]\.strenght: unknown key") as e:
        gdof.PsfField.parse(bad)
    assert e.value.code == "invalid_argument"
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad))
    with pytest.raises(gdof.Error, match=r"bad\.json.*psf_field\.children\[1\]\.strenght"):
        gdof.PsfField.read(str(path))
    with pytest.raises(gdof.Error, match=r"psf_field\.children\[1\]\.strenght"):
        gdof.defocus(gdof.read_image(str(scene[0])), filter="vibrate", psf_field=bad)
    with pytest.raises(gdof.Error, match="filter: expected diffusion, bokeh or vibrate, got 'vibrato'"):
        gdof.defocus(gdof.read_image(str(scene[0])), filter="vibrato")
