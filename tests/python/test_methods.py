"""Methods 1 and 2 and light-field extraction from Python against the CLI on
the same inputs: equal bit for bit."""

import json
import subprocess

import pytest
from conftest import SOURCE, images_equal, run_cli, tool

import gdof


@pytest.fixture(scope="module")
def lightfield(tmp_path_factory):
    make = tool("GDOF_EXAMPLE_LIGHTFIELD")
    d = tmp_path_factory.mktemp("lf")
    subprocess.run([make, "-o", str(d / "views"), "--size", "96x64"], check=True, capture_output=True)
    return d / "views"


def test_extract_stack_and_composite_equal_cli(cli, lightfield, tmp_path):
    views = str(lightfield / "view_%02d_%02d.png")
    lf = lightfield / "lf.json"
    stack = SOURCE / "examples/lightfield/stack_generated.json"
    run_cli(cli, "--lightfield", views, "--lf", lf, "--stack", stack, "-o", tmp_path / "cli/ref.####.exr")
    images, manifest = gdof.extract_stack(views, stack=str(stack), lf=str(lf))
    expected = json.loads((tmp_path / "cli/manifest.json").read_text())
    assert len(images) == len(expected["references"]) == 18
    (tmp_path / "py").mkdir()
    ours = json.loads(manifest)
    for i, img in enumerate(images):
        name = f"ref.{i + 1:04d}.exr"
        gdof.write_image(str(tmp_path / "py" / name), img)
        assert images_equal(tmp_path / "cli" / name, tmp_path / "py" / name)
        ours["references"][i]["file"] = name
    assert ours == expected

    # Method 2 over that stack, with the CLI's surfaces.
    surfaces = SOURCE / "examples/lightfield/surfaces_tilt.json"
    manifest_path = tmp_path / "cli/manifest.json"
    run_cli(cli, "--composite", manifest_path, "--surfaces", surfaces, "--soft", "2", "-o", tmp_path / "c_cli.exr")
    out = gdof.composite(str(manifest_path), surfaces=str(surfaces), soft=2)
    gdof.write_image(str(tmp_path / "c_py.exr"), out)
    assert images_equal(tmp_path / "c_cli.exr", tmp_path / "c_py.exr")
    # The surfaces as a dict give the same.
    out2 = gdof.composite(str(manifest_path), surfaces=json.loads(surfaces.read_text()), soft=2)
    assert (out2.pixels == out.pixels).all()


@pytest.mark.parametrize("deep", [False, True])
def test_render_equals_cli(cli, tmp_path, deep):
    scene = SOURCE / "examples/render/generated.json"
    field = SOURCE / "examples/render/generated_two_planes.json"
    flags = ["--spp", "4", "--min-spp", "4"] + (["--deep"] if deep else [])
    try:
        run_cli(cli, "--render", scene, "--blurfield", field, *flags, "-o", tmp_path / "cli.exr")
    except AssertionError as e:
        if "without Embree" in str(e):
            pytest.skip("built without Embree")
        raise
    out = gdof.render(str(scene), gdof.BlurField.read(str(field)), spp=4, min_spp=4, deep=deep)
    assert isinstance(out, gdof.DeepImage if deep else gdof.Image)
    gdof.write_image(str(tmp_path / "py.exr"), out)
    assert images_equal(tmp_path / "cli.exr", tmp_path / "py.exr")
