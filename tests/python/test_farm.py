"""Farm jobs: the Open Job Description template, run locally by `openjd run`
over a 3-frame sequence, renders the frames a direct CLI run does; the
OpenCue outline is built and serialised without a Cuebot."""

import json
import os
import shlex
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from conftest import SOURCE, images_equal, run_cli

import gdof
from gdof.farm import FarmJob, chunk_ranges, parse_frames
from gdof.farm import __main__ as submit
from gdof.farm import openjd

FIELD = SOURCE / "examples/scene/two_planes.json"


def need(module):
    try:
        return __import__(module)
    except ImportError:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true, so this may not skip: {module} is not installed")
        pytest.skip(f"{module} is not installed (tests/python/requirements.txt)")


def openjd_cli():
    exe = Path(sys.executable).with_name("openjd")
    if exe.exists():
        return str(exe)
    found = shutil.which("openjd")
    if not found:
        need("openjd.cli")
    return found


@pytest.fixture
def sequence(scene, tmp_path):
    """in.1001.exr .. in.1003.exr: the scene, each frame brighter."""
    src = gdof.read_image(str(scene[0]))
    d = tmp_path / "in"
    d.mkdir()
    for k, frame in enumerate((1001, 1002, 1003)):
        s = gdof.read_image(str(scene[0]))
        s[0].pixels[0:3] *= 1.0 + 0.25 * k
        gdof.write_image(str(d / f"in.{frame}.exr"), s)
    return d / "in.####.exr"


def test_frames_and_chunks():
    assert parse_frames("1001-1003") == [1001, 1002, 1003]
    assert parse_frames("1-10x4,20") == [1, 5, 9, 20]
    assert parse_frames("3-1") == [3, 2, 1]
    assert chunk_ranges(parse_frames("1001-1005"), 2) == ["1001-1002", "1003-1004", "1005"]
    with pytest.raises(ValueError, match="cannot read 'x'"):
        parse_frames("1-3,x")
    with pytest.raises(ValueError, match="writes nothing"):
        FarmJob(command=["gdof", "in.exr", "--diffuse"], frames="1-3")
    with pytest.raises(ValueError, match="own --frames"):
        FarmJob(command=["gdof", "--frames", "1-3", "in.####.exr", "-o", "o.####.exr"], frames="1-3")


@pytest.mark.parametrize("chunk", [1, 2])
def test_openjd_run_renders_the_direct_cli_frames(cli, sequence, tmp_path, chunk):
    out = tmp_path / "farm"
    job = FarmJob(command=[cli, str(sequence), "--blurfield", str(FIELD), "--diffuse", "-o", str(out / "o.####.exr")],
                  frames="1001-1003", chunk=chunk, env={"GDOF_FARM_TEST": "1"}, name="defocus")
    out.mkdir()
    template = tmp_path / "job.json"
    openjd.write(job, str(template))
    t = json.loads(template.read_text())
    assert t["specificationVersion"] == "jobtemplate-2023-09"
    tasks = t["steps"][0]["parameterSpace"]["taskParameterDefinitions"][0]
    assert tasks["range"] == ([1001, 1002, 1003] if chunk == 1 else ["1001-1002", "1003"])
    assert t["parameterDefinitions"][0] == {"name": "OutputDir", "type": "PATH", "objectType": "DIRECTORY",
                                            "dataFlow": "OUT", "default": "farm",
                                            "description": "where gdof writes its frames"}
    assert t["steps"][0]["script"]["actions"]["onRun"]["args"][-1] == "{{Param.OutputDir}}/o.####.exr"
    r = subprocess.run([openjd_cli(), "run", str(template)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    direct = tmp_path / "direct"
    direct.mkdir()
    run_cli(cli, "--frames", "1001-1003", sequence, "--blurfield", FIELD, "--diffuse", "-o", direct / "o.####.exr")
    for frame in (1001, 1002, 1003):
        assert images_equal(out / f"o.{frame}.exr", direct / f"o.{frame}.exr")
    # The frames differ (each task rendered its own).
    a = gdof.read_image(str(out / "o.1001.exr"))[0].channel("R")
    b = gdof.read_image(str(out / "o.1003.exr"))[0].channel("R")
    assert (b > a).any()


def test_opencue_outline_serialised_without_a_cuebot(tmp_path):
    need("outline")
    from gdof.farm import opencue

    job = FarmJob(command=["gdof", "/shots/in.####.exr", "--diffuse", "-o", "/shots/out/o.####.exr"],
                  frames="1001-1100", chunk=10, env={"OCIO": "/show/config.ocio"}, name="shot_defocus")
    ol = opencue.build(job, show="show", shot="sh010", user="tester")
    layers = ol.get_layers()
    assert len(layers) == 1 and layers[0].get_chunk_size() == 10
    spec = ET.fromstring(opencue.serialize(job, show="show", shot="sh010", user="tester"))
    layer = spec.find("job/layers/layer")
    assert spec.find("job").get("name") == "shot_defocus"
    assert layer.find("range").text == "1001-1100" and layer.find("chunk").text == "10"
    assert shlex.split(layer.find("cmd").text) == ["gdof", "--frames", "#FRAME_START#-#FRAME_END#",
                                                   "/shots/in.####.exr", "--diffuse", "-o", "/shots/out/o.####.exr"]
    assert spec.find("job/env/key").get("name") == "OCIO"
    assert layer.find("outputs/output").text == "/shots/out/o.####.exr"


def test_submit_command_line(tmp_path, capsys):
    need("outline")
    rc = submit.main(["--frames", "1-4", "--chunk", "2", "--openjd", str(tmp_path / "j.json"), "--opencue",
                      str(tmp_path / "j.xml"), "--env", "A=b", "--", "gdof", "i.####.exr", "-o", "/o/x.####.exr"])
    assert rc == 0 and "2 tasks" in capsys.readouterr().out
    assert json.loads((tmp_path / "j.json").read_text())["jobEnvironments"][0]["variables"] == {"A": "b"}
    assert "<range>1-4</range>" in (tmp_path / "j.xml").read_text()
    assert submit.main(["--frames", "1-4", "--openjd", "x.json", "gdof"]) == 2
    assert submit.main(["--frames", "1-4", "--openjd", "x.json", "--", "gdof", "in.exr"]) == 2
    err = capsys.readouterr().err
    assert "after --" in err and "writes nothing" in err
