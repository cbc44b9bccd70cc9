"""LaMa from the user's weights: TorchScript `big-lama.pt` (called model(image, mask)) or ONNX
`lama_fp32.onnx` (inputs `image`, `mask`, fixed 512x512, run by onnxruntime). Path from the `model` option
or the LAMA_MODEL environment variable; nothing is downloaded.

Inputs as LaMa expects them: image (1, 3, H, W) float in [0, 1], mask (1, 1, H, W) float, 1 = fill.
TorchScript takes any size, padded here (reflect) to a multiple of 8 as LaMa's own predictor does; the ONNX
export is fixed at 512x512, so image and mask are resized to it and the result back. Exports differ in
output scale (some return [0, 1], some [0, 255]); values above 2 are read as [0, 255].
"""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.base.plugins import Needs
from engine.inpaint.registry import Inpainter, register

ONNX_SIZE = 512
PAD = 8


@register("lama")
class Lama(Inpainter):
    summary = "LaMa from your weights: big-lama.pt (TorchScript) or lama_fp32.onnx"
    needs = Needs(weights=("LaMa (--model or LAMA_MODEL)",))
    def __init__(self, model: str = "", device: str = "cpu", **options) -> None:
        super().__init__(**options)
        path = Path(model or os.environ.get("LAMA_MODEL", ""))
        if not str(path) or str(path) == "." or not path.is_file():
            raise InputError(f"LaMa weights not found{f' at {path}' if str(path) not in ('', '.') else ''}: "
                             "pass --model /path/big-lama.pt (TorchScript) or lama_fp32.onnx, or set LAMA_MODEL")
        self.device = device
        self.run = self._load_onnx(path) if path.suffix == ".onnx" else self._load_torchscript(path)

    def _load_torchscript(self, path: Path):
        import torch

        try:
            model = torch.jit.load(str(path), map_location=self.device).eval()
        except (RuntimeError, ValueError) as exc:
            raise InputError(f"{path} is not a TorchScript LaMa model ({str(exc).splitlines()[0]})") from exc

        def run(image: np.ndarray, mask: np.ndarray) -> np.ndarray:
            h, w = mask.shape
            ph, pw = -h % PAD, -w % PAD
            image = np.pad(image, ((0, ph), (0, pw), (0, 0)), mode="reflect")
            mask = np.pad(mask, ((0, ph), (0, pw)), mode="reflect")
            with torch.no_grad():
                x = torch.from_numpy(image).permute(2, 0, 1)[None].to(self.device)
                m = torch.from_numpy(mask)[None, None].to(self.device)
                out = model(x, m)[0].permute(1, 2, 0).float().cpu().numpy()
            return out[:h, :w]

        return run

    def _load_onnx(self, path: Path):
        try:
            import onnxruntime
        except ImportError as exc:
            raise InputError("the ONNX LaMa needs onnxruntime: pip install onnxruntime (requirements/engine.txt)"
                             ) from exc
        try:
            session = onnxruntime.InferenceSession(str(path), providers=["CPUExecutionProvider"])
        except Exception as exc:  # onnxruntime raises its own exception types for unreadable models
            raise InputError(f"{path} is not a readable ONNX model ({str(exc).splitlines()[0]})") from exc
        inputs = {i.name for i in session.get_inputs()}
        if inputs != {"image", "mask"}:
            raise InputError(f"{path} has inputs {sorted(inputs)}; a LaMa export takes 'image' and 'mask'")

        def run(image: np.ndarray, mask: np.ndarray) -> np.ndarray:
            h, w = mask.shape
            x = cv2.resize(image, (ONNX_SIZE, ONNX_SIZE), interpolation=cv2.INTER_AREA)
            m = (cv2.resize(mask, (ONNX_SIZE, ONNX_SIZE), interpolation=cv2.INTER_NEAREST) > 0.5).astype(np.float32)
            out = session.run(None, {"image": x.transpose(2, 0, 1)[None].astype(np.float32),
                                     "mask": m[None, None]})[0][0].transpose(1, 2, 0)
            return cv2.resize(out, (w, h), interpolation=cv2.INTER_CUBIC)

        return run

    def inpaint_rgb(self, image, mask, prompt):
        out = self.run(image.astype(np.float32) / 255.0, mask.astype(np.float32))
        scale = 1.0 if out.max() > 2.0 else 255.0
        return np.clip(out * scale + 0.5, 0, 255).astype(np.uint8)
