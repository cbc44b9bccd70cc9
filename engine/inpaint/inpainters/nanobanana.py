"""Nano Banana (Gemini 2.5 Flash Image) through the google-genai SDK: the paper's direct baseline.

It sees no mask: it gets the original input image and a scene prompt naming the object, and paints the
object out itself (Init-NanoBanana in the paper, which trains on these images with no removal step). Its
whole output image is used, as in the paper, unless a mask is given, in which case pixels outside it are
pasted back. RGB only.

The key comes from GEMINI_API_KEY and goes only into the SDK's request header: it is never stored on the
object, printed, or written to a file. `base_url` points the SDK at another endpoint speaking the same wire
format (the tests use a server on loopback).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.base.plugins import Needs
from engine.formats.layout import SceneLayout
from engine.inpaint.registry import Inpainter, register

MODEL = "gemini-2.5-flash-image"

# The paper's prompts (supplement, "Nano Banana Prompt"), keyed by the generator family modelled on each scene.
PAPER_PROMPTS = {
    "statue": (  # the bear scene
        "Remove the grey stone bear sculpture and the square grey stone plinth beneath it from the scene. This "
        "includes the entire bear figure and its base. Inpaint the area by completing and extending the texture of "
        "the large, irregular stone slab, ensuring it appears as a single, continuous, and naturally textured "
        "surface. Extend the surrounding background environment, specifically the large redwood tree trunks, the "
        "green ivy plants, the surrounding leaf litter, and dirt, seamlessly into the space previously occupied by "
        "the statue and its base, ensuring they are not distorted. Ensure the overall natural woodland atmosphere "
        "and perspective are preserved. Remove all contact shadows, complex shadows, and any color-bleed "
        "reflections cast by the removed objects on the stone slab and the forest floor. The small white object on "
        "the stone slab must remain in its position."),
    "tabletop": (  # the kitchen scene
        "Remove the yellow Technic bulldozer toy from the table. This includes the main body, the black treads, "
        "the mechanical arms, and the front bucket. Inpaint the area by extending the textures of the grey woven "
        "placemat and the light pink fabric mat underneath it. Ensure the wood grain of the table visible in the "
        "background is reconstructed seamlessly where the toy was. Remove all contact shadows and yellow "
        "color-bleed reflections on the mats and table surface."),
    "livingroom": (
        "Remove the white fluffy plush creature with horns from the table. This includes its fuzzy white body, "
        "brown horns, pink tongue, and facial features. Inpaint the substantial area it occupied by seamlessly "
        "extending the light-wood grain texture of the table surface. Critically, preserve all surrounding objects "
        "in their precise locations. Remove all contact shadows and any light reflections cast by the creature. "
        "The new, continuous wood surface should have consistent, natural contact shadows for the remaining "
        "objects."),
}


@register("nanobanana")
class NanoBanana(Inpainter):
    summary = "Gemini 2.5 Flash Image paints the object out of the input image (the paper's direct baseline)"
    needs = Needs(keys=("GEMINI_API_KEY",), packages=("google-genai",))
    uses_mask = False

    def __init__(self, model: str = MODEL, base_url: str = "", timeout_s: float = 120.0, **options) -> None:
        super().__init__(**options)
        try:
            from google import genai
            from google.genai import types
        except ImportError as exc:
            raise InputError("nanobanana needs the google-genai package: pip install -r requirements/engine.txt"
                             ) from exc
        if not os.environ.get("GEMINI_API_KEY"):
            raise InputError("GEMINI_API_KEY is not set: export GEMINI_API_KEY=<your Gemini API key> to use "
                             "nanobanana")
        http = types.HttpOptions(base_url=base_url or None, api_version="v1beta", timeout=int(timeout_s * 1000))
        self.client = genai.Client(api_key=os.environ["GEMINI_API_KEY"], http_options=http)
        self.model, self.where = model, base_url or "the Gemini API"
        self.config = types.GenerateContentConfig(response_modalities=["IMAGE"])
        self.types = types

    def default_prompt(self, scene_root: Path) -> str:
        meta = SceneLayout(scene_root).scene_json
        family = json.loads(meta.read_text()).get("family") if meta.is_file() else None
        if family not in PAPER_PROMPTS:
            raise InputError(f"no paper prompt for scene {scene_root}: pass --prompt describing the object to "
                             "remove and what should replace it")
        return PAPER_PROMPTS[family]

    def inpaint(self, image: np.ndarray, mask: np.ndarray | None = None, kind: str = "rgb",
                prompt: str | None = None) -> np.ndarray:
        if kind != "rgb":
            raise InputError("nanobanana inpaints RGB images only; fill depth with another inpainter")
        if not prompt:
            raise InputError("nanobanana needs a prompt naming the object to remove: pass --prompt")
        out = self._generate(np.ascontiguousarray(image, dtype=np.uint8), prompt)
        if mask is None:
            return out
        return np.where(np.asarray(mask, bool)[..., None], out, image)

    def _generate(self, image: np.ndarray, prompt: str) -> np.ndarray:
        import httpx2
        from google.genai import errors

        png = cv2.imencode(".png", cv2.cvtColor(image, cv2.COLOR_RGB2BGR))[1].tobytes()
        parts = [self.types.Part.from_bytes(data=png, mime_type="image/png"), prompt]
        try:
            response = self.client.models.generate_content(model=self.model, contents=parts, config=self.config)
        except errors.APIError as exc:
            raise InputError(f"{self.where} answered {exc.code} {exc.status}: {exc.message}") from exc
        except httpx2.TransportError as exc:  # connection refused, DNS, time-outs
            raise InputError(f"cannot reach {self.where} ({exc}): check the network, or base_url") from exc
        return _image_from(response, image.shape[:2], self.where)


def _image_from(response, shape: tuple[int, int], where: str) -> np.ndarray:
    """The first image part of the answer, at the input's size (Gemini picks its own output resolution)."""
    for candidate in response.candidates or []:
        for part in (candidate.content.parts if candidate.content else None) or []:
            if part.inline_data and (part.inline_data.mime_type or "").startswith("image/"):
                bgr = cv2.imdecode(np.frombuffer(part.inline_data.data, np.uint8), cv2.IMREAD_COLOR)
                if bgr is None:
                    raise InputError(f"{where} returned an image that does not decode")
                rgb = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
                h, w = shape
                return rgb if rgb.shape[:2] == shape else cv2.resize(rgb, (w, h), interpolation=cv2.INTER_AREA)
    reasons = [str(c.finish_reason) for c in response.candidates or []]
    text = " ".join(p.text for c in response.candidates or [] if c.content for p in c.content.parts or [] if p.text)
    raise InputError(f"{where} returned no image (finish reason {', '.join(reasons) or 'none'}"
                     f"{'; said: ' + text[:200] if text else ''}): try again or reword --prompt")
