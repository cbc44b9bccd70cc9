"""The completion methods and their names as the paper writes them. Free of torch, so the benchmark
script can name its cells from Blender's Python too."""

from __future__ import annotations

METHODS = ("init", "direct", "ft")


def method_name(method: str, inpainter: str, refs: int = 3, perceptual: str = "lpips", recolmap: bool = False
                ) -> str:
    """Init-<inpainter>, Direct-<inpainter>, FT-<inpainter>(3|All); FT with L1 as its perceptual term: [l1];
    Init or Direct on poses COLMAP re-estimated from the inpainted images (the paper's ablation): [colmap]."""
    if method == "ft":
        return f"FT-{inpainter}({refs or 'All'})" + ("" if perceptual == "lpips" else f"[{perceptual}]")
    return {"init": f"Init-{inpainter}", "direct": f"Direct-{inpainter}"}[method] + ("[colmap]" if recolmap else "")
