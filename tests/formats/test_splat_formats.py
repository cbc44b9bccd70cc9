"""The splat formats other tools share (engine.formats.splat_files): each written and read back field by field
within its quantisation, each checked against its published layout byte by byte on a hand-made Gaussian, and
`engine export` / `import-splat` over them."""

from __future__ import annotations

import gzip
import json
import struct
from pathlib import Path

import numpy as np
import pytest
from plyfile import PlyData

from engine.base.errors import InputError
from engine.cli import main
from engine.formats.splat_files import FORMATS, SUFFIX, _structured, format_of, read_splat_file, write_splat_file
from engine.formats.splat_ply import SH_C0, property_names, write_vertices

pytestmark = pytest.mark.fast

# the most each format may move a field (position units, log scale, rotation degrees, alpha, rgb, SH coefficient),
# half a quantisation step: .spz fixed point 1/4096, log scale 1/16, colour 1/(0.15 x 255) of f_dc, 9-bit
# smallest-three; compressed .ply 11/10 bits of a chunk's range (10 units, 6 log units here), 10-bit smallest-three;
# .splat float positions and scales, 8-bit quaternion components. The .ply is exact (its angle is float32 noise).
TOLERANCE = {"ply": (0, 0, 0.1, 0, 0, 0), "spz": (1.3e-4, 0.032, 0.3, 0.002, 0.0037, 0.004),
             "compressed-ply": (0.0055, 0.003, 0.3, 0.002, 0.0022, 0.016), "splat": (0, 1e-6, 0.9, 0.002, 0.0022, None)}


