"""What `complete` and `inpaint` do by default: the method and inpainter with the best mean m-PSNR in the true hole
among those below the unfilled hole on no tuning scene (scene seeds 0-99, where every default is chosen:
engine.formats.protocol); the held-out table (seeds 100 and up) only reports how the choice holds
(docs/BENCHMARKS.md, "Held-out table"). A module of its own at the bottom layer, free of torch and numpy, because
the CLI, both stages and the Blender add-on's menus read it.

At 709b800 Ref-telea scored above the unfilled hole on all eight tuning scenes `_s8`/`_s90` (mean 26.72 against
20.29 dB; +0.47 to +20.95), with the rest of every test view kept at 51.8-60.0 dB against the removed scene
(`confine`), so `complete` fills the hole with it. Before, the hole stayed as removal left it: at 5e5ff92 Ref-telea
was below the unfilled hole on statue_s90 (-1.15 dB), where the slab's Gaussians continued under the pedestal, and
at 33d96f8, 6f87d43 and 119642d below it on held-out scenes (statue_s100 -5.37 at 119642d). `--method ''` still
leaves the hole (LEFT).
"""

DEFAULT_METHOD = "reference"  # "": leave the hole
BEST_ON_MEAN = ("reference", "telea")  # (method, inpainter)
DEFAULT_INPAINTER = BEST_ON_MEAN[1]
WHY = ("Ref-telea scored above the unfilled hole on all eight tuning scenes (mean m-PSNR 26.72 against 20.29 dB at "
       "709b800: docs/BENCHMARKS.md, \"Held-out table\")")
LEFT = "--method '' leaves the hole as removal left it"
