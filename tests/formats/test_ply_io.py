"""The 3DGS .ply layout with identities: exact round trip, standard files, clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch
from plyfile import PlyData, PlyElement

from engine.base.errors import InputError
from engine.io.gaussians import new_classifier
from engine.io.ply_io import load_classifier, load_ply, save_classifier, save_ply


def random_gaussians(n: int = 100, k: int = 15) -> dict[str, torch.Tensor]:
    g = torch.Generator().manual_seed(0)
    shapes = {"means": (n, 3), "quats": (n, 4), "scales": (n, 3), "opacities": (n,), "sh0": (n, 1, 3),
              "shN": (n, k, 3), "identity": (n, 16)}
    return {name: torch.randn(*shape, generator=g) for name, shape in shapes.items()}


def test_round_trip_is_exact(tmp_path: Path):
    gaussians = random_gaussians()
    save_ply(tmp_path / "g.ply", gaussians)
    loaded = load_ply(tmp_path / "g.ply")
    assert loaded.keys() == gaussians.keys()
    for name in gaussians:
        assert torch.equal(loaded[name], gaussians[name]), name


def test_layout_is_the_standard_3dgs_one_plus_identity(tmp_path: Path):
    save_ply(tmp_path / "g.ply", random_gaussians(5))
    names = list(PlyData.read(str(tmp_path / "g.ply"))["vertex"].data.dtype.names)
    assert names[:9] == ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"]
    assert names[9:54] == [f"f_rest_{i}" for i in range(45)]
    assert names[54:62] == ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    assert names[62:] == [f"obj_dc_{i}" for i in range(16)]


def test_f_rest_is_channel_major_as_in_the_reference_code(tmp_path: Path):
    gaussians = random_gaussians(3)
    save_ply(tmp_path / "g.ply", gaussians)
    vertex = PlyData.read(str(tmp_path / "g.ply"))["vertex"].data
    # f_rest_{c*15 + k} holds coefficient k of colour channel c
    assert vertex["f_rest_16"][1] == pytest.approx(gaussians["shN"][1, 1, 1].item())
    assert vertex["f_rest_30"][2] == pytest.approx(gaussians["shN"][2, 0, 2].item())


def test_a_plain_3dgs_file_without_identity_loads(tmp_path: Path):
    gaussians = random_gaussians(4, k=0)
    del gaussians["identity"]
    save_ply(tmp_path / "plain.ply", gaussians)
    loaded = load_ply(tmp_path / "plain.ply")
    assert loaded["shN"].shape == (4, 0, 3) and torch.equal(loaded["identity"], torch.zeros(4, 16))


def test_truncated_file_gets_a_clear_error(tmp_path: Path):
    save_ply(tmp_path / "g.ply", random_gaussians())
    data = (tmp_path / "g.ply").read_bytes()
    (tmp_path / "cut.ply").write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match="cut.ply.*truncated"):
        load_ply(tmp_path / "cut.ply")


@pytest.mark.parametrize("content", [b"", b"ply\nformat ascii 1.0\nend_header\n", b"\x00garbage"])
def test_foreign_or_empty_files_get_a_clear_error(tmp_path: Path, content: bytes):
    (tmp_path / "bad.ply").write_bytes(content)
    with pytest.raises(InputError, match="bad.ply"):
        load_ply(tmp_path / "bad.ply")


def test_a_mesh_ply_is_refused_with_the_missing_properties(tmp_path: Path):
    vertex = np.zeros(3, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
    PlyData([PlyElement.describe(vertex, "vertex")]).write(str(tmp_path / "mesh.ply"))
    with pytest.raises(InputError, match="mesh.ply is not a 3DGS .ply: missing .*f_dc_0"):
        load_ply(tmp_path / "mesh.ply")


def test_classifier_round_trip(tmp_path: Path):
    classifier = new_classifier(6)
    save_classifier(tmp_path / "classifier.npz", classifier)
    loaded = load_classifier(tmp_path / "classifier.npz")
    x = torch.randn(10, 16)
    assert torch.equal(loaded(x), classifier(x))
