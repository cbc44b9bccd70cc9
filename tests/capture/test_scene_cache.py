"""Two processes making one output folder at once (engine.base.output_dir, engine.capture.scene_cache): two
trainings of one capture at 1/8 of its size both built the downscaled copy, and the one that finished second
swapped its copy in while the first read from it (`cannot decode image file .../images/03.jpg`)."""

from __future__ import annotations

from pathlib import Path

import pytest

from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.capture.scene_cache import cached_scene


def _written_by_another(final: Path) -> None:
    """What the other process leaves: the finished folder, in place before this one finishes."""
    (final / "sparse").mkdir(parents=True)
    (final / "sparse" / "theirs.txt").write_text("theirs")


def test_a_folder_another_process_filled_meanwhile_is_kept_and_this_one_refused(tmp_path: Path):
    final = tmp_path / "out"
    with pytest.raises(InputError, match="written by another process"):
        with atomic_output_dir(final) as tmp:
            (tmp / "mine.txt").write_text("mine")
            _written_by_another(final)
    assert (final / "sparse" / "theirs.txt").read_text() == "theirs" and not (final / "mine.txt").exists()
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no temporary folder left


def test_the_cache_copy_made_first_is_the_one_both_read(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("SPLATFILL_CACHE", str(tmp_path / "cache"))
    scene = tmp_path / "scene"
    (scene / "sparse" / "0").mkdir(parents=True)
    for name in ("cameras.txt", "images.txt", "points3D.txt"):  # the key reads their times and sizes alone
        (scene / "sparse" / "0" / name).write_text("")
    (scene / "images").mkdir()
    first: list[Path] = []

    def build(tmp: Path) -> None:  # while this one builds, the other process finishes the same copy
        (tmp / "sparse").mkdir()
        (tmp / "sparse" / "mine.txt").write_text("mine")
        first.append(tmp.parent / tmp.name.split(".tmp-")[0].lstrip("."))
        _written_by_another(first[0])

    cache = cached_scene(scene, "resolution8", build)
    assert cache == first[0] and (cache / "sparse" / "theirs.txt").read_text() == "theirs"
    assert not (cache / "sparse" / "mine.txt").exists()


def test_an_empty_folder_given_as_the_output_is_filled(tmp_path: Path):
    (tmp_path / "out").mkdir()
    with atomic_output_dir(tmp_path / "out") as tmp:
        (tmp / "mine.txt").write_text("mine")
    assert (tmp_path / "out" / "mine.txt").read_text() == "mine" and len(list(tmp_path.iterdir())) == 1
