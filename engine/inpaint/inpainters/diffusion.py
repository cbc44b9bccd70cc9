"""Diffusion inpainting from a local diffusers folder (SD-inpainting, SDXL-inpainting, or a PowerPaint /
BrushNet folder that brings its own pipeline.py), with the paper's prompts and settings.

The folder is what `pipeline.save_pretrained(DIR)` writes (model_index.json plus one folder per component);
path from the `model` option or DIFFUSION_MODEL, loaded with local_files_only, so nothing is downloaded.
diffusers ships no PowerPaint or BrushNet pipeline: such a folder must hold a pipeline.py whose pipeline
takes the standard inpainting call (prompt, image, mask_image, negative_prompt, num_inference_steps,
guidance_scale, height, width, generator); it is then loaded as a diffusers custom pipeline.

Settings from the paper (supplement, "PowerPaint and BrushNet Prompt"): one generic positive and negative
prompt for every scene, 45 steps, guidance 20 for RGB and 10 for depth. The pipeline works at a size
divisible by 8 near the image's own, the result is resized back, and every pixel outside the mask is pasted
back from the input (the base class does that), as the paper does.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.base.plugins import Needs
from engine.inpaint.registry import Inpainter, register

POSITIVE = ("Restore only the masked region to match the surrounding scene. Keep lighting, colors, texture, "
            "geometry, and perspective consistent. Do not alter any unmasked pixels. Seamless boundary blend.")
NEGATIVE = ("changes outside mask, global color shift, exposure shift, contrast shift, style change, camera change, "
            "composition change, warped edges, blur, artifacts.")
MULTIPLE = 8  # the VAE downsamples by 8


@register("diffusion")
class Diffusion(Inpainter):
    summary = "a local diffusers inpainting folder (SD, SDXL, PowerPaint, BrushNet)"
    needs = Needs(weights=("diffusers folder (--model or DIFFUSION_MODEL)",), gpu=True)
    def __init__(self, model: str = "", device: str = "", steps: int = 45, guidance_rgb: float = 20.0,
                 guidance_depth: float = 10.0, negative_prompt: str = NEGATIVE, seed: int = 0, **options) -> None:
        super().__init__(**options)
        self.steps, self.guidance_rgb, self.guidance_depth = steps, guidance_rgb, guidance_depth
        self.negative_prompt, self.seed = negative_prompt, seed
        self.pipe = _load(_folder(model), device)

    def inpaint_rgb(self, image, mask, prompt):
        return self._fill(image, mask, prompt, self.guidance_rgb)

    def inpaint_grey(self, grey, mask, prompt):
        return self._fill(grey, mask, prompt, self.guidance_depth)

    def _fill(self, image: np.ndarray, mask: np.ndarray, prompt: str | None, guidance: float) -> np.ndarray:
        import torch
        from PIL import Image

        h, w = mask.shape
        size = (max(MULTIPLE, round(w / MULTIPLE) * MULTIPLE), max(MULTIPLE, round(h / MULTIPLE) * MULTIPLE))
        x = cv2.resize(image, size, interpolation=cv2.INTER_AREA) if size != (w, h) else image
        m = cv2.resize(mask.astype(np.uint8) * 255, size, interpolation=cv2.INTER_NEAREST)
        generator = torch.Generator(device="cpu").manual_seed(self.seed)
        out = self.pipe(prompt=prompt or POSITIVE, negative_prompt=self.negative_prompt, image=Image.fromarray(x),
                        mask_image=Image.fromarray(m), height=size[1], width=size[0],
                        num_inference_steps=self.steps, guidance_scale=guidance, generator=generator,
                        output_type="np").images[0]
        out = np.clip(out * 255.0 + 0.5, 0, 255).astype(np.uint8)
        return cv2.resize(out, (w, h), interpolation=cv2.INTER_CUBIC) if out.shape[:2] != (h, w) else out


def _folder(model: str) -> Path:
    path = Path(model or os.environ.get("DIFFUSION_MODEL", ""))
    if str(path) in ("", "."):
        raise InputError("no diffusion model given: pass --model DIR (a local diffusers inpainting folder with "
                         "model_index.json) or set DIFFUSION_MODEL")
    if not (path / "model_index.json").is_file():
        raise InputError(f"{path / 'model_index.json'} not found: --model must name a diffusers folder, as "
                         "written by pipeline.save_pretrained(DIR)")
    return path


def _load(folder: Path, device: str):
    try:
        import torch
        from diffusers import AutoPipelineForInpainting, DiffusionPipeline
        from diffusers.utils import logging as diffusers_logging
        from transformers.utils import logging as transformers_logging
    except ImportError as exc:
        raise InputError(f"the diffusion inpainter needs {exc.name}: pip install -r requirements/engine.txt"
                         ) from exc
    diffusers_logging.set_verbosity_error()
    transformers_logging.set_verbosity_error()
    device = device or ("cuda" if torch.cuda.is_available() else "cpu")
    options: dict = {"local_files_only": True, "dtype": torch.float16 if device == "cuda" else torch.float32}
    if "safety_checker" in json.loads((folder / "model_index.json").read_text()):
        options.update(safety_checker=None, requires_safety_checker=False)  # it blacks out whole frames
    try:
        if (folder / "pipeline.py").is_file():
            pipe = DiffusionPipeline.from_pretrained(folder, custom_pipeline=str(folder), **options)
        else:
            pipe = AutoPipelineForInpainting.from_pretrained(folder, **options)
    except (OSError, ValueError, KeyError, AttributeError) as exc:
        raise InputError(f"{folder} is not a loadable diffusers inpainting folder ({str(exc).splitlines()[0]})"
                         ) from exc
    pipe.set_progress_bar_config(disable=True)
    return pipe.to(device)
