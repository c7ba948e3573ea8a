"""physik.view(): the page of `physik view` from Python (viewer/view_page.h), byte for byte; bad
folders raise InputError naming the folder; in Jupyter the View displays in place."""
import os

import pytest

import physik
from conftest import cli, scene_path


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory):
    out = str(tmp_path_factory.mktemp("view") / "run")
    status, _, err = cli("simulate", scene_path("pinhead_two_hands"), "--steps", "30", "--every",
                         "3", "--quiet", "--out", out)
    assert status == 0, err
    return out


def test_the_same_page_as_the_cli(run_folder, tmp_path):
    mine = tmp_path / "py.html"
    v = physik.view([run_folder, run_folder], mine, title="two", labels=["a", "b"], max_frames=5)
    theirs = tmp_path / "cli.html"
    status, _, err = cli("view", run_folder, run_folder, "--title", "two", "--label", "a",
                         "--label", "b", "--max-frames", "5", "--out", theirs)
    assert status == 0, err
    assert mine.read_bytes() == theirs.read_bytes()
    assert v.path == str(mine) and v.size == os.path.getsize(mine)


def test_default_path_is_in_the_first_folder(run_folder):
    v = physik.view(run_folder)
    assert v.path == os.path.join(run_folder, "view.html") and os.path.isfile(v.path)


def test_a_folder_that_is_not_a_run_raises_naming_it(tmp_path):
    with pytest.raises(physik.InputError, match=str(tmp_path) + ": not a run folder: no scene.json"):
        physik.view(str(tmp_path), tmp_path / "x.html")


def test_shown_in_place_in_jupyter(run_folder, tmp_path):
    v = physik.view(run_folder, tmp_path / "j.html", title="<b>t</b>")
    frame = v._repr_html_()
    assert frame.startswith('<iframe srcdoc="') and frame.endswith("></iframe>")
    inner = frame[len('<iframe srcdoc="'):frame.index('" style=')]
    assert "<" not in inner and '"' not in inner  # the page is an attribute's text
    assert "&lt;script type=&quot;application/json&quot;" in inner
