"""The inpainter registry, the offline inpainters, and LaMa's two loaders on tiny models built here."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from engine.errors import InputError
from engine.inpainters import create, names

Y, X = np.mgrid[:72, :96]
TEXTURE = np.stack([128 + 60 * np.sin(X / 9), 128 + 60 * np.cos(Y / 11), 100 + X + 0 * Y], -1).astype(np.uint8)
MASK = np.zeros((72, 96), bool)
MASK[25:45, 30:60] = True


def error_in_mask(image: np.ndarray) -> float:
    return float(np.abs(image[MASK].astype(float) - TEXTURE[MASK]).mean())


@pytest.mark.parametrize("name", ["telea", "navier-stokes", "fsr", "shiftmap"])
def test_offline_inpainters_fill_a_texture_far_better_than_leaving_the_hole(name):
    """Mean absolute error inside the hole (0-255), measured: hole left black 104; fsr 2.7, navier-stokes 7.1,
    telea 9.8, shift-map 31.9 (it copies whole patches, which a sinusoid never repeats exactly)."""
    empty = TEXTURE.copy()
    empty[MASK] = 0
    filled = create(name).inpaint(TEXTURE, MASK)
    assert error_in_mask(filled) < 0.4 * error_in_mask(empty)
    assert (filled[~MASK] == TEXTURE[~MASK]).all()  # outside the mask nothing changes


def test_registry_lists_every_inpainter_and_rejects_unknown_names():
    assert {"telea", "navier-stokes", "fsr", "shiftmap", "lama"} <= set(names())
    with pytest.raises(InputError, match="available: fsr"):
        create("photoshop")


def test_an_empty_mask_passes_the_image_through():
    out = create("fsr").inpaint(TEXTURE, np.zeros_like(MASK))
    assert (out == TEXTURE).all()


def test_foreground_depth_range_fills_a_near_hole_more_precisely_than_the_global_range():
    """A tilted table at 2-3 m in front of a wall at 20 m: the foreground range spends the grey levels on
    the table. Measured with fsr: 0.6 mm (foreground) vs 19 mm (global) mean error in the hole."""
    depth = np.where(Y < 8, 20.0, 2.0 + X / 96.0).astype(np.float32)
    errors = {r: np.abs(create("fsr", depth_range=r).inpaint(depth, MASK, kind="depth")[MASK] - depth[MASK]).mean()
              for r in ("global", "foreground")}
    assert errors["foreground"] < 0.25 * errors["global"]
    assert errors["foreground"] < 0.01


class MeanFill(torch.nn.Module):
    """LaMa's call signature: fills the mask with the mean colour of the known pixels."""

    def forward(self, image: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        known = 1 - mask
        mean = (image * known).sum(dim=(2, 3), keepdim=True) / known.sum(dim=(2, 3), keepdim=True)
        return image * known + mean * mask


def test_lama_torchscript_loader_runs_a_tiny_model_at_any_size(tmp_path):
    path = tmp_path / "big-lama.pt"
    torch.jit.script(MeanFill()).save(str(path))
    image, mask = TEXTURE[:70, :93], MASK[:70, :93]  # not multiples of 8: padded and cropped back
    out = create("lama", model=str(path)).inpaint(image, mask)
    expected = image[~mask].reshape(-1, 3).mean(0)
    assert out.shape == image.shape
    assert np.abs(out[mask].astype(float) - expected).max() < 12  # reflect padding adds a few known pixels
    assert (out[~mask] == image[~mask]).all()


def test_lama_onnx_loader_runs_a_tiny_model(tmp_path):
    import onnx
    from onnx import TensorProto, helper

    shape = [1, 3, 512, 512]
    graph = helper.make_graph(
        [helper.make_node("Sub", ["one", "mask"], ["known"]),
         helper.make_node("Mul", ["image", "known"], ["kept"]),
         helper.make_node("Mul", ["mask", "grey"], ["fill"]),
         helper.make_node("Add", ["kept", "fill"], ["output"])],
        "lama_signature",
        [helper.make_tensor_value_info("image", TensorProto.FLOAT, shape),
         helper.make_tensor_value_info("mask", TensorProto.FLOAT, [1, 1, 512, 512])],
        [helper.make_tensor_value_info("output", TensorProto.FLOAT, shape)],
        [helper.make_tensor("one", TensorProto.FLOAT, [], [1.0]), helper.make_tensor("grey", TensorProto.FLOAT, [],
                                                                                        [0.5])])
    path = tmp_path / "lama_fp32.onnx"
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)])
    model.ir_version = 9  # what onnxruntime 1.31 reads (onnx 1.23 writes 14 by default)
    onnx.save(model, str(path))
    out = create("lama", model=str(path)).inpaint(TEXTURE, MASK)
    inner = MASK.copy()
    inner[:, :] = False
    inner[28:42, 33:57] = True  # away from the resized mask's edge
    assert np.abs(out[inner].astype(int) - 128).max() <= 1
    assert (out[~MASK] == TEXTURE[~MASK]).all()


def test_missing_lama_weights_say_how_to_supply_them(tmp_path, monkeypatch):
    monkeypatch.delenv("LAMA_MODEL", raising=False)
    with pytest.raises(InputError, match="LAMA_MODEL"):
        create("lama")
    with pytest.raises(InputError, match="not found at .*nope.pt"):
        create("lama", model=str(tmp_path / "nope.pt"))
    (tmp_path / "bad.pt").write_bytes(b"not a model")
    with pytest.raises(InputError, match="not a TorchScript LaMa model"):
        create("lama", model=str(tmp_path / "bad.pt"))