def gaussians(n: int = 600, degree: int = 3, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    k = (degree + 1) ** 2 - 1
    columns = {c: rng.uniform(-5, 5, n) for c in ("x", "y", "z")}
    columns |= {f"f_dc_{i}": rng.uniform(-1.7, 1.7, n) for i in range(3)}  # colours inside [0, 1]
    columns |= {f"f_rest_{i}": rng.uniform(-0.9, 0.9, n) for i in range(3 * k)}
    columns["opacity"] = rng.normal(0, 2, n)
    columns |= {f"scale_{i}": rng.uniform(-7, -1, n) for i in range(3)}
    quat = rng.normal(0, 1, (n, 4))
    columns |= {f"rot_{i}": (quat / np.linalg.norm(quat, axis=1, keepdims=True))[:, i] for i in range(4)}
    return _structured({c: v.astype(np.float32) for c, v in columns.items()})


def differences(a: np.ndarray, b: np.ndarray) -> tuple:
    stack = lambda v, names: np.stack([v[c].astype(np.float64) for c in names], 1)  # noqa: E731
    sigmoid = lambda v: 1 / (1 + np.exp(-v["opacity"].astype(np.float64)))  # noqa: E731
    qa, qb = stack(a, [f"rot_{i}" for i in range(4)]), stack(b, [f"rot_{i}" for i in range(4)])
    angle = np.degrees(2 * np.arccos(np.clip(np.abs((qa * qb).sum(1)), 0, 1)))
    rest = [c for c in b.dtype.names if c.startswith("f_rest_")]
    return (np.abs(stack(a, "xyz") - stack(b, "xyz")).max(),
            np.abs(stack(a, [f"scale_{i}" for i in range(3)]) - stack(b, [f"scale_{i}" for i in range(3)])).max(),
            angle.max(), np.abs(sigmoid(a) - sigmoid(b)).max(),
            SH_C0 * np.abs(stack(a, [f"f_dc_{i}" for i in range(3)]) - stack(b, [f"f_dc_{i}" for i in range(3)])).max(),
            np.abs(stack(a, rest) - stack(b, rest)).max() if rest else None)


@pytest.mark.parametrize("kind", FORMATS)
def test_every_format_round_trips_each_field_within_its_quantisation(kind: str, tmp_path: Path):
    original = gaussians()
    path = tmp_path / f"scene{SUFFIX[kind]}"
    write_splat_file(path, original, kind)
    assert format_of(path) == kind
    back = read_splat_file(path)
    assert len(back) == len(original)
    for got, most in zip(differences(original, back), TOLERANCE[kind], strict=True):
        assert (got is None) == (most is None) and (got is None or got <= most), (kind, got, most)
    if kind == "spz":  # SH kept to degree 1 when asked: 9 coefficients
        write_splat_file(path, original, kind, sh_degree=1)
        assert sum(c.startswith("f_rest_") for c in read_splat_file(path).dtype.names) == 9


def test_a_standard_ply_export_has_exactly_the_inria_fields_in_plyfile(tmp_path: Path):
    original = gaussians(degree=1)
    identity = np.zeros(len(original), [(f"obj_dc_{i}", "<f4") for i in range(16)])
    merged = np.zeros(len(original), original.dtype.descr + identity.dtype.descr)
    for c in original.dtype.names:
        merged[c] = original[c]
    write_splat_file(tmp_path / "plain.ply", merged, "ply")
    names = [p.name for p in PlyData.read(str(tmp_path / "plain.ply"))["vertex"].properties]
    assert names == property_names(3, with_identity=False)
    write_splat_file(tmp_path / "ours.ply", merged, "ply", identities=True)
    assert [p.name for p in PlyData.read(str(tmp_path / "ours.ply"))["vertex"].properties] == \
        property_names(3, with_identity=True)


def test_an_spz_file_is_the_published_layout_in_right_up_back_axes(tmp_path: Path):
    """One Gaussian at (1, 2, 3) in the .ply's axes (right-down-forward): the header is magic NGSP, version 3, one
    point, degree 0, 12 fractional bits; the position stored is (1, -2, -3) in 24-bit fixed point; alpha 1/2
    is 128 (127.5 rounded), f_dc 0 is 127.5 -> 128, log scale -2 is 128, the identity rotation stores index 3
    (w largest) and zeros. A hand-made version 2 file (first three, x y z) reads back as the same Gaussian."""
    one = _structured({"x": np.float32([1]), "y": np.float32([2]), "z": np.float32([3]), "f_dc_0": np.float32([0]),
                       "f_dc_1": np.float32([0]), "f_dc_2": np.float32([0]), "opacity": np.float32([0]),
                       "scale_0": np.float32([-2]), "scale_1": np.float32([-2]), "scale_2": np.float32([-2]),
                       "rot_0": np.float32([1]), "rot_1": np.float32([0]), "rot_2": np.float32([0]),
                       "rot_3": np.float32([0])})
    write_splat_file(tmp_path / "one.spz", one, "spz")
    raw = gzip.decompress((tmp_path / "one.spz").read_bytes())
    assert struct.unpack_from("<IIIBBBB", raw) == (0x5053474E, 3, 1, 0, 12, 0, 0)
    fixed = [int.from_bytes(raw[16 + 3 * i:19 + 3 * i], "little", signed=True) for i in range(3)]
    assert fixed == [4096, -8192, -12288]
    assert raw[25] == 128 and list(raw[26:29]) == [128] * 3 and list(raw[29:32]) == [128] * 3
    assert int.from_bytes(raw[32:36], "little") == 3 << 30
    v2 = struct.pack("<IIIBBBB", 0x5053474E, 2, 1, 0, 12, 0, 0) + raw[16:32] + bytes([128, 128, 128])
    (tmp_path / "v2.spz").write_bytes(gzip.compress(v2))
    back = read_splat_file(tmp_path / "v2.spz")
    assert [float(back[c][0]) for c in ("x", "y", "z", "scale_0", "rot_0")] == pytest.approx([1, 2, 3, -2, 1], abs=0.01)


def test_a_splat_record_and_a_compressed_ply_are_their_published_layouts(tmp_path: Path):
    one = gaussians(n=1)
    write_splat_file(tmp_path / "one.splat", one, "splat")
    raw = (tmp_path / "one.splat").read_bytes()
    assert len(raw) == 32 and struct.unpack_from("<3f", raw) == pytest.approx([float(one[c][0]) for c in "xyz"])
    assert struct.unpack_from("<3f", raw, 12) == pytest.approx([np.exp(float(one[f"scale_{i}"][0])) for i in range(3)])
    assert raw[27] == round(255 / (1 + np.exp(-float(one["opacity"][0]))))
    write_splat_file(tmp_path / "one.compressed.ply", gaussians(n=300, degree=0), "compressed-ply")
    data = PlyData.read(str(tmp_path / "one.compressed.ply"))
    assert [e.name for e in data.elements] == ["chunk", "vertex"] and len(data["chunk"]) == 2
    chunk, vertex = data["chunk"][0], data["vertex"][0]
    x = chunk["min_x"] + (int(vertex["packed_position"]) >> 21) / 2047 * (chunk["max_x"] - chunk["min_x"])
    assert x == pytest.approx(float(gaussians(n=300, degree=0)["x"][0]), abs=0.006)


def test_export_writes_each_format_from_a_runs_stage_and_import_reads_it_back(tmp_path: Path):
    run = tmp_path / "run"
    (run / "removed").mkdir(parents=True)
    original = gaussians(degree=1)
    write_vertices(run / "removed" / "point_cloud.ply", {c: original[c] for c in original.dtype.names})
    for kind in FORMATS:
        assert main(["export", "--run", str(run), "--stage", "removed", "--format", kind]) == 0
        out = run / "exports" / f"removed{SUFFIX[kind]}"
        assert len(read_splat_file(out)) == len(original)
    assert main(["export", "--run", str(run), "--stage", "complete", "--format", "spz"]) == 2  # none finished
    assert main(["export", "--run", str(run), "--format", "obj"]) == 2
    with pytest.raises(InputError, match="32-byte"):
        (tmp_path / "cut.splat").write_bytes(b"\0" * 33)
        read_splat_file(tmp_path / "cut.splat")
    with pytest.raises(InputError, match="not gzip"):
        (tmp_path / "bad.spz").write_bytes(b"not a splat")
        read_splat_file(tmp_path / "bad.spz")
    assert json.dumps(FORMATS)  # the CLI's --format values
