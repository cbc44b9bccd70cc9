"""Classical inpainters that need no weights: OpenCV's Telea and Navier-Stokes, and cv2.xphoto's FSR
(frequency-selective reconstruction) and shift-map (exemplar-based: copies whole patches from elsewhere in
the image, so texture survives where diffusion-style fills blur)."""

from __future__ import annotations

import cv2
import numpy as np

from engine.base.plugins import Needs
from engine.inpaint.registry import Inpainter, register

RADIUS = 5  # px of neighbourhood Telea and Navier-Stokes look at


class OpenCvInpainter(Inpainter):
    """OpenCV's inpainters run in C++ without Python's lock, so a run's views can go at once."""

    def parallel_views(self) -> str:
        return "threads"


@register("telea")
class Telea(OpenCvInpainter):
    summary = "OpenCV Telea: smooth fill from the hole's border"
    def inpaint_rgb(self, image, mask, prompt):
        return cv2.inpaint(image, mask.astype(np.uint8), RADIUS, cv2.INPAINT_TELEA)


@register("navier-stokes")
class NavierStokes(OpenCvInpainter):
    summary = "OpenCV Navier-Stokes: smooth fill along isophotes"
    def inpaint_rgb(self, image, mask, prompt):
        return cv2.inpaint(image, mask.astype(np.uint8), RADIUS, cv2.INPAINT_NS)


def _xphoto(image: np.ndarray, mask: np.ndarray, method: int) -> np.ndarray:
    """cv2.xphoto.inpaint takes the mask the other way round: non-zero marks the *known* pixels."""
    known = (~mask).astype(np.uint8) * 255
    out = np.zeros_like(image)
    cv2.xphoto.inpaint(image, known, out, method)
    return out


@register("fsr")
class FrequencySelective(OpenCvInpainter):
    summary = "OpenCV xphoto frequency-selective reconstruction"
    needs = Needs(packages=("opencv-contrib",))
    def inpaint_rgb(self, image, mask, prompt):
        return _xphoto(image, mask, cv2.xphoto.INPAINT_FSR_FAST)


@register("shiftmap")
class ShiftMap(OpenCvInpainter):
    summary = "OpenCV xphoto shift-map: texture synthesis by copying patches"
    needs = Needs(packages=("opencv-contrib",))
    def inpaint_rgb(self, image, mask, prompt):
        # shift-map works in Lab, as its authors' OpenCV sample does
        lab = cv2.cvtColor(image, cv2.COLOR_RGB2Lab)
        return cv2.cvtColor(_xphoto(lab, mask, cv2.xphoto.INPAINT_SHIFTMAP), cv2.COLOR_Lab2RGB)
